/* Verification: single stress point yield of the Drucker-Prager model,
 * eq. (8) read with tension-positive stress (DESIGN.md "Sign convention"):
 * f = ||dev s|| + alpha tr s - R. References (REFERENCES.md, "Single stress
 * point"): uniaxial compression R/(sqrt(2/3) - alpha) = 0.25452 MPa,
 * tension R/(sqrt(2/3) + alpha) = 0.21433 MPa, pure shear R/sqrt(2) =
 * 0.13435 MPa, triaxial compression q = (R + 3 alpha sr)/(sqrt(2/3) -
 * alpha), apex mean stress R/(3 alpha) = 0.90476 MPa; oedometric
 * compression with zero dilatancy keeps p = K |eps_vol|.
 * Damage is off: yield acts on the effective stress (below eq. (8)), and
 * these paths stay below e0 until yield anyway. */
#include "material_testing.h"

static const double sqrt_two_thirds = 0.81649658092772603;

/* Closed forms. */
static double compression_yield(void)
{
    return PAPER_R / (sqrt_two_thirds - PAPER_ALPHA);
}
static double tension_yield(void)
{
    return PAPER_R / (sqrt_two_thirds + PAPER_ALPHA);
}
static double shear_yield(void)
{
    return PAPER_R / sqrt(2.0);
}
static double triaxial_yield(double sr)
{
    return (PAPER_R + 3.0 * PAPER_ALPHA * sr) / (sqrt_two_thirds - PAPER_ALPHA);
}

/* Elastic strain of a stress: C^-1 : s. */
static void elastic_strain(const double s[6], double e[6])
{
    const double mean = gsn_voigt_trace(s) / 3.0;
    for (int a = 0; a < 6; ++a)
        e[a] = (s[a] - (a < 3 ? mean : 0.0)) / (2.0 * PAPER_MU) +
               (a < 3 ? mean / (3.0 * PAPER_K) : 0.0);
}

/* Yield onset by bisection: the largest t such that one elastic-damage
 * step from the point p0 with the strain increment t * C^-1 : direction
 * leaves no plastic strain. Returns t (the stress added along direction at
 * first yield). */
static double bisect_yield(const struct point *p0, const double direction[6])
{
    double e[6];
    elastic_strain(direction, e);
    double lo = 0.0, hi = 1e7; /* Pa: far above every yield stress here */
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        const double t = 0.5 * (lo + hi);
        double de[6];
        for (int a = 0; a < 6; ++a)
            de[a] = t * e[a];
        struct point p = *p0;
        point_strain_step(&p, de);
        if (point_state(&p, "equivalent_plastic_strain") > 0.0)
            hi = t;
        else
            lo = t;
    }
    return lo;
}

/* Loads the point past yield along an axial strain path with the other
 * normal stresses held at lateral (mixed control) and no shear strain; the
 * axial stress after yield is the perfectly plastic limit. Returns it. */
static double axial_plateau(struct point *p, double axial_strain_step,
                            int steps, double lateral, double *residual)
{
    const int controlled[6] = {0, 1, 1, 0, 0, 0};
    const double target[6] = {0.0, lateral, lateral, 0.0, 0.0, 0.0};
    *residual = 0.0;
    for (int n = 0; n < steps; ++n) {
        double de[6] = {axial_strain_step, 0, 0, 0, 0, 0};
        *residual =
            fmax(*residual, point_mixed_step(p, de, controlled, target));
    }
    return p->stress[0];
}

