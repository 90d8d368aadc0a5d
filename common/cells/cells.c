/* Nodal domains (seed paper section 4): each particle's Voronoi cell,
 * clipped to the body, as facets with quadrature points.
 *
 * TOOLCHAIN.md, "Clipped Voronoi cells": CGAL's Delaunay triangulation gives
 * the neighbours (one thread); each cell starts as a box holding the body
 * and is clipped by the bisector planes of its neighbours, nearest first,
 * until the next neighbour is farther than twice the cell's radius (the
 * security radius). A cell that meets boundary triangles of the mesh is cut
 * by their planes where they form a convex patch; elsewhere it is
 * intersected with every tetrahedron near it (the tetrahedra are convex
 * pieces whose union is the body) and its facets are kept piece by piece,
 * so non-convex cells near re-entrant edges come out right. Cells
 * are clipped in parallel in blocks; the results do not depend on the
 * thread count. */
#include "geoscni/cells.h"
#include "delaunay.h"
#include "geoscni/error.h"
#include "geoscni/tensor.h"
#include "polyhedron.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { BLOCK_CELLS = 64, MESSAGE_SIZE = 512 };

/* Relative tolerances, of the box diagonal. */
#define DOMAIN_EPS 1e-14       /* a vertex this close to a plane is on it */
#define DOMAIN_EPS_RETRY 1e-11 /* second try after a topology failure */
#define DOMAIN_DUPLICATE 1e-12 /* particles this close are duplicates */
#define DOMAIN_CONVEX 1e-12    /* boundary patches flatter than this are flat */

static double now(void)
{
    return omp_get_wtime();
}

/* ---- spatial bins of the body's tetrahedra and boundary triangles ------ */

struct bins {
    int n[3];
    double lo[3], size[3];
    int *offset; /* bin count + 1 */
    int *item;
};

static void bins_free(struct bins *b)
{
    free(b->offset);
    free(b->item);
    memset(b, 0, sizeof *b);
}

static void bins_range(const struct bins *b, const double lo[3],
                       const double hi[3], int first[3], int last[3])
{
    for (int k = 0; k < 3; ++k) {
        int a = (int)floor((lo[k] - b->lo[k]) / b->size[k]);
        int c = (int)floor((hi[k] - b->lo[k]) / b->size[k]);
        first[k] = a < 0 ? 0 : (a >= b->n[k] ? b->n[k] - 1 : a);
        last[k] = c < 0 ? 0 : (c >= b->n[k] ? b->n[k] - 1 : c);
    }
}

/* Walks the items of the bins that overlap [lo, hi] in bin order (x
 * fastest), each item once per mark: stamp[item] keeps the last mark that
 * saw it. */
struct bins_walk {
    const struct bins *bins;
    int *stamp, mark;
    int first[3], last[3], at[3]; /* the bins to read; the one being read */
    int entry, end;               /* the items of the bin being read */
};

static void bins_walk_open(struct bins_walk *walk)
{
    const struct bins *b = walk->bins;
    long bin =
        ((long)walk->at[2] * b->n[1] + walk->at[1]) * b->n[0] + walk->at[0];
    walk->entry = b->offset[bin];
    walk->end = b->offset[bin + 1];
}

static void bins_walk_start(struct bins_walk *walk, const struct bins *bins,
                            const double lo[3], const double hi[3], int *stamp,
                            int mark)
{
    walk->bins = bins;
    walk->stamp = stamp;
    walk->mark = mark;
    bins_range(bins, lo, hi, walk->first, walk->last);
    memcpy(walk->at, walk->first, sizeof walk->at);
    bins_walk_open(walk);
}

/* The next item not yet seen under this mark, or -1 when done. */
static int bins_walk_next(struct bins_walk *walk)
{
    for (;;) {
        while (walk->entry < walk->end) {
            int item = walk->bins->item[walk->entry++];
            if (walk->stamp[item] == walk->mark)
                continue;
            walk->stamp[item] = walk->mark;
            return item;
        }
        int k = 0;
        while (k < 3 && ++walk->at[k] > walk->last[k])
            walk->at[k] = walk->first[k], ++k;
        if (k == 3)
            return -1;
        bins_walk_open(walk);
    }
}

/* Whether the bounding box of `count` points v (3 each, relative to x) misses
 * the box [lo, hi]: strictly apart, or, with touching_misses, also where the
 * two only touch. */
static int points_miss_box(const double *v, int count, const double x[3],
                           const double lo[3], const double hi[3],
                           int touching_misses)
{
    for (int k = 0; k < 3; ++k) {
        double a = v[k], c = v[k];
        for (int p = 1; p < count; ++p) {
            a = gsn_min(a, v[3 * p + k]);
            c = gsn_max(c, v[3 * p + k]);
        }
        if (touching_misses ? a + x[k] >= hi[k] || c + x[k] <= lo[k]
                            : a + x[k] > hi[k] || c + x[k] < lo[k])
            return 1;
    }
    return 0;
}

