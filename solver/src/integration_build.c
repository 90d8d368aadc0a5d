/* Integration of the weak form on the reference configuration: SCNI
 * (smoothed gradients, seed paper eqs. (19)-(20)), DNI (gradients at the
 * particles), Gauss quadrature on background cells, and the modified-SCNI
 * stabilization; all produce one struct gsn_quadrature (geoscni/kernels.h,
 * docs/kernels.md). */
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "kernel_rows.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void gsn_kernel_options_from_case(const struct gsn_case *c,
                                  struct gsn_kernel_options *options)
{
    options->support = c->kernel_support;
    options->basis_order = c->kernel_basis_order;
    options->integration = c->integration;
    options->gauss_points = c->gauss_points;
    options->stabilization = c->stabilization;
    options->stabilization_coefficient = c->stabilization_coefficient;
    options->stabilization_subcells = GSN_DEFAULT_STABILIZATION_SUBCELLS;
    options->cover_neighbours = 0;
    options->held_facet = options->held_particle = NULL;
    options->window_cut = c->kernel_window_cut;
}

void gsn_quadrature_destroy(struct gsn_quadrature **q)
{
    if (!q || !*q)
        return;
    struct gsn_quadrature *p = *q;
    free(p->point_weight);
    free(p->point_position);
    free(p->point_particle);
    gsn_shape_rows_free(&p->gradient);
    gsn_shape_rows_free(&p->particle_values);
    free(p->boundary_point_facet);
    free(p->boundary_point_position);
    free(p->boundary_point_weight);
    gsn_shape_rows_free(&p->boundary_values);
    gsn_rk_destroy(&p->rk);
    free(p);
    *q = NULL;
}

static size_t rows_bytes(const struct gsn_shape_rows *r)
{
    if (!r->offset)
        return 0;
    size_t nnz = (size_t)r->offset[r->row_count];
    return (size_t)(r->row_count + 1) * sizeof(int) + nnz * sizeof(int) +
           (r->value ? nnz * sizeof(double) : 0) +
           (r->gradient ? 3 * nnz * sizeof(double) : 0);
}

size_t gsn_quadrature_bytes(const struct gsn_quadrature *q)
{
    size_t np = (size_t)q->point_count, nb = (size_t)q->boundary_point_count;
    return np * (4 * sizeof(double) + sizeof(int)) + rows_bytes(&q->gradient) +
           rows_bytes(&q->particle_values) +
           nb * (4 * sizeof(double) + sizeof(int)) +
           rows_bytes(&q->boundary_values);
}

/* ---- SCNI: eq. (20) per particle from its facets ------------------------ */

/* The interpolant on held facets (gsn_kernel_options.held_facet): boundary
 * point b's Psi_I is sum_k weight_k Psi_I(X_particle_k) over its stencil
 * [offset[b], offset[b + 1]), empty where Psi_I itself is used. */
struct held_stencils {
    int *offset; /* boundary points + 1 */
    int *particle;
    double *weight;
    int *facet_point; /* per facet: its first boundary point, or -1 */
};

struct facet_context {
    const struct gsn_model *m;
    const struct gsn_rk *rk;
    const int *particle_facet_offset; /* facets of each particle, ascending */
    const int *particle_facet;
    const struct gsn_shape_rows *nodal;  /* B_L rows (MSCNI) */
    int subcells;                        /* MSCNI: 2 or 6 */
    const struct held_stencils *held;    /* NULL: none */
    const struct gsn_shape_rows *values; /* Psi_I(X_J), rows J */
};

static int compare_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Adds v (3) to the dense accumulator of particle i. */
static inline void accumulate(struct kernel_thread *t, int *touched_count,
                              int i, const double *v)
{
    if (!t->mark[i]) {
        t->mark[i] = 1;
        t->touched[(*touched_count)++] = i;
    }
    for (int k = 0; k < 3; ++k)
        t->dense[3 * (size_t)i + k] += v[k];
}

/* Writes the touched entries in ascending order (scaled by scale) and
 * clears the accumulator. */
static int flush(struct kernel_thread *t, int touched_count, double scale)
{
    gsn_sort_ints(t->touched, touched_count);
    int failed = 0;
    for (int e = 0; e < touched_count; ++e) {
        int i = t->touched[e];
        double *d = t->dense + 3 * (size_t)i;
        double g[3] = {d[0] * scale, d[1] * scale, d[2] * scale};
        failed |= kernel_row_push(t, i, 0.0, g);
        d[0] = d[1] = d[2] = 0.0;
        t->mark[i] = 0;
    }
    return failed;
}

/* The facets' sum of scni_row into the accumulator of t (*touched). */
static int scni_row_facets(const struct facet_context *c, int L,
                           struct kernel_thread *t, int points, int *touched)
{
    const struct gsn_model *m = c->m;
    for (int e = c->particle_facet_offset[L];
         e < c->particle_facet_offset[L + 1]; ++e) {
        int f = c->particle_facet[e];
        double sign = m->facet_owner[f] == L ? 1.0 : -1.0;
        int other =
            m->facet_owner[f] == L ? m->facet_neighbour[f] : m->facet_owner[f];
        const double *normal = m->facet_normal + 3 * (size_t)f;
        int b0 = c->held ? c->held->facet_point[f] : -1;
        for (int q = m->facet_point_offset[f]; q < m->facet_point_offset[f + 1];
             ++q) {
            int b = b0 < 0 ? -1 : b0 + q - m->facet_point_offset[f];
            if (b >= 0 && c->held->offset[b + 1] > c->held->offset[b]) {
                /* a held facet: the interpolant of Psi_I (held_stencils) */
                double w = sign * m->facet_weight[q];
                for (int k = c->held->offset[b]; k < c->held->offset[b + 1];
                     ++k) {
                    int J = c->held->particle[k];
                    double a = c->held->weight[k] * w;
                    for (int r = c->values->offset[J];
                         r < c->values->offset[J + 1]; ++r) {
                        double v[3] = {c->values->value[r] * normal[0] * a,
                                       c->values->value[r] * normal[1] * a,
                                       c->values->value[r] * normal[2] * a};
                        accumulate(t, touched, c->values->index[r], v);
                    }
                }
                continue;
            }
            /* an interior facet's point is evaluated once for both its
             * cells when both rows fall in one chunk (kernel_rows.h) */
            const int *index = t->index;
            const double *psi = t->psi;
            int count = kernel_cache_find(t, points, L, q, &index, &psi);
            if (count < 0) {
                int rc = kernel_evaluate(c->rk, m->facet_point + 3 * (size_t)q,
                                         0, t, &count, "facet point", q);
                if (rc != GSN_OK)
                    return rc;
                if (other > L &&
                    other / KERNEL_ROWS_CHUNK == L / KERNEL_ROWS_CHUNK)
                    kernel_cache_keep(t, q, count);
                index = t->index;
                psi = t->psi;
            }
            double w = sign * m->facet_weight[q];
            for (int n = 0; n < count; ++n) {
                double v[3] = {psi[n] * normal[0] * w, psi[n] * normal[1] * w,
                               psi[n] * normal[2] * w};
                accumulate(t, touched, index[n], v);
            }
        }
    }
    return GSN_OK;
}

