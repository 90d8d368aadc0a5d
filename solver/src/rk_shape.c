/* Reproducing-kernel shape functions (seed paper eqs. (9)-(18)) with the
 * cubic B-spline tensor-product kernel, the cell list that finds the
 * particles covering a point, and the local spacing h_I.
 *
 * Eq. (16) as printed lacks the inverse; the shape function is
 *   Psi_I(X) = h^T(0) M^{-1}(X) h(X_I - X) phi(X_I - X)   (DESIGN.md).
 * The basis is evaluated in scaled coordinates z = (X_I - X)/s, which leaves
 * Psi unchanged (a diagonal similarity of M) and keeps M of order one. */
#include "geoscni/error.h"
#include "geoscni/kernels.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void gsn_shape_rows_free(struct gsn_shape_rows *rows)
{
    if (!rows)
        return;
    free(rows->offset);
    free(rows->index);
    free(rows->value);
    free(rows->gradient);
    memset(rows, 0, sizeof *rows);
}

/* Cubic B-spline w(r), r = |x|/a, and dw/dr (seed paper ref. [7]); the
 * normalization cancels in Psi. */
static inline void bspline(double r, double *w, double *dw)
{
    if (r <= 0.5) {
        *w = 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
        *dw = -8.0 * r + 12.0 * r * r;
    } else if (r < 1.0) {
        double q = 1.0 - r;
        *w = 4.0 / 3.0 * q * q * q;
        *dw = -4.0 * q * q;
    } else {
        *w = 0.0;
        *dw = 0.0;
    }
}

/* Monomial basis h(z) of eq. (11): 1, z0, z1, z2 [, z0^2, z1^2, z2^2,
 * z0 z1, z1 z2, z0 z2]. */
static inline void basis_eval(int size, const double *z, double *h)
{
    h[0] = 1.0;
    h[1] = z[0];
    h[2] = z[1];
    h[3] = z[2];
    if (size == 10) {
        h[4] = z[0] * z[0];
        h[5] = z[1] * z[1];
        h[6] = z[2] * z[2];
        h[7] = z[0] * z[1];
        h[8] = z[1] * z[2];
        h[9] = z[0] * z[2];
    }
}

/* dh/dz_k. */
static inline void basis_derivative(int size, const double *z, int k,
                                    double *dh)
{
    dh[0] = 0.0;
    dh[1] = k == 0;
    dh[2] = k == 1;
    dh[3] = k == 2;
    if (size == 10) {
        dh[4] = k == 0 ? 2.0 * z[0] : 0.0;
        dh[5] = k == 1 ? 2.0 * z[1] : 0.0;
        dh[6] = k == 2 ? 2.0 * z[2] : 0.0;
        dh[7] = k == 0 ? z[1] : (k == 1 ? z[0] : 0.0);
        dh[8] = k == 1 ? z[2] : (k == 2 ? z[1] : 0.0);
        dh[9] = k == 0 ? z[2] : (k == 2 ? z[0] : 0.0);
    }
}

static inline double dot(int n, const double *a, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i)
        s += a[i] * b[i];
    return s;
}

/* Cholesky M = L L^T in place (lower triangle); 1 if not positive. */
static inline int cholesky(int n, double *a)
{
    for (int j = 0; j < n; ++j) {
        double d = a[j * n + j];
        for (int k = 0; k < j; ++k)
            d -= a[j * n + k] * a[j * n + k];
        if (!(d > 0.0))
            return 1;
        d = sqrt(d);
        a[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = a[i * n + j];
            for (int k = 0; k < j; ++k)
                s -= a[i * n + k] * a[j * n + k];
            a[i * n + j] = s / d;
        }
    }
    return 0;
}

