/* model.h5: allocation, atomic writing, and reading with range checks so a
 * damaged file gives a message, never an out-of-bounds index. */
#include "geoscni/model.h"
#include "geoscni/error.h"
#include "geoscni/files.h"

#include <stdlib.h>
#include <string.h>

#define MODEL_ATTR_PARTICLE_COUNT "particle_count"

static int model_calloc(void **array, size_t count, size_t size)
{
    *array = calloc(count ? count : 1, size);
    GSN_CHECK(*array != NULL, GSN_ERR_MEMORY,
              "cannot allocate %zu entries of %zu bytes", count, size);
    return GSN_OK;
}

int gsn_model_allocate(struct gsn_model *m, int particle_count,
                       int particle_surface_entries, int facet_count,
                       int facet_point_count, int surface_count,
                       int tetrahedron_count)
{
    memset(m, 0, sizeof *m);
    GSN_CHECK(particle_count >= 0 && particle_surface_entries >= 0 &&
                  facet_count >= 0 && facet_point_count >= 0 &&
                  surface_count >= 0 && tetrahedron_count >= 0,
              GSN_ERR_INTERNAL, "negative model size");
    size_t n = (size_t)particle_count, nf = (size_t)facet_count;
    size_t np = (size_t)facet_point_count;
    m->particle_count = particle_count;
    m->facet_count = facet_count;
    m->surface_count = surface_count;
    m->tetrahedron_count = tetrahedron_count;
    int rc = GSN_OK;
    void **arrays[] = {
        (void **)&m->position,           (void **)&m->volume,
        (void **)&m->centroid,           (void **)&m->particle_surface_offset,
        (void **)&m->particle_surface,   (void **)&m->facet_owner,
        (void **)&m->facet_neighbour,    (void **)&m->facet_surface,
        (void **)&m->facet_area,         (void **)&m->facet_normal,
        (void **)&m->facet_point_offset, (void **)&m->facet_point,
        (void **)&m->facet_weight,       (void **)&m->surface_name,
        (void **)&m->surface_tag,        (void **)&m->surface_area,
        (void **)&m->tetrahedra,         (void **)&m->tetrahedron_face,
        (void **)&m->particle_volume,    (void **)&m->tetrahedron_volume};
    const size_t counts[] = {3 * n,
                             n,
                             3 * n,
                             n + 1,
                             (size_t)particle_surface_entries,
                             nf,
                             nf,
                             nf,
                             nf,
                             3 * nf,
                             nf + 1,
                             3 * np,
                             np,
                             (size_t)surface_count,
                             (size_t)surface_count,
                             (size_t)surface_count,
                             4 * (size_t)tetrahedron_count,
                             4 * (size_t)tetrahedron_count,
                             n,
                             (size_t)tetrahedron_count};
    const size_t sizes[] = {
        sizeof(double), sizeof(double),     sizeof(double), sizeof(int),
        sizeof(int),    sizeof(int),        sizeof(int),    sizeof(int),
        sizeof(double), sizeof(double),     sizeof(int),    sizeof(double),
        sizeof(double), GSN_H5_STRING_SIZE, sizeof(int),    sizeof(double),
        sizeof(int),    sizeof(int),        sizeof(int),    sizeof(int)};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; ++i)
        GSN_CALL_GOTO(model_calloc(arrays[i], counts[i], sizes[i]), rc, fail);
    for (size_t i = 0; i < n; ++i)
        m->particle_volume[i] = -1;
    for (int t = 0; t < tetrahedron_count; ++t)
        m->tetrahedron_volume[t] = -1;
    GSN_CALL_GOTO(gsn_model_allocate_volumes(m, 0), rc, fail);
    return GSN_OK;
fail:
    gsn_model_free(m);
    return rc;
}

int gsn_model_allocate_volumes(struct gsn_model *m, int volume_count)
{
    free(m->volume_name);
    free(m->volume_tag);
    m->volume_name = NULL;
    m->volume_tag = NULL;
    m->volume_count = volume_count;
    GSN_CALL(model_calloc((void **)&m->volume_name, (size_t)volume_count,
                          GSN_H5_STRING_SIZE));
    GSN_CALL(model_calloc((void **)&m->volume_tag, (size_t)volume_count,
                          sizeof(int)));
    return GSN_OK;
}

