/* The body as tetrahedra whose nodes are the particles (cells.h,
 * gsn_body): checked at the current positions, and made again when some
 * have turned inside out (issue 15). The new body is the set of Delaunay
 * tetrahedra of the current positions whose centroids lie inside the old
 * body's boundary surface (its winding number, counted along a ray, so a
 * surface that has folded over itself still encloses what it did) or that
 * are small against their nodes' spacing (GSN_BODY_ALPHA), and its
 * boundary faces take the surfaces of the old boundary triangles nearest
 * to them: the boundary and its names follow the particles. */
#include "delaunay.h"
#include "geoscni/cells.h"
#include "geoscni/error.h"
#include "geoscni/tensor.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Tetrahedra of less than this share of the mean volume are flat. */
#define GSN_BODY_FLAT 1e-10
/* A Delaunay tetrahedron whose circumradius is at most this many times the
 * largest nearest-neighbour distance of its nodes is body wherever it
 * lies (an alpha shape): so is the soil that has flowed past the old
 * boundary (around a footing's corner, where the old surface is stretched
 * over it). Chosen on the deep penetration (docs/deep_penetration.md): 0.6
 * still left that soil out (B/10 rough ended at 0.65 B), 1.0 and 1.2
 * bridged the gap beside the footing (B/5 rough 0.80 and 0.73 B against
 * 1 B); 0.8: 1 B and 0.87 B. A cubic lattice's circumradius is 0.87 h. */
#define GSN_BODY_ALPHA 0.8

const int gsn_cells_tetrahedron_face[4][3] = {
    {1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

double gsn_cells_triangle_area(const double *a, const double *b,
                               const double *c)
{
    double u[3], w[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        w[k] = c[k] - a[k];
    }
    double n0 = u[1] * w[2] - u[2] * w[1], n1 = u[2] * w[0] - u[0] * w[2],
           n2 = u[0] * w[1] - u[1] * w[0];
    return 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
}

void gsn_body_free(struct gsn_body *b)
{
    free(b->tetrahedra);
    free(b->face);
    memset(b, 0, sizeof *b);
}

int gsn_body_copy(const struct gsn_body *from, struct gsn_body *to)
{
    memset(to, 0, sizeof *to);
    size_t entries = 4 * (size_t)from->tetrahedron_count;
    to->tetrahedra = malloc(sizeof(int) * (entries ? entries : 1));
    to->face = malloc(sizeof(int) * (entries ? entries : 1));
    if (!to->tetrahedra || !to->face) {
        gsn_body_free(to);
        return gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__, __func__,
                               "cannot copy %d tetrahedra",
                               from->tetrahedron_count);
    }
    memcpy(to->tetrahedra, from->tetrahedra, sizeof(int) * entries);
    memcpy(to->face, from->face, sizeof(int) * entries);
    to->tetrahedron_count = from->tetrahedron_count;
    return GSN_OK;
}

double gsn_body_tetrahedron_volume(const double *x, const int v[4])
{
    const double *a = &x[3 * v[0]];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            e[i][k] = x[3 * v[i + 1] + k] - a[k];
    return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
            e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
            e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
           6.0;
}

int gsn_body_worst(const struct gsn_body *b, const double *x, double *ratio)
{
    double total = 0.0, smallest = INFINITY;
    int worst = -1;
    for (int t = 0; t < b->tetrahedron_count; ++t) {
        double v = gsn_body_tetrahedron_volume(x, &b->tetrahedra[4 * t]);
        total += v;
        if (v < smallest) {
            smallest = v;
            worst = t;
        }
    }
    *ratio = b->tetrahedron_count > 0 && total > 0.0
                 ? smallest / (total / b->tetrahedron_count)
                 : -INFINITY;
    return worst;
}

/* ---- the old boundary: oriented triangles in bins ----------------------- */

struct boundary {
    int count;
    int *vertex; /* count x 3, outward */
    int *label;  /* count: surface index or GSN_MODEL_FACE_UNTAGGED */
    const double *x;
    double lo[3], size; /* bins: a grid of cubes of this size from lo */
    int grid[3];
    int *bin_offset, *bin_triangle;       /* 3D bins of the triangles' boxes */
    int *column_offset, *column_triangle; /* x-y columns, for the rays */
};

static void boundary_free(struct boundary *s)
{
    free(s->vertex);
    free(s->label);
    free(s->bin_offset);
    free(s->bin_triangle);
    free(s->column_offset);
    free(s->column_triangle);
    memset(s, 0, sizeof *s);
}

static void triangle_box(const struct boundary *s, int t, double lo[3],
                         double hi[3])
{
    for (int k = 0; k < 3; ++k) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            double c = s->x[3 * s->vertex[3 * t + j] + k];
            lo[k] = gsn_min(lo[k], c);
            hi[k] = gsn_max(hi[k], c);
        }
}

