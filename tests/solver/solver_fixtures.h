/* Boxes of particles for the solver tests: a lattice (optionally jittered)
 * with its clipped Voronoi cells (gsn_pre_domains_box, surfaces xmin, xmax,
 * ymin, ymax, zmin, zmax), written as OUTDIR/model.h5 for geoscni solve. */
#ifndef GEOSCNI_SOLVER_FIXTURES_H
#define GEOSCNI_SOLVER_FIXTURES_H

#include "geoscni/error.h"
#include "geoscni/model.h"
#include "geoscni/pre.h"

#include <stdio.h>
#include <stdlib.h>

/* count[k] particles along axis k on [lo, hi], interior particles moved by
 * up to jitter x spacing (deterministic). Writes folder/model.h5. */
static inline int fixture_box_model(const char *folder, const int count[3],
                                    const double lo[3], const double hi[3],
                                    double jitter, const struct gsn_case *c)
{
    int n = count[0] * count[1] * count[2];
    double *points = malloc(sizeof(double) * 3 * (size_t)n);
    if (!points)
        return GSN_ERR_MEMORY;
    unsigned state = 2024u;
    int at = 0;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                int index[3] = {i, j, k};
                for (int a = 0; a < 3; ++a) {
                    double h = (hi[a] - lo[a]) / (count[a] - 1);
                    double x = lo[a] + index[a] * h;
                    state = state * 1664525u + 1013904223u;
                    double r = (double)(state >> 8) / 16777216.0 - 0.5;
                    if (index[a] > 0 && index[a] < count[a] - 1)
                        x += 2.0 * r * jitter * h;
                    points[at++] = x;
                }
            }
    struct gsn_model m;
    int rc = gsn_pre_domains_box(points, n, lo, hi, c->facet_points, &m);
    free(points);
    if (rc != GSN_OK)
        return rc;
    char path[4096];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    rc = gsn_model_write(path, &m, c);
    gsn_model_free(&m);
    return rc;
}

#endif