int gsn_model_copy_volumes(const struct gsn_model *from, struct gsn_model *to)
{
    GSN_CALL(gsn_model_allocate_volumes(to, from->volume_count));
    memcpy(to->volume_name, from->volume_name,
           sizeof *from->volume_name * (size_t)from->volume_count);
    memcpy(to->volume_tag, from->volume_tag,
           sizeof(int) * (size_t)from->volume_count);
    memcpy(to->particle_volume, from->particle_volume,
           sizeof(int) * (size_t)from->particle_count);
    if (to->tetrahedron_count == from->tetrahedron_count)
        memcpy(to->tetrahedron_volume, from->tetrahedron_volume,
               sizeof(int) * (size_t)from->tetrahedron_count);
    return GSN_OK;
}

void gsn_model_free(struct gsn_model *m)
{
    free(m->volume_name);
    free(m->volume_tag);
    free(m->particle_volume);
    free(m->tetrahedron_volume);
    free(m->position);
    free(m->volume);
    free(m->centroid);
    free(m->particle_surface_offset);
    free(m->particle_surface);
    free(m->facet_owner);
    free(m->facet_neighbour);
    free(m->facet_surface);
    free(m->facet_area);
    free(m->facet_normal);
    free(m->facet_point_offset);
    free(m->facet_point);
    free(m->facet_weight);
    free(m->surface_name);
    free(m->surface_tag);
    free(m->surface_area);
    free(m->tetrahedra);
    free(m->tetrahedron_face);
    memset(m, 0, sizeof *m);
}

/* Pointer to each dataset's array and its row count, in schema order. */
static void model_arrays(const struct gsn_model *m, void *data[], size_t rows[])
{
    size_t n = (size_t)m->particle_count, nf = (size_t)m->facet_count;
    size_t entries =
        m->particle_surface_offset ? (size_t)m->particle_surface_offset[n] : 0;
    size_t points =
        m->facet_point_offset ? (size_t)m->facet_point_offset[nf] : 0;
    void *d[GSN_MODEL_DATASET_COUNT] = {
        [GSN_MODEL_POSITION] = m->position,
        [GSN_MODEL_VOLUME] = m->volume,
        [GSN_MODEL_CENTROID] = m->centroid,
        [GSN_MODEL_PARTICLE_SURFACE_OFFSET] = m->particle_surface_offset,
        [GSN_MODEL_PARTICLE_SURFACE] = m->particle_surface,
        [GSN_MODEL_FACET_OWNER] = m->facet_owner,
        [GSN_MODEL_FACET_NEIGHBOUR] = m->facet_neighbour,
        [GSN_MODEL_FACET_SURFACE] = m->facet_surface,
        [GSN_MODEL_FACET_AREA] = m->facet_area,
        [GSN_MODEL_FACET_NORMAL] = m->facet_normal,
        [GSN_MODEL_FACET_POINT_OFFSET] = m->facet_point_offset,
        [GSN_MODEL_FACET_POINT] = m->facet_point,
        [GSN_MODEL_FACET_WEIGHT] = m->facet_weight,
        [GSN_MODEL_SURFACE_NAME] = m->surface_name,
        [GSN_MODEL_SURFACE_TAG] = m->surface_tag,
        [GSN_MODEL_SURFACE_AREA] = m->surface_area,
        [GSN_MODEL_TETRAHEDRA] = m->tetrahedra,
        [GSN_MODEL_TETRAHEDRON_FACE] = m->tetrahedron_face,
        [GSN_MODEL_VOLUME_NAME] = m->volume_name,
        [GSN_MODEL_VOLUME_TAG] = m->volume_tag,
        [GSN_MODEL_PARTICLE_VOLUME] = m->particle_volume,
        [GSN_MODEL_TETRAHEDRON_VOLUME] = m->tetrahedron_volume};
    size_t r[GSN_MODEL_DATASET_COUNT] = {
        [GSN_MODEL_POSITION] = n,
        [GSN_MODEL_VOLUME] = n,
        [GSN_MODEL_CENTROID] = n,
        [GSN_MODEL_PARTICLE_SURFACE_OFFSET] = n + 1,
        [GSN_MODEL_PARTICLE_SURFACE] = entries,
        [GSN_MODEL_FACET_OWNER] = nf,
        [GSN_MODEL_FACET_NEIGHBOUR] = nf,
        [GSN_MODEL_FACET_SURFACE] = nf,
        [GSN_MODEL_FACET_AREA] = nf,
        [GSN_MODEL_FACET_NORMAL] = nf,
        [GSN_MODEL_FACET_POINT_OFFSET] = nf + 1,
        [GSN_MODEL_FACET_POINT] = points,
        [GSN_MODEL_FACET_WEIGHT] = points,
        [GSN_MODEL_SURFACE_NAME] = (size_t)m->surface_count,
        [GSN_MODEL_SURFACE_TAG] = (size_t)m->surface_count,
        [GSN_MODEL_SURFACE_AREA] = (size_t)m->surface_count,
        [GSN_MODEL_TETRAHEDRA] = (size_t)m->tetrahedron_count,
        [GSN_MODEL_TETRAHEDRON_FACE] = (size_t)m->tetrahedron_count,
        [GSN_MODEL_VOLUME_NAME] = (size_t)m->volume_count,
        [GSN_MODEL_VOLUME_TAG] = (size_t)m->volume_count,
        [GSN_MODEL_PARTICLE_VOLUME] = n,
        [GSN_MODEL_TETRAHEDRON_VOLUME] = (size_t)m->tetrahedron_count};
    memcpy(data, d, sizeof d);
    memcpy(rows, r, sizeof r);
}

