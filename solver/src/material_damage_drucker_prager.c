/* Model "damage_drucker_prager": the coupled isotropic damage +
 * Drucker-Prager soil of the seed paper (section 2, eqs. (6)-(8)),
 * integrated by the elastic-damage predictor / plastic corrector split of
 * Simo & Ju 1987 as in the seed paper's Fig. 3.
 *
 * Per step, from the effective stress already rotated by the objective
 * update (stress_update.h) and the strain increment d eps:
 *   1. e_t += ||d eps||                     (eq. (7): e_t = int ||eps_dot||)
 *   2. zeta = max(zeta_n, zeta(e_t))        (eq. (7); never decreases)
 *   3. trial effective stress = sbar + C : d eps          (predictor)
 *   4. if f = ||dev sbar|| + alpha tr sbar - R > 0 (eq. (8), tension
 *      positive, DESIGN.md "Sign convention"): return to the cone along the
 *      potential ||dev sbar|| + beta tr sbar (beta = alpha: associated),
 *        dl = f / (2 mu + 9 K alpha beta),
 *        sbar = trial - dl (2 mu n + 3 K beta I),  n = dev trial / ||dev||;
 *      when the cone return overshoots the axis (2 mu dl > ||dev trial||),
 *      return to the apex sbar = R / (3 alpha) I instead
 *      (de Souza Neto et al. 2008, section 8.3.3).
 *   5. nominal stress sigma = (1 - zeta) sbar                      (eq. (6))
 * Plasticity is perfect (R and alpha constant) and acts on the effective
 * stress, as the paper says under eq. (8). Damage and plasticity are each
 * optional (has_damage, has_plasticity of the case).
 *
 * Equivalent plastic strain: int sqrt(2/3) ||dev eps_dot_p|| dt, with the
 * plastic strain increment C^-1 : (trial - sbar). */
#include "material.h"

#include "geoscni/error.h"
#include "geoscni/tensor.h"

#include <math.h>
#include <stdlib.h>

/* Offsets of the state variables in a point's state. */
enum {
    DDP_DAMAGE = 0,
    DDP_EQUIVALENT_STRAIN = 1,
    DDP_EQUIVALENT_PLASTIC_STRAIN = 2,
    DDP_EFFECTIVE_STRESS = 3,
    DDP_NONLOCAL_STRAIN = 9,
    DDP_STATE_SIZE = 10
};

static const struct gsn_state_variable ddp_state_variables[] = {
    {"damage", GSN_STATE_SCALAR, "-", "damage zeta, seed paper eq. (7)"},
    {"equivalent_strain", GSN_STATE_SCALAR, "-",
     "e_t = integral of ||strain rate|| dt, seed paper eq. (7)"},
    {"equivalent_plastic_strain", GSN_STATE_SCALAR, "-",
     "integral of sqrt(2/3) ||dev plastic strain rate|| dt"},
    {"effective_stress", GSN_STATE_TENSOR, "Pa",
     "effective Cauchy stress (1 - zeta)^-1 sigma, seed paper eq. (6), "
     "Voigt xx yy zz xy yz xz, tension positive"},
    {"nonlocal_strain", GSN_STATE_SCALAR, "-",
     "with damage.length L: e_t averaged over a ball of radius L at the end "
     "of the last step, the argument of eq. (7) (Pijaudier-Cabot & Bazant "
     "1987); 0 without"},
};

struct ddp {
    double K, mu;       /* Pa */
    int has_damage;     /* eqs. (6)-(7) */
    double e0, ef;      /* damage thresholds, - */
    double length;      /* nonlocal radius L, m; 0: the local law */
    int has_plasticity; /* eq. (8) */
    double alpha, R;    /* yield function, -, Pa */
    double apex;        /* R / (3 alpha): the cone's apex, Pa; 0 if alpha = 0 */
    double beta;        /* dilatancy of the potential, - */
};

