/* Verification: isochoric simple shear at small strain (no rotation: the
 * material update alone with d eps_xy = d gamma / 2), Drucker-Prager
 * without damage (REFERENCES.md, "Single stress point"):
 * - zero dilatancy (beta = 0): tau plateaus at R / sqrt(2) = 0.13435 MPa
 *   (the flow is deviatoric, the pressure stays 0);
 * - associated flow (beta = alpha): the dilatant flow, constrained by the
 *   isochoric path, builds pressure; sigma_xy = 0.18270 MPa and mean stress
 *   -0.32563 MPa at gamma = 0.1 (reference: small-strain return mapping in
 *   1e4-2e4 steps, 5 digits).
 * On this path the stress stays on a line in the (tau, p) plane and the
 * return direction is constant, so the return map is exact for any step:
 * the measured step error is round-off, checked against a closed form. */
#include "material_testing.h"

static void shear(const struct gsn_material_model *m, int N, double gamma,
                  double out[6], double *eps_p)
{
    struct point p;
    point_init(&p, m, NULL);
    const double de[6] = {0, 0, 0, 0.5 * gamma / N, 0, 0};
    for (int n = 0; n < N; ++n)
        point_strain_step(&p, de);
    memcpy(out, p.stress, sizeof p.stress);
    *eps_p = point_state(&p, "equivalent_plastic_strain");
}

static void test_zero_dilatancy(void)
{
    struct gsn_material par = paper_material(0, 1, 0.0);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    const int counts[3] = {10, 100, 10000};
    for (int k = 0; k < 3; ++k) {
        double s[6], eps_p;
        shear(m, counts[k], 0.1, s, &eps_p);
        printf("beta = 0, N = %5d: tau = %.12e Pa (R/sqrt 2 = %.12e), "
               "mean %.1e Pa\n",
               counts[k], s[3], PAPER_R / sqrt(2.0), mean_stress(s));
        /* exact plateau for any step: radial return of a pure shear */
        TEST_REL(s[3], PAPER_R / sqrt(2.0), 1e-14);
        TEST_NEAR(s[3], 0.13435e6, 5e0);      /* 5 digits */
        TEST_NEAR(mean_stress(s), 0.0, 1e-9); /* round-off of 1e5 Pa */
        TEST_TRUE(eps_p > 0.04);
    }
    gsn_material_model_destroy(&m);
}

/* Closed form of the isochoric simple shear (derived for this test): the
 * deviator stays a pure xy shear, so the state is (tau, p) with ||s|| =
 * sqrt(2) tau; after yield at gamma_y = R / (sqrt(2) mu), consistency
 * sqrt(2) d tau + 3 alpha d p = 0 with d tau = mu d gamma - sqrt(2) mu
 * d lambda and d p = -3 K beta d lambda gives
 * lambda = sqrt(2) mu (gamma - gamma_y) / (2 mu + 9 K alpha beta),
 * p = -3 K beta lambda, tau = (R - 3 alpha p) / sqrt(2). Linear in gamma:
 * the return map of any step size lands on it exactly. */
static void shear_closed_form(double gamma, double beta, double *tau, double *p)
{
    const double K = PAPER_K, mu = PAPER_MU, a = PAPER_ALPHA, R = PAPER_R;
    const double gamma_y = R / (sqrt(2.0) * mu);
    const double lambda =
        sqrt(2.0) * mu * (gamma - gamma_y) / (2.0 * mu + 9.0 * K * a * beta);
    *p = -3.0 * K * beta * lambda;
    *tau = (R - 3.0 * a * *p) / sqrt(2.0);
}

static void test_associated(void)
{
    struct gsn_material par = paper_material(0, 1, PAPER_ALPHA);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    double tau, p;
    shear_closed_form(0.1, PAPER_ALPHA, &tau, &p);
    printf("closed form at gamma = 0.1: sigma_xy = %.10f MPa, mean = %.10f "
           "MPa (references 0.18270, -0.32563)\n",
           tau * 1e-6, p * 1e-6);
    /* REFERENCES.md numbers, 5 digits: half a unit of the last digit */
    TEST_NEAR(tau, 0.18270e6, 5.0);
    TEST_NEAR(p, -0.32563e6, 5.0);
    const int counts[5] = {1, 2, 10, 1000, 100000};
    for (int k = 0; k < 5; ++k) {
        double s[6], eps_p;
        shear(m, counts[k], 0.1, s, &eps_p);
        const double e_xy = fabs(s[3] / tau - 1.0);
        const double e_mean = fabs(mean_stress(s) / p - 1.0);
        printf("beta = alpha, N = %6d: sigma_xy = %.10f MPa, mean = %.10f "
               "MPa, relative step error %.1e, %.1e\n",
               counts[k], s[3] * 1e-6, mean_stress(s) * 1e-6, e_xy, e_mean);
        /* The step error is zero on this path (linear in gamma): what is
         * left is the round-off of N steps (a few 1e-16 each). */
        TEST_TRUE(e_xy <= 1e-11);
        TEST_TRUE(e_mean <= 1e-11);
        TEST_NEAR(yield_function(s, PAPER_ALPHA, PAPER_R), 0.0,
                  1e-9); /* on the cone: round-off of 1e5 Pa terms */
        TEST_NEAR(s[3], 0.18270e6, 5.0); /* 5 digits */
        TEST_NEAR(mean_stress(s), -0.32563e6, 5.0);
    }
    /* Non-associated flow with beta = alpha / 2 follows the same closed
     * form (a check that beta, not alpha, drives the dilatancy). */
    par.dp_dilatancy = 0.5 * PAPER_ALPHA;
    struct gsn_material_model *half = model_make("damage_drucker_prager", &par);
    double s[6], eps_p;
    shear(half, 1000, 0.1, s, &eps_p);
    shear_closed_form(0.1, 0.5 * PAPER_ALPHA, &tau, &p);
    TEST_REL(s[3], tau, 1e-11); /* as above */
    TEST_REL(mean_stress(s), p, 1e-11);
    gsn_material_model_destroy(&half);
    gsn_material_model_destroy(&m);
}

int main(void)
{
    test_begin();
    test_zero_dilatancy();
    test_associated();
    return test_end("material_simple_shear_plastic");
}