/* Row L: (1/V_L) sum over the facets of L of sum_q Psi_I(x_q) N w_q, with
 * N outward from L (the neighbour side uses the owner's points with the
 * opposite normal, so interior facets cancel exactly: eq. (24)). */
static int scni_row(void *context, int L, struct kernel_thread *t)
{
    const struct facet_context *c = context;
    const struct gsn_model *m = c->m;
    const int points = m->facet_point_offset[m->facet_count];
    int touched = 0;
    /* the particles covering any facet point of the cell, found once: each
     * point then looks among them (the same neighbours, in the same order,
     * as a search of its own) */
    double lo[3] = {INFINITY, INFINITY, INFINITY};
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int e = c->particle_facet_offset[L];
         e < c->particle_facet_offset[L + 1]; ++e) {
        int f = c->particle_facet[e];
        for (int q = m->facet_point_offset[f]; q < m->facet_point_offset[f + 1];
             ++q)
            for (int k = 0; k < 3; ++k) {
                double x = m->facet_point[3 * (size_t)q + k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
    }
    if (lo[0] <= hi[0]) {
        int found = gsn_rk_box_neighbours(c->rk, lo, hi, GSN_RK_MAX_NEIGHBOURS,
                                          t->candidate);
        t->candidate_count = found <= GSN_RK_MAX_NEIGHBOURS ? found : -1;
    }
    int rc = scni_row_facets(c, L, t, points, &touched);
    t->candidate_count = -1;
    if (rc != GSN_OK)
        return rc;
    if (flush(t, touched, 1.0 / m->volume[L])) {
        snprintf(t->message, sizeof t->message, "out of memory at row %d", L);
        return GSN_ERR_MEMORY;
    }
    return GSN_OK;
}

/* ---- MSCNI: sub-cell gradients ------------------------------------------
 * The cell of L is split into pyramids with apex X_L over its facets
 * (volume h A / 3, h the height of X_L over the facet; they add up to V_L
 * when the cell is star-shaped from X_L; pyramids of no or negative volume
 * are left out, the stabilization only needs positive weights). Pyramids
 * are grouped by the dominant direction of their outward normal (+x, -x,
 * +y, -y, +z, -z: six sub-cells; or its sign only: two). The gradient of
 * sub-cell s is grad Psi at the volume centroid of its pyramids (each
 * pyramid's centroid is apex + 3/4 (facet centroid - apex)); one
 * evaluation per sub-cell. Linear completeness of grad Psi
 * (eq. (18)) makes B_s - B_L vanish on every linear field, so the
 * stabilization keeps the patch test exact, while a checkerboard, invisible
 * to B_L, has B_s != 0. Row S L + s holds B_s - B_L. */

static void pyramid(const struct gsn_model *m, int f, int L, double sign,
                    int subcells, double *volume, double *centroid, int *group)
{
    double area = 0.0, c[3] = {0, 0, 0};
    for (int q = m->facet_point_offset[f]; q < m->facet_point_offset[f + 1];
         ++q) {
        area += m->facet_weight[q];
        for (int k = 0; k < 3; ++k)
            c[k] += m->facet_weight[q] * m->facet_point[3 * (size_t)q + k];
    }
    const double *x = m->position + 3 * (size_t)L;
    const double *nf = m->facet_normal + 3 * (size_t)f;
    double height = 0.0;
    int axis = 0;
    for (int k = 0; k < 3; ++k) {
        c[k] = area > 0.0 ? c[k] / area : x[k];
        height += sign * nf[k] * (c[k] - x[k]);
        if (fabs(nf[k]) > fabs(nf[axis]))
            axis = k;
    }
    *volume = height * area / 3.0;
    for (int k = 0; k < 3; ++k)
        centroid[k] = x[k] + 0.75 * (c[k] - x[k]);
    *group = subcells == 6 ? 2 * axis + (sign * nf[axis] < 0.0)
                           : (sign * nf[axis] < 0.0);
}

/* The sub-cells of particle L's nodal domain: the pyramids from X_L over
 * its facets, grouped (pyramid); their volumes v (m^3) and first moments
 * x (sum of volume times centroid). Pyramids of facets through X_L have
 * no volume and are left out. */
static void subcell_pyramids(const struct gsn_model *m,
                             const struct facet_context *c, int L, double v[6],
                             double x[6][3])
{
    for (int e = c->particle_facet_offset[L];
         e < c->particle_facet_offset[L + 1]; ++e) {
        int f = c->particle_facet[e], group;
        double sign = m->facet_owner[f] == L ? 1.0 : -1.0;
        double volume, centroid[3];
        pyramid(m, f, L, sign, c->subcells, &volume, centroid, &group);
        if (!(volume > 1e-12 * m->volume[L]))
            continue;
        v[group] += volume;
        for (int k = 0; k < 3; ++k)
            x[group][k] += volume * centroid[k];
    }
}

static int mscni_row(void *context, int row, struct kernel_thread *t)
{
    const struct facet_context *c = context;
    int L = row / c->subcells, s = row % c->subcells, touched = 0;
    double volume[6] = {0}, moment[6][3] = {{0}};
    subcell_pyramids(c->m, c, L, volume, moment);
    if (volume[s] > 0.0) {
        /* B_s: grad Psi at the centroid of the sub-cell's pyramids */
        double point[3];
        for (int k = 0; k < 3; ++k)
            point[k] = moment[s][k] / volume[s];
        int count;
        int rc =
            kernel_evaluate(c->rk, point, 1, t, &count, "sub-cell point", row);
        if (rc != GSN_OK)
            return rc;
        for (int n = 0; n < count; ++n)
            accumulate(t, &touched, t->index[n], t->gradient + 3 * n);
        /* minus B_L */
        const struct gsn_shape_rows *b = c->nodal;
        for (int e = b->offset[L]; e < b->offset[L + 1]; ++e) {
            double v[3] = {-b->gradient[3 * (size_t)e],
                           -b->gradient[3 * (size_t)e + 1],
                           -b->gradient[3 * (size_t)e + 2]};
            accumulate(t, &touched, b->index[e], v);
        }
    }
    if (flush(t, touched, 1.0)) {
        snprintf(t->message, sizeof t->message, "out of memory at row %d", row);
        return GSN_ERR_MEMORY;
    }
    return GSN_OK;
}

static void mscni_weights(const struct gsn_model *m,
                          const struct facet_context *c, double coefficient,
                          double *weight, double *position)
{
#pragma omp parallel for schedule(static)
    for (int L = 0; L < m->particle_count; ++L) {
        double v[6] = {0}, x[6][3] = {{0}};
        subcell_pyramids(m, c, L, v, x);
        for (int s = 0; s < c->subcells; ++s) {
            size_t p = c->subcells * (size_t)L + (size_t)s;
            weight[p] = coefficient * v[s];
            for (int k = 0; k < 3; ++k)
                position[3 * p + k] = v[s] > 0.0
                                          ? x[s][k] / v[s]
                                          : m->position[3 * (size_t)L + k];
        }
    }
}

/* ---- Gauss on background cells ----------------------------------------- */

/* Gauss-Legendre on [0, 1]: n points and weights, n = 1..6. */
static int gauss_rule(int n, double *x, double *w)
{
    static const double t[6][6] = {
        {0.0},
        {-0.5773502691896257645, 0.5773502691896257645},
        {-0.7745966692414833770, 0.0, 0.7745966692414833770},
        {-0.8611363115940525752, -0.3399810435848562648, 0.3399810435848562648,
         0.8611363115940525752},
        {-0.9061798459386639928, -0.5384693101056830910, 0.0,
         0.5384693101056830910, 0.9061798459386639928},
        {-0.9324695142031520279, -0.6612093864662645137, -0.2386191860831969086,
         0.2386191860831969086, 0.6612093864662645137, 0.9324695142031520279}};
    static const double u[6][6] = {
        {2.0},
        {1.0, 1.0},
        {0.5555555555555555556, 0.8888888888888888889, 0.5555555555555555556},
        {0.3478548451374538574, 0.6521451548625461426, 0.6521451548625461426,
         0.3478548451374538574},
        {0.2369268850561890875, 0.4786286704993664680, 0.5688888888888888889,
         0.4786286704993664680, 0.2369268850561890875},
        {0.1713244923791703450, 0.3607615730481386076, 0.4679139345726910473,
         0.4679139345726910473, 0.3607615730481386076, 0.1713244923791703450}};
    if (n < 1 || n > 6)
        return 1;
    for (int i = 0; i < n; ++i) {
        x[i] = 0.5 * (t[n - 1][i] + 1.0);
        w[i] = 0.5 * u[n - 1][i];
    }
    return 0;
}

/* Trilinear map of a hexahedron (vertex (i,j,k) at i + 2j + 4k): position
 * and |det J| at reference point r in [0,1]^3. */
static void hex_map(const double *v, const double *r, double *x, double *det)
{
    double jac[3][3] = {{0}};
    for (int k = 0; k < 3; ++k)
        x[k] = 0.0;
    for (int a = 0; a < 8; ++a) {
        int b[3] = {a & 1, (a >> 1) & 1, (a >> 2) & 1};
        double f[3], df[3];
        for (int d = 0; d < 3; ++d) {
            f[d] = b[d] ? r[d] : 1.0 - r[d];
            df[d] = b[d] ? 1.0 : -1.0;
        }
        double n = f[0] * f[1] * f[2];
        double dn[3] = {df[0] * f[1] * f[2], f[0] * df[1] * f[2],
                        f[0] * f[1] * df[2]};
        for (int k = 0; k < 3; ++k) {
            x[k] += n * v[3 * a + k];
            for (int d = 0; d < 3; ++d)
                jac[k][d] += dn[d] * v[3 * a + k];
        }
    }
    *det = fabs(jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1]) -
                jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0]) +
                jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0]));
}

