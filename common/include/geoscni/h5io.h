/* Small HDF5 helpers in which every HDF5 call is checked (STYLE.md rule 4).
 * Datasets are described by the tables of schema.h; each one written gets
 * its units and description as attributes. */
#ifndef GEOSCNI_H5IO_H
#define GEOSCNI_H5IO_H

#include "geoscni/schema.h"

#include <hdf5.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Fixed width of the strings of a GSN_H5_STRING dataset (bytes). */
enum { GSN_H5_STRING_SIZE = 64 };

/* Creates (truncates) an HDF5 file and writes the root attributes: schema
 * version, kind, code and library versions, and the resolved case YAML. */
int gsn_h5_create(const char *path, const char *kind, const char *case_yaml,
                  hid_t *file);

/* Opens a file and refuses one of another schema version or kind. */
int gsn_h5_open(const char *path, const char *kind, int writable, hid_t *file);

/* Closes a file (or group) and sets the handle to H5I_INVALID_HID; accepts an
 * invalid handle. A write that fails says so, with "no space left on device"
 * when the disk is full (files.h, gsn_write_error_raise); so do the other
 * writers below. */
int gsn_h5_close(hid_t *handle);

/* Writes what HDF5 holds of an open file to disk. */
int gsn_h5_flush(hid_t file);

/* Refuses a file that lacks any of count datasets, or holds one of another
 * type or column count, naming what is missing. */
int gsn_h5_require(hid_t loc, const struct gsn_dataset_info *infos, int count);

/* Writes rows x info->columns values (doubles, ints, or for a string
 * dataset rows fixed-width strings of GSN_H5_STRING_SIZE bytes); creates the
 * groups on its path. A dataset that exists with the same shape is
 * overwritten in place. */
int gsn_h5_write(hid_t loc, const struct gsn_dataset_info *info, size_t rows,
                 const void *data);

/* Row count of a dataset, after checking its type and columns. */
int gsn_h5_rows(hid_t loc, const struct gsn_dataset_info *info, size_t *rows);

/* Reads a dataset of exactly rows rows into data. */
int gsn_h5_read(hid_t loc, const struct gsn_dataset_info *info, size_t rows,
                void *data);

/* Root or group attributes. */
int gsn_h5_attr_write_double(hid_t loc, const char *name, double value);
int gsn_h5_attr_write_int(hid_t loc, const char *name, int value);
int gsn_h5_attr_write_string(hid_t loc, const char *name, const char *value);
int gsn_h5_attr_read_double(hid_t loc, const char *name, double *value);
int gsn_h5_attr_read_int(hid_t loc, const char *name, int *value);
/* Reads a string attribute into a malloc'ed string; the caller frees it. */
int gsn_h5_attr_read_string(hid_t loc, const char *name, char **value);

/* Creates a group and the groups on its path, or opens it if it exists. */
int gsn_h5_group(hid_t loc, const char *path, hid_t *group);

/* Opens an existing group (what, e.g. "frame group", names it in the
 * message); a missing or damaged one is an error naming the file. */
int gsn_h5_group_open(hid_t loc, const char *path, const char *what,
                      hid_t *group);

/* 1 if every link on path exists below loc, else 0. */
int gsn_h5_exists(hid_t loc, const char *path);

#ifdef __cplusplus
}
#endif
#endif
