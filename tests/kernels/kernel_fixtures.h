/* Shared fixtures of the kernel tests: a regular lattice with its nodal
 * domains built by hand (boxes, halved at faces, quartered at edges,
 * eighthed at corners; every facet stored once), the linear patch test and
 * the stiffness action f_int(d) of a linear elastic body. */
#ifndef GEOSCNI_TESTS_KERNEL_FIXTURES_H
#define GEOSCNI_TESTS_KERNEL_FIXTURES_H

#include "geoscni/kernels.h"
#include "geoscni/model.h"
#include "testing.h"

#include <string.h>

static inline double fixture_uniform(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* n^3 particle positions x (3 each) on [0, (n - 1) h]^3, lattice order,
 * the interior coordinates jittered by +-jitter h (a particle on a face
 * stays on it). */
static inline void fixture_jittered_lattice(int n, double h, double jitter,
                                            unsigned long long seed, double *x)
{
    int p = 0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i, ++p) {
                int ijk[3] = {i, j, k};
                for (int d = 0; d < 3; ++d) {
                    double v = ijk[d] * h;
                    if (ijk[d] > 0 && ijk[d] < n - 1)
                        v += jitter * h * (2.0 * fixture_uniform(&seed) - 1.0);
                    x[3 * p + d] = v;
                }
            }
}

/* Adds one rectangular facet: centre c, normal axis d (+1 direction from
 * the owner), half-extents e[3] (e[d] unused), gauss 1 or 2 per direction. */
static inline void fixture_facet(struct gsn_model *m, int *f, int *qp,
                                 int owner, int neighbour, int d, double sign,
                                 const double *c, const double *e, int gauss)
{
    int a = (d + 1) % 3, b = (d + 2) % 3;
    m->facet_owner[*f] = owner;
    m->facet_neighbour[*f] = neighbour;
    m->facet_surface[*f] = -1;
    m->facet_area[*f] = 4.0 * e[a] * e[b];
    for (int k = 0; k < 3; ++k)
        m->facet_normal[3 * *f + k] = k == d ? sign : 0.0;
    m->facet_point_offset[*f] = *qp;
    double g = gauss == 1 ? 0.0 : 0.57735026918962576451;
    for (int j = 0; j < gauss; ++j)
        for (int i = 0; i < gauss; ++i) {
            double *x = m->facet_point + 3 * *qp;
            memcpy(x, c, 3 * sizeof *x);
            if (gauss == 2) {
                x[a] += (i ? g : -g) * e[a];
                x[b] += (j ? g : -g) * e[b];
            }
            m->facet_weight[*qp] = m->facet_area[*f] / (gauss * gauss);
            ++*qp;
        }
    ++*f;
    m->facet_point_offset[*f] = *qp;
}

/* nx x ny x nz particles, spacing h, first particle at the origin. */
static inline int fixture_lattice(const int *size, double h, int gauss,
                                  struct gsn_model *m)
{
    int nx = size[0], ny = size[1], nz = size[2], n = nx * ny * nz;
    /* facets: interior (n_d - 1) per line per direction, 2 per line on the
     * boundary */
    int facets = (nx + 1) * ny * nz + nx * (ny + 1) * nz + nx * ny * (nz + 1);
    int cells = (nx - 1) * (ny - 1) * (nz - 1);
    int rc = gsn_model_allocate(m, n, 0, facets, facets * gauss * gauss, 0,
                                6 * cells);
    if (rc)
        return rc;
    int f = 0, qp = 0;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                int ijk[3] = {i, j, k}, p = i + nx * (j + ny * k);
                double lo[3], hi[3], vol = 1.0;
                for (int d = 0; d < 3; ++d) {
                    double x = ijk[d] * h;
                    m->position[3 * p + d] = x;
                    lo[d] = ijk[d] == 0 ? x : x - 0.5 * h;
                    hi[d] = ijk[d] == size[d] - 1 ? x : x + 0.5 * h;
                    vol *= hi[d] - lo[d];
                    m->centroid[3 * p + d] = 0.5 * (lo[d] + hi[d]);
                }
                m->volume[p] = vol;
                for (int d = 0; d < 3; ++d) {
                    double c[3], e[3];
                    for (int k2 = 0; k2 < 3; ++k2) {
                        c[k2] = 0.5 * (lo[k2] + hi[k2]);
                        e[k2] = 0.5 * (hi[k2] - lo[k2]);
                    }
                    int stride = d == 0 ? 1 : (d == 1 ? nx : nx * ny);
                    /* the face at lo: boundary only (interior ones are the
                     * +d facet of the previous particle) */
                    if (ijk[d] == 0) {
                        c[d] = lo[d];
                        fixture_facet(m, &f, &qp, p, -1, d, -1.0, c, e, gauss);
                    }
                    c[d] = hi[d];
                    fixture_facet(m, &f, &qp, p,
                                  ijk[d] == size[d] - 1 ? -1 : p + stride, d,
                                  1.0, c, e, gauss);
                }
            }
    m->facet_count = f;
    /* tetrahedra: each lattice cube split into 6 around its diagonal 0-7
     * (vertex a = i + 2j + 4k of the cube) */
    static const int kuhn[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                   {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    const int stride[3] = {1, nx, nx * ny};
    int t = 0;
    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i)
                for (int r = 0; r < 6; ++r, ++t) {
                    int vertex = i + nx * (j + ny * k);
                    m->tetrahedra[4 * t] = vertex;
                    for (int s2 = 0; s2 < 3; ++s2) {
                        vertex += stride[kuhn[r][s2]];
                        m->tetrahedra[4 * t + s2 + 1] = vertex;
                    }
                }
    m->particle_surface_offset[0] = 0;
    return GSN_OK;
}

