/* Objective stress update, seed paper Fig. 3 (see stress_update.h). */
#include "stress_update.h"

#include "geoscni/error.h"
#include "geoscni/tensor.h"

#include <stdlib.h>

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

/* The strain increments and rotations Q of n points from their G, all in
 * columns (column doubles a component). */
static void column_increments(size_t n, size_t column, const double *restrict G,
                              double *restrict de, double *restrict Q)
{
#pragma omp simd
    for (size_t i = 0; i < n; ++i)
        increment_strided(&G[i], column, &de[i], column, &Q[i], column);
}

/* Rotates one symmetric tensor (6 columns at t) of n points by their
 * rotations Q (columns). */
static void column_rotate(size_t n, size_t column, const double *restrict Q,
                          double *restrict t)
{
#pragma omp simd
    for (size_t i = 0; i < n; ++i)
        rotate_strided(&Q[i], column, &t[i], column);
}

/* Rotates the stress (unless the model recomputes it from its state) and
 * every tensor state variable of n points in columns. */
static void rotate_columns(const struct gsn_material_ops *ops, size_t n,
                           size_t column, const double *restrict Q,
                           double *stress, double *state)
{
    if (!ops->stress_from_state)
        column_rotate(n, column, Q, stress);
    int offset = 0;
    for (int v = 0; v < ops->state_variable_count; ++v) {
        const enum gsn_state_kind kind = ops->state_variables[v].kind;
        if (kind == GSN_STATE_TENSOR)
            column_rotate(n, column, Q, state + (size_t)offset * column);
        offset += (int)kind;
    }
}

int gsn_stress_update_columns(const struct gsn_material_model *model, size_t n,
                              size_t column,
                              const double *restrict gradient_increment,
                              double *restrict stress, double *restrict state,
                              double *restrict strain_increment)
{
    double Q[9 * GSN_MATERIAL_MAX_COLUMN];
    column_increments(n, column, gradient_increment, strain_increment, Q);
    rotate_columns(model->ops, n, column, Q, stress, state);
    GSN_CALL(model->ops->update(model->context, n, column, strain_increment,
                                stress, state));
    return GSN_OK;
}

/* A batch of point-major arrays in columns, GSN_MATERIAL_COLUMN points. */
struct column_batch {
    double G[9 * STRESS_UPDATE_BLOCK], stress[6 * STRESS_UPDATE_BLOCK];
    double de[6 * STRESS_UPDATE_BLOCK], *state;
};

/* Points [first, first + n) of the arrays into b's columns. */
static void batch_in(struct column_batch *b, size_t ns, size_t first, size_t n,
                     const double *restrict gradient_increment,
                     const double *restrict stress, const double *state)
{
    const size_t C = STRESS_UPDATE_BLOCK;
    gsn_material_to_columns(n, 9, gradient_increment + 9 * first, 9, b->G, C);
    gsn_material_to_columns(n, 6, stress + 6 * first, 6, b->stress, C);
    if (ns > 0)
        gsn_material_to_columns(n, (int)ns, state + ns * first, ns, b->state,
                                C);
}

/* b's columns back into points [first, first + n) of the arrays. */
static void batch_out(const struct column_batch *b, size_t ns, size_t first,
                      size_t n, double *restrict stress, double *state,
                      double *restrict strain_increment)
{
    const size_t C = STRESS_UPDATE_BLOCK;
    gsn_material_from_columns(n, 6, b->stress, C, stress + 6 * first, 6);
    if (ns > 0)
        gsn_material_from_columns(n, (int)ns, b->state, C, state + ns * first,
                                  ns);
    if (strain_increment)
        gsn_material_from_columns(n, 6, b->de, C, strain_increment + 6 * first,
                                  6);
}

/* gsn_stress_update_split on the n points of batch b: half the strain
 * increment, the rotation, the other half. */
static int split_columns(const struct gsn_material_model *model, size_t n,
                         struct column_batch *b)
{
    const size_t C = STRESS_UPDATE_BLOCK;
    double Q[9 * STRESS_UPDATE_BLOCK], half[6 * STRESS_UPDATE_BLOCK];
    column_increments(n, C, b->G, b->de, Q);
    for (size_t a = 0; a < 6; ++a)
        for (size_t i = 0; i < n; ++i)
            half[a * C + i] = 0.5 * b->de[a * C + i];
    GSN_CALL(
        model->ops->update(model->context, n, C, half, b->stress, b->state));
    rotate_columns(model->ops, n, C, Q, b->stress, b->state);
    GSN_CALL(
        model->ops->update(model->context, n, C, half, b->stress, b->state));
    return GSN_OK;
}

/* Runs one of the two updates below over point-major arrays, in batches of
 * columns, with the floating-point exceptions held (material.h). */
static int update_rows(const struct gsn_material_model *model, int split,
                       size_t count, const double *restrict gradient_increment,
                       double *restrict stress, double *restrict state,
                       double *restrict strain_increment)
{
    const size_t ns = (size_t)model->ops->state_size;
    struct column_batch b;
    b.state = ns ? malloc(sizeof(double) * ns * STRESS_UPDATE_BLOCK) : NULL;
    GSN_CHECK(ns == 0 || b.state, GSN_ERR_MEMORY, "out of memory");
    fenv_t caller;
    gsn_hold_exceptions(&caller);
    int rc = GSN_OK;
    for (size_t first = 0; first < count && rc == GSN_OK;
         first += STRESS_UPDATE_BLOCK) {
        const size_t n = count - first < STRESS_UPDATE_BLOCK
                             ? count - first
                             : STRESS_UPDATE_BLOCK;
        batch_in(&b, ns, first, n, gradient_increment, stress, state);
        rc = split ? split_columns(model, n, &b)
                   : gsn_stress_update_columns(model, n, STRESS_UPDATE_BLOCK,
                                               b.G, b.stress, b.state, b.de);
        batch_out(&b, ns, first, n, stress, state, strain_increment);
    }
    gsn_release_exceptions(&caller);
    free(b.state);
    GSN_CALL(rc);
    return GSN_OK;
}

int gsn_stress_update(const struct gsn_material_model *model, size_t count,
                      const double *restrict gradient_increment,
                      double *restrict stress, double *restrict state,
                      double *restrict strain_increment)
{
    return update_rows(model, 0, count, gradient_increment, stress, state,
                       strain_increment);
}

int gsn_stress_update_split(const struct gsn_material_model *model,
                            size_t count,
                            const double *restrict gradient_increment,
                            double *restrict stress, double *restrict state,
                            double *restrict strain_increment)
{
    return update_rows(model, 1, count, gradient_increment, stress, state,
                       strain_increment);
}