static int bin_coordinate(const struct boundary *s, int k, double c)
{
    int i = (int)floor((c - s->lo[k]) / s->size);
    return i < 0 ? 0 : i >= s->grid[k] ? s->grid[k] - 1 : i;
}

/* Fills CSR lists of the triangles whose boxes meet each bin (columns:
 * dimension 2, the x-y columns; else the 3D bins). */
static int bins_fill(struct boundary *s, int columns, int **offset_out,
                     int **triangle_out)
{
    size_t bins = (size_t)s->grid[0] * (size_t)s->grid[1] *
                  (size_t)(columns ? 1 : s->grid[2]);
    int *offset = calloc(bins + 1, sizeof(int));
    GSN_CHECK(offset, GSN_ERR_MEMORY, "cannot allocate %zu bins", bins);
    int *triangle = NULL;
    for (int pass = 0; pass < 2; ++pass) {
        for (int t = 0; t < s->count; ++t) {
            double lo[3], hi[3];
            triangle_box(s, t, lo, hi);
            int a[3], b[3];
            for (int k = 0; k < 3; ++k) {
                a[k] = bin_coordinate(s, k, lo[k]);
                b[k] = bin_coordinate(s, k, hi[k]);
            }
            if (columns)
                a[2] = b[2] = 0;
            for (int i = a[0]; i <= b[0]; ++i)
                for (int j = a[1]; j <= b[1]; ++j)
                    for (int k = a[2]; k <= b[2]; ++k) {
                        size_t bin =
                            ((size_t)k * (size_t)s->grid[1] + (size_t)j) *
                                (size_t)s->grid[0] +
                            (size_t)i;
                        if (pass == 0)
                            offset[bin + 1]++;
                        else
                            triangle[offset[bin]++] = t;
                    }
        }
        if (pass == 0) {
            for (size_t i = 0; i < bins; ++i)
                offset[i + 1] += offset[i];
            triangle = malloc(sizeof(int) * (size_t)(offset[bins] + 1));
            if (!triangle) {
                free(offset);
                return gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__,
                                       __func__, "cannot allocate the bins");
            }
        }
    }
    for (size_t i = bins; i > 0; --i) /* the fill moved each start on */
        offset[i] = offset[i - 1];
    offset[0] = 0;
    *offset_out = offset;
    *triangle_out = triangle;
    return GSN_OK;
}