/* The lattice cells between particles as background hexahedra. */
static inline double *fixture_background(const int *size, double h, int *count)
{
    int cx = size[0] - 1, cy = size[1] - 1, cz = size[2] - 1;
    *count = cx * cy * cz;
    double *v = malloc(24 * (size_t)*count * sizeof *v);
    int c = 0;
    for (int k = 0; k < cz; ++k)
        for (int j = 0; j < cy; ++j)
            for (int i = 0; i < cx; ++i, ++c)
                for (int a = 0; a < 8; ++a) {
                    v[24 * c + 3 * a + 0] = (i + (a & 1)) * h;
                    v[24 * c + 3 * a + 1] = (j + ((a >> 1) & 1)) * h;
                    v[24 * c + 3 * a + 2] = (k + ((a >> 2) & 1)) * h;
                }
    return v;
}

/* Small-strain isotropic elasticity: sigma = lambda tr(eps) I + 2 mu eps
 * with eps = sym(G), G_ij = du_i/dX_j. */
static inline void fixture_stress(double lambda, double mu, const double *g,
                                  double *s)
{
    double tr = g[0] + g[4] + g[8];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            s[3 * i + j] =
                mu * (g[3 * i + j] + g[3 * j + i]) + (i == j ? lambda * tr : 0);
}

/* f_int = sum_p B_p^T sigma(B_p d) w_p (3 per particle); linear elastic at
 * every point (main and stabilization). */
static inline void fixture_internal_force(const struct gsn_quadrature *q,
                                          double lambda, double mu,
                                          const double *d, double *f)
{
    memset(f, 0, 3 * (size_t)q->particle_count * sizeof *f);
    const struct gsn_shape_rows *r = &q->gradient;
    for (int p = 0; p < q->point_count; ++p) {
        double g[9] = {0}, s[9];
        for (int e = r->offset[p]; e < r->offset[p + 1]; ++e)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    g[3 * i + j] +=
                        d[3 * r->index[e] + i] * r->gradient[3 * e + j];
        fixture_stress(lambda, mu, g, s);
        for (int e = r->offset[p]; e < r->offset[p + 1]; ++e)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    f[3 * r->index[e] + i] += s[3 * i + j] *
                                              r->gradient[3 * e + j] *
                                              q->point_weight[p];
    }
}

/* The linear patch test: d_I = A X_I + b, exact traction sigma n on the
 * boundary with the facet quadrature. Returns ||f_int - f_ext|| / ||f_ext||. */