/* A tetrahedron (a, b, c, d) as the collapsed hexahedron a, b, c, c, d, d,
 * d, d (Duffy): barycentric b = r0 (1-r1)(1-r2), c = r1 (1-r2), d = r2. */
static void tet_as_hex(const struct gsn_model *m, int t, double *v)
{
    const int *tet = m->tetrahedra + 4 * (size_t)t;
    const int corner[8] = {0, 1, 2, 2, 3, 3, 3, 3};
    for (int a = 0; a < 8; ++a)
        for (int k = 0; k < 3; ++k)
            v[3 * a + k] = m->position[3 * (size_t)tet[corner[a]] + k];
}

static int gauss_points(const struct gsn_model *m, int n,
                        const double *background, int cell_count,
                        double **position, double **weight, int *count)
{
    double r[6], w[6];
    GSN_CHECK(gauss_rule(n, r, w) == 0, GSN_ERR_INPUT,
              "gauss_points %d: only 1 to 6 per direction", n);
    /* The collapsed hexahedron's det J is quadratic along one axis: one
     * point gives it at the centre, 3/4 of the tetrahedron's volume. */
    GSN_CHECK(background || n >= 2, GSN_ERR_INPUT,
              "integration.points 1 on tetrahedra: one Gauss point per "
              "direction integrates 3/4 of each tetrahedron's volume; use 2 "
              "or more");
    if (!background)
        cell_count = m->tetrahedron_count;
    GSN_CHECK(cell_count > 0, GSN_ERR_INPUT,
              "Gauss integration needs background cells (the model has no "
              "tetrahedra)");
    size_t per = (size_t)n * n * n, total = per * (size_t)cell_count;
    GSN_CHECK(total < 2147483647u, GSN_ERR_INPUT, "too many Gauss points");
    *position = malloc(3 * total * sizeof **position);
    *weight = malloc(total * sizeof **weight);
    GSN_CHECK(*position && *weight, GSN_ERR_MEMORY,
              "cannot allocate %zu Gauss points", total);
#pragma omp parallel for schedule(static)
    for (int c = 0; c < cell_count; ++c) {
        double v[24];
        if (background)
            memcpy(v, background + 24 * (size_t)c, sizeof v);
        else
            tet_as_hex(m, c, v);
        size_t p = per * (size_t)c;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i, ++p) {
                    double ref[3] = {r[i], r[j], r[k]}, det;
                    hex_map(v, ref, *position + 3 * p, &det);
                    (*weight)[p] = w[i] * w[j] * w[k] * det;
                }
    }
    *count = (int)total;
    return GSN_OK;
}

/* ---- assembly of the struct --------------------------------------------- */

