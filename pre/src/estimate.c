/* The particle estimate (estimate.h). gmsh's size at x is
 * size(x) = min(h, f_1(x), ...): a Box field is s inside the box and grows
 * linearly with the distance to it to h over its thickness D; a Threshold
 * field on a surface's Distance is s within the width w and grows linearly
 * to h over D beyond (gmsh 4.8, Mesh/Field.cpp). The node count of a mesh
 * of that size is N = a int dV/size^3 + b int dA/size^2 + c int dl/size
 * (volume, surfaces, curves).
 *
 * The integrals: on a simplex T of dimension k where size is linear with
 * vertex values s_0..s_k, int_T size^-k = k! |T| F_k[s_0, ..., s_k], the
 * divided difference of F_k with F_k^(k)(s) = s^-k (Hermite-Genocchi):
 * F_1 = ln s, F_2 = -ln s, F_3 = ln(s) / 2. Elements are split in 2, 4 or 8
 * (edge midpoints) until the rule on the children agrees with the rule on
 * the parent, and always while they are larger than half a refinement's
 * width, distance or box inside its reach, so that no refinement falls
 * between the samples. */
#include "estimate.h"
#include "geoscni/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Relative agreement of parent and children at which an element is done. */
#define ESTIMATE_TOLERANCE 1e-2
/* Elements where a refinement's breakpoint may lie are split down to its
 * feature length (width, distance, box side, at least its spacing) / this,
 * so that no part of it falls between the samples; no element is split
 * below the smallest of these lengths. On a cube (tests/pre/test_estimate.c)
 * the integrals then come within -1.1 % (a refined face) and -2.7 % (a box
 * with a transition) of the exact ones: the linear rule across the kink
 * where the size starts to grow underestimates. Half the length gives
 * -0.3 % and -1.1 % but triples the time on Slope I's graded case (1.9 s
 * against 0.6 s for geoscni check), more than the coefficients' error is
 * worth. A box without a transition makes the size jump at its faces: its
 * length is divided by 8 (a box of one length inside an element: -6 %). */
#define ESTIMATE_FEATURE_SPLIT 1.0
#define ESTIMATE_JUMP_SPLIT 8.0
/* Size evaluations after which elements are no longer split (about 1 s). */
#define ESTIMATE_BUDGET 4000000L
/* Values closer than this (relative) are one node of a divided difference;
 * all values within ESTIMATE_TAYLOR take the Taylor expansion at their
 * mean (the differences of ln s would cancel). */
#define ESTIMATE_SAME 1e-9
#define ESTIMATE_TAYLOR 1e-3

/* Coefficients a, b, c of the count: least squares on the relative error
 * of gmsh 4.8's node counts (one thread) of the box, L-shape, cylinder and
 * Slope I of geometries/ at 3 to 40 spacings across, 31 meshes per
 * algorithm. The fit is within 9 % of every mesh of 1,000 nodes or more and
 * within 3 % from 10,000 on; the counts themselves jump with the number of
 * divisions of the curves (Slope I: 1,734 nodes at h = 1, 2,535 at 0.9). */
void estimate_coefficients_for(int reproducible,
                               struct estimate_coefficients *k)
{
    if (reproducible) { /* Delaunay */
        k->volume = 0.6872;
        k->surface = 0.8472;
        k->edge = 0.6126;
    } else { /* HXT */
        k->volume = 0.5878;
        k->surface = 0.9484;
        k->edge = 0.6365;
    }
}

/* ---- distances ------------------------------------------------------- */

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double distance2(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return dot(d, d);
}

/* Squared distance from p to triangle abc (Ericson, Real-Time Collision
 * Detection, 5.1.5). */
double estimate_triangle_distance2(const double p[3], const double a[3],
                                   const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], q[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
    }
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return distance2(p, a);
    double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return distance2(p, b);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; ++k)
            q[k] = a[k] + v * ab[k];
        return distance2(p, q);
    }
    double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return distance2(p, c);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; ++k)
            q[k] = a[k] + w * ac[k];
        return distance2(p, q);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; ++k)
            q[k] = b[k] + w * (c[k] - b[k]);
        return distance2(p, q);
    }
    double denominator = 1.0 / (va + vb + vc);
    double v = vb * denominator, w = vc * denominator;
    for (int k = 0; k < 3; ++k)
        q[k] = a[k] + ab[k] * v + ac[k] * w;
    return distance2(p, q);
}