static inline void cholesky_solve(int n, const double *l, double *x)
{
    for (int i = 0; i < n; ++i) {
        double s = x[i];
        for (int k = 0; k < i; ++k)
            s -= l[i * n + k] * x[k];
        x[i] = s / l[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = x[i];
        for (int k = i + 1; k < n; ++k)
            s -= l[k * n + i] * x[k];
        x[i] = s / l[i * n + i];
    }
}

static inline double norm1(int n, const double *a)
{
    double best = 0.0;
    for (int j = 0; j < n; ++j) {
        double s = 0.0;
        for (int i = 0; i < n; ++i)
            s += fabs(a[i * n + j]);
        if (s > best)
            best = s;
    }
    return best;
}

/* Factors the moment matrix (m x m) into factor (Cholesky) and its inverse
 * (column by column through column, m doubles of scratch); *condition gets
 * the 1-norm condition number. Returns 1 if M is not positive or its
 * condition number exceeds GSN_RK_CONDITION_LIMIT. */
static inline int factor_checked(int m, const double *moment, double *factor,
                                 double *inverse, double *column,
                                 double *condition)
{
    memcpy(factor, moment, (size_t)m * (size_t)m * sizeof *factor);
    if (cholesky(m, factor))
        return 1;
    for (int j = 0; j < m; ++j) {
        memset(column, 0, (size_t)m * sizeof *column);
        column[j] = 1.0;
        cholesky_solve(m, factor, column);
        for (int i = 0; i < m; ++i)
            inverse[i * m + j] = column[i];
    }
    *condition = norm1(m, moment) * norm1(m, inverse);
    return !(*condition <= GSN_RK_CONDITION_LIMIT);
}

size_t gsn_rk_work_size(const struct gsn_rk *rk, int count)
{
    size_t m = (size_t)rk->basis_size;
    /* gsn_rk_hessian_point needs 16 per neighbour */
    return 16 * (size_t)count + 4 * m * m + 8 * m;
}

/* gsn_rk_shape_point for a basis of m terms: inlined with m a constant
 * (4 or 10), so that the small loops over the basis unroll (SCNI's rows
 * on Slope I: 18% less CPU, bench/kernels_bench). */
static inline int shape_point(const struct gsn_rk *rk, const int m,
                              const double x[3], int count, const int *index,
                              double *work, double *psi, double *gradient,
                              double *condition)
{
    const size_t mm = (size_t)m * (size_t)m;
    double *z = work;                      /* 3 per neighbour */
    double *phi = z + 3 * (size_t)count;   /* 1 */
    double *dphi = phi + count;            /* 3 */
    double *hb = dphi + 3 * (size_t)count; /* h_I . b */
    double *moment = hb + count;
    double *factor = moment + mm;
    double *inverse = factor + mm;
    double *b = inverse + mm;
    double *g = b + m; /* 3 m: dM/dX_k b, then db/dX_k */
    double *h = g + 3 * m;
    double *dh = h + m;
    *condition = INFINITY;
    if (count < m)
        return 1;

    double s = 0.0;
    for (int n = 0; n < count; ++n)
        if (rk->radius[index[n]] > s)
            s = rk->radius[index[n]];

    /* Kernel values and derivatives; moment matrix eq. (15). One division
     * a neighbour (and one for s): they were most of this loop's time. */
    const double inverse_s = 1.0 / s;
    memset(moment, 0, mm * sizeof *moment);
    for (int n = 0; n < count; ++n) {
        const double *xi = rk->position + 3 * (size_t)index[n];
        const double inverse_a = 1.0 / rk->radius[index[n]];
        double w[3], dw[3];
        for (int k = 0; k < 3; ++k) {
            double d = xi[k] - x[k];
            z[3 * n + k] = d * inverse_s;
            bspline(fabs(d) * inverse_a, &w[k], &dw[k]);
            /* d r_k / d X_k = sign(X_k - X_Ik) / a */
            dw[k] *= d > 0.0 ? -inverse_a : inverse_a;
        }
        phi[n] = w[0] * w[1] * w[2];
        if (gradient) {
            dphi[3 * n + 0] = dw[0] * w[1] * w[2];
            dphi[3 * n + 1] = w[0] * dw[1] * w[2];
            dphi[3 * n + 2] = w[0] * w[1] * dw[2];
        }
        basis_eval(m, z + 3 * n, h);
        for (int i = 0; i < m; ++i)
            for (int j = 0; j <= i; ++j)
                moment[i * m + j] += phi[n] * h[i] * h[j];
    }
    for (int i = 0; i < m; ++i)
        for (int j = i + 1; j < m; ++j)
            moment[i * m + j] = moment[j * m + i];

    /* b = M^{-1} h(0), eq. (14); the condition number from the inverse. */
    if (factor_checked(m, moment, factor, inverse, h, condition))
        return 1;
    for (int i = 0; i < m; ++i)
        b[i] = inverse[i * m + 0];

    for (int n = 0; n < count; ++n) {
        basis_eval(m, z + 3 * n, h);
        hb[n] = dot(m, h, b);
        psi[n] = hb[n] * phi[n]; /* eq. (16) */
    }
    if (!gradient)
        return 0;

    /* dM/dX_k b, with dh_I/dX_k = -(1/s) dh/dz_k. */
    memset(g, 0, 3 * (size_t)m * sizeof *g);
    if (m == 4) {
        /* linear basis: dh/dz_k = e_(k+1), so
         * dM/dX_k b = sum_I (dphi_k hb - phi b_(k+1)/s) h_I
         *             - e_(k+1) sum_I phi hb / s */
        double sum = 0.0;
        for (int n = 0; n < count; ++n) {
            const double *zn = z + 3 * n;
            sum += phi[n] * hb[n];
            for (int k = 0; k < 3; ++k) {
                double c = dphi[3 * n + k] * hb[n] - phi[n] * b[k + 1] / s;
                double *gk = g + 4 * k;
                gk[0] += c;
                gk[1] += c * zn[0];
                gk[2] += c * zn[1];
                gk[3] += c * zn[2];
            }
        }
        for (int k = 0; k < 3; ++k)
            g[4 * k + k + 1] -= sum / s;
    } else {
        for (int n = 0; n < count; ++n) {
            basis_eval(m, z + 3 * n, h);
            for (int k = 0; k < 3; ++k) {
                basis_derivative(m, z + 3 * n, k, dh);
                double dhb = -dot(m, dh, b) / s;
                double *gk = g + k * m;
                for (int i = 0; i < m; ++i)
                    gk[i] += dphi[3 * n + k] * hb[n] * h[i] +
                             phi[n] * (-hb[n] * dh[i] / s + dhb * h[i]);
            }
        }
    }
    /* db/dX_k = -M^{-1} (dM/dX_k) b */
    for (int k = 0; k < 3; ++k) {
        double *gk = g + k * m;
        cholesky_solve(m, factor, gk);
        for (int i = 0; i < m; ++i)
            gk[i] = -gk[i];
    }
    for (int n = 0; n < count; ++n) {
        if (m == 4) {
            const double *zn = z + 3 * n;
            for (int k = 0; k < 3; ++k) {
                const double *gk = g + 4 * k;
                double dbh =
                    gk[0] + gk[1] * zn[0] + gk[2] * zn[1] + gk[3] * zn[2];
                gradient[3 * n + k] =
                    (dbh - b[k + 1] / s) * phi[n] + hb[n] * dphi[3 * n + k];
            }
            continue;
        }
        basis_eval(m, z + 3 * n, h);
        for (int k = 0; k < 3; ++k) {
            basis_derivative(m, z + 3 * n, k, dh);
            gradient[3 * n + k] = dot(m, g + k * m, h) * phi[n] -
                                  dot(m, b, dh) / s * phi[n] +
                                  hb[n] * dphi[3 * n + k];
        }
    }
    return 0;
}

int gsn_rk_shape_point(const struct gsn_rk *rk, const double x[3], int count,
                       const int *index, double *work, double *psi,
                       double *gradient, double *condition)
{
    return rk->basis_size == 4 ? shape_point(rk, 4, x, count, index, work, psi,
                                             gradient, condition)
                               : shape_point(rk, 10, x, count, index, work, psi,
                                             gradient, condition);
}

/* d^2 w / dr^2 of bspline. */
static inline double bspline_second(double r)
{
    if (r <= 0.5)
        return -8.0 + 24.0 * r;
    return r < 1.0 ? 8.0 * (1.0 - r) : 0.0;
}

/* Psi_I = phi_I h_I^T b with M b = e_0 (eq. (16)), h_I = h((X_I - X)/s)
 * linear, so dh_I/dX_k = -e_(k+1)/s and d^2 h_I = 0. Differentiating
 * M b = e_0 twice:
 *   b_k  = -M^-1 M_k b,   b_jk = -M^-1 (M_jk b + M_j b_k + M_k b_j),
 *   Psi_jk = phi_jk h.b + phi_j (h_k.b + h.b_k) + phi_k (h_j.b + h.b_j)
 *            + phi (h_j.b_k + h_k.b_j + h.b_jk),
 * with M_k and M_jk the derivatives of sum_I phi_I h_I h_I^T. */
int gsn_rk_hessian_point(const struct gsn_rk *rk, const double x[3], int count,
                         const int *index, double *work, double *hessian,
                         double *condition)
{
    enum { M = 4 };
    *condition = INFINITY;
    if (rk->basis_size != M || count < M)
        return 1;
    double *z = work;                         /* 3 per neighbour */
    double *phi = z + 3 * (size_t)count;      /* 1 */
    double *dphi = phi + count;               /* 3 */
    double *ddphi = dphi + 3 * (size_t)count; /* 9 */
    double s = 0.0;
    for (int n = 0; n < count; ++n)
        s = fmax(s, rk->radius[index[n]]);

    double moment[M * M] = {0}, dmoment[3][M * M] = {{0}};
    double ddmoment[9][M * M] = {{0}};
    for (int n = 0; n < count; ++n) {
        const double *xi = rk->position + 3 * (size_t)index[n];
        const double a = rk->radius[index[n]];
        double w[3], dw[3], ddw[3];
        for (int k = 0; k < 3; ++k) {
            double d = xi[k] - x[k], r = fabs(d) / a;
            z[3 * n + k] = d / s;
            bspline(r, &w[k], &dw[k]);
            dw[k] *= (d > 0.0 ? -1.0 : 1.0) / a;
            ddw[k] = bspline_second(r) / (a * a);
        }
        phi[n] = w[0] * w[1] * w[2];
        for (int j = 0; j < 3; ++j) {
            dphi[3 * n + j] = dw[j] * w[(j + 1) % 3] * w[(j + 2) % 3];
            for (int k = 0; k < 3; ++k)
                ddphi[9 * n + 3 * j + k] =
                    j == k ? ddw[j] * w[(j + 1) % 3] * w[(j + 2) % 3]
                           : dw[j] * dw[k] * w[3 - j - k];
        }
        double h[M] = {1.0, z[3 * n], z[3 * n + 1], z[3 * n + 2]};
        for (int i = 0; i < M; ++i)
            for (int l = 0; l < M; ++l) {
                double hh = h[i] * h[l];
                moment[M * i + l] += phi[n] * hh;
                for (int j = 0; j < 3; ++j) {
                    /* h_j h^T + h h_j^T, h_j = -e_(j+1)/s */
                    double hjh =
                        -((i == j + 1) * h[l] + h[i] * (l == j + 1)) / s;
                    dmoment[j][M * i + l] +=
                        dphi[3 * n + j] * hh + phi[n] * hjh;
                    for (int k = 0; k < 3; ++k) {
                        double hkh =
                            -((i == k + 1) * h[l] + h[i] * (l == k + 1)) / s;
                        double hjhk = ((i == j + 1) * (l == k + 1) +
                                       (i == k + 1) * (l == j + 1)) /
                                      (s * s);
                        ddmoment[3 * j + k][M * i + l] +=
                            ddphi[9 * n + 3 * j + k] * hh +
                            dphi[3 * n + j] * hkh + dphi[3 * n + k] * hjh +
                            phi[n] * hjhk;
                    }
                }
            }
    }
    double factor[M * M], inverse[M * M], column[M];
    if (factor_checked(M, moment, factor, inverse, column, condition))
        return 1;
    double b[M], bk[3][M], bjk[9][M];
    for (int i = 0; i < M; ++i)
        b[i] = inverse[i * M];
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < M; ++i)
            bk[k][i] = -dot(M, &dmoment[k][M * i], b);
        cholesky_solve(M, factor, bk[k]);
    }
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            double *r = bjk[3 * j + k];
            for (int i = 0; i < M; ++i)
                r[i] = -(dot(M, &ddmoment[3 * j + k][M * i], b) +
                         dot(M, &dmoment[j][M * i], bk[k]) +
                         dot(M, &dmoment[k][M * i], bk[j]));
            cholesky_solve(M, factor, r);
        }
    for (int n = 0; n < count; ++n) {
        double h[M] = {1.0, z[3 * n], z[3 * n + 1], z[3 * n + 2]};
        double hb = dot(M, h, b);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                double hjb = -b[j + 1] / s, hkb = -b[k + 1] / s;
                hessian[9 * n + 3 * j + k] =
                    ddphi[9 * n + 3 * j + k] * hb +
                    dphi[3 * n + j] * (hkb + dot(M, h, bk[k])) +
                    dphi[3 * n + k] * (hjb + dot(M, h, bk[j])) +
                    phi[n] * (-bk[k][j + 1] / s - bk[j][k + 1] / s +
                              dot(M, h, bjk[3 * j + k]));
            }
    }
    return 0;
}