static int ddp_create(const struct gsn_material *p, void **context)
{
    GSN_CHECK(isfinite(p->bulk_modulus) && p->bulk_modulus > 0.0, GSN_ERR_INPUT,
              "damage_drucker_prager: bulk modulus must be > 0 Pa (got %g)",
              p->bulk_modulus);
    GSN_CHECK(isfinite(p->shear_modulus) && p->shear_modulus > 0.0,
              GSN_ERR_INPUT,
              "damage_drucker_prager: shear modulus must be > 0 Pa (got %g)",
              p->shear_modulus);
    if (p->has_damage)
        GSN_CHECK(isfinite(p->damage_e0) && isfinite(p->damage_ef) &&
                      p->damage_e0 > 0.0 && p->damage_e0 < p->damage_ef,
                  GSN_ERR_INPUT,
                  "damage_drucker_prager: damage thresholds need "
                  "0 < e0 < ef (got e0 = %g, ef = %g)",
                  p->damage_e0, p->damage_ef);
    GSN_CHECK(isfinite(p->damage_length) && p->damage_length >= 0.0,
              GSN_ERR_INPUT,
              "damage_drucker_prager: damage length must be >= 0 m (got %g)",
              p->damage_length);
    if (p->has_plasticity) {
        GSN_CHECK(isfinite(p->dp_alpha) && p->dp_alpha >= 0.0, GSN_ERR_INPUT,
                  "damage_drucker_prager: alpha must be >= 0 (got %g)",
                  p->dp_alpha);
        GSN_CHECK(isfinite(p->dp_R) && p->dp_R > 0.0, GSN_ERR_INPUT,
                  "damage_drucker_prager: R must be > 0 Pa (got %g)", p->dp_R);
        GSN_CHECK(isfinite(p->dp_dilatancy) && p->dp_dilatancy >= 0.0,
                  GSN_ERR_INPUT,
                  "damage_drucker_prager: dilatancy must be >= 0 (got %g)",
                  p->dp_dilatancy);
    }
    struct ddp *m = calloc(1, sizeof *m);
    GSN_CHECK(m != NULL, GSN_ERR_MEMORY,
              "damage_drucker_prager: out of memory");
    m->K = p->bulk_modulus;
    m->mu = p->shear_modulus;
    m->has_damage = p->has_damage != 0;
    m->e0 = p->damage_e0;
    m->ef = p->damage_ef;
    m->length = p->damage_length;
    m->has_plasticity = p->has_plasticity != 0;
    m->alpha = p->dp_alpha;
    m->R = p->dp_R;
    m->beta = p->dp_dilatancy;
    m->apex = m->alpha > 0.0 ? m->R / (3.0 * m->alpha) : 0.0;
    *context = m;
    return GSN_OK;
}

static int ddp_initialize(const void *context, size_t count,
                          const double *restrict stress, double *restrict state)
{
    (void)context;
    for (size_t i = 0; i < count; ++i) {
        double *q = state + DDP_STATE_SIZE * i;
        q[DDP_DAMAGE] = 0.0;
        q[DDP_EQUIVALENT_STRAIN] = 0.0;
        q[DDP_EQUIVALENT_PLASTIC_STRAIN] = 0.0;
        for (int a = 0; a < 6; ++a)
            q[DDP_EFFECTIVE_STRESS + a] = stress[6 * i + a];
        q[DDP_NONLOCAL_STRAIN] = 0.0;
    }
    return GSN_OK;
}

/* Seed paper eq. (7), without branches (the loop over points below is
 * vectorized): 0 up to e0, 1 from ef. Every case is computed for every
 * point, so no division may trap where its case is not taken: the
 * denominators are kept away from 0 there (e0 > 0). */
static inline double ddp_damage(const struct ddp *m, double e_t)
{
    const double above = e_t > m->e0 ? e_t : m->e0;
    const double zeta = m->ef * (e_t - m->e0) / (above * (m->ef - m->e0));
    return e_t <= m->e0 ? 0.0 : e_t >= m->ef ? 1.0 : zeta;
}

