/* Nonlocal damage: the averaging rows (nonlocal.h). */
#include "nonlocal.h"

#include "geoscni/error.h"
#include "geoscni/kernels.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

void gsn_nonlocal_destroy(struct gsn_nonlocal **nonlocal)
{
    if (!nonlocal || !*nonlocal)
        return;
    free((*nonlocal)->offset);
    free((*nonlocal)->index);
    free((*nonlocal)->weight);
    free(*nonlocal);
    *nonlocal = NULL;
}

double gsn_nonlocal_bytes(double point_count, double entries)
{
    return (point_count + 1.0) * sizeof(int) +
           entries * (sizeof(int) + sizeof(double));
}

/* Point p's row: the points within its radius with their bell weights
 * times volume, normalized (written when index is not NULL). Returns the
 * entries, or -1 past GSN_RK_MAX_NEIGHBOURS candidates. */
static int average_row(const struct gsn_rk *rk, int p, const double *position,
                       const double *volume, const double *radius,
                       int *candidate, int *index, double *weight)
{
    const double L = radius[p];
    if (!(L > 0.0))
        return 0;
    const double *x = position + 3 * (size_t)p;
    int found = gsn_rk_neighbours(rk, x, GSN_RK_MAX_NEIGHBOURS, candidate);
    if (found > GSN_RK_MAX_NEIGHBOURS)
        return -1;
    int count = 0;
    double sum = 0.0;
    for (int c = 0; c < found; ++c) {
        const double *y = position + 3 * (size_t)candidate[c];
        double r2 =
            ((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
             (x[2] - y[2]) * (x[2] - y[2])) /
            (L * L);
        if (r2 >= 1.0)
            continue;
        double w = (1.0 - r2) * (1.0 - r2) * volume[candidate[c]];
        if (index) {
            index[count] = candidate[c];
            weight[count] = w;
        }
        sum += w;
        ++count;
    }
    for (int k = 0; index && k < count; ++k)
        weight[k] /= sum;
    return count;
}

int gsn_nonlocal_create(int point_count, const double *position,
                        const double *volume, const double *radius,
                        struct gsn_nonlocal **out)
{
    *out = NULL;
    double L = 0.0;
    for (int p = 0; p < point_count; ++p)
        L = fmax(L, radius[p]);
    GSN_CHECK(point_count > 0 && L > 0.0 && isfinite(L), GSN_ERR_INPUT,
              "nonlocal damage: no point with a positive length");
    struct gsn_nonlocal *n = calloc(1, sizeof *n);
    GSN_CHECK(n, GSN_ERR_MEMORY, "nonlocal damage: out of memory");
    n->point_count = point_count;
    double *spacing = malloc((size_t)point_count * sizeof *spacing);
    n->offset = calloc((size_t)point_count + 1, sizeof *n->offset);
    struct gsn_rk *rk = NULL;
    int rc = GSN_OK, too_many = -1;
    GSN_CHECK_GOTO(spacing && n->offset, rc, GSN_ERR_MEMORY, done,
                   "nonlocal damage: cannot allocate %d points", point_count);
    /* every point is a candidate, within the longest length */
    for (int p = 0; p < point_count; ++p)
        spacing[p] = L;
    GSN_CALL_GOTO(gsn_rk_create(point_count, position, spacing, 1.0, 1, &rk),
                  rc, done);
    for (int pass = 0; pass < 2; ++pass) {
#pragma omp parallel
        {
            int *candidate = malloc(GSN_RK_MAX_NEIGHBOURS * sizeof *candidate);
#pragma omp for
            for (int p = 0; p < point_count; ++p) {
                int count = -1;
                if (candidate && pass == 0)
                    count = average_row(rk, p, position, volume, radius,
                                        candidate, NULL, NULL);
                else if (candidate)
                    count = average_row(rk, p, position, volume, radius,
                                        candidate, n->index + n->offset[p],
                                        n->weight + n->offset[p]);
                if (count < 0) {
#pragma omp critical(gsn_nonlocal_failure)
                    if (too_many < 0 || p < too_many)
                        too_many = p;
                } else if (pass == 0) {
                    n->offset[p + 1] = count;
                }
            }
            free(candidate);
        }
        GSN_CHECK_GOTO(too_many < 0, rc, GSN_ERR_INPUT, done,
                       "damage.length %g m: the ball about point %d holds "
                       "more than %d points (or memory ran out); give a "
                       "shorter length or a coarser spacing",
                       radius[too_many], too_many, GSN_RK_MAX_NEIGHBOURS);
        if (pass == 1)
            break;
        for (int p = 0; p < point_count; ++p) {
            n->max_row =
                n->offset[p + 1] > n->max_row ? n->offset[p + 1] : n->max_row;
            n->offset[p + 1] += n->offset[p];
        }
        size_t entries = (size_t)n->offset[point_count];
        n->index = malloc((entries ? entries : 1) * sizeof *n->index);
        n->weight = malloc((entries ? entries : 1) * sizeof *n->weight);
        GSN_CHECK_GOTO(n->index && n->weight, rc, GSN_ERR_MEMORY, done,
                       "nonlocal damage: cannot allocate %zu entries", entries);
    }
done:
    gsn_rk_destroy(&rk);
    free(spacing);
    if (rc != GSN_OK)
        gsn_nonlocal_destroy(&n);
    *out = n;
    return rc;
}
