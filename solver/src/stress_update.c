/* Objective stress update, seed paper Fig. 3 (see stress_update.h). */
#include "stress_update.h"

#include "geoscni/error.h"
#include "geoscni/tensor.h"

#define STRESS_UPDATE_BLOCK ((size_t)64) /* points per material call */

void gsn_stress_update_increment(const double gradient[9],
                                 double strain_increment[6], double rotation[9])
{
    const double *G = gradient;
    gsn_matrix_sym_to_voigt(G, strain_increment);
    /* Axial vector a of A = W / 2, W = skw G: A v = a x v. */
    const double a0 = 0.25 * (G[7] - G[5]); /* A_21 = (G_21 - G_12) / 4 */
    const double a1 = 0.25 * (G[2] - G[6]); /* A_02 */
    const double a2 = 0.25 * (G[3] - G[1]); /* A_10 */
    const double aa = a0 * a0 + a1 * a1 + a2 * a2;
    /* Cayley transform: Q = I + 2 / (1 + a.a) (A + A^2), A^2 = a a^T - a.a I
     * (Hughes & Winget 1980; equal to (I - A)^-1 (I + A)). */
    const double c = 2.0 / (1.0 + aa);
    const double A[9] = {0.0, -a2, a1, a2, 0.0, -a0, -a1, a0, 0.0};
    const double a[3] = {a0, a1, a2};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            rotation[3 * i + j] = (i == j ? 1.0 - c * aa : 0.0) +
                                  c * (A[3 * i + j] + a[i] * a[j]);
}

void gsn_stress_update_rotate(const double rotation[9], double tensor[6])
{
    const double *Q = rotation;
    double S[9], T[9];
    gsn_voigt_to_matrix(tensor, S);
    for (int i = 0; i < 3; ++i) /* T = Q S */
        for (int j = 0; j < 3; ++j)
            T[3 * i + j] = Q[3 * i] * S[j] + Q[3 * i + 1] * S[3 + j] +
                           Q[3 * i + 2] * S[6 + j];
    for (int v = 0; v < GSN_VOIGT_SIZE; ++v) { /* Q S Q^T */
        const int i = gsn_voigt_row[v], j = gsn_voigt_col[v];
        tensor[v] = T[3 * i] * Q[3 * j] + T[3 * i + 1] * Q[3 * j + 1] +
                    T[3 * i + 2] * Q[3 * j + 2];
    }
}

/* Rotates the stress (unless the model recomputes it from its state) and
 * every tensor state variable of one point. */
static void rotate_point(const struct gsn_material_ops *ops, const double Q[9],
                         double *stress, double *state)
{
    if (!ops->stress_from_state)
        gsn_stress_update_rotate(Q, stress);
    double *q = state;
    for (int v = 0; v < ops->state_variable_count; ++v) {
        const enum gsn_state_kind kind = ops->state_variables[v].kind;
        if (kind == GSN_STATE_TENSOR)
            gsn_stress_update_rotate(Q, q);
        q += (int)kind;
    }
}

int gsn_stress_update(const struct gsn_material_model *model, size_t count,
                      const double *restrict gradient_increment,
                      double *restrict stress, double *restrict state,
                      double *restrict strain_increment)
{
    const struct gsn_material_ops *ops = model->ops;
    const size_t ns = (size_t)ops->state_size;
    double block[6 * STRESS_UPDATE_BLOCK];
    for (size_t first = 0; first < count; first += STRESS_UPDATE_BLOCK) {
        size_t n = STRESS_UPDATE_BLOCK;
        if (count - first < n)
            n = count - first;
        double *de = block; /* written by gsn_stress_update_increment */
        if (strain_increment)
            de = strain_increment + 6 * first;
        double *q = ns ? state + ns * first : state;
        for (size_t i = 0; i < n; ++i) {
            double Q[9];
            gsn_stress_update_increment(gradient_increment + 9 * (first + i),
                                        de + 6 * i, Q);
            rotate_point(ops, Q, stress + 6 * (first + i),
                         ns ? q + ns * i : NULL);
        }
        int rc = ops->update(model->context, n, de, stress + 6 * first, q);
        if (rc != GSN_OK)
            return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                                  "ops->update(model->context, n, de, ...)");
    }
    return GSN_OK;
}

int gsn_stress_update_split(const struct gsn_material_model *model,
                            size_t count,
                            const double *restrict gradient_increment,
                            double *restrict stress, double *restrict state,
                            double *restrict strain_increment)
{
    const struct gsn_material_ops *ops = model->ops;
    const size_t ns = (size_t)ops->state_size;
    double half[6 * STRESS_UPDATE_BLOCK], rotation[9 * STRESS_UPDATE_BLOCK];
    for (size_t first = 0; first < count; first += STRESS_UPDATE_BLOCK) {
        size_t n = STRESS_UPDATE_BLOCK;
        if (count - first < n)
            n = count - first;
        double *q = ns ? state + ns * first : state;
        for (size_t i = 0; i < n; ++i) {
            double de[6];
            gsn_stress_update_increment(gradient_increment + 9 * (first + i),
                                        de, rotation + 9 * i);
            for (int a = 0; a < 6; ++a) {
                half[6 * i + a] = 0.5 * de[a];
                if (strain_increment)
                    strain_increment[6 * (first + i) + a] = de[a];
            }
        }
        int rc = ops->update(model->context, n, half, stress + 6 * first, q);
        if (rc != GSN_OK)
            return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                                  "ops->update(model->context, n, half, ...)");
        for (size_t i = 0; i < n; ++i)
            rotate_point(ops, rotation + 9 * i, stress + 6 * (first + i),
                         ns ? q + ns * i : NULL);
        rc = ops->update(model->context, n, half, stress + 6 * first, q);
        if (rc != GSN_OK)
            return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                                  "ops->update(model->context, n, half, ...)");
    }
    return GSN_OK;
}