/* Concatenates b after a into a (gradient rows). */
static int rows_append(struct gsn_shape_rows *a, struct gsn_shape_rows *b)
{
    size_t na = (size_t)a->offset[a->row_count];
    size_t nb = (size_t)b->offset[b->row_count];
    GSN_CHECK(na + nb < 2147483647u, GSN_ERR_INPUT, "too many row entries");
    int *offset = realloc(a->offset, ((size_t)a->row_count + b->row_count + 1) *
                                         sizeof *offset);
    GSN_CHECK(offset, GSN_ERR_MEMORY, "cannot grow rows");
    a->offset = offset;
    int *index = realloc(a->index, (na + nb + 1) * sizeof *index);
    GSN_CHECK(index, GSN_ERR_MEMORY, "cannot grow rows");
    a->index = index;
    double *grad = realloc(a->gradient, 3 * (na + nb + 1) * sizeof *grad);
    GSN_CHECK(grad, GSN_ERR_MEMORY, "cannot grow rows");
    a->gradient = grad;
    for (int r = 1; r <= b->row_count; ++r)
        a->offset[a->row_count + r] = (int)na + b->offset[r];
    memcpy(a->index + na, b->index, nb * sizeof *index);
    memcpy(a->gradient + 3 * na, b->gradient, 3 * nb * sizeof *grad);
    a->row_count += b->row_count;
    gsn_shape_rows_free(b);
    return GSN_OK;
}

static int particle_facets(const struct gsn_model *m, int **offset, int **facet)
{
    size_t n = (size_t)m->particle_count;
    *offset = calloc(n + 1, sizeof **offset);
    *facet = malloc((2 * (size_t)m->facet_count + 1) * sizeof **facet);
    GSN_CHECK(*offset && *facet, GSN_ERR_MEMORY,
              "cannot allocate the facets of %zu particles", n);
    for (int f = 0; f < m->facet_count; ++f) {
        (*offset)[m->facet_owner[f] + 1]++;
        if (m->facet_neighbour[f] >= 0)
            (*offset)[m->facet_neighbour[f] + 1]++;
    }
    for (size_t p = 0; p < n; ++p)
        (*offset)[p + 1] += (*offset)[p];
    int *fill = malloc((n + 1) * sizeof *fill);
    GSN_CHECK(fill, GSN_ERR_MEMORY, "cannot allocate %zu ints", n);
    memcpy(fill, *offset, n * sizeof *fill);
    for (int f = 0; f < m->facet_count; ++f) { /* ascending facets */
        (*facet)[fill[m->facet_owner[f]]++] = f;
        if (m->facet_neighbour[f] >= 0)
            (*facet)[fill[m->facet_neighbour[f]]++] = f;
    }
    free(fill);
    return GSN_OK;
}

static int boundary_points(const struct gsn_model *m, struct gsn_quadrature *q)
{
    int count = 0;
    for (int f = 0; f < m->facet_count; ++f)
        if (m->facet_neighbour[f] < 0)
            count += m->facet_point_offset[f + 1] - m->facet_point_offset[f];
    size_t nb = (size_t)count;
    q->boundary_point_count = count;
    q->boundary_point_facet = malloc((nb + 1) * sizeof(int));
    q->boundary_point_position = malloc(3 * (nb + 1) * sizeof(double));
    q->boundary_point_weight = malloc((nb + 1) * sizeof(double));
    GSN_CHECK(q->boundary_point_facet && q->boundary_point_position &&
                  q->boundary_point_weight,
              GSN_ERR_MEMORY, "cannot allocate %d boundary points", count);
    int b = 0;
    for (int f = 0; f < m->facet_count; ++f) {
        if (m->facet_neighbour[f] >= 0)
            continue;
        for (int p = m->facet_point_offset[f]; p < m->facet_point_offset[f + 1];
             ++p, ++b) {
            q->boundary_point_facet[b] = f;
            q->boundary_point_weight[b] = m->facet_weight[p];
            memcpy(q->boundary_point_position + 3 * (size_t)b,
                   m->facet_point + 3 * (size_t)p, 3 * sizeof(double));
        }
    }
    return GSN_OK;
}

/* ---- Held facets: Psi_I through the held particles ----------------------
 * On a boundary facet where an essential boundary holds components K
 * (gsn_kernel_options.held_facet), Psi_I(x_q) is replaced by
 * sum_k phi_k(x_q) Psi_I(X_k) over the nearest HELD_STENCIL particles of
 * the facet's surface that hold K (taken from the row of the facet's
 * owner), phi the linear moving-least-squares interpolant: it reproduces
 * linear fields, so the smoothed gradients keep eq. (18) and the
 * divergence consistency with the tractions, and the facet's boundary
 * integral sum_q Psi_I(x_q) t w_q becomes sum_k Psi_I(X_k) lambda_k, a
 * combination of the constraints' rows, which the mass-orthogonal
 * projection (constraint.h) absorbs: the linear patch test holds without
 * a non-symmetric boundary term (docs/solver.md, "Boundary values"). */
enum { HELD_STENCIL = 8 };

static double squared_distance(const double *a, const double *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}
/* Pivots of the moment matrix below this share of its largest diagonal
 * are a direction the stencil does not span (the normal of a flat
 * surface). */
#define HELD_PIVOT 1e-10
/* The interpolant must reproduce 1 and x to this (relative to the
 * stencil's radius), with weights whose magnitudes add up to at most
 * HELD_WEIGHT_SUM (a nearly collinear stencil reproduces a point off its
 * line only with large weights of both signs); else the point keeps
 * Psi_I itself. */
#define HELD_REPRODUCTION 1e-9
#define HELD_WEIGHT_SUM 3.0

static void held_stencils_free(struct held_stencils *h)
{
    free(h->offset);
    free(h->particle);
    free(h->weight);
    free(h->facet_point);
    memset(h, 0, sizeof *h);
}

/* The weights phi of the linear moving-least-squares interpolant at x
 * through the count points X (weights (1 - (r/R)^2)^2, R = 1.5 x the
 * farthest): sum phi_k (1, X_k) = (1, x) whenever x lies in their affine
 * hull; a direction the points do not span is left out by the pivoted
 * Cholesky factorization of the moment matrix. 1 if the reproduction
 * holds, else 0. */