static int grid_cell(const struct gsn_rk_grid *g, int k, double x)
{
    double c = floor((x - g->origin[k]) / g->cell_size);
    if (c < 0.0)
        return 0;
    if (c > g->size[k] - 1)
        return g->size[k] - 1;
    return (int)c;
}

/* The index of the grid cell holding x (clamped to the grid). */
static size_t grid_index(const struct gsn_rk_grid *g, const double x[3])
{
    return (size_t)grid_cell(g, 0, x[0]) +
           (size_t)g->size[0] * ((size_t)grid_cell(g, 1, x[1]) +
                                 (size_t)g->size[1] * grid_cell(g, 2, x[2]));
}

void gsn_sort_ints(int *a, int n)
{
    while (n > 16) {
        int m = a[n / 2], i = 0, j = n - 1;
        int lo = a[0] < m ? a[0] : m, hi = a[0] < m ? m : a[0];
        int pivot = a[n - 1] < lo ? lo : a[n - 1] > hi ? hi : a[n - 1];
        while (i <= j) {
            while (a[i] < pivot)
                ++i;
            while (a[j] > pivot)
                --j;
            if (i <= j) {
                int v = a[i];
                a[i++] = a[j];
                a[j--] = v;
            }
        }
        /* the smaller part by recursion, the larger by the loop */
        if (j + 1 < n - i) {
            gsn_sort_ints(a, j + 1);
            a += i;
            n -= i;
        } else {
            gsn_sort_ints(a + i, n - i);
            n = j + 1;
        }
    }
    for (int i = 1; i < n; ++i) {
        int v = a[i], j = i - 1;
        while (j >= 0 && a[j] > v) {
            a[j + 1] = a[j];
            --j;
        }
        a[j + 1] = v;
    }
}

