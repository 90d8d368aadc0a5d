/* Model "elastic": isotropic hypoelasticity,
 * sigma_{n+1} = sigma_n + C : d eps with C = K I (x) I + 2 mu (II - I (x) I /
 * 3) (the elastic part of seed paper Fig. 3). Rotated by the objective update
 * (stress_update.h), this is the Jaumann-rate hypoelastic solid of the
 * simple-shear and wave verification cases. No state variables. */
#include "material.h"

#include "geoscni/error.h"
#include "geoscni/tensor.h"

#include <math.h>
#include <stdlib.h>

struct elastic {
    double bulk_modulus;  /* K, Pa */
    double shear_modulus; /* mu, Pa */
};

static int elastic_create(const struct gsn_material *parameters, void **context)
{
    const double K = parameters->bulk_modulus, mu = parameters->shear_modulus;
    GSN_CHECK(isfinite(K) && K > 0.0, GSN_ERR_INPUT,
              "elastic: bulk modulus must be > 0 Pa (got %g)", K);
    GSN_CHECK(isfinite(mu) && mu > 0.0, GSN_ERR_INPUT,
              "elastic: shear modulus must be > 0 Pa (got %g)", mu);
    struct elastic *e = malloc(sizeof *e);
    GSN_CHECK(e != NULL, GSN_ERR_MEMORY, "elastic: out of memory");
    e->bulk_modulus = K;
    e->shear_modulus = mu;
    *context = e;
    return GSN_OK;
}

static int elastic_initialize(const void *context, size_t count,
                              const double *restrict stress,
                              double *restrict state)
{
    (void)context, (void)count, (void)stress, (void)state;
    return GSN_OK;
}

static int elastic_update(const void *context, size_t n, size_t column,
                          const double *restrict strain_increment,
                          double *restrict stress, double *restrict state)
{
    (void)state;
    const struct elastic *e = context;
    const double K = e->bulk_modulus, two_mu = 2.0 * e->shear_modulus;
#pragma omp simd
    for (size_t i = 0; i < n; ++i) {
        const double *de = strain_increment + i;
        double *s = stress + i;
        const double dv = de[0] + de[column] + de[2 * column];
        const double dp = K * dv - two_mu * dv / 3.0;
        for (size_t a = 0; a < 3; ++a)
            s[a * column] += dp + two_mu * de[a * column];
        for (size_t a = 3; a < 6; ++a)
            s[a * column] += two_mu * de[a * column];
    }
    return GSN_OK;
}

static void elastic_destroy(void **context)
{
    if (!context)
        return;
    free(*context);
    *context = NULL;
}

const struct gsn_material_ops gsn_material_elastic_ops = {
    .name = "elastic",
    .description = "isotropic hypoelastic solid (K, mu)",
    .state_variable_count = 0,
    .state_variables = NULL,
    .state_size = 0,
    .stress_from_state = 0,
    .create = elastic_create,
    .initialize = elastic_initialize,
    .update = elastic_update,
    .destroy = elastic_destroy,
};