static int held_weights(const double *X, int count, const double x[3],
                        double *phi)
{
    double radius = 0.0, w[HELD_STENCIL], p[HELD_STENCIL][4];
    for (int k = 0; k < count; ++k)
        radius = fmax(radius, sqrt(squared_distance(&X[3 * k], x)));
    if (count == 0 || radius == 0.0)
        return 0;
    radius *= 1.5;
    double M[4][4] = {{0}};
    for (int k = 0; k < count; ++k) {
        double r2 = squared_distance(&X[3 * k], x) / (radius * radius);
        w[k] = (1.0 - r2) * (1.0 - r2);
        p[k][0] = 1.0;
        for (int a = 0; a < 3; ++a)
            p[k][a + 1] = (X[3 * k + a] - x[a]) / radius;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
                M[a][b] += w[k] * p[k][a] * p[k][b];
    }
    /* pivoted Cholesky P^T M P = L L^T, stopped at rank r */
    int perm[4] = {0, 1, 2, 3}, rank = 0;
    double largest = fmax(fmax(M[0][0], M[1][1]), fmax(M[2][2], M[3][3]));
    double L[4][4] = {{0}};
    for (int k = 0; k < 4; ++k) {
        int j = k;
        for (int i = k + 1; i < 4; ++i)
            if (M[i][i] > M[j][j])
                j = i;
        if (!(M[j][j] > HELD_PIVOT * largest))
            break;
        for (int i = 0; i < 4; ++i) { /* swap rows, then columns, k and j */
            double t = M[k][i];
            M[k][i] = M[j][i];
            M[j][i] = t;
        }
        for (int i = 0; i < 4; ++i) {
            double t = M[i][k];
            M[i][k] = M[i][j];
            M[i][j] = t;
            t = L[k][i];
            if (i < k) {
                L[k][i] = L[j][i];
                L[j][i] = t;
            }
        }
        int t = perm[k];
        perm[k] = perm[j];
        perm[j] = t;
        L[k][k] = sqrt(M[k][k]);
        for (int i = k + 1; i < 4; ++i)
            L[i][k] = M[i][k] / L[k][k];
        for (int i = k + 1; i < 4; ++i)
            for (int jj = k + 1; jj < 4; ++jj)
                M[i][jj] -= L[i][k] * L[jj][k];
        rank = k + 1;
    }
    /* M a = e_0 on the leading rank unknowns, the rest 0 */
    double y[4] = {0}, a[4] = {0};
    for (int i = 0; i < rank; ++i) {
        double v = perm[i] == 0 ? 1.0 : 0.0;
        for (int j = 0; j < i; ++j)
            v -= L[i][j] * y[j];
        y[i] = v / L[i][i];
    }
    for (int i = rank - 1; i >= 0; --i) {
        double v = y[i];
        for (int j = i + 1; j < rank; ++j)
            v -= L[j][i] * y[j];
        y[i] = v / L[i][i];
    }
    for (int i = 0; i < rank; ++i)
        a[perm[i]] = y[i];
    double moment[4] = {0}, magnitude = 0.0;
    for (int k = 0; k < count; ++k) {
        phi[k] = w[k] * (p[k][0] * a[0] + p[k][1] * a[1] + p[k][2] * a[2] +
                         p[k][3] * a[3]);
        magnitude += fabs(phi[k]);
        for (int b = 0; b < 4; ++b)
            moment[b] += phi[k] * p[k][b];
    }
    return magnitude <= HELD_WEIGHT_SUM &&
           fabs(moment[0] - 1.0) <= HELD_REPRODUCTION &&
           fabs(moment[1]) <= HELD_REPRODUCTION &&
           fabs(moment[2]) <= HELD_REPRODUCTION &&
           fabs(moment[3]) <= HELD_REPRODUCTION;
}

/* The stencil of boundary point b (held_stencils): up to HELD_STENCIL
 * particles nearest to it, on its facet's surface and holding what the
 * facet holds, among those whose whole window (uncut) covers the facet's
 * owner; count 0 if the facet holds nothing or the interpolant does not
 * reproduce. candidate: GSN_RK_MAX_NEIGHBOURS ints of scratch. */
static int held_point(const struct gsn_model *m,
                      const struct gsn_kernel_options *o,
                      const struct gsn_rk *whole,
                      const struct gsn_quadrature *q, int b, int *particle,
                      double *weight, int *candidate)
{
    int f = q->boundary_point_facet[b], K = o->held_facet[f];
    if (!K)
        return 0;
    const double *x = &q->boundary_point_position[3 * (size_t)b];
    int owner = m->facet_owner[f], surface = m->facet_surface[f], count = 0;
    int found = gsn_rk_neighbours(whole, &m->position[3 * (size_t)owner],
                                  GSN_RK_MAX_NEIGHBOURS, candidate);
    if (found > GSN_RK_MAX_NEIGHBOURS)
        found = GSN_RK_MAX_NEIGHBOURS;
    double distance[HELD_STENCIL];
    for (int c = 0; c < found; ++c) {
        int J = candidate[c];
        if ((o->held_particle[J] & K) != K ||
            !gsn_model_particle_on_surface(m, J, surface))
            continue;
        double d = squared_distance(&m->position[3 * (size_t)J], x);
        if (count == HELD_STENCIL && d >= distance[count - 1])
            continue;
        int k = count < HELD_STENCIL ? count++ : count - 1;
        while (k > 0 && (distance[k - 1] > d ||
                         (distance[k - 1] == d && particle[k - 1] > J))) {
            distance[k] = distance[k - 1];
            particle[k] = particle[k - 1];
            --k;
        }
        distance[k] = d;
        particle[k] = J;
    }
    double X[3 * HELD_STENCIL];
    for (int k = 0; k < count; ++k)
        memcpy(&X[3 * k], &m->position[3 * (size_t)particle[k]],
               3 * sizeof(double));
    return held_weights(X, count, x, weight) ? count : 0;
}

/* The stencils of every boundary point, and boundary_values made the
 * interpolant's on held facets. */