/* 1 if the support of the particle at xp (radius a) covers x: inside its
 * box and, with a window cut, where its window w(r0) w(r1) w(r2) is at
 * least the cut times its peak w(0)^3 = (2/3)^3. */
static inline int covers(const struct gsn_rk *rk, const double *xp, double a,
                         const double *x)
{
    if (!(fabs(x[0] - xp[0]) < a && fabs(x[1] - xp[1]) < a &&
          fabs(x[2] - xp[2]) < a))
        return 0;
    if (!(rk->window_cut > 0.0))
        return 1;
    double window = 1.0, w, dw;
    for (int k = 0; k < 3; ++k) {
        bspline(fabs(x[k] - xp[k]) / a, &w, &dw);
        window *= 1.5 * w; /* w / w(0) */
    }
    return window >= rk->window_cut;
}

/* The particles of the cell lists whose kernel covers the point x (x not
 * NULL: covers) or reaches the box [lo, hi] (x NULL), into index (the
 * first capacity), in ascending order if they fit. Returns their number. */
static int cell_walk(const struct gsn_rk *rk, const double lo[3],
                     const double hi[3], const double *x, int capacity,
                     int *index)
{
    int count = 0;
    for (int level = 0; level < 2; ++level) {
        const struct gsn_rk_grid *g = &rk->grid[level];
        if (g->count == 0)
            continue;
        int c_lo[3], c_hi[3];
        for (int k = 0; k < 3; ++k) {
            c_lo[k] = grid_cell(g, k, lo[k] - g->max_radius);
            c_hi[k] = grid_cell(g, k, hi[k] + g->max_radius);
        }
        for (int c2 = c_lo[2]; c2 <= c_hi[2]; ++c2)
            for (int c1 = c_lo[1]; c1 <= c_hi[1]; ++c1)
                for (int c0 = c_lo[0]; c0 <= c_hi[0]; ++c0) {
                    size_t cell =
                        (size_t)c0 + (size_t)g->size[0] *
                                         ((size_t)c1 + (size_t)g->size[1] * c2);
                    for (int e = g->cell_offset[cell];
                         e < g->cell_offset[cell + 1]; ++e) {
                        const double *xp = g->cell_data + 4 * (size_t)e;
                        double a = xp[3];
                        int hit =
                            x ? covers(rk, xp, a, x)
                              : xp[0] - a < hi[0] && xp[0] + a > lo[0] &&
                                    xp[1] - a < hi[1] && xp[1] + a > lo[1] &&
                                    xp[2] - a < hi[2] && xp[2] + a > lo[2];
                        if (hit) {
                            if (count < capacity)
                                index[count] = g->cell_particle[e];
                            ++count;
                        }
                    }
                }
    }
    if (count <= capacity)
        gsn_sort_ints(index, count);
    return count;
}

