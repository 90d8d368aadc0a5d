/* The averaging rows of nonlocal damage (nonlocal.h) on a lattice of
 * 17^3 points, spacing h, with the points of one corner octant jittered:
 * every row sums to 1, so a constant field is its own average; away from
 * the faces and the jitter the ball is symmetric, so a linear field is too
 * (the jittered points' rows are not: the control); the weight of a pair
 * is the bell (1 - r^2/L^2)^2 V_q over the row's sum; a point without a
 * length keeps its value; the rows do not depend on the thread count; a
 * ball of more than GSN_RK_MAX_NEIGHBOURS points is refused with its
 * length. */
#include "nonlocal.h"

#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "testing.h"

#include <omp.h>
#include <string.h>

enum { SIDE = 17, N = SIDE * SIDE * SIDE }; /* 4913 > 4096 */
static const double H = 0.25, L = 2.5 * 0.25;

static int jittered(const double *x)
{
    return x[0] < 3 * H && x[1] < 3 * H && x[2] < 3 * H;
}

static void lattice(double *x, double *volume, double *radius)
{
    for (int k = 0, p = 0; k < SIDE; ++k)
        for (int j = 0; j < SIDE; ++j)
            for (int i = 0; i < SIDE; ++i, ++p) {
                double *y = x + 3 * p;
                y[0] = i * H, y[1] = j * H, y[2] = k * H;
                if (jittered(y))
                    for (int a = 0; a < 3; ++a)
                        y[a] += 0.2 * H * sin(1.7 * p + 2.3 * a);
                volume[p] = H * H * H * (1.0 + 0.1 * cos(0.9 * p));
                radius[p] = L;
            }
}

static int interior(const double *x)
{
    for (int a = 0; a < 3; ++a)
        if (x[a] < L + 3 * H || x[a] > (SIDE - 1) * H - L)
            return 0;
    return 1;
}

int main(void)
{
    test_begin();
    static double x[3 * N], volume[N], radius[N], field[N], average[N];
    lattice(x, volume, radius);
    radius[5] = 0.0; /* local damage at one point */
    struct gsn_nonlocal *n = NULL;
    TEST_INT(gsn_nonlocal_create(N, x, volume, radius, &n), GSN_OK);

    /* rows sum to 1; a constant is its own average */
    double worst_sum = 0.0, worst_constant = 0.0;
    for (int p = 0; p < N; ++p) {
        if (p == 5) {
            TEST_INT(n->offset[p + 1] - n->offset[p], 0);
            continue;
        }
        double sum = 0.0;
        for (int k = n->offset[p]; k < n->offset[p + 1]; ++k)
            sum += n->weight[k];
        worst_sum = fmax(worst_sum, fabs(sum - 1.0));
        for (int q = 0; q < N; ++q)
            field[q] = 0.37;
        gsn_nonlocal_average(n, p, field, 1, &average[p]);
        worst_constant = fmax(worst_constant, fabs(average[p] - 0.37) / 0.37);
    }
    printf("rows sum to 1 within %.1e; a constant averages to itself within "
           "%.1e; %d entries, %.1f a row, %d at most\n",
           worst_sum, worst_constant, n->offset[N], (double)n->offset[N] / N,
           n->max_row);
    TEST_TRUE(worst_sum < 1e-14);      /* a sum of < 100 terms */
    TEST_TRUE(worst_constant < 1e-14); /* the same sum times 0.37 */
    /* a ball of 2.5 h holds 4/3 pi 2.5^3 = 65 points of the lattice */
    TEST_TRUE(n->max_row > 50 && n->max_row < 90);

    /* a linear field in the symmetric interior: with equal volumes each
     * pair about the centre weighs the same */
    for (int p = 0; p < N; ++p)
        volume[p] = H * H * H;
    struct gsn_nonlocal *flat = NULL;
    TEST_INT(gsn_nonlocal_create(N, x, volume, radius, &flat), GSN_OK);
    for (int q = 0; q < N; ++q)
        field[q] =
            1.0 + 0.3 * x[3 * q] - 0.2 * x[3 * q + 1] + 0.1 * x[3 * q + 2];
    double worst_linear = 0.0, jitter_linear = 0.0;
    int interior_count = 0;
    for (int p = 0; p < N; ++p) {
        if (p == 5)
            continue;
        gsn_nonlocal_average(flat, p, field, 1, &average[p]);
        double error = fabs(average[p] - field[p]);
        if (interior(x + 3 * p)) {
            worst_linear = fmax(worst_linear, error);
            ++interior_count;
        } else if (jittered(x + 3 * p)) {
            jitter_linear = fmax(jitter_linear, error);
        }
    }
    printf("a linear field: %d symmetric interior points within %.1e, the "
           "jittered corner off by up to %.1e (the control)\n",
           interior_count, worst_linear, jitter_linear);
    TEST_TRUE(interior_count > 50);
    TEST_TRUE(worst_linear < 1e-13);
    TEST_TRUE(jitter_linear > 1e-4);

    /* one weight against the bell: point p's entry for its +x neighbour */
    int p = 6 + SIDE * (6 + SIDE * 6), q = p + 1;
    double sum = 0.0, entry = -1.0;
    for (int k = flat->offset[p]; k < flat->offset[p + 1]; ++k) {
        const double *y = x + 3 * flat->index[k];
        double r2 = 0.0;
        for (int a = 0; a < 3; ++a)
            r2 += (y[a] - x[3 * p + a]) * (y[a] - x[3 * p + a]);
        sum += (1.0 - r2 / (L * L)) * (1.0 - r2 / (L * L));
        if (flat->index[k] == q)
            entry = flat->weight[k];
    }
    double bell = (1.0 - H * H / (L * L)) * (1.0 - H * H / (L * L));
    TEST_REL(entry, bell / sum, 1e-14);

    /* point 5 keeps what it had */
    average[5] = -7.0;
    gsn_nonlocal_average(flat, 5, field, 1, &average[5]);
    TEST_TRUE(average[5] == -7.0);

    /* the same rows on 1 thread as on 2 */
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    struct gsn_nonlocal *one = NULL;
    TEST_INT(gsn_nonlocal_create(N, x, volume, radius, &one), GSN_OK);
    omp_set_num_threads(threads > 1 ? threads : 2);
    TEST_INT(one->offset[N], flat->offset[N]);
    TEST_TRUE(memcmp(one->offset, flat->offset, (N + 1) * sizeof(int)) == 0);
    TEST_TRUE(memcmp(one->index, flat->index,
                     (size_t)flat->offset[N] * sizeof(int)) == 0);
    TEST_TRUE(memcmp(one->weight, flat->weight,
                     (size_t)flat->offset[N] * sizeof(double)) == 0);

    /* a ball far too big for the spacing */
    for (int k = 0; k < N; ++k)
        radius[k] = 40.0 * H; /* every point in every ball */
    struct gsn_nonlocal *big = NULL;
    TEST_INT(gsn_nonlocal_create(N, x, volume, radius, &big), GSN_ERR_INPUT);
    TEST_TRUE(big == NULL);
    TEST_TRUE(strstr(gsn_error_message(), "damage.length 10 m") != NULL);
    gsn_error_clear();

    gsn_nonlocal_destroy(&n);
    gsn_nonlocal_destroy(&flat);
    gsn_nonlocal_destroy(&one);
    gsn_nonlocal_destroy(&n); /* NULL-safe */
    return test_end("nonlocal");
}
