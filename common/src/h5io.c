/* HDF5 helpers. HDF5's own error printing is switched off; every call is
 * checked here and turned into a message that names the file and dataset. */
#include "geoscni/h5io.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/version.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static void h5_quiet(void)
{
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

static herr_t h5_errno_walk(unsigned n, const H5E_error2_t *error, void *data)
{
    (void)n;
    int *found = data;
    const char *at = error->desc ? strstr(error->desc, "errno = ") : NULL;
    if (at && *found == 0)
        *found = atoi(at + 8);
    return 0;
}

/* The errno behind the HDF5 call that just failed: its file driver's
 * message in the error stack says "errno = N" (HDF5's own calls since may
 * have changed errno); else errno. Call before any other HDF5 call. */
static int h5_failure_errno(void)
{
    int found = 0, saved = errno;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, h5_errno_walk, &found);
    return found ? found : saved;
}

static herr_t h5_checksum_walk(unsigned n, const H5E_error2_t *error,
                               void *data)
{
    (void)n;
    int *found = data;
    if (error->desc && strstr(error->desc, "checksum"))
        *found = 1;
    return 0;
}

/* 1 when the HDF5 call that just failed found a metadata checksum that
 * does not match (the data's own is h5_data_checksum's). */
static int h5_failure_checksum(void)
{
    int found = 0;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, h5_checksum_walk, &found);
    return found;
}

#define H5_DAMAGED                                                             \
    "its checksum does not match: the file is damaged (a changed byte); "      \
    "make it again with the stage that wrote it"

/* The file name of a handle, for messages. */
static const char *h5_file_name(hid_t loc, char *buffer, size_t size)
{
    if (H5Fget_name(loc, buffer, size) < 0)
        snprintf(buffer, size, "(HDF5 file)");
    return buffer;
}

static hid_t h5_memory_type(enum gsn_h5_type type, hid_t *owned)
{
    *owned = H5I_INVALID_HID;
    switch (type) {
    case GSN_H5_DOUBLE:
        return H5T_NATIVE_DOUBLE;
    case GSN_H5_INT:
        return H5T_NATIVE_INT;
    case GSN_H5_STRING:
        *owned = H5Tcopy(H5T_C_S1);
        if (*owned < 0 || H5Tset_size(*owned, GSN_H5_STRING_SIZE) < 0 ||
            H5Tset_strpad(*owned, H5T_STR_NULLTERM) < 0)
            return H5I_INVALID_HID;
        return *owned;
    }
    return H5I_INVALID_HID;
}

static H5T_class_t h5_type_class(enum gsn_h5_type type)
{
    return type == GSN_H5_DOUBLE
               ? H5T_FLOAT
               : (type == GSN_H5_INT ? H5T_INTEGER : H5T_STRING);
}

int gsn_h5_group_open(hid_t loc, const char *path, const char *what,
                      hid_t *group)
{
    char file[256];
    h5_file_name(loc, file, sizeof file);
    *group = H5Gopen2(loc, path, H5P_DEFAULT);
    int damaged = *group < 0 && h5_failure_checksum();
    GSN_CHECK(*group >= 0, damaged ? GSN_ERR_IO : GSN_ERR_INPUT,
              "%s: %s '%s' %s", file, what, path,
              damaged ? "cannot be read: " H5_DAMAGED
                      : "is missing (the file was cut short or damaged)");
    return GSN_OK;
}

int gsn_h5_exists(hid_t loc, const char *path)
{
    char partial[512];
    size_t n = strlen(path);
    if (n >= sizeof partial)
        return 0;
    for (size_t i = 0; i <= n; ++i) {
        if (path[i] == '/' || path[i] == '\0') {
            memcpy(partial, path, i);
            partial[i] = '\0';
            if (i > 0 && H5Lexists(loc, partial, H5P_DEFAULT) <= 0)
                return 0;
        }
    }
    return 1;
}