/* Bins items by their bounding boxes (item_lo/item_hi, count x 3). */
static int bins_create(struct bins *b, const double lo[3], const double hi[3],
                       double spacing, int count, const double *item_lo,
                       const double *item_hi)
{
    memset(b, 0, sizeof *b);
    long total = 1;
    for (int k = 0; k < 3; ++k) {
        double extent = hi[k] - lo[k];
        int n = (int)(extent / spacing);
        b->n[k] = n < 1 ? 1 : (n > 512 ? 512 : n);
        b->lo[k] = lo[k];
        b->size[k] = extent > 0.0 ? extent / b->n[k] : 1.0;
        total *= b->n[k];
    }
    b->offset = calloc((size_t)total + 1, sizeof(int));
    GSN_CHECK(b->offset != NULL, GSN_ERR_MEMORY, "cannot allocate %ld bins",
              total);
    for (int pass = 0; pass < 2; ++pass) {
        for (int i = 0; i < count; ++i) {
            int first[3], last[3];
            bins_range(b, &item_lo[3 * i], &item_hi[3 * i], first, last);
            for (int z = first[2]; z <= last[2]; ++z)
                for (int y = first[1]; y <= last[1]; ++y)
                    for (int x = first[0]; x <= last[0]; ++x) {
                        long bin = ((long)z * b->n[1] + y) * b->n[0] + x;
                        if (pass == 0)
                            ++b->offset[bin + 1];
                        else
                            b->item[b->offset[bin]++] = i;
                    }
        }
        if (pass == 0) {
            for (long k = 0; k < total; ++k)
                b->offset[k + 1] += b->offset[k];
            b->item = malloc(sizeof(int) * (size_t)(b->offset[total] + 1));
            GSN_CHECK(b->item != NULL, GSN_ERR_MEMORY,
                      "cannot allocate the bins");
        } else {
            for (long k = total; k > 0; --k)
                b->offset[k] = b->offset[k - 1];
            b->offset[0] = 0;
        }
    }
    return GSN_OK;
}

/* ---- the body's boundary triangles ----------------------------------- */

struct body_index {
    int triangle_count;
    int *triangle;          /* triangle_count x 3 particle indices */
    int *triangle_label;    /* as domain_body's face labels */
    double *triangle_plane; /* outward unit normal n and n.x on it */
    struct bins triangles;  /* bins of the triangles */
    struct bins tetrahedra;
    char *on_boundary; /* per particle: a vertex of a boundary triangle */
};

static void body_index_free(struct body_index *b)
{
    free(b->triangle);
    free(b->triangle_label);
    free(b->triangle_plane);
    free(b->on_boundary);
    bins_free(&b->triangles);
    bins_free(&b->tetrahedra);
    memset(b, 0, sizeof *b);
}

/* Unit normal of triangle v pointing away from particle opposite, and the
 * plane's offset n.x. */
static void triangle_plane(const double *position, const int v[3], int opposite,
                           double plane[4])
{
    const double *a = &position[3 * v[0]], *b = &position[3 * v[1]];
    const double *c = &position[3 * v[2]], *o = &position[3 * opposite];
    double u[3], w[3], n[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        w[k] = c[k] - a[k];
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double side =
        n[0] * (o[0] - a[0]) + n[1] * (o[1] - a[1]) + n[2] * (o[2] - a[2]);
    double scale = (side > 0.0 ? -1.0 : 1.0) / (length > 0.0 ? length : 1.0);
    for (int k = 0; k < 3; ++k)
        plane[k] = scale * n[k];
    plane[3] =
        (plane[0] * (a[0] + b[0] + c[0]) + plane[1] * (a[1] + b[1] + c[1]) +
         plane[2] * (a[2] + b[2] + c[2])) /
        3.0;
}

static int body_index_create(const struct gsn_cells_input *in, double spacing,
                             struct body_index *b)
{
    memset(b, 0, sizeof *b);
    const struct gsn_cells_body *body = &in->body;
    int nt = body->tetrahedron_count, rc = GSN_OK;
    int count = 0;
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 4; ++k)
            count += body->face_label[4 * t + k] != POLY_LABEL_INTERNAL;
    double *lo = malloc(sizeof(double) * 3 * (size_t)(nt > count ? nt : count));
    double *hi = malloc(sizeof(double) * 3 * (size_t)(nt > count ? nt : count));
    b->triangle = malloc(sizeof(int) * 3 * (size_t)(count + 1));
    b->triangle_label = malloc(sizeof(int) * (size_t)(count + 1));
    b->triangle_plane = malloc(sizeof(double) * 4 * (size_t)(count + 1));
    b->on_boundary = calloc((size_t)in->particle_count + 1, 1);
    GSN_CHECK_GOTO(lo && hi && b->triangle && b->triangle_label &&
                       b->triangle_plane && b->on_boundary,
                   rc, GSN_ERR_MEMORY, fail, "cannot allocate the body index");
    count = 0;
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 4; ++k) {
            if (body->face_label[4 * t + k] == POLY_LABEL_INTERNAL)
                continue;
            for (int j = 0; j < 3; ++j) {
                int v =
                    body->tetrahedra[4 * t + gsn_cells_tetrahedron_face[k][j]];
                b->triangle[3 * count + j] = v;
                b->on_boundary[v] = 1;
            }
            b->triangle_label[count] = body->face_label[4 * t + k];
            triangle_plane(in->position, &b->triangle[3 * count],
                           body->tetrahedra[4 * t + k],
                           &b->triangle_plane[4 * count]);
            ++count;
        }
    b->triangle_count = count;
    for (int pass = 0; pass < 2; ++pass) {
        int items = pass == 0 ? count : nt, corners = pass == 0 ? 3 : 4;
        const int *vertex = pass == 0 ? b->triangle : body->tetrahedra;
        for (int i = 0; i < items; ++i)
            for (int k = 0; k < 3; ++k) {
                double a = INFINITY, c = -INFINITY;
                for (int j = 0; j < corners; ++j) {
                    double x = in->position[3 * vertex[corners * i + j] + k];
                    a = x < a ? x : a;
                    c = x > c ? x : c;
                }
                lo[3 * i + k] = a;
                hi[3 * i + k] = c;
            }
        GSN_CALL_GOTO(bins_create(pass == 0 ? &b->triangles : &b->tetrahedra,
                                  in->lo, in->hi, spacing, items, lo, hi),
                      rc, fail);
    }
    free(lo);
    free(hi);
    return GSN_OK;
fail:
    free(lo);
    free(hi);
    body_index_free(b);
    return rc;
}

/* ---- per-block output ------------------------------------------------- */

struct block_output {
    int first, count;
    int *cell_faces; /* faces per cell of the block */
    int face_count, face_capacity;
    int *face_label, *face_points;
    double *face_area, *face_normal;
    int point_count, point_capacity;
    double *point, *weight;
    int crossing, pieced;
    int rc;
    char message[MESSAGE_SIZE];
};