/* Plastic corrector on the effective stress sb (6 components at
 * sb[a * s], in place); returns the norm of the deviatoric plastic strain
 * increment. Every case is computed and one selected, so that the loop over
 * points vectorizes; the selected one has the bits of the branch it
 * stands for. */
static inline double ddp_return(const struct ddp *m, double *restrict sb,
                                size_t s, int cone_only)
{
    const double tr = sb[0] + sb[s] + sb[2 * s];
    const double mean = tr / 3.0;
    double dev[6];
    for (int a = 0; a < 6; ++a)
        dev[a] = sb[a * s] - (a < 3 ? mean : 0.0);
    const double ns = gsn_voigt_norm(dev);
    const double f = ns + m->alpha * tr - m->R; /* eq. (8), tension + */
    const double two_mu = 2.0 * m->mu;
    const double dl = f / (two_mu + 9.0 * m->K * m->alpha * m->beta);
    /* Return to the cone, or to the apex where the cone return would
     * overshoot the axis. */
    const int flows = f > 0.0;
    const int cone = cone_only || two_mu * dl < ns; /* alpha = 0: no apex */
    /* ns > 0 where the cone is taken (f > 0 with ns = 0 needs alpha > 0
     * and then 2 mu dl > 0 = ns) */
    double scale = 1.0 - two_mu * dl / (ns > 0.0 ? ns : 1.0);
    scale = scale < 0.0 ? 0.0 : scale;
    const double mean_new = mean - 3.0 * m->K * m->beta * dl;
    const double apex = m->apex;
    for (int a = 0; a < 6; ++a) {
        const double to_cone = scale * dev[a] + (a < 3 ? mean_new : 0.0);
        const double to_apex = a < 3 ? apex : 0.0;
        sb[a * s] = !flows ? sb[a * s] : cone ? to_cone : to_apex;
    }
    return !flows ? 0.0 : cone ? (1.0 - scale) * ns / two_mu : ns / two_mu;
}

/* What of the model a point goes through: the variants of ddp_point, each
 * with its own loop over the points, since the vectorizer cannot select by
 * a flag that is the same for every point. */
enum {
    DDP_LOCAL_DAMAGE = 1,    /* eq. (7) of e_t */
    DDP_NONLOCAL_DAMAGE = 2, /* eq. (7) of e_t averaged (nonlocal.h) */
    DDP_PLASTIC = 4,         /* eq. (8) */
    DDP_CONE_ONLY = 8        /* alpha = 0: a cylinder, no apex */
};

static int ddp_variant(const struct ddp *m)
{
    int variant = 0;
    if (m->has_damage)
        variant |= m->length > 0.0 ? DDP_NONLOCAL_DAMAGE : DDP_LOCAL_DAMAGE;
    if (m->has_plasticity)
        variant |= DDP_PLASTIC | (m->alpha == 0.0 ? DDP_CONE_ONLY : 0);
    return variant;
}

/* One point of ddp_update; component a of its arrays at x[a * s]. */
__attribute__((always_inline)) static inline void
ddp_point(const struct ddp *m, const double *restrict de, double *restrict q,
          double *restrict stress, size_t s, const int variant)
{
    const double K = m->K, two_mu = 2.0 * m->mu;
    double *sb = q + DDP_EFFECTIVE_STRESS * s;

    /* Elastic-damage predictor (Fig. 3; eqs. (6)-(7)). */
    double d[6];
    for (int a = 0; a < 6; ++a)
        d[a] = de[a * s];
    const double e_t = q[DDP_EQUIVALENT_STRAIN * s] + gsn_voigt_norm(d);
    q[DDP_EQUIVALENT_STRAIN * s] = e_t;
    double zeta = 0.0;
    if (variant & (DDP_LOCAL_DAMAGE | DDP_NONLOCAL_DAMAGE)) {
        zeta = ddp_damage(m, variant & DDP_NONLOCAL_DAMAGE
                                 ? q[DDP_NONLOCAL_STRAIN * s]
                                 : e_t);
        zeta = zeta < q[DDP_DAMAGE * s] ? q[DDP_DAMAGE * s] : zeta;
    }
    q[DDP_DAMAGE * s] = zeta;
    const double dv = de[0] + de[s] + de[2 * s];
    const double dp = K * dv - two_mu * dv / 3.0;
    for (int a = 0; a < 3; ++a)
        sb[a * s] += dp + two_mu * de[a * s];
    for (int a = 3; a < 6; ++a)
        sb[a * s] += two_mu * de[a * s];

    /* Plastic corrector on the effective stress (eq. (8)). */
    if (variant & DDP_PLASTIC)
        q[DDP_EQUIVALENT_PLASTIC_STRAIN * s] +=
            sqrt(2.0 / 3.0) * ddp_return(m, sb, s, variant & DDP_CONE_ONLY);

    /* Nominal stress, eq. (6). */
    for (int a = 0; a < 6; ++a)
        stress[a * s] = (1.0 - zeta) * sb[a * s];
}

