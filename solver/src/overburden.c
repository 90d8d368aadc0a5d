/* The overburden by columns through the tetrahedra (overburden.h): the
 * tetrahedra are bucketed by their extent in plan; a column meets a
 * tetrahedron in one segment, the line clipped by its four faces. */
#include "overburden.h"

#include "geoscni/cells.h"
#include "geoscni/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The column is moved this fraction of the body's size aside. */
#define COLUMN_OFFSET 1e-7

struct plan_grid {
    double e[2][3];     /* plan axes, orthonormal, normal to up */
    double lo[2], cell; /* the grid's corner and cell size, m */
    int size[2];
    int *offset, *tetrahedron; /* CSR: cell -> tetrahedra */
};

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Cells [c0, c1] x [d0, d1] covered by tetrahedron t's plan extent. */
static void tetrahedron_cells(const struct plan_grid *g,
                              const struct gsn_model *m, int t, int range[4])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < 4; ++k)
        for (int a = 0; a < 2; ++a) {
            double s = dot(g->e[a], &m->position[3 * m->tetrahedra[4 * t + k]]);
            lo[a] = fmin(lo[a], s);
            hi[a] = fmax(hi[a], s);
        }
    for (int a = 0; a < 2; ++a) {
        int c0 = (int)floor((lo[a] - g->lo[a]) / g->cell);
        int c1 = (int)floor((hi[a] - g->lo[a]) / g->cell);
        range[2 * a] = c0 < 0 ? 0 : c0;
        range[2 * a + 1] = c1 >= g->size[a] ? g->size[a] - 1 : c1;
    }
}

static int grid_create(const struct gsn_model *m, const struct gsn_case *c,
                       struct plan_grid *g)
{
    memset(g, 0, sizeof *g);
    gsn_plan_axes(c, g->e);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < m->particle_count; ++i)
        for (int k = 0; k < 2; ++k) {
            double s = dot(g->e[k], &m->position[3 * i]);
            lo[k] = fmin(lo[k], s);
            hi[k] = fmax(hi[k], s);
        }
    /* cells about two tetrahedra wide, at most 2000 a side */
    double volume = 0.0;
    for (int t = 0; t < m->tetrahedron_count; ++t)
        volume += fabs(
            gsn_body_tetrahedron_volume(m->position, &m->tetrahedra[4 * t]));
    g->cell = 2.0 * cbrt(volume /
                         (m->tetrahedron_count > 0 ? m->tetrahedron_count : 1));
    for (int k = 0; k < 2; ++k) {
        g->lo[k] = lo[k];
        double span = hi[k] - lo[k];
        if (span / g->cell > 2000.0)
            g->cell = span / 2000.0;
    }
    for (int k = 0; k < 2; ++k)
        g->size[k] = 1 + (int)((hi[k] - lo[k]) / g->cell);
    size_t cells = (size_t)g->size[0] * (size_t)g->size[1];
    g->offset = calloc(cells + 1, sizeof(int));
    GSN_CHECK(g->offset, GSN_ERR_MEMORY, "cannot allocate %zu plan cells",
              cells);
    for (int pass = 0; pass < 2; ++pass) {
        for (int t = 0; t < m->tetrahedron_count; ++t) {
            int r[4];
            tetrahedron_cells(g, m, t, r);
            for (int j = r[2]; j <= r[3]; ++j)
                for (int i = r[0]; i <= r[1]; ++i) {
                    size_t cell = (size_t)j * (size_t)g->size[0] + (size_t)i;
                    if (pass == 0)
                        g->offset[cell + 1]++;
                    else
                        g->tetrahedron[g->offset[cell]++] = t;
                }
        }
        if (pass == 0) {
            for (size_t k = 0; k < cells; ++k)
                g->offset[k + 1] += g->offset[k];
            g->tetrahedron =
                malloc(sizeof(int) * ((size_t)g->offset[cells] + 1));
            GSN_CHECK(g->tetrahedron, GSN_ERR_MEMORY,
                      "cannot allocate the plan cells' tetrahedra");
        }
    }
    /* the fill moved each offset to the next cell's start: back by one */
    for (size_t k = cells; k > 0; --k)
        g->offset[k] = g->offset[k - 1];
    g->offset[0] = 0;
    return GSN_OK;
}

/* The part [t0, t1] of the line q + t up inside tetrahedron v (empty:
 * t0 > t1). */