int gsn_h5_group(hid_t loc, const char *path, hid_t *group)
{
    char partial[512], name[512];
    size_t n = strlen(path);
    *group = H5I_INVALID_HID;
    GSN_CHECK(n < sizeof partial, GSN_ERR_INTERNAL, "group path too long");
    for (size_t i = 0; i <= n; ++i) {
        if ((path[i] != '/' && path[i] != '\0') || i == 0)
            continue;
        memcpy(partial, path, i);
        partial[i] = '\0';
        if (H5Lexists(loc, partial, H5P_DEFAULT) > 0)
            continue;
        hid_t created =
            H5Gcreate2(loc, partial, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        GSN_CHECK(created >= 0, GSN_ERR_IO, "%s: cannot create group '%s'",
                  h5_file_name(loc, name, sizeof name), partial);
        H5Gclose(created);
    }
    *group = H5Gopen2(loc, path, H5P_DEFAULT);
    GSN_CHECK(*group >= 0, GSN_ERR_IO, "%s: cannot open group '%s'",
              h5_file_name(loc, name, sizeof name), path);
    return GSN_OK;
}

/* Parent groups of a dataset path. */
static int h5_make_parents(hid_t loc, const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return GSN_OK;
    char parent[512];
    size_t n = (size_t)(slash - path);
    GSN_CHECK(n < sizeof parent, GSN_ERR_INTERNAL, "dataset path too long");
    memcpy(parent, path, n);
    parent[n] = '\0';
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_group(loc, parent, &group));
    H5Gclose(group);
    return GSN_OK;
}

/* A scalar attribute `name` of HDF5 type `type` on loc, replacing one of
 * that name. */
static int h5_attr_write_scalar(hid_t loc, const char *name, hid_t type,
                                const void *value)
{
    char file[256];
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5I_INVALID_HID;
    int ok = space >= 0 && type >= 0;
    if (ok && H5Aexists(loc, name) > 0)
        ok = H5Adelete(loc, name) >= 0;
    if (ok) {
        attr = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
        ok = attr >= 0 && H5Awrite(attr, type, value) >= 0;
    }
    int error_number = ok ? 0 : h5_failure_errno();
    if (attr >= 0)
        H5Aclose(attr);
    if (space >= 0)
        H5Sclose(space);
    if (!ok) {
        char what[128];
        snprintf(what, sizeof what, "cannot write attribute '%s'", name);
        return GSN_WRITE_ERROR(h5_file_name(loc, file, sizeof file),
                               error_number, what);
    }
    return GSN_OK;
}

int gsn_h5_attr_write_string(hid_t loc, const char *name, const char *value)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    int ok = type >= 0 && H5Tset_size(type, strlen(value) + 1) >= 0 &&
             H5Tset_strpad(type, H5T_STR_NULLTERM) >= 0;
    int rc =
        h5_attr_write_scalar(loc, name, ok ? type : H5I_INVALID_HID, value);
    if (type >= 0)
        H5Tclose(type);
    GSN_CALL(rc);
    return GSN_OK;
}

int gsn_h5_attr_write_double(hid_t loc, const char *name, double value)
{
    GSN_CALL(h5_attr_write_scalar(loc, name, H5T_NATIVE_DOUBLE, &value));
    return GSN_OK;
}

int gsn_h5_attr_write_int(hid_t loc, const char *name, int value)
{
    GSN_CALL(h5_attr_write_scalar(loc, name, H5T_NATIVE_INT, &value));
    return GSN_OK;
}

/* That attribute name of loc exists; a damaged header says so. */
static int h5_attr_require(hid_t loc, const char *name)
{
    char file[256];
    htri_t exists = H5Aexists(loc, name);
    GSN_CHECK(exists >= 0 || !h5_failure_checksum(), GSN_ERR_IO,
              "%s: attribute '%s': " H5_DAMAGED,
              h5_file_name(loc, file, sizeof file), name);
    GSN_CHECK(exists > 0, GSN_ERR_INPUT, "%s: attribute '%s' is missing",
              h5_file_name(loc, file, sizeof file), name);
    return GSN_OK;
}

static int h5_attr_read_scalar(hid_t loc, const char *name, hid_t type,
                               H5T_class_t expected, void *value)
{
    char file[256];
    GSN_CALL(h5_attr_require(loc, name));
    hid_t attr = H5Aopen(loc, name, H5P_DEFAULT);
    hid_t stored = attr >= 0 ? H5Aget_type(attr) : H5I_INVALID_HID;
    hid_t space = attr >= 0 ? H5Aget_space(attr) : H5I_INVALID_HID;
    int ok = stored >= 0 && space >= 0 && H5Tget_class(stored) == expected &&
             H5Sget_simple_extent_npoints(space) == 1 &&
             H5Aread(attr, type, value) >= 0;
    if (space >= 0)
        H5Sclose(space);
    if (stored >= 0)
        H5Tclose(stored);
    if (attr >= 0)
        H5Aclose(attr);
    GSN_CHECK(ok, GSN_ERR_INPUT,
              "%s: attribute '%s' cannot be read as a single %s",
              h5_file_name(loc, file, sizeof file), name,
              expected == H5T_FLOAT ? "number" : "integer");
    return GSN_OK;
}