int gsn_rk_neighbours(const struct gsn_rk *rk, const double x[3], int capacity,
                      int *index)
{
    return cell_walk(rk, x, x, x, capacity, index);
}

int gsn_rk_box_neighbours(const struct gsn_rk *rk, const double lo[3],
                          const double hi[3], int capacity, int *index)
{
    /* widened by a rounding's worth, so that every particle the point test
     * takes for a point of the box is among them, however the two tests
     * round */
    double pad = 1e-12 * rk->max_radius, wide_lo[3], wide_hi[3];
    for (int k = 0; k < 3; ++k) {
        double scale = 1e-15 * (fabs(lo[k]) + fabs(hi[k]));
        wide_lo[k] = lo[k] - pad - scale;
        wide_hi[k] = hi[k] + pad + scale;
    }
    return cell_walk(rk, wide_lo, wide_hi, NULL, capacity, index);
}

int gsn_rk_neighbours_among(const struct gsn_rk *rk, const double x[3],
                            const int *candidate, int candidate_count,
                            int capacity, int *index)
{
    int count = 0;
    for (int c = 0; c < candidate_count; ++c) {
        int p = candidate[c];
        const double *xp = rk->position + 3 * (size_t)p;
        double a = rk->radius[p];
        if (covers(rk, xp, a, x)) {
            if (count < capacity)
                index[count] = p;
            ++count;
        }
    }
    return count;
}