int gsn_model_write(const char *path, const struct gsn_model *m,
                    const struct gsn_case *c)
{
    char temporary[4096];
    char *case_yaml = NULL;
    hid_t file = H5I_INVALID_HID;
    int rc = GSN_OK;
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    if (c)
        GSN_CALL(gsn_case_to_yaml_string(c, &case_yaml));
    GSN_CALL_GOTO(
        gsn_h5_create(temporary, GSN_FILE_KIND_MODEL, case_yaml, &file), rc,
        done);
    GSN_CALL_GOTO(gsn_h5_attr_write_int(file, MODEL_ATTR_PARTICLE_COUNT,
                                        m->particle_count),
                  rc, done);
    if (c) {
        char signature[GSN_PRE_SIGNATURE_SIZE];
        GSN_CALL_GOTO(gsn_case_pre_signature(c, signature, sizeof signature),
                      rc, done);
        GSN_CALL_GOTO(
            gsn_h5_attr_write_string(file, GSN_ATTR_PRE_SIGNATURE, signature),
            rc, done);
        /* the geometry's contents, for run's up-to-date test (a model
         * made without a geometry file, by a test, has none) */
        char hash[GSN_FILE_HASH_SIZE];
        if (gsn_file_hash(c->geometry, hash) == GSN_OK)
            GSN_CALL_GOTO(
                gsn_h5_attr_write_string(file, GSN_ATTR_GEOMETRY_HASH, hash),
                rc, done);
        else
            gsn_error_clear();
    }
    void *data[GSN_MODEL_DATASET_COUNT];
    size_t rows[GSN_MODEL_DATASET_COUNT];
    model_arrays(m, data, rows);
    for (int i = 0; i < GSN_MODEL_DATASET_COUNT; ++i)
        GSN_CALL_GOTO(
            gsn_h5_write(file, &gsn_model_datasets[i], rows[i], data[i]), rc,
            done);
    GSN_CALL_GOTO(gsn_h5_close(&file), rc, done);
    GSN_CALL_GOTO(gsn_file_commit(path), rc, done);
done:
    free(case_yaml);
    gsn_h5_close(&file);
    if (rc != GSN_OK)
        gsn_file_discard(path);
    return rc;
}

static int check_indices(const char *path, const char *what, const int *index,
                         size_t count, int lower, int upper)
{
    for (size_t i = 0; i < count; ++i)
        GSN_CHECK(index[i] >= lower && index[i] < upper, GSN_ERR_INPUT,
                  "%s: %s[%zu] = %d is out of range [%d, %d); the file is "
                  "damaged, run pre again",
                  path, what, i, index[i], lower, upper);
    return GSN_OK;
}

static int check_offsets(const char *path, const char *what, const int *offset,
                         size_t count)
{
    GSN_CHECK(offset[0] == 0, GSN_ERR_INPUT, "%s: %s must start at 0", path,
              what);
    for (size_t i = 0; i < count; ++i)
        GSN_CHECK(offset[i + 1] >= offset[i], GSN_ERR_INPUT,
                  "%s: %s decreases at %zu; the file is damaged, run pre "
                  "again",
                  path, what, i);
    return GSN_OK;
}

