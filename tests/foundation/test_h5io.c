/* model.h5 round trip and the reader's refusals: another schema version,
 * another kind of file, a missing dataset, an index out of range, a file
 * that is not HDF5. Each refusal is an input error with a message, never a
 * crash. */
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/model.h"
#include "testing.h"

#include <string.h>
#include <unistd.h>

/* The schema version as text, for the refusal message. */
#define SCHEMA_STRING(v) #v
#define SCHEMA_TEXT_OF(v) SCHEMA_STRING(v)
#define SCHEMA_TEXT SCHEMA_TEXT_OF(GSN_SCHEMA_VERSION)

/* Two unit cubes side by side: particles at their centres, 11 facets. */
static void build_model(struct gsn_model *m)
{
    TEST_INT(gsn_model_allocate(m, 2, 2, 11, 11, 2, 1), GSN_OK);
    for (int p = 0; p < 2; ++p) {
        m->position[3 * p] = 0.5 + p;
        m->position[3 * p + 1] = m->position[3 * p + 2] = 0.5;
        memcpy(&m->centroid[3 * p], &m->position[3 * p], 3 * sizeof(double));
        m->volume[p] = 1.0;
        m->particle_surface_offset[p + 1] = p + 1;
        m->particle_surface[p] = p;
    }
    int f = 0;
    for (int p = 0; p < 2; ++p) {
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                if (axis == 0 &&
                    ((p == 0 && side == 1) || (p == 1 && side == 0)))
                    continue; /* the shared face, stored once below */
                m->facet_owner[f] = p;
                m->facet_neighbour[f] = -1;
                m->facet_surface[f] = axis == 0 ? p : -1;
                m->facet_area[f] = 1.0;
                m->facet_normal[3 * f + axis] = side ? 1.0 : -1.0;
                f++;
            }
        }
    }
    m->facet_owner[f] = 0;
    m->facet_neighbour[f] = 1;
    m->facet_surface[f] = -1;
    m->facet_area[f] = 1.0;
    m->facet_normal[3 * f] = 1.0;
    f++;
    TEST_INT(f, 11);
    for (int i = 0; i < 11; ++i) {
        m->facet_point_offset[i + 1] = i + 1;
        m->facet_weight[i] = m->facet_area[i];
        m->facet_point[3 * i] = 0.125 * i; /* any value: read back exactly */
    }
    strcpy(m->surface_name[0], "xmin");
    strcpy(m->surface_name[1], "xmax");
    m->surface_tag[0] = 7;
    m->surface_tag[1] = 8;
    m->surface_area[0] = m->surface_area[1] = 1.0;
    int tet[4] = {0, 1, 0, 1};
    memcpy(m->tetrahedra, tet, sizeof tet);
}

static int same_doubles(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, n * sizeof(double)) == 0;
}

static void expect_refusal(const char *path, const char *fragment)
{
    struct gsn_model m;
    int rc = gsn_model_read(path, &m);
    TEST_INT(gsn_error_exit_status(rc), 2); /* bad input or a damaged file */
    if (!strstr(gsn_error_message(), fragment)) {
        TEST_TRUE(!"message names the problem");
        fprintf(stderr, "  message: %s\n  expected to contain: %s\n",
                gsn_error_message(), fragment);
    }
    TEST_TRUE(m.position == NULL); /* nothing half-read is left */
    gsn_error_clear();
}

static void edit_file(const char *path, void (*edit)(hid_t file))
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    TEST_TRUE(file >= 0);
    edit(file);
    H5Fclose(file);
}

static void set_version_99(hid_t file)
{
    TEST_INT(gsn_h5_attr_write_int(file, GSN_ATTR_SCHEMA_VERSION, 99), GSN_OK);
}

static void set_kind_results(hid_t file)
{
    TEST_INT(gsn_h5_attr_write_string(file, GSN_ATTR_FILE_KIND, "results"),
             GSN_OK);
}

static void delete_area(hid_t file)
{
    TEST_TRUE(H5Ldelete(file, "facets/area", H5P_DEFAULT) >= 0);
}

static void corrupt_owner(hid_t file)
{
    /* written as a writer would (with its checksum), so that the reader's
     * range check is what refuses it */
    int owner[11] = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 42};
    TEST_INT(gsn_h5_write(file, &gsn_model_datasets[GSN_MODEL_FACET_OWNER], 11,
                          owner),
             GSN_OK);
}

/* a value changed behind the writer's back (its checksum left as it was) */
static void flip_owner(hid_t file)
{
    int owner[11] = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1}; /* [10] was 0 */
    hid_t dataset = H5Dopen2(file, "facets/owner", H5P_DEFAULT);
    TEST_TRUE(H5Dwrite(dataset, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                       owner) >= 0);
    H5Dclose(dataset);
}