void gsn_rk_destroy(struct gsn_rk **rk)
{
    if (!rk || !*rk)
        return;
    free((*rk)->position);
    free((*rk)->radius);
    for (int level = 0; level < 2; ++level) {
        free((*rk)->grid[level].cell_offset);
        free((*rk)->grid[level].cell_particle);
        free((*rk)->grid[level].cell_data);
    }
    free(*rk);
    *rk = NULL;
}

/* A particle whose support is wider than this many times the median goes
 * to the wide grid (gsn_rk, grid). */
#define GRID_WIDE 1.5

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of the n radii (0 if out of memory). */
static double median_radius(const double *radius, size_t n)
{
    double *copy = malloc(n * sizeof *copy);
    if (!copy)
        return 0.0;
    memcpy(copy, radius, n * sizeof *copy);
    qsort(copy, n, sizeof *copy, compare_double);
    double median = copy[n / 2];
    free(copy);
    return median;
}

/* The cell list of grid `level` (0: radius <= wide, 1: wider) over the
 * box [lo, hi]: cells of its largest radius, coarser if that would give
 * far more cells than particles. */
static int grid_build(struct gsn_rk *rk, int level, double wide,
                      const double lo[3], const double hi[3])
{
    struct gsn_rk_grid *g = &rk->grid[level];
    size_t n = (size_t)rk->particle_count;
    g->count = 0;
    g->max_radius = 0.0;
    for (size_t p = 0; p < n; ++p)
        if ((rk->radius[p] > wide) == level) {
            g->count++;
            g->max_radius = fmax(g->max_radius, rk->radius[p]);
        }
    if (g->count == 0)
        return GSN_OK;
    g->cell_size = g->max_radius;
    for (;;) {
        double cells = 1.0;
        for (int k = 0; k < 3; ++k)
            cells *= floor((hi[k] - lo[k]) / g->cell_size) + 1.0;
        if (cells <= 8.0 * (double)g->count + 64.0)
            break;
        g->cell_size *= 1.5;
    }
    size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
        g->origin[k] = lo[k];
        g->size[k] = (int)floor((hi[k] - lo[k]) / g->cell_size) + 1;
        cells *= (size_t)g->size[k];
    }
    g->cell_offset = calloc(cells + 1, sizeof *g->cell_offset);
    g->cell_particle = malloc((size_t)g->count * sizeof *g->cell_particle);
    g->cell_data = malloc(4 * (size_t)g->count * sizeof *g->cell_data);
    GSN_CHECK(g->cell_offset && g->cell_particle && g->cell_data,
              GSN_ERR_MEMORY, "cannot allocate the cell list");
    for (size_t p = 0; p < n; ++p)
        if ((rk->radius[p] > wide) == level)
            g->cell_offset[grid_index(g, rk->position + 3 * p) + 1]++;
    for (size_t c = 0; c < cells; ++c)
        g->cell_offset[c + 1] += g->cell_offset[c];
    /* Fill in particle order so each cell lists ascending indices. */
    for (size_t p = 0; p < n; ++p)
        if ((rk->radius[p] > wide) == level)
            g->cell_particle[g->cell_offset[grid_index(
                g, rk->position + 3 * p)]++] = (int)p;
    for (size_t c = cells; c > 0; --c)
        g->cell_offset[c] = g->cell_offset[c - 1];
    g->cell_offset[0] = 0;
    for (int e = 0; e < g->count; ++e) {
        size_t p = (size_t)g->cell_particle[e];
        for (int k = 0; k < 3; ++k)
            g->cell_data[4 * (size_t)e + k] = rk->position[3 * p + k];
        g->cell_data[4 * (size_t)e + 3] = rk->radius[p];
    }
    return GSN_OK;
}