static int model_read_file(hid_t file, const char *path, struct gsn_model *m)
{
    GSN_CALL(gsn_h5_require(file, gsn_model_datasets, GSN_MODEL_DATASET_COUNT));
    size_t n = 0, nf = 0, entries = 0, points = 0, surfaces = 0, tets = 0;
    GSN_CALL(gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_POSITION], &n));
    GSN_CALL(
        gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_FACET_OWNER], &nf));
    GSN_CALL(gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_PARTICLE_SURFACE],
                         &entries));
    GSN_CALL(
        gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_FACET_POINT], &points));
    GSN_CALL(gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_SURFACE_NAME],
                         &surfaces));
    GSN_CALL(
        gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_TETRAHEDRA], &tets));
    size_t volumes = 0;
    GSN_CALL(gsn_h5_rows(file, &gsn_model_datasets[GSN_MODEL_VOLUME_NAME],
                         &volumes));
    GSN_CHECK(n < (1u << 30) && nf < (1u << 31) && points < (1u << 31) &&
                  entries < (1u << 30) && tets < (1u << 29),
              GSN_ERR_INPUT, "%s: model too large for 32-bit indices", path);
    GSN_CALL(gsn_model_allocate(m, (int)n, (int)entries, (int)nf, (int)points,
                                (int)surfaces, (int)tets));
    GSN_CHECK(volumes < (1u << 20), GSN_ERR_INPUT,
              "%s: %zu physical volumes; the file is damaged, run pre again",
              path, volumes);
    GSN_CALL(gsn_model_allocate_volumes(m, (int)volumes));
    void *data[GSN_MODEL_DATASET_COUNT];
    size_t rows[GSN_MODEL_DATASET_COUNT];
    model_arrays(m, data, rows);
    rows[GSN_MODEL_PARTICLE_SURFACE] = entries;
    rows[GSN_MODEL_FACET_POINT] = rows[GSN_MODEL_FACET_WEIGHT] = points;
    for (int i = 0; i < GSN_MODEL_DATASET_COUNT; ++i)
        GSN_CALL(gsn_h5_read(file, &gsn_model_datasets[i], rows[i], data[i]));

    GSN_CALL(check_offsets(path, "particles/surface_offset",
                           m->particle_surface_offset, n));
    GSN_CHECK((size_t)m->particle_surface_offset[n] == entries, GSN_ERR_INPUT,
              "%s: particles/surface_offset does not end at %zu", path,
              entries);
    GSN_CALL(
        check_offsets(path, "facets/point_offset", m->facet_point_offset, nf));
    GSN_CHECK((size_t)m->facet_point_offset[nf] == points, GSN_ERR_INPUT,
              "%s: facets/point_offset does not end at %zu", path, points);
    GSN_CALL(check_indices(path, "particles/surface", m->particle_surface,
                           entries, 0, (int)surfaces));
    GSN_CALL(
        check_indices(path, "facets/owner", m->facet_owner, nf, 0, (int)n));
    GSN_CALL(check_indices(path, "facets/neighbour", m->facet_neighbour, nf, -1,
                           (int)n));
    GSN_CALL(check_indices(path, "facets/surface", m->facet_surface, nf, -1,
                           (int)surfaces));
    GSN_CALL(check_indices(path, "mesh/tetrahedra", m->tetrahedra, 4 * tets, 0,
                           (int)n));
    GSN_CALL(check_indices(path, "mesh/tetrahedron_face", m->tetrahedron_face,
                           4 * tets, GSN_MODEL_FACE_UNTAGGED, (int)surfaces));
    GSN_CALL(check_indices(path, "particles/physical_volume",
                           m->particle_volume, n, -1, (int)volumes));
    GSN_CALL(check_indices(path, "mesh/tetrahedron_volume",
                           m->tetrahedron_volume, tets, -1, (int)volumes));
    for (size_t s = 0; s < surfaces; ++s)
        m->surface_name[s][GSN_H5_STRING_SIZE - 1] = '\0';
    for (size_t v = 0; v < volumes; ++v)
        m->volume_name[v][GSN_H5_STRING_SIZE - 1] = '\0';
    return GSN_OK;
}

int gsn_model_read(const char *path, struct gsn_model *m)
{
    memset(m, 0, sizeof *m);
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(path, GSN_FILE_KIND_MODEL, 0, &file));
    int rc = model_read_file(file, path, m);
    gsn_h5_close(&file);
    if (rc != GSN_OK) {
        gsn_model_free(m);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "model_read_file(file, path, m)");
    }
    return GSN_OK;
}

int gsn_model_particle_on_surface(const struct gsn_model *m, int particle,
                                  int surface)
{
    for (int e = m->particle_surface_offset[particle];
         e < m->particle_surface_offset[particle + 1]; ++e)
        if (m->particle_surface[e] == surface)
            return 1;
    return 0;
}

int gsn_model_find_volume(const struct gsn_model *m, const char *name)
{
    for (int v = 0; v < m->volume_count; ++v)
        if (strcmp(m->volume_name[v], name) == 0)
            return v;
    return -1;
}

int gsn_model_find_surface(const struct gsn_model *m, const char *name)
{
    for (int s = 0; s < m->surface_count; ++s)
        if (strcmp(m->surface_name[s], name) == 0)
            return s;
    return -1;
}