static void clip(const double *x, const int v[4], const double q[3],
                 const double up[3], double *t0, double *t1)
{
    static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    *t0 = -INFINITY;
    *t1 = INFINITY;
    for (int f = 0; f < 4; ++f) {
        const double *a = &x[3 * v[face[f][0]]], *b = &x[3 * v[face[f][1]]],
                     *c = &x[3 * v[face[f][2]]], *o = &x[3 * v[f]];
        double ab[3], ac[3], n[3], qa[3], oa[3];
        for (int k = 0; k < 3; ++k) {
            ab[k] = b[k] - a[k];
            ac[k] = c[k] - a[k];
            qa[k] = q[k] - a[k];
            oa[k] = o[k] - a[k];
        }
        cross(ab, ac, n);
        double side = dot(n, oa) > 0.0 ? 1.0 : -1.0; /* the inside */
        double alpha = side * dot(n, qa), beta = side * dot(n, up);
        if (beta > 0.0)
            *t0 = fmax(*t0, -alpha / beta);
        else if (beta < 0.0)
            *t1 = fmin(*t1, -alpha / beta);
        else if (alpha < 0.0)
            *t1 = -INFINITY;
    }
}

/* The weight per area of the column above q: sum over the tetrahedra it
 * meets of rho |g| times the length above q (split at the water table,
 * head above q's height). */
static double column(const struct plan_grid *g, const struct gsn_model *m,
                     const double *density, const double *saturated,
                     const double q[3], const double up[3], double table,
                     double gravity)
{
    int i = (int)floor((dot(g->e[0], q) - g->lo[0]) / g->cell);
    int j = (int)floor((dot(g->e[1], q) - g->lo[1]) / g->cell);
    if (i < 0 || j < 0 || i >= g->size[0] || j >= g->size[1])
        return 0.0;
    size_t cell = (size_t)j * (size_t)g->size[0] + (size_t)i;
    double weight = 0.0;
    for (int k = g->offset[cell]; k < g->offset[cell + 1]; ++k) {
        int t = g->tetrahedron[k];
        double t0, t1;
        clip(m->position, &m->tetrahedra[4 * t], q, up, &t0, &t1);
        t0 = fmax(t0, 0.0);
        if (!(t1 > t0))
            continue;
        double wet = fmax(0.0, fmin(t1, table) - t0); /* below the table */
        weight += gravity * (saturated[t] * wet + density[t] * (t1 - t0 - wet));
    }
    return weight;
}

int gsn_overburden(const struct gsn_model *m, const struct gsn_case *c,
                   int count, const double *points, double *sigma_v)
{
    double gravity = sqrt(dot(c->gravity, c->gravity)), up[3];
    GSN_CHECK(gsn_up(c, up), GSN_ERR_INTERNAL, "overburden without gravity");
    int nt = m->tetrahedron_count, rc = GSN_OK;
    double *density = malloc(sizeof(double) * 2 * ((size_t)nt + 1));
    GSN_CHECK(density, GSN_ERR_MEMORY, "cannot allocate %d densities", nt);
    double *saturated = density + nt + 1;
    struct plan_grid g;
    memset(&g, 0, sizeof g);
    for (int t = 0; t < nt; ++t) {
        int v = m->tetrahedron_volume[t];
        int k = v >= 0 ? gsn_case_find_material(c, m->volume_name[v]) : 0;
        if (k < 0 || (v < 0 && c->materials_by_volume))
            k = 0; /* not the original mesh: pre checked the volumes */
        density[t] = c->materials[k].density;
        saturated[t] = c->materials[k].saturated_density;
    }
    GSN_CALL_GOTO(grid_create(m, c, &g), rc, done);
    double size = g.cell * (g.size[0] > g.size[1] ? g.size[0] : g.size[1]);
    double d = COLUMN_OFFSET * size;
    /* four sides, a direction no mesh line is likely to follow */
    const double side[4][2] = {{0.8431, 0.5377},
                               {-0.5377, 0.8431},
                               {-0.8431, -0.5377},
                               {0.5377, -0.8431}};
#pragma omp parallel for schedule(dynamic, 256)
    for (int p = 0; p < count; ++p) {
        const double *x = &points[3 * (size_t)p];
        double head = c->water.present
                          ? gsn_water_table_height(c, x) - dot(up, x)
                          : -INFINITY;
        double best = 0.0;
        for (int s = 0; s < 4; ++s) {
            double q[3];
            for (int k = 0; k < 3; ++k)
                q[k] = x[k] +
                       d * (side[s][0] * g.e[0][k] + side[s][1] * g.e[1][k]);
            best = fmax(
                best, column(&g, m, density, saturated, q, up, head, gravity));
        }
        sigma_v[p] = -best;
    }
done:
    free(g.offset);
    free(g.tetrahedron);
    free(density);
    return rc;
}