static int held_build(const struct gsn_model *m,
                      const struct gsn_kernel_options *o,
                      struct gsn_quadrature *q, struct held_stencils *h)
{
    const struct gsn_shape_rows *values = &q->particle_values;
    int nb = q->boundary_point_count, n = m->particle_count;
    size_t wide = (size_t)HELD_STENCIL * (size_t)(nb + 1);
    h->offset = calloc((size_t)nb + 1, sizeof(int));
    h->particle = malloc(wide * sizeof(int));
    h->weight = malloc(wide * sizeof(double));
    h->facet_point = malloc(((size_t)m->facet_count + 1) * sizeof(int));
    double *dense = calloc((size_t)n + 1, sizeof(double));
    int *touched = malloc(((size_t)n + 1) * sizeof(int));
    int *mark = calloc((size_t)n + 1, sizeof(int));
    struct gsn_shape_rows rows = {0};
    int rc = GSN_OK;
    GSN_CHECK_GOTO(h->offset && h->particle && h->weight && h->facet_point &&
                       dense && touched && mark,
                   rc, GSN_ERR_MEMORY, done, "cannot allocate held stencils");
    for (int f = 0; f < m->facet_count; ++f)
        h->facet_point[f] = -1;
    for (int b = nb - 1; b >= 0; --b)
        h->facet_point[q->boundary_point_facet[b]] = b;
    /* the stencils' candidates do not depend on kernel.window_cut */
    const struct gsn_rk whole = gsn_rk_whole_window(q->rk);
#pragma omp parallel
    {
        int *candidate = malloc(GSN_RK_MAX_NEIGHBOURS * sizeof *candidate);
#pragma omp for schedule(dynamic, 64)
        for (int b = 0; b < nb; ++b)
            h->offset[b + 1] =
                candidate ? held_point(m, o, &whole, q, b,
                                       &h->particle[HELD_STENCIL * b],
                                       &h->weight[HELD_STENCIL * b], candidate)
                          : -1;
        free(candidate);
    }
    for (int b = 0; b < nb; ++b)
        GSN_CHECK_GOTO(h->offset[b + 1] >= 0, rc, GSN_ERR_MEMORY, done,
                       "cannot allocate held stencils' candidates");
    /* compact the stencils (offset[b + 1] held the count) */
    for (int b = 0; b < nb; ++b) {
        int count = h->offset[b + 1];
        if (o->held_facet[q->boundary_point_facet[b]]) {
            q->held_point_count += count > 0;
            q->held_fallback_count += count == 0;
        }
        h->offset[b + 1] = h->offset[b] + count;
        memmove(&h->particle[h->offset[b]], &h->particle[HELD_STENCIL * b],
                (size_t)count * sizeof(int));
        memmove(&h->weight[h->offset[b]], &h->weight[HELD_STENCIL * b],
                (size_t)count * sizeof(double));
    }
    /* boundary_values: the interpolant where there is a stencil */
    const struct gsn_shape_rows *old = &q->boundary_values;
    size_t capacity = (size_t)old->offset[nb] + 1;
    rows.row_count = nb;
    rows.offset = calloc((size_t)nb + 1, sizeof(int));
    rows.index = malloc(capacity * sizeof(int));
    rows.value = malloc(capacity * sizeof(double));
    GSN_CHECK_GOTO(rows.offset && rows.index && rows.value, rc, GSN_ERR_MEMORY,
                   done, "cannot allocate boundary values");
    for (int b = 0; b < nb; ++b) {
        int listed = 0;
        if (h->offset[b + 1] > h->offset[b]) {
            for (int k = h->offset[b]; k < h->offset[b + 1]; ++k) {
                int J = h->particle[k];
                for (int e = values->offset[J]; e < values->offset[J + 1];
                     ++e) {
                    int I = values->index[e];
                    if (!mark[I]) {
                        mark[I] = 1;
                        touched[listed++] = I;
                    }
                    dense[I] += h->weight[k] * values->value[e];
                }
            }
            qsort(touched, (size_t)listed, sizeof(int), compare_int);
        } else {
            for (int e = old->offset[b]; e < old->offset[b + 1]; ++e) {
                touched[listed++] = old->index[e];
                dense[old->index[e]] = old->value[e];
            }
        }
        size_t need = (size_t)rows.offset[b] + (size_t)listed;
        if (need > capacity) {
            capacity = 2 * need;
            int *index = realloc(rows.index, capacity * sizeof(int));
            if (index)
                rows.index = index;
            double *value = realloc(rows.value, capacity * sizeof(double));
            if (value)
                rows.value = value;
            GSN_CHECK_GOTO(index && value, rc, GSN_ERR_MEMORY, done,
                           "cannot grow boundary values");
        }
        for (int l = 0; l < listed; ++l) {
            rows.index[rows.offset[b] + l] = touched[l];
            rows.value[rows.offset[b] + l] = dense[touched[l]];
            dense[touched[l]] = 0.0;
            mark[touched[l]] = 0;
        }
        rows.offset[b + 1] = rows.offset[b] + listed;
    }
    gsn_shape_rows_free(&q->boundary_values);
    q->boundary_values = rows;
    rows = (struct gsn_shape_rows){0};
done:
    gsn_shape_rows_free(&rows);
    free(dense);
    free(touched);
    free(mark);
    return rc;
}

static int nodal_points(const struct gsn_model *m, struct gsn_quadrature *q)
{
    size_t n = (size_t)m->particle_count;
    q->point_count = q->main_point_count = m->particle_count;
    q->point_weight = malloc(n * sizeof(double));
    q->point_position = malloc(3 * n * sizeof(double));
    q->point_particle = malloc(n * sizeof(int));
    GSN_CHECK(q->point_weight && q->point_position && q->point_particle,
              GSN_ERR_MEMORY, "cannot allocate %zu points", n);
    memcpy(q->point_weight, m->volume, n * sizeof(double));
    memcpy(q->point_position, m->position, 3 * n * sizeof(double));
    for (size_t p = 0; p < n; ++p)
        q->point_particle[p] = (int)p;
    return GSN_OK;
}

/* ---- NSNI: strain gradients at the nodal points ---------------------------
 * Naturally stabilized nodal integration (Hillman & Chen 2016): the strain
 * in the nodal domain is expanded about X_L, eps(x) = eps_L + (x - X_L) .
 * grad eps(X_L), so that int_{Omega_L} eps : C : eps takes, besides the
 * nodal term, sum_k M_Lk eps_,k : C : eps_,k with the second moments
 * M_Lk = int_{Omega_L} (x_k - X_Lk)^2 (the first moments are left out).
 * Row 3 L + k holds d/dX_k grad Psi_I(X_L), the gradient row of dPsi_I/dX_k:
 * eps_,k = sym(sum_I d_I (x) row), zero for every linear field (linear
 * completeness, eq. (18)), while a checkerboard, invisible to B_L, has
 * large second derivatives. Here the second derivatives are the direct ones
 * of the linear RK functions (the paper's implicit gradients are a cheaper
 * build of the same thing); one evaluation per row, at the particle. */
static int nsni_row(void *context, int row, struct kernel_thread *t)
{
    const struct facet_context *c = context;
    int L = row / 3, k = row % 3;
    if (t->hessian_row < 0 || t->hessian_row / 3 != L) {
        /* the three rows of L share one evaluation (rows come in order
         * within a thread's chunk) */
        int rc = kernel_evaluate(c->rk, c->m->position + 3 * (size_t)L, 2, t,
                                 &t->hessian_count, "NSNI point", L);
        t->hessian_row = -1;
        if (rc != GSN_OK)
            return rc;
        t->hessian_row = row;
    }
    int count = t->hessian_count;
    for (int n = 0; n < count; ++n)
        if (kernel_row_push(t, t->index[n], 0.0, t->hessian + 9 * n + 3 * k)) {
            snprintf(t->message, sizeof t->message, "out of memory at row %d",
                     row);
            return GSN_ERR_MEMORY;
        }
    return GSN_OK;
}

/* coefficient M_Lk and X_L for the three NSNI points of every particle:
 * M_Lk = int y_k^2 dV = (1/5) sum over the facets of int y_k^2 (y . N) dS,
 * y = x - X_L (the divergence of y y_k^2 is 5 y_k^2), exact with the
 * facets' degree-2 points and a fair estimate with one point each. */