static void block_free(struct block_output *b)
{
    free(b->cell_faces);
    free(b->face_label);
    free(b->face_points);
    free(b->face_area);
    free(b->face_normal);
    free(b->point);
    free(b->weight);
}

static int grow(void **array, int *capacity, int needed, size_t size)
{
    if (needed <= *capacity)
        return 1;
    int c = *capacity ? *capacity : 256;
    while (c < needed)
        c *= 2;
    void *p = realloc(*array, size * (size_t)c);
    if (!p)
        return 0;
    *array = p;
    *capacity = c;
    return 1;
}

static int block_reserve(struct block_output *b, int faces, int points)
{
    int fc = b->face_capacity, ok = 1;
    int need = b->face_count + faces;
    ok &= grow((void **)&b->face_label, &fc, need, sizeof(int));
    fc = b->face_capacity;
    ok &= grow((void **)&b->face_points, &fc, need, sizeof(int));
    fc = b->face_capacity;
    ok &= grow((void **)&b->face_area, &fc, need, sizeof(double));
    fc = b->face_capacity;
    ok &= grow((void **)&b->face_normal, &fc, need, 3 * sizeof(double));
    if (ok)
        b->face_capacity = fc;
    int pc = b->point_capacity;
    need = b->point_count + points;
    ok &= grow((void **)&b->point, &pc, need, 3 * sizeof(double));
    pc = b->point_capacity;
    ok &= grow((void **)&b->weight, &pc, need, sizeof(double));
    if (ok)
        b->point_capacity = pc;
    return ok;
}

/* ---- one cell ----------------------------------------------------------- */

struct worker {
    struct gsn_poly cell, piece, tet;
    struct gsn_poly_scratch scratch;
    int *order; /* neighbours sorted by distance */
    double *distance2;
    int order_capacity;
    int *stamp; /* per tetrahedron / triangle: last cell that looked */
    int *stamp_triangle;
    int *hit; /* boundary triangles that meet the cell */
};

struct context {
    const struct gsn_cells_input *in;
    const int *offset, *neighbour;
    const struct body_index *body;
    double eps, area_eps, drop_area;
    double convex_tolerance; /* a vertex this far out breaks convexity */
};

static int clip_checked(struct gsn_poly *p, struct gsn_poly_scratch *s,
                        const double n[3], double b, int label, double eps,
                        double eps_retry)
{
    enum gsn_poly_clip_result r = gsn_poly_clip(p, s, n, b, label, eps);
    if (r == POLY_CLIP_TOPOLOGY)
        r = gsn_poly_clip(p, s, n, b, label, eps_retry);
    return r;
}

/* Adds the faces of p (local coordinates around x) to the block; faces
 * labelled INTERNAL are dropped. Returns 0 on memory failure, -1 if a hull
 * face is left (the cell reaches outside the body). */
static int emit_faces(struct block_output *b, const struct gsn_poly *p,
                      const double x[3], int facet_points, double drop_area,
                      int *cell_faces)
{
    for (int f = 0; f < p->face_count; ++f) {
        int label = p->face_label[f];
        if (label == POLY_LABEL_INTERNAL)
            continue;
        double area[3];
        gsn_poly_face_area(p, f, area);
        double a =
            sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
        if (a <= drop_area)
            continue; /* rounding noise: a face that only touches */
        if (label == POLY_LABEL_HULL)
            return -1;
        int vertices = p->face_start[f + 1] - p->face_start[f];
        if (!block_reserve(b, 1, 3 * vertices))
            return 0;
        int k = b->face_count++;
        double normal[3] = {area[0] / a, area[1] / a, area[2] / a};
        b->face_label[k] = label;
        b->face_area[k] = a;
        memcpy(&b->face_normal[3 * k], normal, sizeof normal);
        double *point = &b->point[3 * b->point_count];
        int q = gsn_poly_face_quadrature(p, f, normal, facet_points, point,
                                         &b->weight[b->point_count]);
        for (int i = 0; i < q; ++i)
            for (int j = 0; j < 3; ++j)
                point[3 * i + j] += x[j];
        b->face_points[k] = q;
        b->point_count += q;
        ++*cell_faces;
    }
    return 1;
}

/* The boundary triangles that meet the cell (absolute bounding box lo, hi)
 * in a set of positive area, into w->hit; returns their count. */
static int cell_boundary_hits(const struct context *ctx, struct worker *w,
                              int i, const double lo[3], const double hi[3])
{
    const struct body_index *body = ctx->body;
    const double *x = &ctx->in->position[3 * i];
    const double *position = ctx->in->position;
    int hits = 0;
    struct bins_walk walk;
    bins_walk_start(&walk, &body->triangles, lo, hi, w->stamp_triangle, i);
    for (int t; (t = bins_walk_next(&walk)) >= 0;) {
        double tri[3][3];
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                tri[c][k] = position[3 * body->triangle[3 * t + c] + k] - x[k];
        if (!points_miss_box(&tri[0][0], 3, x, lo, hi, 0) &&
            gsn_poly_meets_triangle(&w->cell, &tri[0][0], ctx->eps,
                                    ctx->area_eps))
            w->hit[hits++] = t;
    }
    return hits;
}

/* Whether the boundary triangles that meet a cell form a convex patch: each
 * one's plane has every other on its inner side, and coplanar ones carry the
 * same label. Then the body inside the cell is the cell cut by their planes
 * (a point of the cell beyond one plane that were in the body would need
 * another boundary triangle in the cell beyond that plane). */
