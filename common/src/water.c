/* The water table of the case file (water:; docs/site.md, "Water"): its
 * height over any place, from a level, a section's line or points spread
 * over the site (linear on their Delaunay triangles in plan). */
#include "geoscni/case.h"

#include <math.h>
#include <string.h>

int gsn_up(const struct gsn_case *c, double up[3])
{
    double g =
        sqrt(c->gravity[0] * c->gravity[0] + c->gravity[1] * c->gravity[1] +
             c->gravity[2] * c->gravity[2]);
    for (int k = 0; k < 3; ++k)
        up[k] = g > 0.0 ? -c->gravity[k] / g : 0.0;
    return g > 0.0;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double gsn_height(const struct gsn_case *c, const double x[3])
{
    double up[3];
    gsn_up(c, up);
    return dot3(up, x);
}

void gsn_plan_axes(const struct gsn_case *c, double e[2][3])
{
    double up[3];
    gsn_up(c, up);
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        axis = fabs(up[k]) < fabs(up[axis]) ? k : axis;
    double length = 0.0;
    for (int k = 0; k < 3; ++k) {
        e[0][k] = (k == axis ? 1.0 : 0.0) - up[axis] * up[k];
        length += e[0][k] * e[0][k];
    }
    for (int k = 0; k < 3; ++k)
        e[0][k] /= sqrt(length);
    e[1][0] = up[1] * e[0][2] - up[2] * e[0][1];
    e[1][1] = up[2] * e[0][0] - up[0] * e[0][2];
    e[1][2] = up[0] * e[0][1] - up[1] * e[0][0];
}

/* The plan coordinates of x on the axes e (6: the two axes' components). */
static void to_plan(const double *e, const double x[3], double p[2])
{
    p[0] = dot3(e, x);
    p[1] = dot3(e + 3, x);
}

/* The horizontal unit direction of a section line (from its first point to
 * its last). */
static void section_direction(const struct gsn_case *c, double d[3])
{
    double up[3], span[3], length = 0.0;
    gsn_up(c, up);
    const struct gsn_water *w = &c->water;
    for (int k = 0; k < 3; ++k)
        span[k] = w->points[w->point_count - 1][k] - w->points[0][k];
    double rise = dot3(span, up);
    for (int k = 0; k < 3; ++k) {
        d[k] = span[k] - rise * up[k];
        length += d[k] * d[k];
    }
    length = sqrt(length);
    for (int k = 0; k < 3; ++k)
        d[k] = length > 0.0 ? d[k] / length : 0.0;
}

/* Twice the signed area of the plan triangle a b c. */
static double orient(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* 1 if d lies inside the circumcircle of the counterclockwise a b c. */
static int in_circle(const double a[2], const double b[2], const double c[2],
                     const double d[2])
{
    double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0],
           by = b[1] - d[1], cx = c[0] - d[0], cy = c[1] - d[1];
    return (ax * ax + ay * ay) * (bx * cy - cx * by) -
               (bx * bx + by * by) * (ax * cy - cx * ay) +
               (cx * cx + cy * cy) * (ax * by - bx * ay) >
           0.0;
}

enum { WORK_TRIANGLES = 8 * GSN_MAX_WATER_POINTS + 8 };

/* The Delaunay triangles of the points in plan (Bowyer-Watson from a
 * triangle around them all), counterclockwise. */
static void triangulate(struct gsn_water *w, double plan[][2])
{
    int n = w->point_count;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 2; ++a) {
            lo[a] = fmin(lo[a], plan[i][a]);
            hi[a] = fmax(hi[a], plan[i][a]);
        }
    double size = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    double mid[2] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])};
    plan[n][0] = mid[0] - 20.0 * size, plan[n][1] = mid[1] - 10.0 * size;
    plan[n + 1][0] = mid[0] + 20.0 * size,
             plan[n + 1][1] = mid[1] - 10.0 * size;
    plan[n + 2][0] = mid[0], plan[n + 2][1] = mid[1] + 20.0 * size;
    int t[WORK_TRIANGLES][3], count = 1;
    t[0][0] = n, t[0][1] = n + 1, t[0][2] = n + 2;
    for (int p = 0; p < n; ++p) {
        int edges[3 * WORK_TRIANGLES][2], edge_count = 0, kept = 0;
        for (int k = 0; k < count; ++k) {
            if (!in_circle(plan[t[k][0]], plan[t[k][1]], plan[t[k][2]],
                           plan[p])) {
                memcpy(t[kept++], t[k], sizeof t[k]);
                continue;
            }
            for (int e = 0; e < 3; ++e) { /* an edge of two bad ones goes */
                int a = t[k][e], b = t[k][(e + 1) % 3], shared = -1;
                for (int f = 0; f < edge_count && shared < 0; ++f)
                    if (edges[f][0] == b && edges[f][1] == a)
                        shared = f;
                if (shared >= 0)
                    edges[shared][0] = edges[shared][1] = -1;
                else
                    edges[edge_count][0] = a, edges[edge_count++][1] = b;
            }
        }
        count = kept;
        for (int f = 0; f < edge_count; ++f)
            if (edges[f][0] >= 0 && count < WORK_TRIANGLES) {
                t[count][0] = edges[f][0];
                t[count][1] = edges[f][1];
                t[count++][2] = p;
            }
    }
    w->triangle_count = 0;
    for (int k = 0; k < count; ++k)
        if (t[k][0] < n && t[k][1] < n && t[k][2] < n &&
            orient(plan[t[k][0]], plan[t[k][1]], plan[t[k][2]]) > 0.0 &&
            w->triangle_count < 2 * GSN_MAX_WATER_POINTS)
            memcpy(w->triangles[w->triangle_count++], t[k], sizeof t[k]);
}