static void nsni_weights(const struct gsn_model *m,
                         const struct facet_context *c, double coefficient,
                         double *weight, double *position)
{
#pragma omp parallel for schedule(static)
    for (int L = 0; L < m->particle_count; ++L) {
        const double *X = m->position + 3 * (size_t)L;
        double moment[3] = {0, 0, 0};
        for (int e = c->particle_facet_offset[L];
             e < c->particle_facet_offset[L + 1]; ++e) {
            int f = c->particle_facet[e];
            double sign = m->facet_owner[f] == L ? 1.0 : -1.0;
            const double *normal = m->facet_normal + 3 * (size_t)f;
            for (int q = m->facet_point_offset[f];
                 q < m->facet_point_offset[f + 1]; ++q) {
                const double *x = m->facet_point + 3 * (size_t)q;
                double y[3] = {x[0] - X[0], x[1] - X[1], x[2] - X[2]};
                double flux =
                    sign * m->facet_weight[q] *
                    (y[0] * normal[0] + y[1] * normal[1] + y[2] * normal[2]);
                for (int k = 0; k < 3; ++k)
                    moment[k] += y[k] * y[k] * flux;
            }
        }
        for (int k = 0; k < 3; ++k) {
            size_t p = 3 * (size_t)L + (size_t)k;
            weight[p] = coefficient * fmax(moment[k] / 5.0, 0.0);
            memcpy(position + 3 * p, X, 3 * sizeof(double));
        }
    }
}

/* Appends the stabilization points (MSCNI sub-cells or NSNI strain
 * gradients, S per particle) to the nodal points. */
static int stabilize(const struct gsn_model *m, struct facet_context *c,
                     enum gsn_stabilization kind, double coefficient,
                     struct gsn_quadrature *q)
{
    int nsni = kind == GSN_STABILIZATION_NSNI;
    size_t S = nsni ? 3 : (size_t)c->subcells;
    size_t n = (size_t)m->particle_count, ns = S * n, total = n + ns;
    double *w = realloc(q->point_weight, total * sizeof *w);
    GSN_CHECK(w, GSN_ERR_MEMORY, "cannot grow points");
    q->point_weight = w;
    double *x = realloc(q->point_position, 3 * total * sizeof *x);
    GSN_CHECK(x, GSN_ERR_MEMORY, "cannot grow points");
    q->point_position = x;
    int *owner = realloc(q->point_particle, total * sizeof *owner);
    GSN_CHECK(owner, GSN_ERR_MEMORY, "cannot grow points");
    q->point_particle = owner;
    for (size_t s = 0; s < ns; ++s)
        owner[n + s] = (int)(s / S);
    (nsni ? nsni_weights : mscni_weights)(m, c, coefficient, w + n, x + 3 * n);
    struct gsn_shape_rows rows;
    c->nodal = &q->gradient;
    GSN_CALL(kernel_rows_build(c->rk, (int)ns, nsni ? nsni_row : mscni_row, c,
                               0, 1, &rows));
    GSN_CALL(rows_append(&q->gradient, &rows));
    q->point_count = (int)total;
    return GSN_OK;
}

static int check_model(const struct gsn_model *m)
{
    GSN_CHECK(m->particle_count > 0, GSN_ERR_INPUT,
              "the model has no particles");
    for (int p = 0; p < m->particle_count; ++p)
        GSN_CHECK(m->volume[p] > 0.0, GSN_ERR_INPUT,
                  "particle %d has nodal volume %g", p, m->volume[p]);
    return GSN_OK;
}

/* spacing_floor (NULL: none): the least h_I of each particle (the support
 * repair below); failure_point: where an ill-conditioned point is
 * reported. */
static int quadrature_build(const struct gsn_model *m,
                            const struct gsn_kernel_options *o,
                            const double *background, int background_count,
                            const double *spacing_floor, double *failure_point,
                            struct gsn_quadrature *q)
{
    int n = m->particle_count;
    GSN_CALL(check_model(m));
    GSN_CHECK(o->stabilization == GSN_STABILIZATION_NONE ||
                  o->integration != GSN_INTEGRATION_GAUSS,
              GSN_ERR_INPUT,
              "stabilization %s applies to nodal integration (scni or "
              "dni), not gauss",
              gsn_stabilization_name(o->stabilization));
    GSN_CHECK(o->stabilization != GSN_STABILIZATION_NSNI || o->basis_order == 1,
              GSN_ERR_INPUT,
              "stabilization nsni needs the linear basis (kernel.basis: "
              "linear)");
    GSN_CHECK(o->stabilization != GSN_STABILIZATION_MSCNI ||
                  o->stabilization_subcells == 2 ||
                  o->stabilization_subcells == 6,
              GSN_ERR_INPUT, "MSCNI sub-cells %d: only 2 or 6",
              o->stabilization_subcells);
    q->method = o->integration;
    q->stabilization = o->stabilization;
    q->particle_count = n;
    double *spacing = malloc((size_t)n * sizeof *spacing);
    GSN_CHECK(spacing, GSN_ERR_MEMORY, "cannot allocate %d doubles", n);
    int rc = gsn_rk_spacing_from_facets(
        m, o->cover_neighbours ? o->support : 0.0, spacing);
    for (int p = 0; p < n && spacing_floor; ++p)
        spacing[p] = fmax(spacing[p], spacing_floor[p]);
    if (rc == GSN_OK)
        rc = gsn_rk_create(n, m->position, spacing, o->support, o->basis_order,
                           &q->rk);
    free(spacing);
    GSN_CALL(rc);
    q->rk->failure_point = failure_point;
    q->rk->window_cut = o->window_cut;

    /* Psi_I(X_J), with gradients for DNI */
    int dni = o->integration == GSN_INTEGRATION_DNI;
    GSN_CALL(
        gsn_rk_shape_rows(q->rk, n, m->position, dni, &q->particle_values));
    GSN_CALL(boundary_points(m, q));
    GSN_CALL(gsn_rk_shape_rows(q->rk, q->boundary_point_count,
                               q->boundary_point_position, 0,
                               &q->boundary_values));
    struct held_stencils held = {0};
    if (o->held_facet) {
        rc = held_build(m, o, q, &held);
        if (rc != GSN_OK) {
            held_stencils_free(&held);
            return rc;
        }
    }

