/* The convergence estimate (convergence.h) on sequences computed by hand:
 * exact power laws give their order and limit to rounding; the published
 * example of Celik et al. (2008), Table 1, to the digits printed there;
 * oscillating, diverging and out-of-range sequences are flagged, with the
 * cautious value and error; four levels or more by least squares, with
 * scatter, and the strip footing's study. */
#include "geoscni/convergence.h"
#include "geoscni/error.h"
#include "testing.h"

#include <string.h>

/* phi(h) = limit + c h^p at the given spacings (finest first) */
static void power_law(int n, const double *h, double limit, double c, double p,
                      double *phi)
{
    for (int i = 0; i < n; ++i)
        phi[i] = limit + c * pow(h[i], p);
}

int main(void)
{
    test_begin();
    struct gsn_convergence c;

    /* Constant ratio 1.5, second order: exact to rounding (a few ulps of
     * the values, amplified by 1 / (r^p - 1) = 0.8). */
    double h[4] = {1.0, 1.5, 2.25, 3.375}, phi[4];
    power_law(3, h, 10.0, 2.0, 2.0, phi);
    TEST_INT(gsn_convergence_estimate(3, h, phi, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.order, 2.0, 1e-12);
    TEST_NEAR(c.extrapolated, 10.0, 1e-13);
    /* the error is 1.25 |phi_ext - phi_1| = 1.25 * 2 */
    TEST_NEAR(c.error, 2.5, 1e-12);
    TEST_TRUE(strcmp(c.reason, "") == 0);
    TEST_TRUE(isnan(c.scatter));
    /* the level error, and the spacing where it falls to 0.5: 2 h^2 = 0.5 */
    TEST_NEAR(gsn_convergence_level_error(&c, phi[1]), 4.5 + 2.5, 1e-12);
    TEST_NEAR(gsn_convergence_spacing_for(&c, h[0], phi[0], 0.5), 0.5, 1e-12);

    /* Order 3, above the nominal 2: the limit is still the extrapolation,
     * but the error is the larger of 1.25 |phi_ext - phi_1| = 1.25 * 0.1 and
     * 3 |phi_2 - phi_1| / (1.5^2 - 1) = 3 * 0.2375 / 1.25 = 0.57. */
    power_law(3, h, 4.0, 0.1, 3.0, phi);
    TEST_INT(gsn_convergence_estimate(3, h, phi, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.order, 3.0, 1e-10);
    TEST_NEAR(c.extrapolated, 4.0, 1e-13);
    TEST_NEAR(c.error, 3.0 * 0.1 * (pow(1.5, 3.0) - 1.0) / 1.25, 1e-12);

    /* Ratios that differ (1.4 then 1.5), order 1.5, decreasing: the
     * iteration of eq. (3) recovers both. */
    double hv[3] = {0.2, 0.28, 0.42}, phiv[3];
    power_law(3, hv, 5.0, -3.0, 1.5, phiv);
    TEST_INT(gsn_convergence_estimate(3, hv, phiv, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.order, 1.5, 1e-10);
    TEST_NEAR(c.extrapolated, 5.0, 1e-12);

    /* Celik et al. (2008), Table 1, first column: N = 18000, 8000, 4500 in
     * 2D (r21 = 1.5, r32 = 4/3), phi = 6.063, 5.972, 5.863; printed p = 1.53,
     * phi_ext = 6.1685, GCI_fine = 2.2% (to their last digit). */
    double hc[3] = {1.0, 1.5, 2.0}, phic[3] = {6.063, 5.972, 5.863};
    TEST_INT(gsn_convergence_estimate(3, hc, phic, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.order, 1.53, 0.005);
    TEST_NEAR(c.extrapolated, 6.1685, 0.00005);
    TEST_NEAR(c.error / phic[0], 0.022, 0.0005);

    /* Four levels of one power law, by least squares: the order (golden
     * sections to 1e-9), the limit, no scatter, and the error 1.25 |phi_1 -
     * phi_0| = 1.25 * 0.3. */
    power_law(4, h, 1.0, 0.3, 1.2, phi);
    TEST_INT(gsn_convergence_estimate(4, h, phi, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.order, 1.2, 1e-7);
    TEST_NEAR(c.extrapolated, 1.0, 1e-7);
    TEST_NEAR(c.scatter, 0.0, 1e-7);
    TEST_NEAR(c.error, 1.25 * 0.3, 1e-6);

    /* Five levels of a power law with alternating scatter of 0.1%: the
     * limit within the error, the scatter seen. */
    double h5[5] = {1.0, 1.5, 2.25, 3.375, 5.0625}, noisy[5];
    power_law(5, h5, 1.0, 0.3, 1.5, noisy);
    for (int i = 0; i < 5; ++i)
        noisy[i] += i % 2 ? -1e-3 : 1e-3;
    TEST_INT(gsn_convergence_estimate(5, h5, noisy, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_TRUE(c.scatter > 1e-4);
    TEST_TRUE(fabs(c.extrapolated - 1.0) <= c.error);

    /* The strip footing's four levels (docs/converge.md: peak pressure,
     * Pa, at representative spacings 0.111 to 0.333 m): the best order is
     * below 0.5, so the value is the fit at order 1 with safety 3, worked
     * out by hand (numpy, 2026-12-03): 1.0646e6 +- 7.81e4 Pa; not trusted,
     * and Prandtl's c N_c = 1.0568e6 Pa lies within it. */
    double hs[4] = {0.111043834, 0.158961748, 0.233188638, 0.332903174};
    double strip[4] = {1086396.92, 1110617.49, 1125458.51, 1145276.74};
    TEST_INT(gsn_convergence_estimate(4, hs, strip, &c), GSN_OK);
    TEST_TRUE(!c.trusted);
    TEST_TRUE(c.order < 0.5);
    TEST_NEAR(c.extrapolated, 1.0646e6, 50.0);
    TEST_NEAR(c.error, 7.81e4, 50.0);
    TEST_TRUE(fabs(c.extrapolated - 1.0568e6) <= c.error);
    TEST_TRUE(strstr(c.reason, "order 1") != NULL);

    /* Non-monotone: up then down. Flagged; the finest value, with three
     * times the larger change over r - 1 = 0.5. */
    double h3[3] = {1.0, 1.5, 2.25}, wave[3] = {1.00, 1.10, 1.05};
    TEST_INT(gsn_convergence_estimate(3, h3, wave, &c), GSN_OK);
    TEST_TRUE(!c.trusted);
    TEST_TRUE(strstr(c.reason, "oscillate") != NULL);
    TEST_NEAR(c.extrapolated, 1.00, 0.0);
    TEST_NEAR(c.error, 3.0 * 0.10 / 0.5, 1e-12);
    TEST_TRUE(isnan(gsn_convergence_spacing_for(&c, 1.0, 1.0, 0.01)));

    /* Monotone but the changes grow under refinement: not converging. */
    double grow[3] = {1.00, 1.10, 1.15};
    TEST_INT(gsn_convergence_estimate(3, h3, grow, &c), GSN_OK);
    TEST_TRUE(!c.trusted);
    TEST_TRUE(c.order < 0.0);
    TEST_TRUE(strstr(c.reason, "does not converge") != NULL);

    /* Order 6: outside the range the asymptotic regime allows. */
    power_law(3, h3, 2.0, 0.01, 6.0, phi);
    TEST_INT(gsn_convergence_estimate(3, h3, phi, &c), GSN_OK);
    TEST_TRUE(!c.trusted);
    TEST_NEAR(c.order, 6.0, 1e-9);
    TEST_TRUE(strstr(c.reason, "asymptotic") != NULL);

    /* Four levels at order 6 (the fit's best): outside the range, so the
     * order-1 fit with safety 3, not trusted. */
    power_law(4, h, 2.0, 0.01, 6.0, phi);
    TEST_INT(gsn_convergence_estimate(4, h, phi, &c), GSN_OK);
    TEST_TRUE(!c.trusted);
    TEST_NEAR(c.order, 6.0, 1e-6);
    TEST_TRUE(strstr(c.reason, "outside") != NULL);

    /* Levels that agree exactly: trusted, no error. */
    double same[3] = {3.0, 3.0, 3.0};
    TEST_INT(gsn_convergence_estimate(3, h3, same, &c), GSN_OK);
    TEST_TRUE(c.trusted);
    TEST_NEAR(c.error, 0.0, 0.0);

    /* Bad input: two levels, spacings not growing, a NaN value. */
    TEST_INT(gsn_convergence_estimate(2, h3, same, &c), GSN_ERR_INPUT);
    gsn_error_clear();
    double flat[3] = {1.0, 1.0, 2.0};
    TEST_INT(gsn_convergence_estimate(3, flat, same, &c), GSN_ERR_INPUT);
    gsn_error_clear();
    return test_end("test_convergence");
}