static int boundary_create(const struct gsn_body *b, const double *x,
                           int particle_count, struct boundary *s)
{
    memset(s, 0, sizeof *s);
    s->x = x;
    int count = 0;
    for (int f = 0; f < 4 * b->tetrahedron_count; ++f)
        count += b->face[f] != GSN_MODEL_FACE_INTERNAL;
    GSN_CHECK(count > 0, GSN_ERR_INPUT, "the body has no boundary");
    s->vertex = malloc(sizeof(int) * 3 * (size_t)count);
    s->label = malloc(sizeof(int) * (size_t)count);
    GSN_CHECK(s->vertex && s->label, GSN_ERR_MEMORY,
              "cannot allocate %d boundary triangles", count);
    for (int f = 0; f < 4 * b->tetrahedron_count; ++f) {
        if (b->face[f] == GSN_MODEL_FACE_INTERNAL)
            continue;
        const int *v = &b->tetrahedra[4 * (f / 4)];
        for (int j = 0; j < 3; ++j)
            s->vertex[3 * s->count + j] =
                v[gsn_cells_tetrahedron_face[f % 4][j]];
        s->label[s->count++] = b->face[f];
    }
    double hi[3], area = 0.0;
    for (int k = 0; k < 3; ++k) {
        s->lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int i = 0; i < particle_count; ++i)
        for (int k = 0; k < 3; ++k) {
            s->lo[k] = fmin(s->lo[k], x[3 * i + k]);
            hi[k] = fmax(hi[k], x[3 * i + k]);
        }
    for (int t = 0; t < s->count; ++t)
        area += gsn_cells_triangle_area(&x[3 * s->vertex[3 * t]],
                                        &x[3 * s->vertex[3 * t + 1]],
                                        &x[3 * s->vertex[3 * t + 2]]);
    /* bins of about two triangles across, at most 1024 a direction */
    s->size = 2.0 * sqrt(2.0 * area / s->count) + 1e-300;
    for (int k = 0; k < 3; ++k)
        s->size = fmax(s->size, (hi[k] - s->lo[k]) / 1024.0);
    for (int k = 0; k < 3; ++k)
        s->grid[k] = (int)fmax(ceil((hi[k] - s->lo[k]) / s->size), 1.0);
    GSN_CALL(bins_fill(s, 1, &s->column_offset, &s->column_triangle));
    GSN_CALL(bins_fill(s, 0, &s->bin_offset, &s->bin_triangle));
    return GSN_OK;
}