/* ddp_point over n points in columns. */
__attribute__((always_inline)) static inline void
ddp_columns(const struct ddp *m, size_t n, size_t column,
            const double *restrict de, double *restrict q,
            double *restrict stress, const int variant)
{
#pragma omp simd
    for (size_t i = 0; i < n; ++i)
        ddp_point(m, &de[i], &q[i], &stress[i], column, variant);
}

/* The points go through ddp_point in columns, the loop over them
 * vectorized; a non-finite stress is reported after, naming the first such
 * point. */
static int ddp_update(const void *context, size_t n, size_t column,
                      const double *restrict strain_increment,
                      double *restrict stress, double *restrict state)
{
    /* a copy that the stores of the loop below cannot reach */
    const struct ddp model = *(const struct ddp *)context;
    switch (ddp_variant(&model)) { /* every variant ddp_variant makes */
#define DDP_CASE(v)                                                            \
    case v:                                                                    \
        ddp_columns(&model, n, column, strain_increment, state, stress, v);    \
        break
        DDP_CASE(0);
        DDP_CASE(DDP_LOCAL_DAMAGE);
        DDP_CASE(DDP_NONLOCAL_DAMAGE);
        DDP_CASE(DDP_PLASTIC);
        DDP_CASE(DDP_PLASTIC | DDP_CONE_ONLY);
        DDP_CASE(DDP_LOCAL_DAMAGE | DDP_PLASTIC);
        DDP_CASE(DDP_LOCAL_DAMAGE | DDP_PLASTIC | DDP_CONE_ONLY);
        DDP_CASE(DDP_NONLOCAL_DAMAGE | DDP_PLASTIC);
        DDP_CASE(DDP_NONLOCAL_DAMAGE | DDP_PLASTIC | DDP_CONE_ONLY);
#undef DDP_CASE
    }
    for (size_t i = 0; i < n; ++i) {
        double t = 0.0;
        for (size_t a = 0; a < 6; ++a)
            t += stress[a * column + i];
        if (!isfinite(t)) {
            const double *d = strain_increment + i;
            return gsn_error_raise(
                GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
                "damage_drucker_prager: non-finite stress at point %zu "
                "of the batch (strain increment %g %g %g %g %g %g)",
                i, d[0], d[column], d[2 * column], d[3 * column], d[4 * column],
                d[5 * column]);
        }
    }
    return GSN_OK;
}

static void ddp_destroy(void **context)
{
    if (!context)
        return;
    free(*context);
    *context = NULL;
}

const struct gsn_material_ops gsn_material_damage_drucker_prager_ops = {
    .name = "damage_drucker_prager",
    .description = "isotropic damage (seed eqs. (6)-(7)) + Drucker-Prager "
                   "perfect plasticity (eq. (8)) on the effective stress",
    .state_variable_count =
        (int)(sizeof ddp_state_variables / sizeof ddp_state_variables[0]),
    .state_variables = ddp_state_variables,
    .state_size = DDP_STATE_SIZE,
    .stress_from_state = 1,
    .create = ddp_create,
    .initialize = ddp_initialize,
    .update = ddp_update,
    .destroy = ddp_destroy,
};
