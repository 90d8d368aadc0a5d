/* Objective stress update of the seed paper's Fig. 3: Hughes & Winget 1980
 * (IJNME 15:1862) integration of the Jaumann rate, followed by the
 * material's elastic-damage predictor and plastic corrector (material.h).
 *
 * Per point, from the incremental displacement gradient on the mid-step
 * configuration, G = d(Delta u) / d(x_{n+1/2}) with
 * x_{n+1/2} = x_n + Delta u / 2 (row-major, G_ij = d Delta u_i / d x_j):
 *   Delta eps   = (G + G^T) / 2,   Delta omega = (G - G^T) / 2,
 *   Q           = (I - Delta omega / 2)^-1 (I + Delta omega / 2),
 *   sigma      <- Q sigma Q^T  (and every tensor state variable alike),
 *   then the material update with Delta eps.
 * This is the plain Hughes-Winget update, sigma_{n+1} = Q sigma_n Q^T +
 * C : Delta eps for an elastic step, first order in time for simple shear
 * (REFERENCES.md, "Objective update"); a rigid rotation is exact to round
 * off when G is taken on x_{n+1/2} (Delta eps = 0 and Q = R exactly). */
#ifndef GEOSCNI_STRESS_UPDATE_H
#define GEOSCNI_STRESS_UPDATE_H

#include "material.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* From one incremental gradient G (9, row-major, dimensionless) the strain
 * increment (6, Voigt, tensor shear) and the Hughes-Winget rotation Q
 * (9, row-major), Q = (I - W/2)^-1 (I + W/2) with W = skw G, in the closed
 * (Cayley) form Q = I + 2 / (1 + |a|^2) (A + A^2), A = W/2, a its axial
 * vector. */
void gsn_stress_update_increment(const double gradient[9],
                                 double strain_increment[6],
                                 double rotation[9]);

/* Rotates a symmetric tensor in Voigt storage: t <- Q t Q^T. */
void gsn_stress_update_rotate(const double rotation[9], double tensor[6]);

/* The whole update of Fig. 3 for count points (pure: no allocation; the
 * caller parallelizes over batches): gradient_increment is count x 9
 * (G on x_{n+1/2} of each point); stress (count x 6, nominal, Pa) and state
 * (count x state_size) are updated in place from t_n to t_{n+1}.
 * strain_increment, if not NULL, receives the count x 6 strain increments
 * (e.g. for the internal energy). Returns the material's code. */
int gsn_stress_update(const struct gsn_material_model *model, size_t count,
                      const double *restrict gradient_increment,
                      double *restrict stress, double *restrict state,
                      double *restrict strain_increment);

/* gsn_stress_update on n <= GSN_MATERIAL_MAX_COLUMN points in columns
 * (material.h: component c of point i at x[c * column + i]); the strain
 * increments (6 columns) are required. The caller holds the floating-point
 * exceptions (gsn_hold_exceptions). */
int gsn_stress_update_columns(const struct gsn_material_model *model, size_t n,
                              size_t column,
                              const double *restrict gradient_increment,
                              double *restrict stress, double *restrict state,
                              double *restrict strain_increment);

/* A second-order variant (not the paper's): the material step is split
 * around the rotation, half strain increment, rotation by Q, half strain
 * increment; for hypoelasticity sigma_{n+1} = Q (sigma_n + C : Delta eps / 2)
 * Q^T + C : Delta eps / 2 (REFERENCES.md, "Objective update": max error / mu
 * in simple shear to gamma = pi 1.2e-2, 1.2e-4, 1.2e-6 for N = 10, 100,
 * 1000). Two material calls per step; e_t still grows by ||Delta eps||.
 * Same arguments as gsn_stress_update. */
int gsn_stress_update_split(const struct gsn_material_model *model,
                            size_t count,
                            const double *restrict gradient_increment,
                            double *restrict stress, double *restrict state,
                            double *restrict strain_increment);

#ifdef __cplusplus
}
#endif
#endif