int gsn_rk_create(int particle_count, const double *position,
                  const double *spacing, double support, int basis_order,
                  struct gsn_rk **out)
{
    *out = NULL;
    GSN_CHECK(particle_count > 0, GSN_ERR_INPUT, "no particles");
    GSN_CHECK(support > 0.0 && isfinite(support), GSN_ERR_INPUT,
              "kernel support %g must be positive", support);
    GSN_CHECK(basis_order == 1 || basis_order == 2, GSN_ERR_INPUT,
              "basis order %d: only 1 (linear) or 2 (quadratic)", basis_order);
    size_t n = (size_t)particle_count;
    struct gsn_rk *rk = calloc(1, sizeof *rk);
    GSN_CHECK(rk != NULL, GSN_ERR_MEMORY, "cannot allocate the RK struct");
    int rc = GSN_OK;
    rk->particle_count = particle_count;
    rk->basis_order = basis_order;
    rk->basis_size = basis_order == 1 ? 4 : 10;
    rk->position = malloc(3 * n * sizeof *rk->position);
    rk->radius = malloc(n * sizeof *rk->radius);
    GSN_CHECK_GOTO(rk->position && rk->radius, rc, GSN_ERR_MEMORY, fail,
                   "cannot allocate %d particles", particle_count);
    memcpy(rk->position, position, 3 * n * sizeof *rk->position);
    double lo[3] = {INFINITY, INFINITY, INFINITY};
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    rk->max_radius = 0.0;
    for (size_t p = 0; p < n; ++p) {
        GSN_CHECK_GOTO(
            spacing[p] > 0.0 && isfinite(spacing[p]), rc, GSN_ERR_INPUT, fail,
            "particle %zu: spacing %g must be positive", p, spacing[p]);
        rk->radius[p] = support * spacing[p];
        if (rk->radius[p] > rk->max_radius)
            rk->max_radius = rk->radius[p];
        for (int k = 0; k < 3; ++k) {
            double v = position[3 * p + k];
            GSN_CHECK_GOTO(isfinite(v), rc, GSN_ERR_INPUT, fail,
                           "particle %zu: position is not finite", p);
            lo[k] = fmin(lo[k], v);
            hi[k] = fmax(hi[k], v);
        }
    }
    double wide = GRID_WIDE * median_radius(rk->radius, n);
    GSN_CHECK_GOTO(wide > 0.0, rc, GSN_ERR_MEMORY, fail,
                   "cannot sort %zu radii", n);
    for (int level = 0; level < 2; ++level)
        GSN_CALL_GOTO(grid_build(rk, level, wide, lo, hi), rc, fail);
    *out = rk;
    return GSN_OK;
fail:
    gsn_rk_destroy(&rk);
    return rc;
}

