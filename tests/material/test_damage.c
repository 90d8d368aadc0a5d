/* Verification: the damage law of seed paper eqs. (6)-(7) at a single
 * point. zeta(e_t) = ef (e_t - e0) / (e_t (ef - e0)) between e0 and ef,
 * e_t = integral of ||eps_dot|| dt; nominal stress = (1 - zeta) effective.
 * References (REFERENCES.md, "Damage"): zeta = 0.20080, 0.80321, 0.98394 at
 * e_t = 0.025, 0.1, 1.0 (e_t = |eps| on a uniaxial-strain path); elastic
 * simple-shear cycles of amplitude 0.01 add 0.007071 per quarter cycle:
 * zeta = 0.0574, 0.2941, 0.6490 after 3, 4, 8 quarter cycles.
 * With damage.length, eq. (7) takes the nonlocal strain. */
#include "material_testing.h"

static double zeta_closed_form(double e_t)
{
    if (e_t <= PAPER_E0)
        return 0.0;
    if (e_t >= PAPER_EF)
        return 1.0;
    return PAPER_EF * (e_t - PAPER_E0) / (e_t * (PAPER_EF - PAPER_E0));
}

/* Uniaxial strain in compression, steps of 1e-3 (damage with and without
 * plasticity: e_t depends on the strain path only). */
static void test_zeta_of_strain(int plasticity)
{
    struct gsn_material par = paper_material(1, plasticity, PAPER_ALPHA);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p;
    point_init(&p, m, NULL);
    const double checkpoints[3] = {0.025, 0.1, 1.0};
    const double reference[3] = {0.20080, 0.80321, 0.98394};
    int next = 0;
    double previous = 0.0;
    int monotone = 1;
    for (int n = 1; n <= 1000; ++n) {
        const double de[6] = {-1e-3, 0, 0, 0, 0, 0};
        point_strain_step(&p, de);
        const double zeta = point_state(&p, "damage");
        monotone &= zeta >= previous;
        previous = zeta;
        /* nominal = (1 - zeta) effective, eq. (6): a product, exact */
        const int off = gsn_material_state_offset(m->ops, "effective_stress");
        for (int a = 0; a < 6; ++a)
            TEST_TRUE(p.stress[a] == (1.0 - zeta) * p.state[off + a]);
        if (n == 19)
            TEST_TRUE(zeta == 0.0); /* below e0 */
        if (next < 3 && n == (int)lround(checkpoints[next] * 1000)) {
            const double e_t = point_state(&p, "equivalent_strain");
            printf("plasticity %d: e_t = %.15f zeta = %.10f (closed form "
                   "%.10f, reference %.5f)\n",
                   plasticity, e_t, zeta, zeta_closed_form(checkpoints[next]),
                   reference[next]);
            /* e_t is a sum of n equal increments: round-off of n terms */
            TEST_REL(e_t, checkpoints[next], 1e-13);
            TEST_REL(zeta, zeta_closed_form(checkpoints[next]), 1e-12);
            /* references rounded to 5 digits: half a unit */
            TEST_NEAR(zeta, reference[next], 5e-6);
            ++next;
        }
    }
    TEST_INT(next, 3);
    TEST_TRUE(monotone);
    gsn_material_model_destroy(&m);
}

/* Past ef the point carries no stress; zeta stays at 1. */
static void test_full_damage(void)
{
    struct gsn_material par = paper_material(1, 1, PAPER_ALPHA);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p;
    point_init(&p, m, NULL);
    for (int n = 0; n < 60; ++n) {
        const double de[6] = {0, 0, 0, 0.1, 0, 0}; /* ||de|| = 0.1 sqrt 2 */
        point_strain_step(&p, de);
    }
    TEST_TRUE(point_state(&p, "equivalent_strain") > PAPER_EF);
    TEST_TRUE(point_state(&p, "damage") == 1.0);
    for (int a = 0; a < 6; ++a)
        TEST_TRUE(p.stress[a] == 0.0);
    gsn_material_model_destroy(&m);
}

/* Load-unload-reload in uniaxial strain: zeta never decreases, and grows
 * in every step once e_t > e0 (unloading also moves e_t). */
