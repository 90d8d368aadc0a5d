/* Tensor conventions used by every stage (STYLE.md rule 8).
 *
 * - SI units throughout: m, s, kg, Pa, N, J.
 * - Stress is Cauchy stress, tension positive. The Drucker-Prager yield
 *   function of seed paper eq. (8) is read with a compression-positive trace,
 *   i.e. ||dev s|| + alpha tr s - R <= 0 in tension-positive stress
 *   (DESIGN.md, "Sign convention").
 * - Symmetric tensors are stored as 6 doubles in the Voigt order
 *   xx yy zz xy yz xz (the order of the output arrays). Stress components
 *   are tensor components; strain-like arrays (GSN_VOIGT_*) also store
 *   tensor shear components (eps_xy, not gamma_xy = 2 eps_xy) unless a
 *   name says "engineering".
 * - Full 3x3 tensors are row-major: A[3*i + j] = A_ij. A gradient
 *   G_ij = d u_i / d x_j.
 * - Vectors of particles are structure-of-arrays or n x 3 row-major
 *   (x_I = position[3*I + k]), as each dataset says. */
#ifndef GEOSCNI_TENSOR_H
#define GEOSCNI_TENSOR_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

enum gsn_voigt {
    GSN_VOIGT_XX = 0,
    GSN_VOIGT_YY = 1,
    GSN_VOIGT_ZZ = 2,
    GSN_VOIGT_XY = 3,
    GSN_VOIGT_YZ = 4,
    GSN_VOIGT_XZ = 5,
    GSN_VOIGT_SIZE = 6
};

/* Row and column of each Voigt entry in a 3x3 tensor. */
static const int gsn_voigt_row[GSN_VOIGT_SIZE] = {0, 1, 2, 0, 1, 0};
static const int gsn_voigt_col[GSN_VOIGT_SIZE] = {0, 1, 2, 1, 2, 2};

/* Voigt entry of tensor component (i, j). */
static inline int gsn_voigt_index(int i, int j)
{
    static const int table[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
    return table[i][j];
}

/* Full 3x3 (row-major) from Voigt, and symmetric part of a 3x3 to Voigt. */
static inline void gsn_voigt_to_matrix(const double v[6], double m[9])
{
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j)
            m[3 * i + j] = v[gsn_voigt_index(i, j)];
}

static inline void gsn_matrix_sym_to_voigt(const double m[9], double v[6])
{
#pragma GCC unroll 6
    for (int a = 0; a < GSN_VOIGT_SIZE; ++a) {
        const int i = gsn_voigt_row[a], j = gsn_voigt_col[a];
        v[a] = 0.5 * (m[3 * i + j] + m[3 * j + i]);
    }
}

/* The smaller and the larger of two numbers that are not NaN: one
 * instruction, where fmin and fmax are library calls (their NaN rules);
 * for the loops over points, vertices and edges. */
static inline double gsn_min(double a, double b)
{
    return b < a ? b : a;
}

static inline double gsn_max(double a, double b)
{
    return b > a ? b : a;
}

/* Trace and Frobenius norm of a symmetric tensor in Voigt storage. */
static inline double gsn_voigt_trace(const double v[6])
{
    return v[0] + v[1] + v[2];
}

static inline double gsn_voigt_norm(const double v[6])
{
    double s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    s += 2.0 * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    return sqrt(s);
}

/* Determinant of a 3x3 row-major matrix. */
static inline double gsn_matrix_determinant(const double m[9])
{
    return m[0] * (m[4] * m[8] - m[5] * m[7]) -
           m[1] * (m[3] * m[8] - m[5] * m[6]) +
           m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/* inverse = m^-1 by cofactors; returns det m (the inverse is undefined
 * when it is 0). */
static inline double gsn_matrix_inverse(const double m[9], double inverse[9])
{
    double det = gsn_matrix_determinant(m);
    double s = 1.0 / det;
    inverse[0] = (m[4] * m[8] - m[5] * m[7]) * s;
    inverse[1] = (m[2] * m[7] - m[1] * m[8]) * s;
    inverse[2] = (m[1] * m[5] - m[2] * m[4]) * s;
    inverse[3] = (m[5] * m[6] - m[3] * m[8]) * s;
    inverse[4] = (m[0] * m[8] - m[2] * m[6]) * s;
    inverse[5] = (m[2] * m[3] - m[0] * m[5]) * s;
    inverse[6] = (m[3] * m[7] - m[4] * m[6]) * s;
    inverse[7] = (m[1] * m[6] - m[0] * m[7]) * s;
    inverse[8] = (m[0] * m[4] - m[1] * m[3]) * s;
    return det;
}

/* cof m = det(m) m^-T, by cofactors (no division: defined for any m). */
static inline void gsn_matrix_cofactor(const double m[9], double c[9])
{
    c[0] = m[4] * m[8] - m[5] * m[7];
    c[1] = m[5] * m[6] - m[3] * m[8];
    c[2] = m[3] * m[7] - m[4] * m[6];
    c[3] = m[2] * m[7] - m[1] * m[8];
    c[4] = m[0] * m[8] - m[2] * m[6];
    c[5] = m[1] * m[6] - m[0] * m[7];
    c[6] = m[1] * m[5] - m[2] * m[4];
    c[7] = m[2] * m[3] - m[0] * m[5];
    c[8] = m[0] * m[4] - m[1] * m[3];
}

/* c = a b for 3x3 row-major matrices (c must not alias a or b). */
static inline void gsn_matrix_multiply(const double a[9], const double b[9],
                                       double c[9])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] +
                           a[3 * i + 2] * b[6 + j];
}

#ifdef __cplusplus
}
#endif
#endif
