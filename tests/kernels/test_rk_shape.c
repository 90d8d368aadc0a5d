/* RK shape functions (seed paper eqs. (9)-(18)): the cell-list neighbour
 * search against brute force, the reproducing conditions of eq. (18) at
 * random points, gradients against finite differences, thread-count
 * independence, and the error for a singular moment matrix. */
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "kernel_fixtures.h"
#include "testing.h"

#include <omp.h>
#include <string.h>

static int brute_neighbours(const struct gsn_rk *rk, const double *x, int *out)
{
    int count = 0;
    for (int p = 0; p < rk->particle_count; ++p) {
        const double *xp = rk->position + 3 * p;
        double a = rk->radius[p];
        if (fabs(x[0] - xp[0]) < a && fabs(x[1] - xp[1]) < a &&
            fabs(x[2] - xp[2]) < a)
            out[count++] = p;
    }
    return count;
}

/* Checks eq. (17) up to the basis order at point x. */
static double reproducing_error(const struct gsn_rk *rk, const double *x,
                                int count, const int *index, const double *psi,
                                const double *grad)
{
    double err = 0.0;
    /* monomials X^p for |p| <= order, and their derivatives */
    int order = rk->basis_order;
    for (int p0 = 0; p0 <= order; ++p0)
        for (int p1 = 0; p1 + p0 <= order; ++p1)
            for (int p2 = 0; p2 + p1 + p0 <= order; ++p2) {
                int pw[3] = {p0, p1, p2};
                double v = 0.0, g[3] = {0, 0, 0};
                for (int n = 0; n < count; ++n) {
                    const double *xi = rk->position + 3 * index[n];
                    double mono =
                        pow(xi[0], p0) * pow(xi[1], p1) * pow(xi[2], p2);
                    v += psi[n] * mono;
                    for (int k = 0; k < 3; ++k)
                        g[k] += grad[3 * n + k] * mono;
                }
                double exact = pow(x[0], p0) * pow(x[1], p1) * pow(x[2], p2);
                err = fmax(err, fabs(v - exact));
                for (int k = 0; k < 3; ++k) {
                    double d = 0.0;
                    if (pw[k] > 0) {
                        int q[3] = {p0, p1, p2};
                        q[k] -= 1;
                        d = pw[k] * pow(x[0], q[0]) * pow(x[1], q[1]) *
                            pow(x[2], q[2]);
                    }
                    err = fmax(err, fabs(g[k] - d));
                }
            }
    return err;
}

static void check_basis(int order, double jitter, double support)
{
    enum { N = 7, POINTS = 400 };
    int np = N * N * N;
    double *x = malloc(3 * (size_t)np * sizeof *x);
    double *h = malloc((size_t)np * sizeof *h);
    fixture_jittered_lattice(N, 1.0 / (N - 1), jitter,
                             12345ULL + (unsigned long long)order, x);
    for (int p = 0; p < np; ++p)
        h[p] = 1.0 / (N - 1);
    struct gsn_rk *rk = NULL;
    TEST_INT(gsn_rk_create(np, x, h, support, order, &rk), GSN_OK);
    int index[GSN_RK_MAX_NEIGHBOURS], brute[GSN_RK_MAX_NEIGHBOURS];
    double *work =
        malloc(gsn_rk_work_size(rk, GSN_RK_MAX_NEIGHBOURS) * sizeof *work);
    double psi[GSN_RK_MAX_NEIGHBOURS], grad[3 * GSN_RK_MAX_NEIGHBOURS];
    double psi_p[GSN_RK_MAX_NEIGHBOURS], psi_m[GSN_RK_MAX_NEIGHBOURS];
    double max_err = 0.0, max_fd = 0.0, max_cond = 0.0;
    int mismatches = 0;
    unsigned long long seed = 99;
    for (int t = 0; t < POINTS; ++t) {
        double q[3];
        for (int k = 0; k < 3; ++k)
            q[k] = fixture_uniform(&seed);
        if (t < 8) /* the corners of the box */
            for (int k = 0; k < 3; ++k)
                q[k] = (t >> k) & 1;
        int count = gsn_rk_neighbours(rk, q, GSN_RK_MAX_NEIGHBOURS, index);
        int nb = brute_neighbours(rk, q, brute);
        if (count != nb || memcmp(index, brute, (size_t)nb * sizeof(int)))
            ++mismatches;
        double cond;
        TEST_INT(
            gsn_rk_shape_point(rk, q, count, index, work, psi, grad, &cond), 0);
        max_cond = fmax(max_cond, cond);
        max_err =
            fmax(max_err, reproducing_error(rk, q, count, index, psi, grad));
        /* central differences: truncation O(step^2 |Psi'''|) ~ 1e-8 h^-1
         * for step 1e-5 and h = 1/6, cancellation 1e-16/step ~ 1e-11 */
        double step = 1e-5;
        for (int k = 0; k < 3; ++k) {
            double qp[3] = {q[0], q[1], q[2]}, qm[3] = {q[0], q[1], q[2]};
            qp[k] += step;
            qm[k] -= step;
            /* keep the same neighbour list: kernels vanish smoothly (C2) */
            gsn_rk_shape_point(rk, qp, count, index, work, psi_p, NULL, &cond);
            gsn_rk_shape_point(rk, qm, count, index, work, psi_m, NULL, &cond);
            for (int n = 0; n < count; ++n)
                max_fd = fmax(max_fd, fabs((psi_p[n] - psi_m[n]) / (2 * step) -
                                           grad[3 * n + k]) *
                                          h[0]);
        }
    }
    printf("basis %d jitter %.2f support %.2f: eq. (18) max error %.2e, "
           "gradient vs FD %.2e, max condition %.3g\n",
           order, jitter, support, max_err, max_fd, max_cond);
    TEST_INT(mismatches, 0);
    /* eq. (18) is an identity: round-off of O(condition x eps) ~ 1e-13 */
    TEST_TRUE(max_err <= 1e-12);
    /* see the step comment above; scaled by h to be dimensionless */
    TEST_TRUE(max_fd <= 1e-7);
    free(work);
    gsn_rk_destroy(&rk);
    free(x);
    free(h);
}