static int patch_is_convex(const struct context *ctx, const struct worker *w,
                           int hits)
{
    const struct body_index *body = ctx->body;
    const double *position = ctx->in->position;
    double tolerance = ctx->convex_tolerance;
    for (int a = 0; a < hits; ++a) {
        const double *plane = &body->triangle_plane[4 * w->hit[a]];
        for (int b = 0; b < hits; ++b) {
            if (b == a)
                continue;
            int t = w->hit[b], on = 0;
            for (int c = 0; c < 3; ++c) {
                const double *v = &position[3 * body->triangle[3 * t + c]];
                double d = plane[0] * v[0] + plane[1] * v[1] + plane[2] * v[2] -
                           plane[3];
                if (d > tolerance)
                    return 0;
                on += d >= -tolerance;
            }
            if (on == 3 &&
                body->triangle_label[t] != body->triangle_label[w->hit[a]])
                return 0;
        }
    }
    return 1;
}

/* Cuts the cell (into w->piece) by the planes of the triangles that meet
 * it; returns 0 if that does not close the cell inside the body. */
static int cell_cut_by_patch(const struct context *ctx, struct worker *w, int i,
                             int hits)
{
    const struct body_index *body = ctx->body;
    const double *x = &ctx->in->position[3 * i];
    gsn_poly_copy(&w->piece, &w->cell);
    for (int h = 0; h < hits; ++h) {
        int t = w->hit[h];
        const double *plane = &body->triangle_plane[4 * t];
        double b =
            plane[3] - (plane[0] * x[0] + plane[1] * x[1] + plane[2] * x[2]);
        int r = clip_checked(&w->piece, &w->scratch, plane, b,
                             body->triangle_label[t], ctx->eps,
                             DOMAIN_EPS_RETRY / DOMAIN_EPS * ctx->eps);
        if (r != POLY_CLIP_UNCHANGED && r != POLY_CLIP_CUT)
            return 0;
    }
    for (int f = 0; f < w->piece.face_count; ++f)
        if (w->piece.face_label[f] == POLY_LABEL_HULL)
            return 0;
    return 1;
}

/* Intersects the cell with the tetrahedra near it and emits the pieces. */
static int cell_emit_pieces(const struct context *ctx, struct worker *w, int i,
                            const double lo[3], const double hi[3],
                            struct block_output *b, double *volume,
                            double moment[3], int *cell_faces)
{
    const struct gsn_cells_body *body = &ctx->in->body;
    const double *position = ctx->in->position;
    const double *x = &position[3 * i];
    *volume = 0.0;
    moment[0] = moment[1] = moment[2] = 0.0;
    struct bins_walk walk;
    bins_walk_start(&walk, &ctx->body->tetrahedra, lo, hi, w->stamp, i);
    for (int t; (t = bins_walk_next(&walk)) >= 0;) {
        double v[4][3];
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k)
                v[c][k] = position[3 * body->tetrahedra[4 * t + c] + k] - x[k];
        if (points_miss_box(&v[0][0], 4, x, lo, hi, 1) ||
            !gsn_poly_init_tetrahedron(&w->tet, &v[0][0],
                                       &body->face_label[4 * t]))
            continue;
        gsn_poly_copy(&w->piece, &w->cell);
        int empty = 0;
        for (int f = 0; f < 4 && !empty; ++f) {
            const double *plane = &w->tet.face_plane[4 * f];
            int r = clip_checked(&w->piece, &w->scratch, plane, plane[3],
                                 w->tet.face_label[f], ctx->eps,
                                 DOMAIN_EPS_RETRY / DOMAIN_EPS * ctx->eps);
            if (r == POLY_CLIP_OVERFLOW || r == POLY_CLIP_TOPOLOGY)
                return r == POLY_CLIP_OVERFLOW ? -2 : -3;
            empty = r == POLY_CLIP_EMPTY;
        }
        if (empty)
            continue;
        double pv, pm[3];
        gsn_poly_volume(&w->piece, &pv, pm);
        if (pv <= 0.0)
            continue;
        *volume += pv;
        for (int k = 0; k < 3; ++k)
            moment[k] += pm[k];
        int r = emit_faces(b, &w->piece, x, ctx->in->facet_points,
                           ctx->drop_area, cell_faces);
        if (r <= 0)
            return r == 0 ? 0 : -1;
    }
    return 1;
}

static void sort_neighbours(int *order, double *d2, int count)
{
    for (int a = 1; a < count; ++a) {
        int o = order[a];
        double d = d2[a];
        int c = a - 1;
        while (c >= 0 && (d2[c] > d || (d2[c] == d && order[c] > o))) {
            order[c + 1] = order[c];
            d2[c + 1] = d2[c];
            --c;
        }
        order[c + 1] = o;
        d2[c + 1] = d;
    }
}

static int block_fail(struct block_output *b, int code, const char *format,
                      int i, const double *x)
{
    b->rc = code;
    snprintf(b->message, sizeof b->message, format, i, x[0], x[1], x[2]);
    return code;
}