static void test_never_decreases(void)
{
    struct gsn_material par = paper_material(1, 1, PAPER_ALPHA);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p;
    point_init(&p, m, NULL);
    double previous = 0.0;
    int decreased = 0, grew_after_onset = 1;
    for (int n = 0; n < 300; ++n) {
        const double sign = (n / 50) % 2 ? 1.0 : -1.0; /* 50 out, 50 back */
        const double de[6] = {sign * 1e-3, 0, 0, 0, 0, 0};
        point_strain_step(&p, de);
        const double zeta = point_state(&p, "damage");
        decreased |= zeta < previous;
        if (point_state(&p, "equivalent_strain") > PAPER_E0 + 1e-3)
            grew_after_onset &= zeta > previous;
        previous = zeta;
    }
    TEST_TRUE(!decreased);
    TEST_TRUE(grew_after_onset);
    TEST_REL(point_state(&p, "equivalent_strain"), 0.3, 1e-13); /* sum */
    TEST_REL(previous, zeta_closed_form(0.3), 1e-12);
    gsn_material_model_destroy(&m);
}

/* Elastic simple-shear cycles (amplitude gamma = 0.01 < 0.014683, the
 * shear yield strain), through the objective update: G = d gamma e_x e_y,
 * ||d eps|| = d gamma / sqrt 2 per step. */
static void test_elastic_cycles(void)
{
    struct gsn_material par = paper_material(1, 1, PAPER_ALPHA);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p;
    point_init(&p, m, NULL);
    const int steps_per_quarter = 100;
    const double dgamma = 0.01 / steps_per_quarter;
    const double reference[9] = {0, 0, 0, 0.0574, 0.2941, 0, 0, 0, 0.6490};
    double previous = 0.0;
    int decreased = 0;
    for (int quarter = 1; quarter <= 8; ++quarter) {
        /* gamma: 0 -> 0.01 -> 0 -> -0.01 -> 0 -> ... */
        const double sign =
            (quarter == 1 || quarter == 4 || quarter == 5 || quarter == 8)
                ? 1.0
                : -1.0;
        for (int n = 0; n < steps_per_quarter; ++n) {
            double G[9] = {0};
            G[1] = sign * dgamma;
            point_gradient_step(&p, G);
            decreased |= point_state(&p, "damage") < previous;
            previous = point_state(&p, "damage");
        }
        const double e_t = point_state(&p, "equivalent_strain");
        /* 0.01/sqrt(2) per quarter: sum of 100 equal terms */
        TEST_REL(e_t, quarter * 0.01 / sqrt(2.0), 1e-13);
        if (quarter == 2)
            TEST_TRUE(previous == 0.0); /* e_t = 0.0141 < e0 */
        if (reference[quarter] > 0.0) {
            printf("after %d quarter cycles: e_t = %.6f zeta = %.6f "
                   "(reference %.4f)\n",
                   quarter, e_t, previous, reference[quarter]);
            TEST_NEAR(previous, reference[quarter], 5e-5); /* 4 digits */
        }
    }
    TEST_TRUE(!decreased);
    TEST_TRUE(point_state(&p, "equivalent_plastic_strain") == 0.0);
    gsn_material_model_destroy(&m);
}

/* With damage.length the damage follows the nonlocal strain the solver
 * writes into the state (nonlocal.h), not the point's own e_t: a point
 * strained past ef keeps zeta = 0 while its average is 0, then takes
 * zeta(average) for the averages 0.025 and 0.1, and never decreases. */
static void test_nonlocal_argument(void)
{
    struct gsn_material par = paper_material(1, 1, PAPER_ALPHA);
    par.damage_length = 0.7;
    struct gsn_material_model *m = model_make("damage_drucker_prager", &par);
    struct point p;
    point_init(&p, m, NULL);
    const int average = gsn_material_state_offset(m->ops, "nonlocal_strain");
    TEST_TRUE(average >= 0);
    TEST_TRUE(p.state[average] == 0.0);
    const double de[6] = {0, 0, 0, 0.1, 0, 0};
    for (int n = 0; n < 40; ++n)
        point_strain_step(&p, de);
    TEST_TRUE(point_state(&p, "equivalent_strain") > PAPER_EF);
    TEST_TRUE(point_state(&p, "damage") == 0.0);
    const double given[3] = {0.025, 0.1, 0.05};
    const double expected[3] = {zeta_closed_form(0.025), zeta_closed_form(0.1),
                                zeta_closed_form(0.1)};
    for (int k = 0; k < 3; ++k) {
        p.state[average] = given[k];
        point_strain_step(&p, de);
        TEST_TRUE(point_state(&p, "damage") == expected[k]);
    }
    gsn_material_model_destroy(&m);
}

int main(void)
{
    test_begin();
    test_zeta_of_strain(0);
    test_zeta_of_strain(1);
    test_full_damage();
    test_never_decreases();
    test_elastic_cycles();
    test_nonlocal_argument();
    return test_end("material_damage");
}
