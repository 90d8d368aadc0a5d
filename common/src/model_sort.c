/* Spatial ordering of a model's particles (Morton / Z-order), so that the
 * neighbours of a particle lie near it in memory: the solver's passes over
 * the shape-function rows then gather from cache instead of from RAM. */
#include "geoscni/error.h"
#include "geoscni/model.h"

#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

struct sort_key {
    uint64_t code;
    int index;
};

static int compare_keys(const void *a, const void *b)
{
    const struct sort_key *x = a, *y = b;
    if (x->code != y->code)
        return x->code < y->code ? -1 : 1;
    return x->index - y->index;
}

/* Spreads the low 21 bits of v to every third bit. */
static uint64_t spread_bits(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

static int permute_doubles(double **array, const int *old_of_new, int count,
                           int columns)
{
    double *sorted =
        malloc(sizeof(double) * (size_t)columns * (size_t)(count ? count : 1));
    GSN_CHECK(sorted, GSN_ERR_MEMORY, "out of memory");
    for (int i = 0; i < count; ++i)
        memcpy(&sorted[(size_t)columns * i],
               &(*array)[(size_t)columns * old_of_new[i]],
               sizeof(double) * (size_t)columns);
    free(*array);
    *array = sorted;
    return GSN_OK;
}

static int permute_ints(int **array, const int *old_of_new, int count)
{
    int *sorted = malloc(sizeof(int) * (size_t)(count ? count : 1));
    GSN_CHECK(sorted, GSN_ERR_MEMORY, "out of memory");
    for (int i = 0; i < count; ++i)
        sorted[i] = (*array)[old_of_new[i]];
    free(*array);
    *array = sorted;
    return GSN_OK;
}

/* Reorders a CSR list (offset, values) by old_of_new rows, renaming
 * values through rename (or not, if NULL). */
static int permute_csr(int **offset, int **values, const int *old_of_new,
                       int rows, const int *rename)
{
    int *new_offset = malloc(sizeof(int) * (size_t)(rows + 1));
    int *new_values = malloc(sizeof(int) * (size_t)((*offset)[rows] + 1));
    if (!new_offset || !new_values) {
        free(new_offset);
        free(new_values);
        GSN_CHECK(0, GSN_ERR_MEMORY, "out of memory");
    }
    new_offset[0] = 0;
    for (int i = 0; i < rows; ++i) {
        int old = old_of_new[i], at = new_offset[i];
        for (int e = (*offset)[old]; e < (*offset)[old + 1]; ++e)
            new_values[at++] = rename ? rename[(*values)[e]] : (*values)[e];
        new_offset[i + 1] = at;
    }
    free(*offset);
    free(*values);
    *offset = new_offset;
    *values = new_values;
    return GSN_OK;
}

static int sort_facets(struct gsn_model *m)
{
    int nf = m->facet_count;
    struct sort_key *keys = malloc(sizeof *keys * (size_t)(nf ? nf : 1));
    int *old_of_new = malloc(sizeof(int) * (size_t)(nf ? nf : 1));
    int *point_old = malloc(sizeof(int) * (size_t)(nf ? nf : 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(keys && old_of_new && point_old, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    for (int f = 0; f < nf; ++f) {
        keys[f].code = (uint64_t)m->facet_owner[f];
        keys[f].index = f;
    }
    qsort(keys, (size_t)nf, sizeof *keys, compare_keys);
    for (int f = 0; f < nf; ++f)
        old_of_new[f] = keys[f].index;
    int *int_arrays[] = {m->facet_owner, m->facet_neighbour, m->facet_surface};
    for (int a = 0; a < 3; ++a) {
        for (int f = 0; f < nf; ++f)
            point_old[f] = int_arrays[a][old_of_new[f]];
        memcpy(int_arrays[a], point_old, sizeof(int) * (size_t)nf);
    }
    GSN_CALL_GOTO(permute_doubles(&m->facet_area, old_of_new, nf, 1), rc, done);
    GSN_CALL_GOTO(permute_doubles(&m->facet_normal, old_of_new, nf, 3), rc,
                  done);
    /* The quadrature points move with their facets. */
    int points = m->facet_point_offset[nf];
    double *point = malloc(sizeof(double) * 3 * (size_t)(points + 1));
    double *weight = malloc(sizeof(double) * (size_t)(points + 1));
    int *offset = malloc(sizeof(int) * (size_t)(nf + 1));
    GSN_CHECK_GOTO(point && weight && offset, rc, GSN_ERR_MEMORY, points_done,
                   "out of memory");
    offset[0] = 0;
    for (int f = 0; f < nf; ++f) {
        int old = old_of_new[f], at = offset[f];
        for (int q = m->facet_point_offset[old];
             q < m->facet_point_offset[old + 1]; ++q, ++at) {
            memcpy(&point[3 * at], &m->facet_point[3 * q], 3 * sizeof(double));
            weight[at] = m->facet_weight[q];
        }
        offset[f + 1] = at;
    }
    free(m->facet_point);
    free(m->facet_weight);
    free(m->facet_point_offset);
    m->facet_point = point;
    m->facet_weight = weight;
    m->facet_point_offset = offset;
    point = weight = NULL;
    offset = NULL;
points_done:
    free(point);
    free(weight);
    free(offset);
done:
    free(keys);
    free(old_of_new);
    free(point_old);
    return rc;
}

int gsn_model_sort_spatially(struct gsn_model *m)
{
    int n = m->particle_count;
    if (n == 0)
        return GSN_OK;
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX};
    double hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double x = m->position[3 * i + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    double size = hi[0] - lo[0];
    for (int k = 1; k < 3; ++k)
        size = hi[k] - lo[k] > size ? hi[k] - lo[k] : size;
    double scale = size > 0 ? 2097151.0 / size : 0.0;
    struct sort_key *keys = malloc(sizeof *keys * (size_t)n);
    int *old_of_new = malloc(sizeof(int) * (size_t)n);
    int *new_of_old = malloc(sizeof(int) * (size_t)n);
    int rc = GSN_OK;
    GSN_CHECK_GOTO(keys && old_of_new && new_of_old, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    for (int i = 0; i < n; ++i) {
        uint64_t code = 0;
        for (int k = 0; k < 3; ++k)
            code |= spread_bits(
                        (uint64_t)((m->position[3 * i + k] - lo[k]) * scale))
                    << k;
        keys[i].code = code;
        keys[i].index = i;
    }
    qsort(keys, (size_t)n, sizeof *keys, compare_keys);
    for (int i = 0; i < n; ++i) {
        old_of_new[i] = keys[i].index;
        new_of_old[keys[i].index] = i;
    }
    GSN_CALL_GOTO(permute_doubles(&m->position, old_of_new, n, 3), rc, done);
    GSN_CALL_GOTO(permute_doubles(&m->volume, old_of_new, n, 1), rc, done);
    GSN_CALL_GOTO(permute_doubles(&m->centroid, old_of_new, n, 3), rc, done);
    GSN_CALL_GOTO(permute_ints(&m->particle_volume, old_of_new, n), rc, done);
    GSN_CALL_GOTO(permute_csr(&m->particle_surface_offset, &m->particle_surface,
                              old_of_new, n, NULL),
                  rc, done);
    for (int f = 0; f < m->facet_count; ++f) {
        m->facet_owner[f] = new_of_old[m->facet_owner[f]];
        if (m->facet_neighbour[f] >= 0)
            m->facet_neighbour[f] = new_of_old[m->facet_neighbour[f]];
    }
    for (int t = 0; t < 4 * m->tetrahedron_count; ++t)
        m->tetrahedra[t] = new_of_old[m->tetrahedra[t]];
    GSN_CALL_GOTO(sort_facets(m), rc, done);
done:
    free(keys);
    free(old_of_new);
    free(new_of_old);
    return rc;
}