static inline double fixture_patch_test(const struct gsn_model *m,
                                        const struct gsn_quadrature *q)
{
    const double lambda = 21.30e6, mu = 9.15e6; /* the paper's soil */
    const double a[9] = {1.0e-3, 0.4e-3, -0.7e-3, 0.9e-3, -0.5e-3,
                         0.3e-3, 0.2e-3, 1.1e-3,  0.6e-3};
    const double b[3] = {0.01, -0.02, 0.03};
    int n = m->particle_count;
    double *d = malloc(3 * (size_t)n * sizeof *d);
    double *f = malloc(3 * (size_t)n * sizeof *f);
    double *g = calloc(3 * (size_t)n, sizeof *g);
    for (int p = 0; p < n; ++p)
        for (int i = 0; i < 3; ++i) {
            d[3 * p + i] = b[i];
            for (int j = 0; j < 3; ++j)
                d[3 * p + i] += a[3 * i + j] * m->position[3 * p + j];
        }
    fixture_internal_force(q, lambda, mu, d, f);
    double s[9];
    fixture_stress(lambda, mu, a, s);
    const struct gsn_shape_rows *r = &q->boundary_values;
    for (int p = 0; p < q->boundary_point_count; ++p) {
        const double *nf = m->facet_normal + 3 * q->boundary_point_facet[p];
        double t[3];
        for (int i = 0; i < 3; ++i)
            t[i] =
                s[3 * i] * nf[0] + s[3 * i + 1] * nf[1] + s[3 * i + 2] * nf[2];
        for (int e = r->offset[p]; e < r->offset[p + 1]; ++e)
            for (int i = 0; i < 3; ++i)
                g[3 * r->index[e] + i] +=
                    r->value[e] * t[i] * q->boundary_point_weight[p];
    }
    double num = 0.0, den = 0.0;
    for (int e = 0; e < 3 * n; ++e) {
        num += (f[e] - g[e]) * (f[e] - g[e]);
        den += g[e] * g[e];
    }
    free(d);
    free(f);
    free(g);
    return sqrt(num / den);
}

/* eq. (23) at every particle and eq. (24) at the particles whose kernel
 * covers no boundary point; errors relative to 1/h and h^2. The second
 * line of eq. (23) is taken with the origin at X_L (it holds for any
 * origin): in absolute coordinates the round-off of sum_I grad Psi_I, about
 * 1e-13/h, is multiplied by |X_L| / h, 30 on the 20 m slope. */
static inline void fixture_completeness(const struct gsn_model *m,
                                        const struct gsn_quadrature *q,
                                        double h, double *err23, double *err24,
                                        int *interior)
{
    int n = m->particle_count;
    const struct gsn_shape_rows *r = &q->gradient;
    *err23 = 0.0;
    for (int L = 0; L < n; ++L) {
        double s0[3] = {0}, s1[9] = {0};
        for (int e = r->offset[L]; e < r->offset[L + 1]; ++e)
            for (int j = 0; j < 3; ++j) {
                s0[j] += r->gradient[3 * e + j];
                for (int k = 0; k < 3; ++k)
                    s1[3 * j + k] += r->gradient[3 * e + j] *
                                     (m->position[3 * r->index[e] + k] -
                                      m->position[3 * L + k]);
            }
        for (int j = 0; j < 3; ++j) {
            *err23 = fmax(*err23, fabs(s0[j]) * h);
            for (int k = 0; k < 3; ++k)
                *err23 = fmax(*err23, fabs(s1[3 * j + k] - (j == k)));
        }
    }
    /* eq. (24): sum_L grad Psi_I(X_L) V_L for each I */
    size_t un = n > 0 ? (size_t)n : 1;
    double *sum = calloc(3 * un, sizeof *sum);
    int *boundary = calloc(un, sizeof *boundary);
    for (int L = 0; L < n; ++L)
        for (int e = r->offset[L]; e < r->offset[L + 1]; ++e)
            for (int j = 0; j < 3; ++j)
                sum[3 * r->index[e] + j] +=
                    r->gradient[3 * e + j] * q->point_weight[L];
    const struct gsn_shape_rows *b = &q->boundary_values;
    for (int e = 0; e < b->offset[b->row_count]; ++e)
        boundary[b->index[e]] = 1;
    *err24 = 0.0;
    *interior = 0;
    for (int i = 0; i < n; ++i) {
        if (boundary[i])
            continue;
        ++*interior;
        for (int j = 0; j < 3; ++j)
            *err24 = fmax(*err24, fabs(sum[3 * i + j]) / (h * h));
    }
    free(sum);
    free(boundary);
}

#endif