int gsn_h5_attr_read_double(hid_t loc, const char *name, double *value)
{
    GSN_CALL(
        h5_attr_read_scalar(loc, name, H5T_NATIVE_DOUBLE, H5T_FLOAT, value));
    return GSN_OK;
}

int gsn_h5_attr_read_int(hid_t loc, const char *name, int *value)
{
    GSN_CALL(
        h5_attr_read_scalar(loc, name, H5T_NATIVE_INT, H5T_INTEGER, value));
    return GSN_OK;
}

int gsn_h5_attr_read_string(hid_t loc, const char *name, char **value)
{
    char file[256];
    *value = NULL;
    GSN_CALL(h5_attr_require(loc, name));
    hid_t attr = H5Aopen(loc, name, H5P_DEFAULT);
    hid_t stored = attr >= 0 ? H5Aget_type(attr) : H5I_INVALID_HID;
    int ok = stored >= 0 && H5Tget_class(stored) == H5T_STRING &&
             H5Tis_variable_str(stored) == 0;
    size_t size = ok ? H5Tget_size(stored) : 0;
    if (ok) {
        *value = calloc(size + 1, 1);
        ok = *value && H5Aread(attr, stored, *value) >= 0;
    }
    if (stored >= 0)
        H5Tclose(stored);
    if (attr >= 0)
        H5Aclose(attr);
    if (!ok) {
        free(*value);
        *value = NULL;
    }
    GSN_CHECK(ok, GSN_ERR_INPUT, "%s: attribute '%s' is not a readable string",
              h5_file_name(loc, file, sizeof file), name);
    return GSN_OK;
}

int gsn_h5_create(const char *path, const char *kind, const char *case_yaml,
                  hid_t *file)
{
    h5_quiet();
    /* the 1.8 format's superblock, object headers (the attributes, with
     * each dataset's checksum), heaps and B-trees carry checksums of their
     * own, so damaged metadata is found as damaged data is. Not the 1.10
     * format: its superblock marks a file open for writing, and a run
     * killed with its results.h5.part open left it unreadable (no restart,
     * no post of what it had); nor HDF5's Fletcher32 filter on chunked
     * data: the 1.8 chunk index has no checksum of its own (a flipped bit
     * of a chunk's filter mask skipped the data's check; test_h5_damage). */
    hid_t access = H5Pcreate(H5P_FILE_ACCESS);
    if (access >= 0 &&
        H5Pset_libver_bounds(access, H5F_LIBVER_V18, H5F_LIBVER_LATEST) < 0) {
        H5Pclose(access);
        access = H5I_INVALID_HID;
    }
    GSN_CHECK(access >= 0, GSN_ERR_LIBRARY, "%s: cannot set HDF5's file format",
              path);
    *file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, access);
    H5Pclose(access);
    if (*file < 0)
        return GSN_WRITE_ERROR(path, h5_failure_errno(),
                               "cannot create the file (is the folder "
                               "writable?)");
    int rc = GSN_OK;
    GSN_CALL_GOTO(gsn_h5_attr_write_int(*file, GSN_ATTR_SCHEMA_VERSION,
                                        GSN_SCHEMA_VERSION),
                  rc, fail);
    GSN_CALL_GOTO(gsn_h5_attr_write_string(*file, GSN_ATTR_FILE_KIND, kind), rc,
                  fail);
    GSN_CALL_GOTO(gsn_h5_attr_write_string(*file, GSN_ATTR_CODE_VERSION,
                                           gsn_code_version()),
                  rc, fail);
    GSN_CALL_GOTO(gsn_h5_attr_write_string(*file, GSN_ATTR_LIBRARY_VERSIONS,
                                           gsn_library_versions()),
                  rc, fail);
    GSN_CALL_GOTO(gsn_h5_attr_write_string(*file, GSN_ATTR_CASE,
                                           case_yaml ? case_yaml : ""),
                  rc, fail);
    return GSN_OK;
fail:
    gsn_h5_close(file);
    return rc;
}