/* NSNI's second derivatives (linear basis): they annihilate the linear
 * basis (the derivative of eq. (18) twice), are symmetric, and agree with
 * central differences of the gradient. */
static void check_hessian(double jitter, double support)
{
    enum { N = 7, POINTS = 200 };
    int np = N * N * N;
    double hh = 1.0 / (N - 1);
    double *x = malloc(3 * (size_t)np * sizeof *x);
    double *h = malloc((size_t)np * sizeof *h);
    fixture_jittered_lattice(N, hh, jitter, 777ULL, x);
    for (int p = 0; p < np; ++p)
        h[p] = hh;
    struct gsn_rk *rk = NULL;
    TEST_INT(gsn_rk_create(np, x, h, support, 1, &rk), GSN_OK);
    int index[GSN_RK_MAX_NEIGHBOURS];
    double *work =
        malloc(gsn_rk_work_size(rk, GSN_RK_MAX_NEIGHBOURS) * sizeof *work);
    double *hess = malloc(9 * GSN_RK_MAX_NEIGHBOURS * sizeof *hess);
    double psi[GSN_RK_MAX_NEIGHBOURS], gp[3 * GSN_RK_MAX_NEIGHBOURS];
    double gm[3 * GSN_RK_MAX_NEIGHBOURS];
    double max_identity = 0.0, max_asym = 0.0, max_fd = 0.0;
    long entries = 0, above = 0;
    unsigned long long seed = 5;
    for (int t = 0; t < POINTS; ++t) {
        double q[3], cond;
        for (int k = 0; k < 3; ++k)
            q[k] = fixture_uniform(&seed);
        int count = gsn_rk_neighbours(rk, q, GSN_RK_MAX_NEIGHBOURS, index);
        TEST_INT(gsn_rk_hessian_point(rk, q, count, index, work, hess, &cond),
                 0);
        for (int a = 0; a < 9; ++a) {
            /* sum_I Psi_I,jk p(X_I) = 0 for p = 1, x, y, z; scaled by h^2 */
            double sum[4] = {0, 0, 0, 0};
            for (int n = 0; n < count; ++n) {
                const double *xi = x + 3 * (size_t)index[n];
                double v = hess[9 * n + a];
                sum[0] += v;
                for (int k = 0; k < 3; ++k)
                    sum[k + 1] += v * (xi[k] - q[k]) / hh;
            }
            for (int k = 0; k < 4; ++k)
                max_identity = fmax(max_identity, fabs(sum[k]) * hh * hh);
        }
        for (int n = 0; n < count; ++n)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k)
                    max_asym = fmax(max_asym, fabs(hess[9 * n + 3 * j + k] -
                                                   hess[9 * n + 3 * k + j]) *
                                                  hh * hh);
        double step = 1e-6;
        for (int k = 0; k < 3; ++k) {
            double qp[3] = {q[0], q[1], q[2]}, qm[3] = {q[0], q[1], q[2]};
            qp[k] += step;
            qm[k] -= step;
            gsn_rk_shape_point(rk, qp, count, index, work, psi, gp, &cond);
            gsn_rk_shape_point(rk, qm, count, index, work, psi, gm, &cond);
            for (int n = 0; n < count; ++n)
                for (int j = 0; j < 3; ++j) {
                    double fd = (gp[3 * n + j] - gm[3 * n + j]) / (2 * step);
                    double e = fabs(fd - hess[9 * n + 3 * j + k]) * hh * hh;
                    max_fd = fmax(max_fd, e);
                    above += e > 1e-7;
                    ++entries;
                }
        }
    }
    printf("hessian, jitter %.2f support %.2f: identity %.2e, asymmetry "
           "%.2e, vs FD of the gradient max %.2e (%ld of %ld above 1e-7)\n",
           jitter, support, max_identity, max_asym, max_fd, above, entries);
    /* identities: round-off of O(condition x eps) */
    TEST_TRUE(max_identity <= 1e-11);
    TEST_TRUE(max_asym <= 1e-11);
    /* the spline's third derivative jumps at r = 0.5 and 1, so a
     * difference that straddles a jump errs by up to step |jump| h^2 ~
     * 1e-6 x 6^3 / 36 ~ 6e-6; elsewhere it is O(step^2) and cancellation
     * (1e-16 / step ~ 1e-10, scaled) */
    TEST_TRUE(max_fd <= 1e-5); /* measured 2e-9 */
    TEST_TRUE(above * 100 <= entries);
    free(hess);
    free(work);
    gsn_rk_destroy(&rk);
    free(x);
    free(h);
}