static void test_uniaxial_and_triaxial(double beta)
{
    struct gsn_material par = paper_material(0, 1, beta);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p0;
    point_init(&p0, m, NULL);

    /* Onset from the natural state. */
    const double compression[6] = {-1, 0, 0, 0, 0, 0};
    const double tension[6] = {1, 0, 0, 0, 0, 0};
    const double shear[6] = {0, 0, 0, 1, 0, 0};
    const double sc = bisect_yield(&p0, compression);
    const double st = bisect_yield(&p0, tension);
    const double ss = bisect_yield(&p0, shear);
    printf("beta %.2f: yield onset compression %.10e tension %.10e shear "
           "%.10e Pa (rel. errors %.1e %.1e %.1e)\n",
           beta, sc, st, ss, fabs(sc / compression_yield() - 1),
           fabs(st / tension_yield() - 1), fabs(ss / shear_yield() - 1));
    /* Bisection to 1e-15 and round-off of f (terms of 1e5 Pa): 1e-10 is
     * the tolerance with a margin of 1e4. */
    TEST_REL(sc, compression_yield(), 1e-10);
    TEST_REL(st, tension_yield(), 1e-10);
    TEST_REL(ss, shear_yield(), 1e-10);
    /* Rounded references of REFERENCES.md (5 digits: half a unit). */
    TEST_NEAR(sc, 0.25452e6, 5e0);
    TEST_NEAR(st, 0.21433e6, 5e0);
    TEST_NEAR(ss, 0.13435e6, 5e0);

    /* Past yield under mixed control: the axial stress stays at the
     * limit whatever the flow rule (perfect plasticity). */
    double residual;
    struct point p = p0;
    double s = axial_plateau(&p, -2.5e-4, 200, 0.0, &residual);
    printf("beta %.2f: uniaxial compression plateau %.10e Pa (rel. error "
           "%.1e) after eps_p = %.3e (lateral residual %.1e Pa)\n",
           beta, -s, fabs(-s / compression_yield() - 1),
           point_state(&p, "equivalent_plastic_strain"), residual);
    TEST_TRUE(point_state(&p, "equivalent_plastic_strain") > 1e-2);
    /* Newton to 1e-9 Pa on the lateral stresses; the return puts the
     * point on f = 0 to round-off: 1e-10 relative holds with a margin. */
    TEST_REL(-s, compression_yield(), 1e-10);
    TEST_TRUE(residual <= 1e-9);

    p = p0;
    s = axial_plateau(&p, 2.5e-4, 100, 0.0, &residual);
    printf("beta %.2f: uniaxial tension plateau %.10e Pa (rel. error %.1e)\n",
           beta, s, fabs(s / tension_yield() - 1));
    TEST_TRUE(point_state(&p, "equivalent_plastic_strain") > 1e-3);
    TEST_REL(s, tension_yield(), 1e-10); /* as above */

    /* Pure shear under mixed control (normal stresses held at zero). */
    p = p0;
    {
        const int controlled[6] = {1, 1, 1, 0, 0, 0};
        const double target[6] = {0};
        for (int n = 0; n < 100; ++n) {
            double de[6] = {0, 0, 0, 2.5e-4, 0, 0};
            point_mixed_step(&p, de, controlled, target);
        }
        printf("beta %.2f: pure shear plateau %.10e Pa (rel. error %.1e)\n",
               beta, p.stress[3], fabs(p.stress[3] / shear_yield() - 1));
        TEST_TRUE(point_state(&p, "equivalent_plastic_strain") > 1e-2);
        TEST_REL(p.stress[3], shear_yield(), 1e-10); /* as above */
    }

    /* Triaxial compression: isotropic confinement sr (elastic), then axial
     * loading with the lateral stresses held at -sr. */
    const double sr[4] = {0.05e6, 0.1e6, 0.2e6, 0.5e6};
    const double q_ref[4] = {0.26859e6, 0.28265e6, 0.31079e6, 0.39518e6};
    for (int k = 0; k < 4; ++k) {
        const double iso[6] = {-sr[k], -sr[k], -sr[k], 0, 0, 0};
        double e_iso[6];
        elastic_strain(iso, e_iso);
        struct point c = p0;
        point_strain_step(&c, e_iso);
        TEST_TRUE(point_state(&c, "equivalent_plastic_strain") == 0.0);
        const double q_onset = bisect_yield(&c, compression);
        const double q_plateau =
            -(axial_plateau(&c, -2.5e-4, 200, -sr[k], &residual) + sr[k]);
        printf("beta %.2f: triaxial sr = %.2f MPa: q onset %.10e plateau "
               "%.10e Pa (closed form %.10e, rel. errors %.1e %.1e)\n",
               beta, sr[k] * 1e-6, q_onset, q_plateau, triaxial_yield(sr[k]),
               fabs(q_onset / triaxial_yield(sr[k]) - 1),
               fabs(q_plateau / triaxial_yield(sr[k]) - 1));
        TEST_REL(q_onset, triaxial_yield(sr[k]), 1e-10);   /* as above */
        TEST_REL(q_plateau, triaxial_yield(sr[k]), 1e-10); /* as above */
        TEST_NEAR(q_onset, q_ref[k], 5e0); /* 5-digit references */
        TEST_TRUE(point_state(&c, "equivalent_plastic_strain") > 1e-2);
    }
    gsn_material_model_destroy(&m);
}

/* Hydrostatic tension returns to the apex, sbar = R/(3 alpha) I, for any
 * dilatancy; a trial with a small deviator and a large tension too (the
 * cone return would overshoot the axis). */