/* Builds cell i into the block. */
static int cell_build(const struct context *ctx, struct worker *w, int i,
                      struct block_output *b, double *volume, double *centroid)
{
    const struct gsn_cells_input *in = ctx->in;
    const double *x = &in->position[3 * i];
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = in->lo[k] - x[k];
        hi[k] = in->hi[k] - x[k];
    }
    gsn_poly_init_box(&w->cell, lo, hi, in->box_label);

    int begin = ctx->offset[i], count = ctx->offset[i + 1] - begin;
    if (count > w->order_capacity) {
        int c = 2 * count;
        int *order = realloc(w->order, sizeof(int) * (size_t)c);
        if (order)
            w->order = order;
        double *d2 = realloc(w->distance2, sizeof(double) * (size_t)c);
        if (d2)
            w->distance2 = d2;
        if (!order || !d2)
            return block_fail(b, GSN_ERR_MEMORY,
                              "cannot allocate neighbours of particle %d "
                              "(%g, %g, %g)",
                              i, x);
        w->order_capacity = c;
    }
    for (int e = 0; e < count; ++e) {
        int j = ctx->neighbour[begin + e];
        const double *y = &in->position[3 * j];
        w->order[e] = j;
        w->distance2[e] = (y[0] - x[0]) * (y[0] - x[0]) +
                          (y[1] - x[1]) * (y[1] - x[1]) +
                          (y[2] - x[2]) * (y[2] - x[2]);
    }
    sort_neighbours(w->order, w->distance2, count);
    double radius2 = gsn_poly_radius2(&w->cell);
    for (int e = 0; e < count; ++e) {
        /* security radius: a neighbour farther than twice the farthest
         * vertex cannot cut the cell */
        if (w->distance2[e] > 4.0 * radius2 * (1.0 + 1e-12))
            break;
        int j = w->order[e];
        const double *y = &in->position[3 * j];
        double d = sqrt(w->distance2[e]);
        double n[3] = {(y[0] - x[0]) / d, (y[1] - x[1]) / d, (y[2] - x[2]) / d};
        int r = clip_checked(&w->cell, &w->scratch, n, 0.5 * d, j, ctx->eps,
                             DOMAIN_EPS_RETRY / DOMAIN_EPS * ctx->eps);
        if (r == POLY_CLIP_EMPTY)
            return block_fail(b, GSN_ERR_INPUT,
                              "the Voronoi cell of particle %d (%g, %g, %g) "
                              "is empty",
                              i, x);
        if (r == POLY_CLIP_OVERFLOW || r == POLY_CLIP_TOPOLOGY)
            return block_fail(b, GSN_ERR_NUMERICAL,
                              "the Voronoi cell of particle %d (%g, %g, %g) "
                              "could not be clipped (degenerate neighbours)",
                              i, x);
        if (r == POLY_CLIP_CUT)
            radius2 = gsn_poly_radius2(&w->cell);
    }

    int cell_faces = 0, r = 1;
    double v = 0.0, moment[3] = {0.0, 0.0, 0.0};
    int pieces = ctx->in->body.tetrahedron_count > 0;
    if (pieces) {
        /* absolute bounding box of the cell */
        double clo[3] = {INFINITY, INFINITY, INFINITY};
        double chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < w->cell.vertex_count; ++k)
            for (int c = 0; c < 3; ++c) {
                double z = w->cell.vertex[3 * k + c] + x[c];
                clo[c] = z < clo[c] ? z : clo[c];
                chi[c] = z > chi[c] ? z : chi[c];
            }
        int hits = cell_boundary_hits(ctx, w, i, clo, chi);
        pieces = hits > 0;
        if (pieces) {
            ++b->crossing;
            if (!in->tetrahedra_only && patch_is_convex(ctx, w, hits) &&
                cell_cut_by_patch(ctx, w, i, hits)) {
                gsn_poly_volume(&w->piece, &v, moment);
                r = emit_faces(b, &w->piece, x, in->facet_points,
                               ctx->drop_area, &cell_faces);
            } else {
                ++b->pieced;
                r = cell_emit_pieces(ctx, w, i, clo, chi, b, &v, moment,
                                     &cell_faces);
            }
        }
    }
    if (!pieces) {
        gsn_poly_volume(&w->cell, &v, moment);
        r = emit_faces(b, &w->cell, x, in->facet_points, ctx->drop_area,
                       &cell_faces);
    }
    if (r == 0)
        return block_fail(b, GSN_ERR_MEMORY,
                          "cannot allocate the facets of particle %d "
                          "(%g, %g, %g)",
                          i, x);
    if (r == -1)
        return block_fail(b, GSN_ERR_INPUT,
                          "the nodal domain of particle %d (%g, %g, %g) "
                          "reaches outside the body: the mesh boundary is "
                          "not closed",
                          i, x);
    if (r < -1)
        return block_fail(b, GSN_ERR_NUMERICAL,
                          "the nodal domain of particle %d (%g, %g, %g) "
                          "could not be intersected with the mesh",
                          i, x);
    if (!(v > 0.0))
        return block_fail(b, GSN_ERR_INPUT,
                          "the nodal domain of particle %d (%g, %g, %g) has "
                          "no volume",
                          i, x);
    *volume = v;
    for (int k = 0; k < 3; ++k)
        centroid[k] = x[k] + moment[k] / v;
    b->cell_faces[i - b->first] = cell_faces;
    return GSN_OK;
}

/* ---- duplicates -------------------------------------------------------- */

/* A particle's position with its index, sorted to find exact duplicates. */
struct sorted_point {
    double x[3];
    int index;
};

static int compare_points(const void *pa, const void *pb)
{
    const struct sorted_point *a = pa, *b = pb;
    for (int k = 0; k < 3; ++k)
        if (a->x[k] != b->x[k])
            return a->x[k] < b->x[k] ? -1 : 1;
    return a->index - b->index;
}

static int check_exact_duplicates(const double *x, int n)
{
    struct sorted_point *order = malloc(sizeof *order * (size_t)(n + 1));
    GSN_CHECK(order != NULL, GSN_ERR_MEMORY, "cannot allocate %d points", n);
    for (int i = 0; i < n; ++i) {
        memcpy(order[i].x, &x[3 * i], sizeof order[i].x);
        order[i].index = i;
    }
    qsort(order, (size_t)n, sizeof *order, compare_points);
    int a = -1, b = -1, count = 0;
    for (int k = 0; k + 1 < n; ++k) {
        const double *p = order[k].x, *q = order[k + 1].x;
        if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
            if (count++ == 0) {
                a = order[k].index;
                b = order[k + 1].index;
            }
        }
    }
    free(order);
    GSN_CHECK(count == 0, GSN_ERR_INPUT,
              "%d duplicate particles, the first: %d and %d both at "
              "(%.17g, %.17g, %.17g)",
              count, a, b, x[3 * a], x[3 * a + 1], x[3 * a + 2]);
    return GSN_OK;
}