static double box_distance(const double box[6], const double x[3])
{
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        double d = fmax(fmax(box[k] - x[k], x[k] - box[k + 3]), 0.0);
        sum += d * d;
    }
    return sqrt(sum);
}

/* A refinement with what the integration needs: each triangle's bounding
 * sphere, to skip the far ones, and the last nearest triangle, tried
 * first. */
struct field {
    const struct estimate_refinement *r;
    const double *position;
    double *sphere; /* 4 per triangle: centre, radius */
    int last;       /* the nearest triangle of the last query */
    double reach;   /* the field is below h closer than this */
    double feature; /* the length on which it changes */
};

static double field_distance(struct field *f, const double x[3])
{
    if (f->r->kind == GSN_REFINE_BOX)
        return box_distance(f->r->box, x);
    double best = HUGE_VAL;
    for (int u = -1; u < f->r->triangle_count; ++u) {
        int t = u < 0 ? f->last : u;
        if (u == f->last || t >= f->r->triangle_count)
            continue;
        const double *sphere = &f->sphere[4 * t];
        double centre = sqrt(distance2(x, sphere)) - sphere[3];
        if (centre > 0 && centre * centre >= best)
            continue;
        const int *v = &f->r->triangles[3 * t];
        double d = estimate_triangle_distance2(x, &f->position[3 * v[0]],
                                               &f->position[3 * v[1]],
                                               &f->position[3 * v[2]]);
        if (d < best) {
            best = d;
            f->last = t;
        }
    }
    return sqrt(best);
}

/* gmsh's field at distance d (Box: to the box; Threshold: to the surface). */
static double field_size(const struct estimate_refinement *r, double h,
                         double d)
{
    double near = r->kind == GSN_REFINE_BOX ? 0.0 : r->width;
    if (d <= near)
        return r->spacing;
    if (r->distance > 0 && d < near + r->distance)
        return r->spacing + (d - near) / r->distance * (h - r->spacing);
    return h;
}

/* ---- the rule on a simplex ------------------------------------------- */

static const double factorial[4] = {1, 1, 2, 6};