static void test_apex(void)
{
    const double betas[3] = {PAPER_ALPHA, 0.0, 0.2};
    for (int b = 0; b < 3; ++b) {
        struct gsn_material par = paper_material(0, 1, betas[b]);
        struct gsn_material_model *m =
            model_make("damage_drucker_prager", &par);
        struct point p;
        point_init(&p, m, NULL);
        for (int n = 0; n < 20; ++n) {
            const double de[6] = {2e-3, 2e-3, 2e-3, 0, 0, 0};
            point_strain_step(&p, de);
        }
        const double apex = PAPER_R / (3.0 * PAPER_ALPHA);
        /* exact apex value, round-off only */
        TEST_REL(mean_stress(p.stress), apex, 1e-14);
        TEST_NEAR(mean_stress(p.stress), 0.90476e6, 5e0); /* 5 digits */
        TEST_TRUE(p.stress[3] == 0.0 && p.stress[4] == 0.0);
        point_init(&p, m, NULL);
        const double de[6] = {0.02, 0.02, 0.02, 1e-4, -2e-4, 0.5e-4};
        point_strain_step(&p, de);
        TEST_REL(p.stress[0], apex, 1e-14); /* round-off */
        TEST_REL(p.stress[1], apex, 1e-14);
        TEST_REL(p.stress[2], apex, 1e-14);
        TEST_TRUE(p.stress[3] == 0.0 && p.stress[4] == 0.0 &&
                  p.stress[5] == 0.0);
        /* on the cone: just below the apex region the cone return holds */
        point_init(&p, m, NULL);
        const double de2[6] = {0.002, 0.002, 0.002, 2e-2, 0, 0};
        point_strain_step(&p, de2);
        TEST_TRUE(p.stress[3] > 0.0);
        TEST_NEAR(yield_function(p.stress, PAPER_ALPHA, PAPER_R), 0.0,
                  1e-9); /* f = 0 after a return, round-off of 1e5 Pa */
        gsn_material_model_destroy(&m);
    }
}

/* Oedometric (uniaxial strain) compression with zero dilatancy: the plastic
 * flow is deviatoric, so p = -tr(sigma)/3 = K |eps_vol| after yield too. */
static void test_oedometric(void)
{
    for (int damage = 0; damage <= 1; ++damage) {
        struct gsn_material par = paper_material(damage, 1, 0.0);
        struct gsn_material_model *m =
            model_make("damage_drucker_prager", &par);
        struct point p;
        point_init(&p, m, NULL);
        double eps = 0.0, max_error = 0.0, onset = -1.0;
        const int steps = 400;
        for (int n = 1; n <= steps; ++n) {
            const double de[6] = {-2.5e-4, 0, 0, 0, 0, 0};
            point_strain_step(&p, de);
            eps = n * 2.5e-4;
            if (onset < 0 && point_state(&p, "equivalent_plastic_strain") > 0)
                onset = eps;
            const double zeta = point_state(&p, "damage");
            const double p_eff = -mean_stress(p.stress) / (1.0 - zeta);
            max_error = fmax(max_error, fabs(p_eff / (PAPER_K * eps) - 1.0));
        }
        /* Yield at |eps| = R / (2 mu sqrt(2/3) - 3 K alpha) (f = 0 on this
         * elastic path). */
        const double eps_y = PAPER_R / (2.0 * PAPER_MU * sqrt_two_thirds -
                                        3.0 * PAPER_K * PAPER_ALPHA);
        printf("oedometric (damage %d): yield at eps %.4e (closed form "
               "%.6e), max |p/(K eps_vol) - 1| = %.2e over %d steps to "
               "eps = %.2f (eps_p %.4f)\n",
               damage, onset, eps_y, max_error, steps, eps,
               point_state(&p, "equivalent_plastic_strain"));
        TEST_TRUE(onset > eps_y && onset < eps_y + 2.5e-4);
        TEST_TRUE(point_state(&p, "equivalent_plastic_strain") > 0.03);
        /* Round-off accumulated over 400 steps (a few 1e-16 each). */
        TEST_TRUE(max_error <= 1e-12);
        gsn_material_model_destroy(&m);
    }
}

int main(void)
{
    test_begin();
    test_uniaxial_and_triaxial(PAPER_ALPHA);
    test_uniaxial_and_triaxial(0.0);
    test_apex();
    test_oedometric();
    return test_end("material_yield_points");
}