static int check_near_duplicates(const double *x, int n, const int *offset,
                                 const int *neighbour, double tolerance)
{
    /* the nearest neighbour of a point is a Delaunay neighbour */
    for (int i = 0; i < n; ++i)
        for (int e = offset[i]; e < offset[i + 1]; ++e) {
            int j = neighbour[e];
            double d2 = 0.0;
            for (int k = 0; k < 3; ++k)
                d2 += (x[3 * i + k] - x[3 * j + k]) *
                      (x[3 * i + k] - x[3 * j + k]);
            GSN_CHECK(d2 > tolerance * tolerance, GSN_ERR_INPUT,
                      "duplicate particles: %d (%.17g, %.17g, %.17g) and %d "
                      "(%.17g, %.17g, %.17g) are %.3g m apart",
                      i, x[3 * i], x[3 * i + 1], x[3 * i + 2], j, x[3 * j],
                      x[3 * j + 1], x[3 * j + 2], sqrt(d2));
        }
    return GSN_OK;
}

/* ---- assembly ---------------------------------------------------------- */

struct cell_faces {
    const int *offset; /* n + 1 into the arrays below */
    const int *label, *points, *point_offset;
    const double *area, *normal, *point, *weight;
};

/* Sum of the areas and count of the faces of cell i labelled j. */
static void faces_toward(const struct cell_faces *c, int i, int j, double *area,
                         int *count)
{
    *area = 0.0;
    *count = 0;
    for (int f = c->offset[i]; f < c->offset[i + 1]; ++f)
        if (c->label[f] == j) {
            *area += c->area[f];
            ++*count;
        }
}

static int assemble(const struct cell_faces *c, int n, const double *volume,
                    const double *position, struct gsn_cells_result *out)
{
    int total = c->offset[n];
    char *keep = malloc((size_t)total + 1);
    GSN_CHECK(keep != NULL, GSN_ERR_MEMORY, "cannot allocate %d flags", total);
    int facets = 0, points = 0;
    double twin_error = 0.0;
    for (int i = 0; i < n; ++i) {
        double scale_i = cbrt(volume[i]) * cbrt(volume[i]);
        for (int f = c->offset[i]; f < c->offset[i + 1]; ++f) {
            int j = c->label[f];
            keep[f] = 1;
            if (j < 0)
                continue;
            /* decide once per pair, at the first face of i toward j */
            int first = 1;
            for (int g = c->offset[i]; g < f && first; ++g)
                first = c->label[g] != j;
            if (!first) {
                for (int g = c->offset[i]; g < f; ++g)
                    if (c->label[g] == j) {
                        keep[f] = keep[g];
                        break;
                    }
                continue;
            }
            double a_ij, a_ji;
            int n_ij, n_ji;
            faces_toward(c, i, j, &a_ij, &n_ij);
            faces_toward(c, j, i, &a_ji, &n_ji);
            double scale = fmin(scale_i, cbrt(volume[j]) * cbrt(volume[j]));
            double error = fabs(a_ij - a_ji) / scale;
            if (error > twin_error)
                twin_error = error;
            if (error > GSN_CELLS_TOLERANCE_TWIN) {
                free(keep);
                const double *x = &position[3 * i], *y = &position[3 * j];
                GSN_CHECK(0, GSN_ERR_INPUT,
                          "the facet of particle %d (%g, %g, %g) toward %d "
                          "(%g, %g, %g) has area %.17g but its twin %.17g "
                          "(%.3g of V^(2/3), tolerance %g)",
                          i, x[0], x[1], x[2], j, y[0], y[1], y[2], a_ij, a_ji,
                          error, GSN_CELLS_TOLERANCE_TWIN);
            }
            /* stored once: by the side with fewer pieces, else the lower */
            keep[f] = n_ji == 0 || n_ij < n_ji || (n_ij == n_ji && i < j);
        }
        for (int f = c->offset[i]; f < c->offset[i + 1]; ++f)
            if (keep[f]) {
                ++facets;
                points += c->points[f];
            }
    }
    int rc = GSN_OK;
    out->facet_count = facets;
    out->twin_error = twin_error;
    out->facet_owner = malloc(sizeof(int) * (size_t)(facets + 1));
    out->facet_neighbour = malloc(sizeof(int) * (size_t)(facets + 1));
    out->facet_surface = malloc(sizeof(int) * (size_t)(facets + 1));
    out->facet_area = malloc(sizeof(double) * (size_t)(facets + 1));
    out->facet_normal = malloc(sizeof(double) * 3 * (size_t)(facets + 1));
    out->facet_point_offset = malloc(sizeof(int) * (size_t)(facets + 1));
    out->facet_point = malloc(sizeof(double) * 3 * (size_t)(points + 1));
    out->facet_weight = malloc(sizeof(double) * (size_t)(points + 1));
    GSN_CHECK_GOTO(
        out->facet_owner && out->facet_neighbour && out->facet_surface &&
            out->facet_area && out->facet_normal && out->facet_point_offset &&
            out->facet_point && out->facet_weight,
        rc, GSN_ERR_MEMORY, done, "cannot allocate %d facets", facets);
    int k = 0, p = 0;
    out->facet_point_offset[0] = 0;
    for (int i = 0; i < n; ++i)
        for (int f = c->offset[i]; f < c->offset[i + 1]; ++f) {
            if (!keep[f])
                continue;
            int label = c->label[f];
            out->facet_owner[k] = i;
            out->facet_neighbour[k] = label >= 0 ? label : -1;
            out->facet_surface[k] =
                label >= 0 || label <= POLY_LABEL_HULL ? -1 : -1 - label;
            out->facet_area[k] = c->area[f];
            memcpy(&out->facet_normal[3 * k], &c->normal[3 * f],
                   sizeof(double[3]));
            int q0 = c->point_offset[f];
            memcpy(&out->facet_point[3 * p], &c->point[3 * q0],
                   sizeof(double) * 3 * (size_t)c->points[f]);
            memcpy(&out->facet_weight[p], &c->weight[q0],
                   sizeof(double) * (size_t)c->points[f]);
            p += c->points[f];
            out->facet_point_offset[++k] = p;
        }
done:
    free(keep);
    return rc;
}