/* F_k^(l)(x) of the header, l = 0..k. */
static double antiderivative(int k, int l, double x)
{
    static const double scale[4] = {0, 1, -1, 0.5};
    if (l == 0)
        return scale[k] * log(x);
    double value = scale[k] * factorial[l - 1] / pow(x, l);
    return l % 2 ? value : -value;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* int over a k-simplex of measure |T| of size^-k, size linear with the
 * vertex values s[0..k]. */
static double simplex_rule(int k, double measure, const double *s)
{
    double x[4], mean = 0.0;
    for (int i = 0; i <= k; ++i) {
        x[i] = s[i];
        mean += s[i] / (k + 1);
    }
    qsort(x, (size_t)k + 1, sizeof(double), compare_doubles);
    if (x[k] - x[0] <= ESTIMATE_TAYLOR * x[0]) {
        /* F_k[x] = F^(k)(m)/k! + F^(k+2)(m)/(k+2)! h_2(x - m) + O(d^3) */
        double h2 = 0.0;
        for (int i = 0; i <= k; ++i)
            for (int j = i; j <= k; ++j)
                h2 += (x[i] - mean) * (x[j] - mean);
        double value = 1.0 / (factorial[k] * pow(mean, k)) +
                       k * (k + 1) * h2 / (factorial[k] * (k + 1) * (k + 2)) /
                           pow(mean, k + 2);
        return factorial[k] * measure * value;
    }
    double table[4];
    for (int i = 0; i <= k; ++i)
        table[i] = antiderivative(k, 0, x[i]);
    for (int l = 1; l <= k; ++l)
        for (int i = 0; i + l <= k; ++i) {
            double gap = x[i + l] - x[i];
            table[i] = gap <= ESTIMATE_SAME * x[i]
                           ? antiderivative(k, l, 0.5 * (x[i] + x[i + l])) /
                                 factorial[l]
                           : (table[i + 1] - table[i]) / gap;
        }
    return factorial[k] * measure * table[0];
}

/* ---- adaptive integration -------------------------------------------- */

struct integrator {
    struct field *fields;
    int field_count;
    double h, floor;
    long evaluations;
    double done, cap; /* accepted volume integral, and where to stop */
    int stopped;
};

static double size_at(struct integrator *g, const double x[3])
{
    double size = g->h;
    ++g->evaluations;
    for (int i = 0; i < g->field_count; ++i)
        size = fmin(size, field_size(g->fields[i].r, g->h,
                                     field_distance(&g->fields[i], x)));
    return size;
}

/* 1 if the distance to a field's surface or box may cross one of its
 * breakpoints (where the size stops being constant or linear in it) within
 * [low, high]. */
static int field_straddles(const struct estimate_refinement *r, double low,
                           double high)
{
    double near = r->kind == GSN_REFINE_BOX ? 0.0 : r->width;
    double breakpoints[2] = {near, near + r->distance};
    for (int b = 0; b < 2; ++b)
        if (low <= breakpoints[b] && breakpoints[b] < high)
            return 1;
    return 0;
}

/* 1 if some field may reach below h somewhere within radius of centre;
 * *split: one of its breakpoints may lie inside the element, which is
 * larger than that field's feature length. */
static int element_reached(struct integrator *g, const double centre[3],
                           double radius, double diameter, int *split)
{
    int reached = 0;
    *split = 0;
    for (int i = 0; i < g->field_count; ++i) {
        struct field *f = &g->fields[i];
        double d = field_distance(f, centre);
        if (d - radius >= f->reach)
            continue;
        reached = 1;
        if (diameter > f->feature &&
            field_straddles(f->r, d - radius, d + radius))
            *split = 1;
    }
    return reached;
}

/* Children of a k-simplex (vertices v, sizes s): 2, 4 or 8 sets of k + 1
 * indices into the vertices followed by the edge midpoints. */
static const int segment_children[2][2] = {{0, 2}, {2, 1}};
static const int triangle_children[4][3] = {
    {0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}}; /* 3: 01, 4: 12, 5: 20 */
/* 4: 01, 5: 02, 6: 03, 7: 12, 8: 13, 9: 23; the inner octahedron split
 * along 02-13 */
static const int tetrahedron_children[8][4] = {
    {0, 4, 5, 6}, {4, 1, 7, 8}, {5, 7, 2, 9}, {6, 8, 9, 3},
    {5, 8, 4, 6}, {5, 8, 6, 9}, {5, 8, 9, 7}, {5, 8, 7, 4}};
static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

static double integrate(struct integrator *g, int k, double (*v)[3],
                        const double *s, double measure, double diameter,
                        double coarse);

static double integrate_children(struct integrator *g, int k, double (*v)[3],
                                 const double *s, double measure,
                                 double diameter, double coarse, int split)
{
    double points[10][3], sizes[10];
    int n = k + 1, count = k == 1 ? 2 : k == 2 ? 4 : 8;
    for (int i = 0; i < n; ++i) {
        memcpy(points[i], v[i], sizeof(double[3]));
        sizes[i] = s[i];
    }
    if (k == 1) {
        for (int j = 0; j < 3; ++j)
            points[2][j] = 0.5 * (v[0][j] + v[1][j]);
        sizes[2] = size_at(g, points[2]);
    } else {
        int edge_count = k == 2 ? 3 : 6;
        for (int e = 0; e < edge_count; ++e) {
            int a = k == 2 ? e : edges[e][0];
            int b = k == 2 ? (e + 1) % 3 : edges[e][1];
            for (int j = 0; j < 3; ++j)
                points[n + e][j] = 0.5 * (v[a][j] + v[b][j]);
            sizes[n + e] = size_at(g, points[n + e]);
        }
    }
    double child_v[8][4][3], child_s[8][4], child_rule[8], fine = 0.0;
    for (int c = 0; c < count; ++c) {
        const int *index = k == 1   ? segment_children[c]
                           : k == 2 ? triangle_children[c]
                                    : tetrahedron_children[c];
        for (int i = 0; i < n; ++i) {
            memcpy(child_v[c][i], points[index[i]], sizeof(double[3]));
            child_s[c][i] = sizes[index[i]];
        }
        child_rule[c] = simplex_rule(k, measure / count, child_s[c]);
        fine += child_rule[c];
    }
    int settled = fabs(fine - coarse) <= ESTIMATE_TOLERANCE * fine ||
                  diameter <= g->floor;
    if (g->stopped || (!split && settled)) {
        if (k == 3)
            g->done += fine;
        return fine;
    }
    double sum = 0.0;
    for (int c = 0; c < count; ++c)
        sum += integrate(g, k, child_v[c], child_s[c], measure / count,
                         0.5 * diameter, child_rule[c]);
    return sum;
}

/* int size^-k over a k-simplex whose rule on its vertices gave coarse. */
static double integrate(struct integrator *g, int k, double (*v)[3],
                        const double *s, double measure, double diameter,
                        double coarse)
{
    double centre[3] = {0, 0, 0}, radius = 0.0;
    for (int i = 0; i <= k; ++i)
        for (int j = 0; j < 3; ++j)
            centre[j] += v[i][j] / (k + 1);
    for (int i = 0; i <= k; ++i)
        radius = fmax(radius, sqrt(distance2(centre, v[i])));
    int split = 0;
    if (!element_reached(g, centre, radius, diameter, &split)) {
        double exact = measure / pow(g->h, k); /* size h throughout */
        if (k == 3)
            g->done += exact;
        return exact;
    }
    if (g->stopped || g->evaluations > ESTIMATE_BUDGET || g->done > g->cap) {
        g->stopped = 1;
        if (k == 3)
            g->done += coarse;
        return coarse;
    }
    return integrate_children(g, k, v, s, measure, diameter, coarse, split);
}

static double simplex_measure(int k, double (*v)[3])
{
    double a[3], b[3], c[3];
    for (int j = 0; j < 3; ++j) {
        a[j] = v[1][j] - v[0][j];
        b[j] = k > 1 ? v[2][j] - v[0][j] : 0.0;
        c[j] = k > 2 ? v[3][j] - v[0][j] : 0.0;
    }
    double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    if (k == 1)
        return sqrt(dot(a, a));
    if (k == 2)
        return 0.5 * sqrt(dot(n, n));
    return fabs(dot(n, c)) / 6.0;
}

/* int size^-k over the k-simplices of the body. */
static double integrate_all(struct integrator *g, const double *position, int k,
                            int count, const int *simplices)
{
    double sum = 0.0;
    for (int e = 0; e < count; ++e) {
        double v[4][3], s[4], diameter = 0.0;
        for (int i = 0; i <= k; ++i) {
            memcpy(v[i], &position[3 * simplices[(k + 1) * e + i]],
                   sizeof(double[3]));
            s[i] = size_at(g, v[i]);
        }
        for (int i = 0; i <= k; ++i)
            for (int j = 0; j < i; ++j)
                diameter = fmax(diameter, sqrt(distance2(v[i], v[j])));
        double measure = simplex_measure(k, v);
        sum += integrate(g, k, v, s, measure, diameter,
                         simplex_rule(k, measure, s));
    }
    return sum;
}

static int integrals_compute(const struct estimate_body *body, double h,
                             const struct estimate_refinement *refinements,
                             int refinement_count, double cap,
                             double integrals[3], int *stopped)
{
    GSN_CHECK(h > 0 && refinement_count >= 0 &&
                  refinement_count <= GSN_MAX_REFINEMENTS,
              GSN_ERR_INTERNAL, "estimate: spacing %g, %d refinements", h,
              refinement_count);
    struct field fields[GSN_MAX_REFINEMENTS];
    memset(fields, 0, sizeof fields);
    struct integrator g = {fields, refinement_count, h, HUGE_VAL, 0, 0, cap, 0};
    int rc = GSN_OK;
    for (int i = 0; i < refinement_count; ++i) {
        const struct estimate_refinement *r = &refinements[i];
        struct field *f = &fields[i];
        f->r = r;
        f->position = body->position;
        double lengths[4] = {r->width, r->distance, HUGE_VAL, HUGE_VAL};
        if (r->kind == GSN_REFINE_BOX) {
            lengths[0] =
                fmin(fmin(r->box[3] - r->box[0], r->box[4] - r->box[1]),
                     r->box[5] - r->box[2]);
            f->reach = r->distance;
        } else {
            f->reach = r->width + r->distance;
        }
        f->feature = HUGE_VAL;
        for (int j = 0; j < 2; ++j)
            if (lengths[j] > 0)
                f->feature = fmin(f->feature, lengths[j]);
        /* gmsh resolves nothing thinner than the spacing there */
        f->feature =
            fmax(f->feature == HUGE_VAL ? 0.0 : f->feature, r->spacing);
        /* a box without a transition makes the size jump at its faces */
        f->feature /= r->kind == GSN_REFINE_BOX && r->distance == 0
                          ? ESTIMATE_JUMP_SPLIT
                          : ESTIMATE_FEATURE_SPLIT;
        g.floor = fmin(g.floor, f->feature);
        if (r->kind == GSN_REFINE_BOX)
            continue;
        f->sphere =
            malloc(sizeof(double) * 4 * ((size_t)r->triangle_count + 1));
        GSN_CHECK_GOTO(f->sphere != NULL, rc, GSN_ERR_MEMORY, done,
                       "cannot allocate %d triangles", r->triangle_count);
        for (int t = 0; t < r->triangle_count; ++t) {
            double *sphere = &f->sphere[4 * t];
            const int *v = &r->triangles[3 * t];
            for (int j = 0; j < 3; ++j)
                sphere[j] = (body->position[3 * v[0] + j] +
                             body->position[3 * v[1] + j] +
                             body->position[3 * v[2] + j]) /
                            3.0;
            sphere[3] = 0.0;
            for (int c = 0; c < 3; ++c)
                sphere[3] =
                    fmax(sphere[3],
                         sqrt(distance2(sphere, &body->position[3 * v[c]])));
        }
    }
    integrals[0] = integrate_all(&g, body->position, 3, body->tetrahedron_count,
                                 body->tetrahedra);
    integrals[1] = integrate_all(&g, body->position, 2, body->triangle_count,
                                 body->triangles);
    integrals[2] = integrate_all(&g, body->position, 1, body->segment_count,
                                 body->segments);
    *stopped = g.stopped;
done:
    for (int i = 0; i < refinement_count; ++i)
        free(fields[i].sphere);
    return rc;
}

int estimate_integrals(const struct estimate_body *body, double spacing,
                       const struct estimate_refinement *refinements,
                       int refinement_count, double integrals[3])
{
    int stopped = 0;
    GSN_CALL(integrals_compute(body, spacing, refinements, refinement_count,
                               HUGE_VAL, integrals, &stopped));
    return GSN_OK;
}

int estimate_particles(const struct estimate_body *body, double spacing,
                       const struct estimate_refinement *refinements,
                       int refinement_count,
                       const struct estimate_coefficients *k, double cap,
                       double *count, int *at_least)
{
    double integrals[3];
    int stopped = 0;
    GSN_CALL(integrals_compute(body, spacing, refinements, refinement_count,
                               cap / k->volume, integrals, &stopped));
    *count = k->volume * integrals[0] + k->surface * integrals[1] +
             k->edge * integrals[2];
    /* stopped past the cap (or the budget): the elements left unsplit make
     * the rest a guess */
    *at_least = stopped;
    if (stopped && *count < cap)
        *count = cap;
    return GSN_OK;
}
