/* Objective stress update, seed paper Fig. 3 (see stress_update.h). */
#include "stress_update.h"

#include "geoscni/error.h"
#include "geoscni/tensor.h"

/* Points per material call: one block of columns (material.h). */
#define STRESS_UPDATE_BLOCK ((size_t)GSN_MATERIAL_COLUMN)

/* The formulas below read component c of a point at x[c * s]: s = 1 for
 * one point's own array, GSN_MATERIAL_COLUMN for a block's columns, where
 * the loops over points vectorize. */

/* gsn_stress_update_increment with strides. */
static inline void increment_strided(const double *restrict G, size_t gs,
                                     double *restrict de, size_t ds,
                                     double *restrict Q, size_t qs)
{
    for (int a = 0; a < GSN_VOIGT_SIZE; ++a) { /* sym G */
        const int i = gsn_voigt_row[a], j = gsn_voigt_col[a];
        de[a * ds] = 0.5 * (G[(3 * i + j) * gs] + G[(3 * j + i) * gs]);
    }
    /* Axial vector a of A = W / 2, W = skw G: A v = a x v. */
    const double a0 = 0.25 * (G[7 * gs] - G[5 * gs]); /* A_21 */
    const double a1 = 0.25 * (G[2 * gs] - G[6 * gs]); /* A_02 */
    const double a2 = 0.25 * (G[3 * gs] - G[1 * gs]); /* A_10 */
    const double aa = a0 * a0 + a1 * a1 + a2 * a2;
    /* Cayley transform: Q = I + 2 / (1 + a.a) (A + A^2), A^2 = a a^T - a.a I
     * (Hughes & Winget 1980; equal to (I - A)^-1 (I + A)). */
    const double c = 2.0 / (1.0 + aa);
    const double A[9] = {0.0, -a2, a1, a2, 0.0, -a0, -a1, a0, 0.0};
    const double a[3] = {a0, a1, a2};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            Q[(3 * i + j) * qs] = (i == j ? 1.0 - c * aa : 0.0) +
                                  c * (A[3 * i + j] + a[i] * a[j]);
}