    struct facet_context c = {m,
                              q->rk,
                              NULL,
                              NULL,
                              NULL,
                              o->stabilization_subcells,
                              o->held_facet ? &held : NULL,
                              &q->particle_values};
    if (o->integration == GSN_INTEGRATION_GAUSS) {
        held_stencils_free(&held); /* boundary_values have it */
        int count = 0;
        GSN_CALL(gauss_points(m, o->gauss_points, background, background_count,
                              &q->point_position, &q->point_weight, &count));
        q->point_count = q->main_point_count = count;
        q->point_particle = malloc((size_t)(count + 1) * sizeof(int));
        GSN_CHECK(q->point_particle, GSN_ERR_MEMORY, "cannot allocate points");
        for (int p = 0; p < count; ++p)
            q->point_particle[p] = -1;
        /* the values stay: the lumped mass of eq. (28) sums them */
        GSN_CALL(gsn_rk_shape_rows(q->rk, count, q->point_position, 1,
                                   &q->gradient));
        return GSN_OK;
    }
    int *offset = NULL, *facet = NULL;
    rc = nodal_points(m, q);
    if (rc == GSN_OK)
        rc = particle_facets(m, &offset, &facet);
    c.particle_facet_offset = offset;
    c.particle_facet = facet;
    if (rc == GSN_OK && dni) {
        /* DNI: the gradient rows are the gradients at the particles */
        struct gsn_shape_rows *g = &q->gradient, *v = &q->particle_values;
        size_t nnz = (size_t)v->offset[n];
        g->row_count = n;
        g->offset = malloc(((size_t)n + 1) * sizeof(int));
        g->index = malloc((nnz + 1) * sizeof(int));
        g->gradient = v->gradient;
        v->gradient = NULL;
        if (g->offset && g->index) {
            memcpy(g->offset, v->offset, ((size_t)n + 1) * sizeof(int));
            memcpy(g->index, v->index, nnz * sizeof(int));
        } else {
            rc = gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__, __func__,
                                 "cannot allocate DNI rows");
        }
    } else if (rc == GSN_OK) {
        rc = kernel_rows_build(q->rk, n, scni_row, &c, 0, 1, &q->gradient);
    }
    if (rc == GSN_OK && o->stabilization != GSN_STABILIZATION_NONE)
        rc =
            stabilize(m, &c, o->stabilization, o->stabilization_coefficient, q);
    free(offset);
    free(facet);
    held_stencils_free(&held);
    GSN_CALL(rc);
    return GSN_OK;
}

/* Ill-conditioned points an updated reference's build repairs at most. */
enum { SUPPORT_REPAIRS = 32 };
/* A repaired point is covered by at least as many particles as the basis
 * has terms and REPAIR_COVER_EXTRA more, and by as many more of the
 * nearest as it takes for them not to lie in one plane (the base of a
 * footing, a face: their moment matrix is singular whatever their
 * number), at most REPAIR_MOST; each reaches it at 1 / REPAIR_REACH of its
 * support (the cubic spline there is 0.05 of its peak: a point at the
 * support's edge would weigh nothing). */
enum { REPAIR_COVER_EXTRA = 4, REPAIR_MOST = 64 };
#define REPAIR_REACH 1.5
/* Offsets whose second moment has det / (trace / 3)^3 above this span
 * space (1 for a sphere's, 0 for a plane's). */
#define REPAIR_SPREAD 1e-3

/* det / (trace / 3)^3 of the second moment of x - mean over the points
 * `index[0..count)` of positions X. */
static double spread(const double *X, const int *index, int count)
{
    double mean[3] = {0, 0, 0}, M[9] = {0};
    for (int k = 0; k < count; ++k)
        for (int a = 0; a < 3; ++a)
            mean[a] += X[3 * (size_t)index[k] + a] / count;
    for (int k = 0; k < count; ++k)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                M[3 * a + b] += (X[3 * (size_t)index[k] + a] - mean[a]) *
                                (X[3 * (size_t)index[k] + b] - mean[b]);
    double det = M[0] * (M[4] * M[8] - M[5] * M[7]) -
                 M[1] * (M[3] * M[8] - M[5] * M[6]) +
                 M[2] * (M[3] * M[7] - M[4] * M[6]);
    double third = (M[0] + M[4] + M[8]) / 3.0;
    return third > 0.0 ? det / (third * third * third) : 0.0;
}

/* Raises floor (the least h_I) of the particles nearest to x (see above)
 * so that their kernels (box half-width support h_I) reach x within
 * 1 / REPAIR_REACH of it. */
static int repair_supports(const struct gsn_model *m,
                           const struct gsn_kernel_options *o,
                           const double x[3], double *floor)
{
    int want = (o->basis_order == 2 ? 10 : 4) + REPAIR_COVER_EXTRA;
    int nearest[REPAIR_MOST];
    double distance[REPAIR_MOST];
    int found = 0;
    for (int i = 0; i < m->particle_count; ++i) {
        const double *X = &m->position[3 * (size_t)i];
        double d =
            fmax(fabs(X[0] - x[0]), fmax(fabs(X[1] - x[1]), fabs(X[2] - x[2])));
        if (found == REPAIR_MOST && d >= distance[found - 1])
            continue;
        int k = found < REPAIR_MOST ? found++ : found - 1;
        while (k > 0 && distance[k - 1] > d) {
            distance[k] = distance[k - 1];
            nearest[k] = nearest[k - 1];
            --k;
        }
        distance[k] = d;
        nearest[k] = i;
    }
    GSN_CHECK(found >= want, GSN_ERR_NUMERICAL,
              "the point (%g, %g, %g) cannot be covered: %d particles", x[0],
              x[1], x[2], m->particle_count);
    int count = want;
    while (count < found && spread(m->position, nearest, count) < REPAIR_SPREAD)
        ++count;
    for (int k = 0; k < count; ++k)
        floor[nearest[k]] =
            fmax(floor[nearest[k]], distance[k] * REPAIR_REACH / o->support);
    return GSN_OK;
}

int gsn_quadrature_create(const struct gsn_model *m,
                          const struct gsn_kernel_options *options,
                          const double *background_cells,
                          int background_cell_count,
                          struct gsn_quadrature **out)
{
    *out = NULL;
    double failure[3] = {NAN, NAN, NAN}, *floor = NULL;
    int rc = GSN_OK;
    for (int attempt = 0;; ++attempt) {
        struct gsn_quadrature *q = calloc(1, sizeof *q);
        GSN_CHECK_GOTO(q, rc, GSN_ERR_MEMORY, done,
                       "cannot allocate the quadrature");
        rc = quadrature_build(m, options, background_cells,
                              background_cell_count, floor, failure, q);
        if (rc == GSN_OK) {
            q->rk->failure_point = NULL;
            q->support_repairs = attempt;
            *out = q;
            break;
        }
        gsn_quadrature_destroy(&q);
        /* an updated reference: supports raised to cover the point that
         * failed, once per such point (docs/solver.md, "Support repair") */
        if (rc != GSN_ERR_NUMERICAL || !options->cover_neighbours ||
            attempt == SUPPORT_REPAIRS || !isfinite(failure[0]))
            break;
        if (!floor) {
            floor = calloc((size_t)m->particle_count + 1, sizeof *floor);
            GSN_CHECK_GOTO(floor, rc, GSN_ERR_MEMORY, done,
                           "cannot allocate %d doubles", m->particle_count);
        }
        GSN_CALL_GOTO(repair_supports(m, options, failure, floor), rc, done);
        failure[0] = NAN;
        gsn_error_clear();
    }
done:
    free(floor);
    GSN_CALL(rc);
    return GSN_OK;
}