int main(void)
{
    test_begin();
    char folder[] = "/tmp/geoscni-test-h5io-XXXXXX";
    TEST_TRUE(mkdtemp(folder) != NULL);
    char path[256], copy[256], command[600];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    snprintf(copy, sizeof copy, "%s/edited.h5", folder);

    struct gsn_case c;
    TEST_INT(gsn_case_load("cases/valid.yaml", &c), GSN_OK);
    struct gsn_model m, r;
    build_model(&m);
    TEST_INT(gsn_model_write(path, &m, &c), GSN_OK);
    char temporary[300];
    gsn_path_temporary(temporary, sizeof temporary, path);
    TEST_TRUE(access(temporary, F_OK) != 0); /* renamed when complete */

    /* Bit-exact round trip. */
    TEST_INT(gsn_model_read(path, &r), GSN_OK);
    TEST_INT(r.particle_count, 2);
    TEST_INT(r.facet_count, 11);
    TEST_TRUE(same_doubles(m.position, r.position, 6));
    TEST_TRUE(same_doubles(m.facet_normal, r.facet_normal, 33));
    TEST_TRUE(same_doubles(m.facet_point, r.facet_point, 33));
    TEST_TRUE(memcmp(m.facet_neighbour, r.facet_neighbour, 11 * sizeof(int)) ==
              0);
    TEST_TRUE(strcmp(r.surface_name[1], "xmax") == 0);
    TEST_INT(gsn_model_find_surface(&r, "xmax"), 1);
    TEST_INT(gsn_model_find_surface(&r, "top"), -1);
    TEST_INT(r.surface_tag[1], 8);
    gsn_model_free(&r);
    TEST_TRUE(r.position == NULL && r.particle_count == 0);

    /* Root attributes and per-dataset units and descriptions. */
    hid_t file = H5I_INVALID_HID;
    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_MODEL, 0, &file), GSN_OK);
    char *text = NULL;
    TEST_INT(gsn_h5_attr_read_string(file, GSN_ATTR_LIBRARY_VERSIONS, &text),
             GSN_OK);
    TEST_TRUE(text && strstr(text, "gmsh") && strstr(text, "CGAL") &&
              strstr(text, "HDF5") && strstr(text, "VTK"));
    free(text);
    TEST_INT(gsn_h5_attr_read_string(file, GSN_ATTR_CASE, &text), GSN_OK);
    TEST_TRUE(text && strstr(text, "bulk_modulus: 27400000"));
    free(text);
    TEST_INT(gsn_h5_attr_read_string(file, GSN_ATTR_CODE_VERSION, &text),
             GSN_OK);
    free(text);
    for (int i = 0; i < GSN_MODEL_DATASET_COUNT; ++i) {
        hid_t dataset = H5Dopen2(file, gsn_model_datasets[i].path, H5P_DEFAULT);
        TEST_TRUE(dataset >= 0);
        TEST_INT(gsn_h5_attr_read_string(dataset, GSN_ATTR_UNITS, &text),
                 GSN_OK);
        TEST_TRUE(text && strcmp(text, gsn_model_datasets[i].units) == 0);
        free(text);
        TEST_INT(gsn_h5_attr_read_string(dataset, GSN_ATTR_DESCRIPTION, &text),
                 GSN_OK);
        TEST_TRUE(text && strlen(text) > 10);
        free(text);
        H5Dclose(dataset);
    }
    gsn_h5_close(&file);
    TEST_TRUE(file == H5I_INVALID_HID);

    /* Refusals, each on an edited copy. */
    struct {
        void (*edit)(hid_t);
        const char *fragment;
    } edits[] = {
        {set_version_99,
         "schema version 99, but this geoscni reads version " SCHEMA_TEXT},
        {set_kind_results, "a results file, but a model file is expected"},
        {flip_owner, "dataset 'facets/owner': its checksum does not match"},
        {delete_area, "dataset 'facets/area' (area of the facet) is missing"},
        {corrupt_owner, "facets/owner[10] = 42 is out of range [0, 2)"},
    };
    for (size_t i = 0; i < sizeof edits / sizeof edits[0]; ++i) {
        snprintf(command, sizeof command, "cp '%s' '%s'", path, copy);
        TEST_INT(system(command), 0);
        edit_file(copy, edits[i].edit);
        expect_refusal(copy, edits[i].fragment);
    }
    FILE *junk = fopen(copy, "w");
    fputs("not an HDF5 file\n", junk);
    fclose(junk);
    expect_refusal(copy, "not found or not an HDF5 file");
    expect_refusal("/nonexistent/model.h5", "not found or not an HDF5 file");

    /* An unwritable place fails cleanly and leaves no file. */
    TEST_INT(gsn_model_write("/nonexistent/model.h5", &m, &c), GSN_ERR_IO);
    gsn_error_clear();

    gsn_model_free(&m);
    snprintf(command, sizeof command, "rm -rf '%s'", folder);
    TEST_INT(system(command), 0);
    return test_end("test_h5io");
}