/* gsn_stress_update_rotate with strides. */
static inline void rotate_strided(const double *restrict Q, size_t qs,
                                  double *restrict t, size_t ts)
{
    double S[9], T[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            S[3 * i + j] = t[gsn_voigt_index(i, j) * ts];
    for (int i = 0; i < 3; ++i) /* T = Q S */
        for (int j = 0; j < 3; ++j)
            T[3 * i + j] = Q[3 * i * qs] * S[j] +
                           Q[(3 * i + 1) * qs] * S[3 + j] +
                           Q[(3 * i + 2) * qs] * S[6 + j];
    for (int v = 0; v < GSN_VOIGT_SIZE; ++v) { /* Q S Q^T */
        const int i = gsn_voigt_row[v], j = gsn_voigt_col[v];
        t[v * ts] = T[3 * i] * Q[3 * j * qs] +
                    T[3 * i + 1] * Q[(3 * j + 1) * qs] +
                    T[3 * i + 2] * Q[(3 * j + 2) * qs];
    }
}

void gsn_stress_update_increment(const double gradient[9],
                                 double strain_increment[6], double rotation[9])
{
    increment_strided(gradient, 1, strain_increment, 1, rotation, 1);
}

void gsn_stress_update_rotate(const double rotation[9], double tensor[6])
{
    rotate_strided(rotation, 1, tensor, 1);
}

/* The strain increments (point-major, into de) and rotations (columns) of n
 * points of a block. */
static void block_increments(size_t n, const double *restrict gradient,
                             double *restrict de, double *restrict Q)
{
    double G[9 * STRESS_UPDATE_BLOCK], de_columns[6 * STRESS_UPDATE_BLOCK];
    gsn_material_to_columns(n, 9, gradient, 9, G, STRESS_UPDATE_BLOCK);
#pragma omp simd
    for (size_t i = 0; i < n; ++i)
        increment_strided(&G[i], STRESS_UPDATE_BLOCK, &de_columns[i],
                          STRESS_UPDATE_BLOCK, &Q[i], STRESS_UPDATE_BLOCK);
    gsn_material_from_columns(n, 6, de_columns, STRESS_UPDATE_BLOCK, de, 6);
}

/* Rotates one symmetric tensor (6 doubles at `tensor`, `stride` doubles a
 * point) of n points of a block by their rotations Q (columns). */
static void block_rotate(size_t n, const double *restrict Q,
                         double *restrict tensor, size_t stride)
{
    double t[6 * STRESS_UPDATE_BLOCK];
    gsn_material_to_columns(n, 6, tensor, stride, t, STRESS_UPDATE_BLOCK);
#pragma omp simd
    for (size_t i = 0; i < n; ++i)
        rotate_strided(&Q[i], STRESS_UPDATE_BLOCK, &t[i], STRESS_UPDATE_BLOCK);
    gsn_material_from_columns(n, 6, t, STRESS_UPDATE_BLOCK, tensor, stride);
}

/* Rotates the stress (unless the model recomputes it from its state) and
 * every tensor state variable of n points of a block. */
static void rotate_block(const struct gsn_material_ops *ops, size_t n,
                         const double *restrict Q, double *stress,
                         double *state)
{
    if (!ops->stress_from_state)
        block_rotate(n, Q, stress, 6);
    int offset = 0;
    for (int v = 0; v < ops->state_variable_count; ++v) {
        const enum gsn_state_kind kind = ops->state_variables[v].kind;
        if (kind == GSN_STATE_TENSOR)
            block_rotate(n, Q, state + offset, (size_t)ops->state_size);
        offset += (int)kind;
    }
}

int gsn_stress_update(const struct gsn_material_model *model, size_t count,
                      const double *restrict gradient_increment,
                      double *restrict stress, double *restrict state,
                      double *restrict strain_increment)
{
    const struct gsn_material_ops *ops = model->ops;
    const size_t ns = (size_t)ops->state_size;
    double block[6 * STRESS_UPDATE_BLOCK], Q[9 * STRESS_UPDATE_BLOCK];
    fenv_t caller;
    gsn_hold_exceptions(&caller);
    int rc = GSN_OK;
    for (size_t first = 0; first < count && rc == GSN_OK;
         first += STRESS_UPDATE_BLOCK) {
        size_t n = STRESS_UPDATE_BLOCK;
        if (count - first < n)
            n = count - first;
        double *de = block;
        if (strain_increment)
            de = strain_increment + 6 * first;
        double *q = ns ? state + ns * first : state;
        block_increments(n, gradient_increment + 9 * first, de, Q);
        rotate_block(ops, n, Q, stress + 6 * first, q);
        rc = ops->update(model->context, n, de, stress + 6 * first, q);
    }
    gsn_release_exceptions(&caller);
    if (rc != GSN_OK)
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "ops->update(model->context, n, de, ...)");
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
    double half[6 * STRESS_UPDATE_BLOCK], de[6 * STRESS_UPDATE_BLOCK];
    double Q[9 * STRESS_UPDATE_BLOCK];
    for (size_t first = 0; first < count; first += STRESS_UPDATE_BLOCK) {
        size_t n = STRESS_UPDATE_BLOCK;
        if (count - first < n)
            n = count - first;
        double *q = ns ? state + ns * first : state;
        double *d = strain_increment ? strain_increment + 6 * first : de;
        block_increments(n, gradient_increment + 9 * first, d, Q);
        for (size_t a = 0; a < 6 * n; ++a)
            half[a] = 0.5 * d[a];
        int rc = ops->update(model->context, n, half, stress + 6 * first, q);
        if (rc != GSN_OK)
            return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                                  "ops->update(model->context, n, half, ...)");
        rotate_block(ops, n, Q, stress + 6 * first, q);
        rc = ops->update(model->context, n, half, stress + 6 * first, q);
        if (rc != GSN_OK)
            return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                                  "ops->update(model->context, n, half, ...)");
    }
    return GSN_OK;
}