int gsn_h5_open(const char *path, const char *kind, int writable, hid_t *file)
{
    h5_quiet();
    *file = H5I_INVALID_HID;
    GSN_CHECK(H5Fis_hdf5(path) > 0, GSN_ERR_INPUT,
              "%s: not found or not an HDF5 file", path);
    *file =
        H5Fopen(path, writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
    GSN_CHECK(*file >= 0, GSN_ERR_IO, "%s: cannot open the HDF5 file%s", path,
              h5_failure_checksum() ? ": " H5_DAMAGED
                                    : " (damaged, or written by another "
                                      "program?)");
    int rc = GSN_OK, version = -1;
    char *stored_kind = NULL;
    GSN_CHECK_GOTO(H5Aexists(*file, GSN_ATTR_SCHEMA_VERSION) > 0, rc,
                   GSN_ERR_INPUT, fail,
                   "%s: not a geoscni file (no '%s' attribute)", path,
                   GSN_ATTR_SCHEMA_VERSION);
    GSN_CALL_GOTO(
        gsn_h5_attr_read_int(*file, GSN_ATTR_SCHEMA_VERSION, &version), rc,
        fail);
    GSN_CHECK_GOTO(version == GSN_SCHEMA_VERSION, rc, GSN_ERR_INPUT, fail,
                   "%s: schema version %d, but this geoscni reads version "
                   "%d; run the stage that wrote it again",
                   path, version, GSN_SCHEMA_VERSION);
    GSN_CALL_GOTO(
        gsn_h5_attr_read_string(*file, GSN_ATTR_FILE_KIND, &stored_kind), rc,
        fail);
    GSN_CHECK_GOTO(strcmp(stored_kind, kind) == 0, rc, GSN_ERR_INPUT, fail,
                   "%s: a %s file, but a %s file is expected here", path,
                   stored_kind, kind);
    free(stored_kind);
    return GSN_OK;
fail:
    free(stored_kind);
    gsn_h5_close(file);
    return rc;
}

int gsn_h5_close(hid_t *handle)
{
    if (*handle < 0)
        return GSN_OK;
    H5I_type_t type = H5Iget_type(*handle);
    char file[256];
    h5_file_name(*handle, file, sizeof file);
    herr_t status = -1;
    if (type == H5I_FILE)
        status = H5Fclose(*handle);
    else if (type == H5I_GROUP)
        status = H5Gclose(*handle);
    else if (type == H5I_DATASET)
        status = H5Dclose(*handle);
    int error_number = status >= 0 ? 0 : h5_failure_errno();
    *handle = H5I_INVALID_HID;
    if (status < 0) /* closing a file writes what HDF5 still holds */
        return GSN_WRITE_ERROR(file, error_number, "cannot close the file");
    return GSN_OK;
}

int gsn_h5_flush(hid_t file)
{
    char name[256];
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0)
        return GSN_OK;
    int error_number = h5_failure_errno();
    return GSN_WRITE_ERROR(h5_file_name(file, name, sizeof name), error_number,
                           "cannot write to the file");
}

/* The checksum of a dataset's data as it is in memory (zlib's CRC-32 of
 * every byte, a string's to its fixed size): written beside the data as an
 * attribute of the dataset, whose header the 1.8 format checksums too; a
 * read recomputes it. */
static uint32_t h5_data_checksum(enum gsn_h5_type type, size_t values,
                                 const void *data)
{
    size_t size = type == GSN_H5_DOUBLE
                      ? sizeof(double)
                      : (type == GSN_H5_INT ? sizeof(int) : GSN_H5_STRING_SIZE);
    size_t bytes = values * size;
    uLong crc = crc32(0L, Z_NULL, 0);
    const unsigned char *at = data;
    while (bytes > 0) { /* zlib takes at most UINT_MAX a call */
        uInt piece = bytes > (1u << 30) ? (1u << 30) : (uInt)bytes;
        crc = crc32(crc, at, piece);
        at += piece;
        bytes -= piece;
    }
    return (uint32_t)crc;
}

static int h5_checksum_write(hid_t dataset, const struct gsn_dataset_info *info,
                             size_t rows, const void *data)
{
    unsigned value =
        h5_data_checksum(info->type, rows * (size_t)info->columns, data);
    return h5_attr_write_scalar(dataset, GSN_ATTR_CHECKSUM, H5T_NATIVE_UINT,
                                &value);
}

