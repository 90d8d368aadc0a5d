/* The checks that every model passes before it is written (issue 3,
 * point 3; TOOLCHAIN.md, "Clipped Voronoi cells": they catch every bug seen
 * so far). By the divergence theorem, for a closed cell of volume V,
 * sum over its facets of A n = 0 and of A n_j (c_k - x_k) = V delta_jk for
 * any point x; the second holds with the facets' quadrature points because
 * every rule integrates linear functions exactly. A facet is stored once and
 * counts for its neighbour with the opposite normal, so these sums also
 * check that the twins match (seed paper eq. (24) needs exactly that). */
#include "geoscni/cells.h"
#include "geoscni/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void accumulate(const struct gsn_model *m, int f, int cell, double sign,
                       double *closure, double *moment)
{
    const double *n = &m->facet_normal[3 * f];
    const double *x = &m->position[3 * cell];
    for (int j = 0; j < 3; ++j)
        closure[3 * cell + j] += sign * m->facet_area[f] * n[j];
    for (int q = m->facet_point_offset[f]; q < m->facet_point_offset[f + 1];
         ++q) {
        const double *p = &m->facet_point[3 * q];
        double w = sign * m->facet_weight[q];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                moment[9 * cell + 3 * j + k] += w * n[j] * (p[k] - x[k]);
    }
}

static int check_facets(const struct gsn_model *m, double *closure,
                        double *moment)
{
    int n = m->particle_count;
    for (int f = 0; f < m->facet_count; ++f) {
        int o = m->facet_owner[f], b = m->facet_neighbour[f];
        GSN_CHECK(o >= 0 && o < n && b >= -1 && b < n && b != o, GSN_ERR_INPUT,
                  "facet %d has owner %d and neighbour %d (of %d particles)", f,
                  o, b, n);
        double sum = 0.0;
        for (int q = m->facet_point_offset[f]; q < m->facet_point_offset[f + 1];
             ++q)
            sum += m->facet_weight[q];
        /* the weights are the fan triangles' areas: rounding only */
        GSN_CHECK(fabs(sum - m->facet_area[f]) <= 1e-12 * m->facet_area[f],
                  GSN_ERR_INPUT,
                  "facet %d of particle %d: weights add up to %.17g, area "
                  "%.17g",
                  f, o, sum, m->facet_area[f]);
        accumulate(m, f, o, 1.0, closure, moment);
        if (b >= 0)
            accumulate(m, f, b, -1.0, closure, moment);
    }
    return GSN_OK;
}

int gsn_cells_check(const struct gsn_model *m, double body_volume,
                    struct gsn_cells_report *report)
{
    struct gsn_cells_report r;
    memset(&r, 0, sizeof r);
    r.twin_error = report ? report->twin_error : 0.0;
    int n = m->particle_count, rc = GSN_OK;
    GSN_CHECK(n > 0, GSN_ERR_INPUT, "the model has no particles");
    double *closure = calloc(3 * (size_t)n, sizeof(double));
    double *moment = calloc(9 * (size_t)n, sizeof(double));
    GSN_CHECK_GOTO(closure && moment, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate the checks of %d cells", n);
    GSN_CALL_GOTO(check_facets(m, closure, moment), rc, done);

    double total = 0.0;
    int worst_closure = 0, worst_moment = 0;
    r.min_volume = INFINITY;
    for (int i = 0; i < n; ++i) {
        double v = m->volume[i];
        const double *x = &m->position[3 * i];
        GSN_CHECK_GOTO(v > 0.0, rc, GSN_ERR_INPUT, done,
                       "the nodal domain of particle %d (%g, %g, %g) has "
                       "volume %g",
                       i, x[0], x[1], x[2], v);
        total += v;
        r.min_volume = fmin(r.min_volume, v);
        double *c = &closure[3 * i];
        double e =
            sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / (cbrt(v) * cbrt(v));
        if (e > r.closure_error) {
            r.closure_error = e;
            worst_closure = i;
        }
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                double d = fabs(moment[9 * i + 3 * j + k] - (j == k ? v : 0.0));
                if (d / v > r.moment_error) {
                    r.moment_error = d / v;
                    worst_moment = i;
                }
            }
    }
    r.volume_error = fabs(total - body_volume) / body_volume;

    for (int s = 0; s < m->surface_count; ++s) {
        if (!(m->surface_area[s] > 0.0))
            continue;
        double area = 0.0;
        for (int f = 0; f < m->facet_count; ++f)
            if (m->facet_surface[f] == s)
                area += m->facet_area[f];
        double e = fabs(area - m->surface_area[s]) / m->surface_area[s];
        r.area_error = fmax(r.area_error, e);
        GSN_CHECK_GOTO(e <= GSN_CELLS_TOLERANCE_AREA, rc, GSN_ERR_INPUT, done,
                       "surface '%s': its boundary facets add up to %.17g "
                       "m^2, gmsh's area is %.17g m^2 (relative error %.3g, "
                       "tolerance %g)",
                       m->surface_name[s], area, m->surface_area[s], e,
                       GSN_CELLS_TOLERANCE_AREA);
    }
    const double *x = &m->position[3 * worst_closure];
    GSN_CHECK_GOTO(r.closure_error <= GSN_CELLS_TOLERANCE_CLOSURE, rc,
                   GSN_ERR_INPUT, done,
                   "the nodal domain of particle %d (%g, %g, %g) does not "
                   "close: |sum A n| = %.3g V^(2/3) (tolerance %g)",
                   worst_closure, x[0], x[1], x[2], r.closure_error,
                   GSN_CELLS_TOLERANCE_CLOSURE);
    x = &m->position[3 * worst_moment];
    GSN_CHECK_GOTO(r.moment_error <= GSN_CELLS_TOLERANCE_MOMENT, rc,
                   GSN_ERR_INPUT, done,
                   "the nodal domain of particle %d (%g, %g, %g): sum A n_j "
                   "(c_k - x_k) differs from V delta_jk by %.3g V "
                   "(tolerance %g)",
                   worst_moment, x[0], x[1], x[2], r.moment_error,
                   GSN_CELLS_TOLERANCE_MOMENT);
    GSN_CHECK_GOTO(
        r.volume_error <= GSN_CELLS_TOLERANCE_VOLUME, rc, GSN_ERR_INPUT, done,
        "the nodal domains add up to %.17g m^3, the body's volume "
        "is %.17g m^3 (relative error %.3g, tolerance %g)",
        total, body_volume, r.volume_error, GSN_CELLS_TOLERANCE_VOLUME);
    GSN_CHECK_GOTO(r.twin_error <= GSN_CELLS_TOLERANCE_TWIN, rc, GSN_ERR_INPUT,
                   done, "twin facets differ by %.3g V^(2/3) (tolerance %g)",
                   r.twin_error, GSN_CELLS_TOLERANCE_TWIN);
done:
    free(closure);
    free(moment);
    if (report)
        *report = r;
    return rc;
}
