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

/* Seed paper eq. (7). */
static inline double ddp_damage(const struct ddp *m, double e_t)
{
    if (e_t <= m->e0)
        return 0.0;
    if (e_t >= m->ef)
        return 1.0;
    return m->ef * (e_t - m->e0) / (e_t * (m->ef - m->e0));
}

/* Plastic corrector on the effective stress sb (Voigt, in place); returns
 * the norm of the deviatoric plastic strain increment. */
static inline double ddp_return(const struct ddp *m, double sb[6])
{
    const double tr = sb[0] + sb[1] + sb[2];
    const double mean = tr / 3.0;
    double s[6] = {sb[0] - mean, sb[1] - mean, sb[2] - mean,
                   sb[3],        sb[4],        sb[5]};
    const double ns = gsn_voigt_norm(s);
    const double f = ns + m->alpha * tr - m->R; /* eq. (8), tension + */
    if (!(f > 0.0))
        return 0.0;
    const double two_mu = 2.0 * m->mu;
    const double dl = f / (two_mu + 9.0 * m->K * m->alpha * m->beta);
    if (two_mu * dl < ns || m->alpha == 0.0) {
        /* Return to the cone. */
        double scale = 1.0 - two_mu * dl / ns;
        if (scale < 0.0)
            scale = 0.0;
        const double mean_new = mean - 3.0 * m->K * m->beta * dl;
        for (int a = 0; a < 3; ++a)
            sb[a] = scale * s[a] + mean_new;
        for (int a = 3; a < 6; ++a)
            sb[a] = scale * s[a];
        return (1.0 - scale) * ns / two_mu;
    }
    /* The cone return would overshoot the axis: return to the apex. */
    const double apex = m->R / (3.0 * m->alpha);
    for (int a = 0; a < 3; ++a)
        sb[a] = apex;
    for (int a = 3; a < 6; ++a)
        sb[a] = 0.0;
    return ns / two_mu;
}

static int ddp_update(const void *context, size_t count,
                      const double *restrict strain_increment,
                      double *restrict stress, double *restrict state)
{
    const struct ddp *m = context;
    const double K = m->K, two_mu = 2.0 * m->mu;
    const double sqrt_two_thirds = sqrt(2.0 / 3.0);
    for (size_t i = 0; i < count; ++i) {
        const double *de = strain_increment + 6 * i;
        double *q = state + DDP_STATE_SIZE * i;
        double *sb = q + DDP_EFFECTIVE_STRESS;

        /* Elastic-damage predictor (Fig. 3; eqs. (6)-(7)). */
        const double e_t = q[DDP_EQUIVALENT_STRAIN] + gsn_voigt_norm(de);
        q[DDP_EQUIVALENT_STRAIN] = e_t;
        double zeta = 0.0;
        if (m->has_damage) {
            /* with damage.length, e_t averaged over it (nonlocal.h) */
            zeta =
                ddp_damage(m, m->length > 0.0 ? q[DDP_NONLOCAL_STRAIN] : e_t);
            if (zeta < q[DDP_DAMAGE])
                zeta = q[DDP_DAMAGE];
        }
        q[DDP_DAMAGE] = zeta;
        const double dv = de[0] + de[1] + de[2];
        const double dp = K * dv - two_mu * dv / 3.0;
        for (int a = 0; a < 3; ++a)
            sb[a] += dp + two_mu * de[a];
        for (int a = 3; a < 6; ++a)
            sb[a] += two_mu * de[a];

        /* Plastic corrector on the effective stress (eq. (8)). */
        if (m->has_plasticity)
            q[DDP_EQUIVALENT_PLASTIC_STRAIN] +=
                sqrt_two_thirds * ddp_return(m, sb);

        /* Nominal stress, eq. (6). */
        double *s = stress + 6 * i;
        for (int a = 0; a < 6; ++a)
            s[a] = (1.0 - zeta) * sb[a];
        if (!isfinite(s[0] + s[1] + s[2] + s[3] + s[4] + s[5]))
            return gsn_error_raise(
                GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
                "damage_drucker_prager: non-finite stress at point %zu of "
                "the batch (strain increment %g %g %g %g %g %g)",
                i, de[0], de[1], de[2], de[3], de[4], de[5]);
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