/* Twice the signed area of (a, b, p) in the x-y plane. */
static double edge_function(const double *a, const double *b, const double *p)
{
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

/* Whether p lies on the edge a -> b of a counter-clockwise triangle in the
 * way that counts it inside: the top-left rule, so that a ray through an
 * edge shared by two triangles crosses exactly one of them. */
static int edge_inside(const double *a, const double *b, const double *p)
{
    double e = edge_function(a, b, p);
    if (e != 0.0)
        return e > 0.0;
    double dx = b[0] - a[0], dy = b[1] - a[1];
    return dy < 0.0 || (dy == 0.0 && dx > 0.0);
}

/* The winding number of the boundary around p: the signed crossings of
 * the ray from p along +z (+1 where it leaves through an outward face). */
static int winding(const struct boundary *s, const double *p)
{
    int i = bin_coordinate(s, 0, p[0]), j = bin_coordinate(s, 1, p[1]);
    size_t column = (size_t)j * (size_t)s->grid[0] + (size_t)i;
    int sum = 0;
    for (int e = s->column_offset[column]; e < s->column_offset[column + 1];
         ++e) {
        int t = s->column_triangle[e];
        const double *a = &s->x[3 * s->vertex[3 * t]];
        const double *b = &s->x[3 * s->vertex[3 * t + 1]];
        const double *c = &s->x[3 * s->vertex[3 * t + 2]];
        double area = edge_function(a, b, c);
        if (area == 0.0)
            continue; /* seen edge-on: the ray grazes it */
        int sign = area > 0.0 ? 1 : -1;
        if (sign < 0) { /* counter-clockwise for the edge rule */
            const double *swap = b;
            b = c;
            c = swap;
        }
        if (!edge_inside(a, b, p) || !edge_inside(b, c, p) ||
            !edge_inside(c, a, p))
            continue;
        double la = edge_function(b, c, p), lb = edge_function(c, a, p),
               lc = edge_function(a, b, p), total = la + lb + lc;
        double z = (la * a[2] + lb * b[2] + lc * c[2]) / total;
        if (z > p[2])
            sum += sign;
    }
    return sum;
}

/* Squared distance from p to triangle t. */
static double triangle_distance2(const struct boundary *s, int t,
                                 const double *p)
{
    const double *a = &s->x[3 * s->vertex[3 * t]];
    const double *b = &s->x[3 * s->vertex[3 * t + 1]];
    const double *c = &s->x[3 * s->vertex[3 * t + 2]];
    double ab[3], ac[3], ap[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
    }
    double d00 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double d01 = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
    double d11 = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
    double d20 = ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2];
    double d21 = ap[0] * ac[0] + ap[1] * ac[1] + ap[2] * ac[2];
    double det = d00 * d11 - d01 * d01;
    double u = 0.0, v = 0.0;
    if (det > 0.0) {
        u = (d11 * d20 - d01 * d21) / det;
        v = (d00 * d21 - d01 * d20) / det;
    }
    if (!(u >= 0.0 && v >= 0.0 && u + v <= 1.0)) {
        /* outside the triangle: the nearest of its three edges */
        const double *ends[3][2] = {{a, b}, {b, c}, {c, a}};
        double best = INFINITY;
        for (int e = 0; e < 3; ++e) {
            const double *q = ends[e][0], *r = ends[e][1];
            double qr[3], qp[3], len = 0.0, dot = 0.0;
            for (int k = 0; k < 3; ++k) {
                qr[k] = r[k] - q[k];
                qp[k] = p[k] - q[k];
                len += qr[k] * qr[k];
                dot += qr[k] * qp[k];
            }
            double f = len > 0.0 ? gsn_min(gsn_max(dot / len, 0.0), 1.0) : 0.0;
            double d = 0.0;
            for (int k = 0; k < 3; ++k)
                d += (qp[k] - f * qr[k]) * (qp[k] - f * qr[k]);
            best = gsn_min(best, d);
        }
        return best;
    }
    double d = 0.0;
    for (int k = 0; k < 3; ++k) {
        double q = ap[k] - u * ab[k] - v * ac[k];
        d += q * q;
    }
    return d;
}

/* The label of the boundary triangle nearest to p: the bins around p, in
 * growing shells until the nearest found is nearer than the shell. */
static int nearest_label(const struct boundary *s, const double *p)
{
    int centre[3];
    for (int k = 0; k < 3; ++k)
        centre[k] = bin_coordinate(s, k, p[k]);
    int grid_max = s->grid[0] > s->grid[1] ? s->grid[0] : s->grid[1];
    grid_max = grid_max > s->grid[2] ? grid_max : s->grid[2];
    double best = INFINITY;
    int label = GSN_MODEL_FACE_UNTAGGED;
    for (int shell = 0; shell <= grid_max; ++shell) {
        for (int i = centre[0] - shell; i <= centre[0] + shell; ++i)
            for (int j = centre[1] - shell; j <= centre[1] + shell; ++j)
                for (int k = centre[2] - shell; k <= centre[2] + shell; ++k) {
                    if (i < 0 || j < 0 || k < 0 || i >= s->grid[0] ||
                        j >= s->grid[1] || k >= s->grid[2])
                        continue;
                    int on_shell = abs(i - centre[0]) == shell ||
                                   abs(j - centre[1]) == shell ||
                                   abs(k - centre[2]) == shell;
                    if (!on_shell)
                        continue;
                    size_t bin = ((size_t)k * (size_t)s->grid[1] + (size_t)j) *
                                     (size_t)s->grid[0] +
                                 (size_t)i;
                    for (int e = s->bin_offset[bin]; e < s->bin_offset[bin + 1];
                         ++e) {
                        int t = s->bin_triangle[e];
                        double d = triangle_distance2(s, t, p);
                        if (d < best || (d == best && s->label[t] < label)) {
                            best = d;
                            label = s->label[t];
                        }
                    }
                }
        /* every triangle not yet seen lies wholly outside the bins seen
         * (a triangle is in every bin its box meets), so at least as far
         * from p as the nearest face of those bins inside the grid */
        double margin = INFINITY;
        for (int k = 0; k < 3; ++k) {
            if (centre[k] - shell > 0)
                margin = gsn_min(
                    margin, p[k] - (s->lo[k] + (centre[k] - shell) * s->size));
            if (centre[k] + shell + 1 < s->grid[k])
                margin = gsn_min(margin, s->lo[k] +
                                             (centre[k] + shell + 1) * s->size -
                                             p[k]);
        }
        if (best < margin * margin)
            break;
    }
    return label;
}