/* Opens a dataset and checks its type class, rank and columns. */
static int h5_dataset_open(hid_t loc, const struct gsn_dataset_info *info,
                           hid_t *dataset, size_t *rows)
{
    char file[256];
    h5_file_name(loc, file, sizeof file);
    *dataset = H5I_INVALID_HID;
    int exists = gsn_h5_exists(loc, info->path);
    GSN_CHECK(exists || !h5_failure_checksum(), GSN_ERR_IO,
              "%s: dataset '%s': " H5_DAMAGED, file, info->path);
    GSN_CHECK(exists, GSN_ERR_INPUT,
              "%s: dataset '%s' (%s) is missing; was the file written by "
              "another version or cut short?",
              file, info->path, info->description);
    *dataset = H5Dopen2(loc, info->path, H5P_DEFAULT);
    GSN_CHECK(*dataset >= 0, GSN_ERR_IO, "%s: cannot open dataset '%s'%s", file,
              info->path, h5_failure_checksum() ? ": " H5_DAMAGED : "");
    hid_t space = H5Dget_space(*dataset);
    hid_t type = H5Dget_type(*dataset);
    hsize_t dims[2] = {0, 0};
    int rank = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
    int ok = rank >= 1 && rank <= 2 && type >= 0 &&
             H5Sget_simple_extent_dims(space, dims, NULL) >= 0 &&
             H5Tget_class(type) == h5_type_class(info->type);
    int columns = rank == 2 ? (int)dims[1] : 1;
    if (space >= 0)
        H5Sclose(space);
    if (type >= 0)
        H5Tclose(type);
    if (!ok || columns != info->columns) {
        H5Dclose(*dataset);
        *dataset = H5I_INVALID_HID;
        GSN_CHECK(0, GSN_ERR_INPUT,
                  "%s: dataset '%s' has the wrong type or shape (expected %d "
                  "column%s of %s)",
                  file, info->path, info->columns,
                  info->columns == 1 ? "" : "s",
                  info->type == GSN_H5_DOUBLE
                      ? "doubles"
                      : (info->type == GSN_H5_INT ? "integers" : "strings"));
    }
    *rows = (size_t)dims[0];
    return GSN_OK;
}

int gsn_h5_require(hid_t loc, const struct gsn_dataset_info *infos, int count)
{
    for (int i = 0; i < count; ++i) {
        size_t rows = 0;
        GSN_CALL(gsn_h5_rows(loc, &infos[i], &rows));
    }
    return GSN_OK;
}

int gsn_h5_rows(hid_t loc, const struct gsn_dataset_info *info, size_t *rows)
{
    hid_t dataset = H5I_INVALID_HID;
    GSN_CALL(h5_dataset_open(loc, info, &dataset, rows));
    H5Dclose(dataset);
    return GSN_OK;
}

/* The data just read from dataset (of file) against the checksum written
 * with it. */
static int h5_checksum_check(hid_t dataset, const char *file,
                             const struct gsn_dataset_info *info, size_t rows,
                             const void *data)
{
    unsigned stored = 0;
    int found = H5Aexists(dataset, GSN_ATTR_CHECKSUM) > 0;
    int damaged = !found && h5_failure_checksum();
    if (found)
        GSN_CALL(h5_attr_read_scalar(dataset, GSN_ATTR_CHECKSUM,
                                     H5T_NATIVE_UINT, H5T_INTEGER, &stored));
    GSN_CHECK(found, GSN_ERR_IO, "%s: dataset '%s' %s", file, info->path,
              damaged ? "cannot be checked: " H5_DAMAGED
                      : "has no checksum: the file is damaged or not "
                        "geoscni's; make it again with the stage that wrote "
                        "it");
    GSN_CHECK(h5_data_checksum(info->type, rows * (size_t)info->columns,
                               data) == stored,
              GSN_ERR_IO, "%s: dataset '%s': " H5_DAMAGED, file, info->path);
    return GSN_OK;
}