/* Rows at points: sorted, equal to the point kernel, and bitwise the same
 * with one and two threads. */
static void check_rows_threads(void)
{
    enum { N = 6 };
    int np = N * N * N;
    double *x = malloc(3 * (size_t)np * sizeof *x);
    double *h = malloc((size_t)np * sizeof *h);
    fixture_jittered_lattice(N, 1.0 / (N - 1), 0.2, 7ULL, x);
    for (int p = 0; p < np; ++p)
        h[p] = 1.0 / (N - 1);
    struct gsn_rk *rk = NULL;
    TEST_INT(gsn_rk_create(np, x, h, 1.5, 1, &rk), GSN_OK);
    struct gsn_shape_rows one, two;
    omp_set_num_threads(1);
    TEST_INT(gsn_rk_shape_rows(rk, np, x, 1, &one), GSN_OK);
    omp_set_num_threads(2);
    TEST_INT(gsn_rk_shape_rows(rk, np, x, 1, &two), GSN_OK);
    int nnz = one.offset[np];
    TEST_INT(two.offset[np], nnz);
    TEST_TRUE(!memcmp(one.index, two.index, (size_t)nnz * sizeof(int)));
    TEST_TRUE(!memcmp(one.value, two.value, (size_t)nnz * sizeof(double)));
    TEST_TRUE(
        !memcmp(one.gradient, two.gradient, 3 * (size_t)nnz * sizeof(double)));
    int sorted = 1;
    for (int r = 0; r < np; ++r)
        for (int e = one.offset[r] + 1; e < one.offset[r + 1]; ++e)
            sorted &= one.index[e - 1] < one.index[e];
    TEST_TRUE(sorted);
    printf("rows at %d particles: %d entries (%.1f per row), threads 1 and "
           "2 identical\n",
           np, nnz, (double)nnz / np);
    gsn_shape_rows_free(&one);
    gsn_shape_rows_free(&two);
    gsn_rk_destroy(&rk);
    free(x);
    free(h);
}

/* Particles on one plane: M is singular off and on the plane; the error
 * names the point and its neighbour count, and nothing is NaN. */
static void check_singular(void)
{
    enum { N = 5 };
    double x[3 * N * N], h[N * N];
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            x[3 * (j * N + i) + 0] = i;
            x[3 * (j * N + i) + 1] = j;
            x[3 * (j * N + i) + 2] = 0.0;
            h[j * N + i] = 1.0;
        }
    struct gsn_rk *rk = NULL;
    TEST_INT(gsn_rk_create(N * N, x, h, 1.5, 1, &rk), GSN_OK);
    double q[3] = {2.0, 2.0, 0.25};
    struct gsn_shape_rows rows;
    gsn_error_clear();
    TEST_INT(gsn_rk_shape_rows(rk, 1, q, 1, &rows), GSN_ERR_NUMERICAL);
    const char *msg = gsn_error_message();
    printf("singular moment matrix: %s\n", msg);
    TEST_TRUE(strstr(msg, "point 0") != NULL);
    TEST_TRUE(strstr(msg, "with 9 particles") != NULL);
    TEST_TRUE(rows.offset == NULL);
    gsn_error_clear();
    gsn_rk_destroy(&rk);
}

int main(void)
{
    test_begin();
    check_basis(1, 0.0, 1.5);
    check_basis(1, 0.3, 1.5);
    check_basis(2, 0.2, 2.5);
    check_hessian(0.0, 1.5);
    check_hessian(0.3, 2.0);
    check_rows_threads();
    check_singular();
    return test_end("test_rk_shape");
}