/* The radius of the sphere through the nodes v of a tetrahedron. */
static double circumradius(const double *x, const int v[4])
{
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = x[3 * v[1] + k] - x[3 * v[0] + k];
        b[k] = x[3 * v[2] + k] - x[3 * v[0] + k];
        c[k] = x[3 * v[3] + k] - x[3 * v[0] + k];
    }
    double bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0]},
           ca[3] = {c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2],
                    c[0] * a[1] - c[1] * a[0]},
           ab[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0]};
    double aa = a[0] * a[0] + a[1] * a[1] + a[2] * a[2],
           bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2],
           cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    double det = 2.0 * (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]), r2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double o = (aa * bc[k] + bb * ca[k] + cc * ab[k]) / det;
        r2 += o * o;
    }
    return sqrt(r2);
}

/* Each particle's distance to its nearest neighbour: the shortest
 * Delaunay edge at it (the nearest neighbour is always a Delaunay one). */
static void nearest_distances(const double *x, int particle_count,
                              const int *tetrahedra, int count, double *nearest)
{
    for (int i = 0; i < particle_count; ++i)
        nearest[i] = INFINITY;
    for (int t = 0; t < count; ++t)
        for (int j = 0; j < 4; ++j)
            for (int l = j + 1; l < 4; ++l) {
                int p = tetrahedra[4 * t + j], q = tetrahedra[4 * t + l];
                double d = 0.0;
                for (int k = 0; k < 3; ++k)
                    d += (x[3 * p + k] - x[3 * q + k]) *
                         (x[3 * p + k] - x[3 * q + k]);
                d = sqrt(d);
                nearest[p] = gsn_min(nearest[p], d);
                nearest[q] = gsn_min(nearest[q], d);
            }
}