int gsn_h5_read(hid_t loc, const struct gsn_dataset_info *info, size_t rows,
                void *data)
{
    char file[256];
    size_t stored_rows = 0;
    hid_t dataset = H5I_INVALID_HID, owned = H5I_INVALID_HID;
    GSN_CALL(h5_dataset_open(loc, info, &dataset, &stored_rows));
    int ok = stored_rows == rows;
    herr_t status = 0;
    int damaged = 0;
    if (ok && rows > 0) {
        hid_t type = h5_memory_type(info->type, &owned);
        status = type >= 0 ? H5Dread(dataset, type, H5S_ALL, H5S_ALL,
                                     H5P_DEFAULT, data)
                           : -1;
        damaged = status < 0 && h5_failure_checksum();
    }
    if (owned >= 0)
        H5Tclose(owned);
    h5_file_name(loc, file, sizeof file);
    int rc = GSN_OK;
    if (!ok)
        rc = gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                             "%s: dataset '%s' has %zu rows, expected %zu",
                             file, info->path, stored_rows, rows);
    else if (status < 0)
        rc = gsn_error_raise(GSN_ERR_IO, __FILE__, __LINE__, __func__,
                             "%s: cannot read dataset '%s'%s", file, info->path,
                             damaged ? ": " H5_DAMAGED : "");
    else
        rc = h5_checksum_check(dataset, file, info, rows, data);
    H5Dclose(dataset);
    return rc;
}

/* Overwrites an existing dataset of the same shape in place (checkpoints
 * rewritten at every frame must not grow the file). */
static int h5_overwrite(hid_t loc, const struct gsn_dataset_info *info,
                        size_t rows, const void *data)
{
    char file[256];
    size_t stored_rows = 0;
    hid_t dataset = H5I_INVALID_HID, owned = H5I_INVALID_HID;
    GSN_CALL(h5_dataset_open(loc, info, &dataset, &stored_rows));
    hid_t type = h5_memory_type(info->type, &owned);
    GSN_CHECK(stored_rows == rows && type >= 0, GSN_ERR_IO,
              "%s: cannot overwrite dataset '%s' (%zu rows, %zu stored)",
              h5_file_name(loc, file, sizeof file), info->path, rows,
              stored_rows);
    int ok = rows == 0 ||
             H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
    int error_number = ok ? 0 : h5_failure_errno();
    int rc = ok ? h5_checksum_write(dataset, info, rows, data) : GSN_OK;
    if (owned >= 0)
        H5Tclose(owned);
    H5Dclose(dataset);
    GSN_CALL(rc);
    if (!ok) {
        char what[600];
        snprintf(what, sizeof what, "cannot overwrite dataset '%s'",
                 info->path);
        return GSN_WRITE_ERROR(h5_file_name(loc, file, sizeof file),
                               error_number, what);
    }
    return GSN_OK;
}

int gsn_h5_write(hid_t loc, const struct gsn_dataset_info *info, size_t rows,
                 const void *data)
{
    char file[256];
    h5_file_name(loc, file, sizeof file);
    if (gsn_h5_exists(loc, info->path)) {
        GSN_CALL(h5_overwrite(loc, info, rows, data));
        return GSN_OK;
    }
    GSN_CALL(h5_make_parents(loc, info->path));
    hsize_t dims[2] = {(hsize_t)rows, (hsize_t)info->columns};
    int rank = info->columns == 1 ? 1 : 2;
    hid_t owned = H5I_INVALID_HID;
    hid_t type = h5_memory_type(info->type, &owned);
    hid_t space = H5Screate_simple(rank, dims, NULL);
    hid_t dataset = H5I_INVALID_HID;
    int ok = type >= 0 && space >= 0;
    if (ok) {
        dataset = H5Dcreate2(loc, info->path, type, space, H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT);
        ok = dataset >= 0;
    }
    if (ok && rows > 0)
        ok = H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
    int error_number = ok ? 0 : h5_failure_errno();
    if (space >= 0)
        H5Sclose(space);
    if (owned >= 0)
        H5Tclose(owned);
    int rc = GSN_OK;
    if (ok) {
        rc = h5_checksum_write(dataset, info, rows, data);
        if (rc == GSN_OK)
            rc = gsn_h5_attr_write_string(dataset, GSN_ATTR_UNITS, info->units);
        if (rc == GSN_OK)
            rc = gsn_h5_attr_write_string(dataset, GSN_ATTR_DESCRIPTION,
                                          info->description);
    }
    if (dataset >= 0)
        H5Dclose(dataset);
    if (!ok) {
        char what[600];
        snprintf(what, sizeof what, "cannot write dataset '%s'", info->path);
        return GSN_WRITE_ERROR(file, error_number, what);
    }
    GSN_CALL(rc);
    return GSN_OK;
}