/* ---- driver ------------------------------------------------------------ */

void gsn_cells_result_free(struct gsn_cells_result *r)
{
    free(r->volume);
    free(r->centroid);
    free(r->facet_owner);
    free(r->facet_neighbour);
    free(r->facet_surface);
    free(r->facet_area);
    free(r->facet_normal);
    free(r->facet_point_offset);
    free(r->facet_point);
    free(r->facet_weight);
    memset(r, 0, sizeof *r);
}

static void worker_free(struct worker *w)
{
    if (!w)
        return;
    free(w->order);
    free(w->distance2);
    free(w->stamp);
    free(w->stamp_triangle);
    free(w->hit);
    free(w);
}

static struct worker *worker_create(int tetrahedra, int triangles)
{
    struct worker *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->stamp = malloc(sizeof(int) * (size_t)(tetrahedra + 1));
    w->stamp_triangle = malloc(sizeof(int) * (size_t)(triangles + 1));
    w->hit = malloc(sizeof(int) * (size_t)(triangles + 1));
    if (!w->stamp || !w->stamp_triangle || !w->hit) {
        worker_free(w);
        return NULL;
    }
    for (int t = 0; t <= tetrahedra; ++t)
        w->stamp[t] = -1;
    for (int t = 0; t <= triangles; ++t)
        w->stamp_triangle[t] = -1;
    return w;
}

static int build_cells(const struct context *ctx, struct gsn_cells_result *out,
                       struct block_output *blocks, int block_count)
{
    const struct gsn_cells_input *in = ctx->in;
    int n = in->particle_count, failed = 0;
    int triangles = ctx->body ? ctx->body->triangle_count : 0;
    int threads = in->threads > 0 ? in->threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads)
    {
        struct worker *w = worker_create(in->body.tetrahedron_count, triangles);
        if (!w) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < block_count; ++k) {
            struct block_output *b = &blocks[k];
            int stop;
#pragma omp atomic read
            stop = failed;
            if (stop || !w)
                continue;
            b->first = k * BLOCK_CELLS;
            b->count = b->first + BLOCK_CELLS > n ? n - b->first : BLOCK_CELLS;
            b->cell_faces = calloc((size_t)b->count, sizeof(int));
            if (!b->cell_faces) {
                b->rc = GSN_ERR_MEMORY;
                snprintf(b->message, sizeof b->message, "out of memory");
            }
            for (int i = b->first; i < b->first + b->count && !b->rc; ++i)
                cell_build(ctx, w, i, b, &out->volume[i],
                           &out->centroid[3 * i]);
            if (b->rc) {
#pragma omp atomic write
                failed = 1;
            }
        }
        worker_free(w);
    }
    for (int k = 0; k < block_count; ++k)
        GSN_CHECK(blocks[k].rc == 0, blocks[k].rc, "%s", blocks[k].message);
    GSN_CHECK(!failed, GSN_ERR_MEMORY, "cannot allocate the cell workspace");
    return GSN_OK;
}

static int gather_blocks(const struct context *ctx, struct block_output *blocks,
                         int block_count, struct gsn_cells_result *out)
{
    int n = ctx->in->particle_count, rc = GSN_OK;
    long faces = 0, points = 0;
    for (int k = 0; k < block_count; ++k) {
        faces += blocks[k].face_count;
        points += blocks[k].point_count;
        out->crossing_count += blocks[k].crossing;
        out->pieced_count += blocks[k].pieced;
    }
    GSN_CHECK(faces < (1L << 31) - 2 && points < (1L << 31) - 2, GSN_ERR_INPUT,
              "too many facets (%ld) for 32-bit indices", faces);
    int *offset = malloc(sizeof(int) * (size_t)(n + 1));
    int *point_offset = malloc(sizeof(int) * (size_t)(faces + 1));
    int *label = malloc(sizeof(int) * (size_t)(faces + 1));
    int *count = malloc(sizeof(int) * (size_t)(faces + 1));
    double *area = malloc(sizeof(double) * (size_t)(faces + 1));
    double *normal = malloc(sizeof(double) * 3 * (size_t)(faces + 1));
    double *point = malloc(sizeof(double) * 3 * (size_t)(points + 1));
    double *weight = malloc(sizeof(double) * (size_t)(points + 1));
    GSN_CHECK_GOTO(offset && point_offset && label && count && area && normal &&
                       point && weight,
                   rc, GSN_ERR_MEMORY, done, "cannot allocate %ld faces",
                   faces);
    int f = 0, p = 0;
    offset[0] = 0;
    for (int k = 0; k < block_count; ++k) {
        const struct block_output *b = &blocks[k];
        for (int c = 0; c < b->count; ++c)
            offset[b->first + c + 1] = offset[b->first + c] + b->cell_faces[c];
        memcpy(&label[f], b->face_label, sizeof(int) * (size_t)b->face_count);
        memcpy(&count[f], b->face_points, sizeof(int) * (size_t)b->face_count);
        memcpy(&area[f], b->face_area, sizeof(double) * (size_t)b->face_count);
        memcpy(&normal[3 * f], b->face_normal,
               sizeof(double) * 3 * (size_t)b->face_count);
        memcpy(&point[3 * p], b->point,
               sizeof(double) * 3 * (size_t)b->point_count);
        memcpy(&weight[p], b->weight, sizeof(double) * (size_t)b->point_count);
        for (int g = 0; g < b->face_count; ++g) {
            point_offset[f + g] = p;
            p += b->face_points[g];
        }
        f += b->face_count;
    }
    struct cell_faces cells = {offset, label,  count, point_offset,
                               area,   normal, point, weight};
    GSN_CALL_GOTO(assemble(&cells, n, out->volume, ctx->in->position, out), rc,
                  done);
done:
    free(offset);
    free(point_offset);
    free(label);
    free(count);
    free(area);
    free(normal);
    free(point);
    free(weight);
    return rc;
}