int gsn_body_remesh(const struct gsn_body *old, const double *x,
                    int particle_count, struct gsn_body *out)
{
    memset(out, 0, sizeof *out);
    struct boundary s;
    int count = 0, *tetrahedra = NULL, *neighbour = NULL;
    char *inside = NULL;
    double *nearest = NULL;
    int rc = GSN_OK;
    GSN_CALL(boundary_create(old, x, particle_count, &s));
    int status = gsn_delaunay_tetrahedra(x, particle_count, &count, &tetrahedra,
                                         &neighbour);
    GSN_CHECK_GOTO(status != GSN_DELAUNAY_MEMORY, rc, GSN_ERR_MEMORY, done,
                   "CGAL ran out of memory for %d points", particle_count);
    GSN_CHECK_GOTO(status == GSN_DELAUNAY_OK, rc, GSN_ERR_NUMERICAL, done,
                   "CGAL could not triangulate the %d particles' current "
                   "positions (%s)",
                   particle_count,
                   status == GSN_DELAUNAY_DUPLICATES
                       ? "two particles are at one place"
                   : status == GSN_DELAUNAY_FLAT ? "they span no volume"
                                                 : "CGAL failed");
    inside = malloc((size_t)count + 1);
    GSN_CHECK_GOTO(inside, rc, GSN_ERR_MEMORY, done, "cannot allocate %d flags",
                   count);
    double total = 0.0;
    for (int t = 0; t < count; ++t)
        total += gsn_body_tetrahedron_volume(x, &tetrahedra[4 * t]);
    /* flat ones (nearly coplanar particles, on a plane face most often)
     * hold no volume and no cell needs them */
    double flat = GSN_BODY_FLAT * total / count;
    nearest = malloc(sizeof(double) * ((size_t)particle_count + 1));
    GSN_CHECK_GOTO(nearest, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %d distances", particle_count);
    nearest_distances(x, particle_count, tetrahedra, count, nearest);
    int kept = 0;
#pragma omp parallel for reduction(+ : kept)
    for (int t = 0; t < count; ++t) {
        const int *v = &tetrahedra[4 * t];
        double c[3] = {0.0, 0.0, 0.0}, local = 0.0;
        for (int j = 0; j < 4; ++j) {
            for (int k = 0; k < 3; ++k)
                c[k] += 0.25 * x[3 * v[j] + k];
            local = fmax(local, nearest[v[j]]);
        }
        inside[t] = gsn_body_tetrahedron_volume(x, v) > flat &&
                    (circumradius(x, v) <= GSN_BODY_ALPHA * local ||
                     winding(&s, c) > 0);
        kept += inside[t];
    }
    GSN_CHECK_GOTO(kept > 0, rc, GSN_ERR_NUMERICAL, done,
                   "no tetrahedron of the particles' current positions lies "
                   "inside the body");
    out->tetrahedra = malloc(sizeof(int) * 4 * (size_t)kept);
    out->face = malloc(sizeof(int) * 4 * (size_t)kept);
    GSN_CHECK_GOTO(out->tetrahedra && out->face, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %d tetrahedra", kept);
    for (int t = 0; t < count; ++t)
        if (inside[t]) {
            memcpy(&out->tetrahedra[4 * out->tetrahedron_count],
                   &tetrahedra[4 * t], 4 * sizeof(int));
            for (int k = 0; k < 4; ++k) {
                int other = neighbour[4 * t + k];
                out->face[4 * out->tetrahedron_count + k] =
                    other >= 0 && inside[other] ? GSN_MODEL_FACE_INTERNAL
                                                : GSN_MODEL_FACE_UNTAGGED;
            }
            out->tetrahedron_count++;
        }
        /* the boundary faces take the surface of the nearest old triangle */
#pragma omp parallel for
    for (int f = 0; f < 4 * out->tetrahedron_count; ++f) {
        if (out->face[f] == GSN_MODEL_FACE_INTERNAL)
            continue;
        const int *v = &out->tetrahedra[4 * (f / 4)];
        double c[3] = {0.0, 0.0, 0.0};
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                c[k] +=
                    x[3 * v[gsn_cells_tetrahedron_face[f % 4][j]] + k] / 3.0;
        out->face[f] = nearest_label(&s, c);
    }
done:
    if (rc != GSN_OK)
        gsn_body_free(out);
    boundary_free(&s);
    free(inside);
    free(nearest);
    free(tetrahedra);
    free(neighbour);
    return rc;
}

int gsn_body_of_points(const double *x, int particle_count,
                       struct gsn_body *out)
{
    memset(out, 0, sizeof *out);
    int count = 0, *neighbour = NULL;
    int status = gsn_delaunay_tetrahedra(x, particle_count, &count,
                                         &out->tetrahedra, &neighbour);
    GSN_CHECK(status != GSN_DELAUNAY_MEMORY, GSN_ERR_MEMORY,
              "CGAL ran out of memory for %d points", particle_count);
    GSN_CHECK(status == GSN_DELAUNAY_OK, GSN_ERR_INPUT,
              "CGAL could not triangulate %d points", particle_count);
    out->tetrahedron_count = count;
    out->face = neighbour; /* relabelled in place */
    for (int f = 0; f < 4 * count; ++f)
        out->face[f] = out->face[f] >= 0 ? GSN_MODEL_FACE_INTERNAL
                                         : GSN_MODEL_FACE_UNTAGGED;
    return GSN_OK;
}