int gsn_water_table_prepare(struct gsn_case *c, int *bad)
{
    struct gsn_water *w = &c->water;
    int n = w->point_count;
    w->triangle_count = 0;
    *bad = 0;
    if (n < 2)
        return GSN_WATER_SECTION;
    double e[2][3], plan[GSN_MAX_WATER_POINTS + 3][2];
    gsn_plan_axes(c, e);
    double size = 0.0;
    for (int i = 0; i < n; ++i) {
        to_plan(&e[0][0], w->points[i], plan[i]);
        size =
            fmax(size, hypot(plan[i][0] - plan[0][0], plan[i][1] - plan[0][1]));
    }
    if (!(size > 0.0))
        return GSN_WATER_STACKED;
    /* on one line in plan: the farthest point from the line through the
     * first and the one farthest from it */
    int far = 0;
    for (int i = 1; i < n; ++i)
        if (hypot(plan[i][0] - plan[0][0], plan[i][1] - plan[0][1]) >
            hypot(plan[far][0] - plan[0][0], plan[far][1] - plan[0][1]))
            far = i;
    double off = 0.0;
    for (int i = 0; i < n; ++i)
        off = fmax(off, fabs(orient(plan[0], plan[far], plan[i])) / size);
    if (off <= 1e-9 * size) {
        double d[3];
        section_direction(c, d);
        for (int i = 1; i < n; ++i)
            if (!(dot3(d, w->points[i]) > dot3(d, w->points[i - 1]))) {
                *bad = i;
                return GSN_WATER_BACKWARDS;
            }
        return GSN_WATER_SECTION;
    }
    for (int i = 1; i < n; ++i)
        for (int j = 0; j < i; ++j)
            if (hypot(plan[i][0] - plan[j][0], plan[i][1] - plan[j][1]) <=
                1e-9 * size) {
                *bad = i;
                return GSN_WATER_TWICE;
            }
    triangulate(w, plan);
    return GSN_WATER_SURFACE;
}

/* The height of the spread table over plan place q: linear on the triangle
 * that holds q, else at the nearest place of the hull. */
static double surface_height(const struct gsn_case *c, const double x[3])
{
    const struct gsn_water *w = &c->water;
    double e[2][3], q[2];
    gsn_plan_axes(c, e);
    to_plan(&e[0][0], x, q);
    double best = INFINITY, height = 0.0;
    for (int k = 0; k < w->triangle_count; ++k) {
        double p[3][2], h[3];
        for (int v = 0; v < 3; ++v) {
            to_plan(&e[0][0], w->points[w->triangles[k][v]], p[v]);
            h[v] = gsn_height(c, w->points[w->triangles[k][v]]);
        }
        double area = orient(p[0], p[1], p[2]);
        double l[3] = {orient(q, p[1], p[2]) / area,
                       orient(p[0], q, p[2]) / area,
                       orient(p[0], p[1], q) / area};
        if (l[0] >= -1e-12 && l[1] >= -1e-12 && l[2] >= -1e-12)
            return l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
        /* outside: the nearest place on its edges (the hull's among them) */
        for (int v = 0; v < 3; ++v) {
            const double *a = p[v], *b = p[(v + 1) % 3];
            double ab[2] = {b[0] - a[0], b[1] - a[1]};
            double s = ((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1]) /
                       (ab[0] * ab[0] + ab[1] * ab[1]);
            s = fmin(1.0, fmax(0.0, s));
            double d = hypot(a[0] + s * ab[0] - q[0], a[1] + s * ab[1] - q[1]);
            if (d < best) {
                best = d;
                height = h[v] + s * (h[(v + 1) % 3] - h[v]);
            }
        }
    }
    return height;
}

double gsn_water_table_height(const struct gsn_case *c, const double x[3])
{
    const struct gsn_water *w = &c->water;
    if (w->point_count == 1)
        return w->points[0][0];
    if (w->triangle_count > 0)
        return surface_height(c, x);
    double d[3];
    section_direction(c, d);
    double s = dot3(d, x);
    int last = w->point_count - 1;
    if (s <= dot3(d, w->points[0]))
        return gsn_height(c, w->points[0]);
    if (s >= dot3(d, w->points[last]))
        return gsn_height(c, w->points[last]);
    int i = 0;
    while (i + 1 < last && dot3(d, w->points[i + 1]) < s)
        ++i;
    double s0 = dot3(d, w->points[i]), s1 = dot3(d, w->points[i + 1]);
    double h0 = gsn_height(c, w->points[i]),
           h1 = gsn_height(c, w->points[i + 1]);
    return h0 + (h1 - h0) * (s - s0) / (s1 - s0);
}

double gsn_water_pressure(const struct gsn_case *c, const double x[3])
{
    if (!c->water.present)
        return 0.0;
    double head = gsn_water_table_height(c, x) - gsn_height(c, x);
    return head > 0.0 ? c->water.unit_weight * head : 0.0;
}