/* gsn_rk_spacing_from_facets: supports raised to cover a farther
 * neighbour past COVER_STRETCH times their own, up to COVER_LIMIT times. */
static const double COVER_STRETCH = 1.25, COVER_LIMIT = 2.0;

int gsn_rk_spacing_from_facets(const struct gsn_model *m, double cover_support,
                               double *spacing)
{
    int n = m->particle_count;
    double *area = calloc(2 * ((size_t)n > 0 ? (size_t)n : 1), sizeof *area);
    GSN_CHECK(area != NULL, GSN_ERR_MEMORY, "cannot allocate %d doubles", n);
    double *farthest = area + (n > 0 ? n : 1);
    for (int p = 0; p < n; ++p)
        spacing[p] = 0.0;
    for (int f = 0; f < m->facet_count; ++f) {
        int o = m->facet_owner[f], q = m->facet_neighbour[f];
        if (q < 0)
            continue;
        const double *xo = m->position + 3 * (size_t)o;
        const double *xq = m->position + 3 * (size_t)q;
        double d = sqrt((xo[0] - xq[0]) * (xo[0] - xq[0]) +
                        (xo[1] - xq[1]) * (xo[1] - xq[1]) +
                        (xo[2] - xq[2]) * (xo[2] - xq[2]));
        double a = m->facet_area[f];
        spacing[o] += a * d;
        spacing[q] += a * d;
        area[o] += a;
        area[q] += a;
        if (a > 0.0) {
            farthest[o] = d > farthest[o] ? d : farthest[o];
            farthest[q] = d > farthest[q] ? d : farthest[q];
        }
    }
    for (int p = 0; p < n; ++p) {
        if (!(area[p] > 0.0)) {
            free(area);
            GSN_CHECK(0, GSN_ERR_INPUT,
                      "particle %d shares no facet with another particle: "
                      "no local spacing",
                      p);
        }
        spacing[p] /= area[p];
        /* 1e-6 past the farthest neighbour: inside the support; only
         * where a cell is stretched (an undeformed mesh has 0.5% of its
         * particles past 1.25, half of them past 1), and at most twice the
         * support (a neighbour farther off is an outlier, not a sliver) */
        double cover = farthest[p] * (1.0 + 1e-6) / cover_support;
        if (cover_support > 0.0 && cover > COVER_STRETCH * spacing[p])
            spacing[p] = fmin(cover, COVER_LIMIT * spacing[p]);
    }
    free(area);
    return GSN_OK;
}
