/* Unit tests of the material interface (material.h) and of the kinematics
 * of the objective update (stress_update.h): registry, state layout,
 * parameter checks, the elastic step C : d eps, and the closed-form
 * Hughes-Winget rotation against the matrix formula. */
#include "material_testing.h"

static void test_registry(void)
{
    TEST_TRUE(gsn_material_count() >= 2);
    for (int i = 0; i < gsn_material_count(); ++i) {
        const struct gsn_material_ops *ops = gsn_material_at(i);
        TEST_TRUE(gsn_material_find(ops->name) == ops);
        /* state_size is the sum of the kinds, offsets in order */
        int size = 0;
        for (int v = 0; v < ops->state_variable_count; ++v) {
            TEST_INT(
                gsn_material_state_offset(ops, ops->state_variables[v].name),
                size);
            size += (int)ops->state_variables[v].kind;
        }
        TEST_INT(ops->state_size, size);
        TEST_TRUE(ops->state_size <= POINT_STATE_CAPACITY);
        TEST_TRUE(ops->create && ops->initialize && ops->update &&
                  ops->destroy);
    }
    TEST_TRUE(gsn_material_at(gsn_material_count()) == NULL);
    TEST_TRUE(gsn_material_find("no_such_model") == NULL);

    struct gsn_material p = paper_material(1, 1, PAPER_ALPHA);
    struct gsn_material_model *m = NULL;
    TEST_INT(gsn_material_model_create("no_such_model", &p, &m), GSN_ERR_INPUT);
    TEST_TRUE(m == NULL);
    TEST_TRUE(strstr(gsn_error_message(), "damage_drucker_prager") != NULL);
    gsn_error_clear();

    const struct gsn_material_ops *ddp =
        gsn_material_find("damage_drucker_prager");
    TEST_TRUE(ddp != NULL);
    TEST_TRUE(gsn_material_state_offset(ddp, "damage") >= 0);
    TEST_TRUE(gsn_material_state_offset(ddp, "equivalent_strain") >= 0);
    TEST_TRUE(gsn_material_state_offset(ddp, "equivalent_plastic_strain") >= 0);
    TEST_TRUE(gsn_material_state_offset(ddp, "effective_stress") >= 0);
    TEST_INT(gsn_material_state_offset(gsn_material_find("elastic"), "damage"),
             -1);

    TEST_TRUE(strcmp(gsn_material_name_for_case(&p), "damage_drucker_prager") ==
              0);
    p.has_damage = p.has_plasticity = 0;
    TEST_TRUE(strcmp(gsn_material_name_for_case(&p), "elastic") == 0);

    gsn_material_model_destroy(&m); /* NULL-safe */
    m = model_make("elastic", &p);
    gsn_material_model_destroy(&m);
    TEST_TRUE(m == NULL);
}

static void expect_rejected(const char *name, struct gsn_material p)
{
    struct gsn_material_model *m = NULL;
    TEST_INT(gsn_material_model_create(name, &p, &m), GSN_ERR_INPUT);
    TEST_TRUE(m == NULL);
    gsn_error_clear();
}

static void test_parameter_checks(void)
{
    struct gsn_material p = paper_material(1, 1, PAPER_ALPHA);
    for (int i = 0; i < gsn_material_count(); ++i) {
        const char *name = gsn_material_at(i)->name;
        struct gsn_material q = p;
        q.bulk_modulus = -1.0;
        expect_rejected(name, q);
        q = p;
        q.shear_modulus = 0.0;
        expect_rejected(name, q);
    }
    struct gsn_material q = p;
    q.damage_e0 = 6.0; /* e0 >= ef */
    expect_rejected("damage_drucker_prager", q);
    q = p;
    q.dp_R = 0.0;
    expect_rejected("damage_drucker_prager", q);
    q = p;
    q.dp_alpha = -0.1;
    expect_rejected("damage_drucker_prager", q);
    q = p;
    q.dp_dilatancy = -0.1;
    expect_rejected("damage_drucker_prager", q);
}

/* An elastic step is sigma += K tr(de) I + 2 mu dev(de), for both models
 * (damage_drucker_prager with damage and plasticity off), on a batch. */