int gsn_cells_build(const struct gsn_cells_input *in,
                    struct gsn_cells_result *out)
{
    memset(out, 0, sizeof *out);
    int n = in->particle_count, rc = GSN_OK;
    GSN_CHECK(n >= 1, GSN_ERR_INPUT, "no particles");
    GSN_CHECK(in->facet_points == 1 || in->facet_points == 3, GSN_ERR_INPUT,
              "facet_points must be 1 or 3, not %d", in->facet_points);
    double diagonal = 0.0;
    for (int k = 0; k < 3; ++k) {
        GSN_CHECK(in->hi[k] > in->lo[k], GSN_ERR_INPUT,
                  "the box is empty along axis %d: [%g, %g]", k, in->lo[k],
                  in->hi[k]);
        diagonal += (in->hi[k] - in->lo[k]) * (in->hi[k] - in->lo[k]);
    }
    diagonal = sqrt(diagonal);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double x = in->position[3 * i + k];
            GSN_CHECK(isfinite(x) && x >= in->lo[k] && x <= in->hi[k],
                      GSN_ERR_INPUT,
                      "particle %d (%g, %g, %g) is outside the box [%g, %g] "
                      "x [%g, %g] x [%g, %g]",
                      i, in->position[3 * i], in->position[3 * i + 1],
                      in->position[3 * i + 2], in->lo[0], in->hi[0], in->lo[1],
                      in->hi[1], in->lo[2], in->hi[2]);
        }
    GSN_CALL(check_exact_duplicates(in->position, n));

    double t0 = now();
    int *offset = NULL, *neighbour = NULL;
    int status = gsn_delaunay_neighbours(in->position, n, &offset, &neighbour);
    GSN_CHECK(status != GSN_DELAUNAY_MEMORY, GSN_ERR_MEMORY,
              "CGAL ran out of memory for %d points", n);
    GSN_CHECK(status != GSN_DELAUNAY_DUPLICATES, GSN_ERR_INPUT,
              "CGAL merged duplicate particles");
    GSN_CHECK(status == GSN_DELAUNAY_OK, GSN_ERR_LIBRARY,
              "CGAL's Delaunay triangulation failed on %d points", n);
    out->time_delaunay = now() - t0;
    struct body_index body;
    memset(&body, 0, sizeof body);
    int block_count = (n + BLOCK_CELLS - 1) / BLOCK_CELLS;
    struct block_output *blocks = calloc((size_t)block_count, sizeof *blocks);
    out->particle_count = n;
    out->volume = calloc((size_t)n, sizeof(double));
    out->centroid = calloc(3 * (size_t)n, sizeof(double));
    GSN_CHECK_GOTO(blocks && out->volume && out->centroid, rc, GSN_ERR_MEMORY,
                   done, "cannot allocate %d cells", n);
    GSN_CALL_GOTO(check_near_duplicates(in->position, n, offset, neighbour,
                                        DOMAIN_DUPLICATE * diagonal),
                  rc, done);
    if (in->body.tetrahedron_count > 0) {
        double spacing =
            2.0 * cbrt((in->hi[0] - in->lo[0]) * (in->hi[1] - in->lo[1]) *
                       (in->hi[2] - in->lo[2]) / n);
        GSN_CALL_GOTO(body_index_create(in, spacing, &body), rc, done);
    }
    struct context ctx = {in,
                          offset,
                          neighbour,
                          &body,
                          DOMAIN_EPS * diagonal,
                          DOMAIN_EPS * DOMAIN_EPS * diagonal * diagonal,
                          DOMAIN_EPS * DOMAIN_EPS * diagonal * diagonal,
                          DOMAIN_CONVEX * diagonal};
    t0 = now();
    GSN_CALL_GOTO(build_cells(&ctx, out, blocks, block_count), rc, done);
    GSN_CALL_GOTO(gather_blocks(&ctx, blocks, block_count, out), rc, done);
    out->time_cells = now() - t0;
done:
    for (int k = 0; blocks && k < block_count; ++k)
        block_free(&blocks[k]);
    free(blocks);
    body_index_free(&body);
    free(offset);
    free(neighbour);
    if (rc != GSN_OK)
        gsn_cells_result_free(out);
    return rc;
}

int gsn_cells_model_create(struct gsn_cells_result *r,
                           int particle_surface_entries, int surface_count,
                           int tetrahedron_count, struct gsn_model *m)
{
    int n = r->particle_count, nf = r->facet_count;
    int points = r->facet_point_offset[nf];
    GSN_CALL(gsn_model_allocate(m, n, particle_surface_entries, nf, points,
                                surface_count, tetrahedron_count));
    memcpy(m->volume, r->volume, sizeof(double) * (size_t)n);
    memcpy(m->centroid, r->centroid, sizeof(double) * 3 * (size_t)n);
    memcpy(m->facet_owner, r->facet_owner, sizeof(int) * (size_t)nf);
    memcpy(m->facet_neighbour, r->facet_neighbour, sizeof(int) * (size_t)nf);
    memcpy(m->facet_surface, r->facet_surface, sizeof(int) * (size_t)nf);
    memcpy(m->facet_area, r->facet_area, sizeof(double) * (size_t)nf);
    memcpy(m->facet_normal, r->facet_normal, sizeof(double) * 3 * (size_t)nf);
    memcpy(m->facet_point_offset, r->facet_point_offset,
           sizeof(int) * (size_t)(nf + 1));
    memcpy(m->facet_point, r->facet_point, sizeof(double) * 3 * (size_t)points);
    memcpy(m->facet_weight, r->facet_weight, sizeof(double) * (size_t)points);
    return GSN_OK;
}