static void test_elastic_step(void)
{
    struct gsn_material p = paper_material(0, 0, 0.0);
    struct gsn_material_model *el = model_make("elastic", &p);
    struct gsn_material_model *dp = model_make("damage_drucker_prager", &p);
    enum { N = 5 };
    double de[6 * N], s_el[6 * N], s_dp[6 * N], q_dp[10 * N];
    for (int i = 0; i < 6 * N; ++i) {
        de[i] = 1e-4 * sin(1.0 + 0.7 * i);
        s_el[i] = 1e5 * cos(0.3 * i);
    }
    memcpy(s_dp, s_el, sizeof s_el);
    TEST_INT(dp->ops->state_size, 10);
    TEST_INT(gsn_material_initialize(dp, N, s_dp, q_dp), GSN_OK);
    TEST_INT(gsn_material_update(el, N, de, s_el, NULL), GSN_OK);
    TEST_INT(gsn_material_update(dp, N, de, s_dp, q_dp), GSN_OK);
    for (int i = 0; i < N; ++i) {
        const double *d = de + 6 * i;
        const double tr = d[0] + d[1] + d[2];
        for (int a = 0; a < 6; ++a) {
            double expected =
                1e5 * cos(0.3 * (6 * i + a)) + 2.0 * PAPER_MU * d[a] +
                (a < 3 ? (PAPER_K - 2.0 * PAPER_MU / 3.0) * tr : 0.0);
            /* a few ulps of the 1e5 Pa stresses */
            TEST_NEAR(s_el[6 * i + a], expected, 1e-9);
            TEST_NEAR(s_dp[6 * i + a], expected, 1e-9);
        }
        /* e_t = ||de|| after one step (eq. (7)) */
        TEST_REL(q_dp[10 * i + 1], gsn_voigt_norm(d), 1e-15);
        TEST_INT(q_dp[10 * i + 0] == 0.0, 1);
    }
    gsn_material_model_destroy(&el);
    gsn_material_model_destroy(&dp);
}

/* The closed-form Q against (I - W/2)^-1 (I + W/2) by a 3x3 inverse,
 * orthogonality, and Q sigma Q^T against full matrix products. */
static void test_rotation(void)
{
    for (int trial = 0; trial < 20; ++trial) {
        const double scale = pow(10.0, -3.0 + 0.2 * trial); /* up to ~8 */
        double G[9];
        for (int k = 0; k < 9; ++k)
            G[k] = scale * sin(3.0 * trial + 1.3 * k + 0.1);
        double de[6], Q[9];
        gsn_stress_update_increment(G, de, Q);
        double Im[9], Ip[9], inv[9], Qref[9];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double w = 0.5 * (G[3 * i + j] - G[3 * j + i]);
                Im[3 * i + j] = (i == j) - 0.5 * w;
                Ip[3 * i + j] = (i == j) + 0.5 * w;
            }
        gsn_matrix_inverse(Im, inv);
        gsn_matrix_multiply(inv, Ip, Qref);
        double QQt[9], Qt[9];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                Qt[3 * i + j] = Q[3 * j + i];
        gsn_matrix_multiply(Q, Qt, QQt);
        for (int k = 0; k < 9; ++k) {
            TEST_NEAR(Q[k], Qref[k], 1e-14);      /* round-off of O(1) */
            TEST_NEAR(QQt[k], k % 4 == 0, 1e-15); /* orthogonal */
        }
        double sym[6];
        gsn_matrix_sym_to_voigt(G, sym);
        for (int a = 0; a < 6; ++a)
            TEST_TRUE(de[a] == sym[a]);

        double s[6] = {1.0, -2.0, 0.5, 0.3, -0.7, 0.2}, S[9], T[9], R[9];
        gsn_voigt_to_matrix(s, S);
        gsn_matrix_multiply(Q, S, T);
        gsn_matrix_multiply(T, Qt, R);
        gsn_stress_update_rotate(Q, s);
        for (int a = 0; a < 6; ++a) /* round-off of O(1) entries */
            TEST_NEAR(s[a], R[3 * gsn_voigt_row[a] + gsn_voigt_col[a]], 1e-14);
    }
}

/* The batched objective update equals point-by-point updates (blocks of
 * the batch must not mix points), for more points than one block. */
static void test_batch(void)
{
    struct gsn_material p = paper_material(1, 1, 0.03);
    struct gsn_material_model *m = model_make("damage_drucker_prager", &p);
    enum { N = 150 };
    static double G[9 * N], s[6 * N], q[10 * N], de[6 * N];
    for (int i = 0; i < 9 * N; ++i)
        G[i] = 0.02 * sin(0.37 * i);
    for (int i = 0; i < 6 * N; ++i)
        s[i] = 1e5 * sin(0.11 * i) - (i % 6 < 3 ? 2e5 : 0.0);
    TEST_INT(gsn_material_initialize(m, N, s, q), GSN_OK);
    struct point points[N];
    for (int i = 0; i < N; ++i)
        point_init(&points[i], m, s + 6 * i);
    TEST_INT(gsn_stress_update(m, N, G, s, q, de), GSN_OK);
    for (int i = 0; i < N; ++i) {
        point_gradient_step(&points[i], G + 9 * i);
        for (int a = 0; a < 6; ++a)
            TEST_TRUE(points[i].stress[a] == s[6 * i + a]);
        for (int k = 0; k < 10; ++k)
            TEST_TRUE(points[i].state[k] == q[10 * i + k]);
        double sym[6];
        gsn_matrix_sym_to_voigt(G + 9 * i, sym);
        for (int a = 0; a < 6; ++a)
            TEST_TRUE(de[6 * i + a] == sym[a]);
    }
    gsn_material_model_destroy(&m);
}

int main(void)
{
    test_begin();
    test_registry();
    test_parameter_checks();
    test_elastic_step();
    test_rotation();
    test_batch();
    return test_end("material_interface");
}
