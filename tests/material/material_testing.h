/* Helpers of the single-stress-point material tests: the paper material,
 * one point driven by strain increments, by incremental gradients (through
 * the objective update), or by mixed strain/stress control. */
#ifndef GEOSCNI_MATERIAL_TESTING_H
#define GEOSCNI_MATERIAL_TESTING_H

#include "geoscni/error.h"
#include "geoscni/tensor.h"
#include "material.h"
#include "stress_update.h"
#include "testing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Paper material (seed paper section 6; REFERENCES.md). */
#define PAPER_K 27.4e6
#define PAPER_MU 9.15e6
#define PAPER_ALPHA 0.07
#define PAPER_R 0.19e6
#define PAPER_E0 0.02
#define PAPER_EF 5.0

static inline struct gsn_material paper_material(int damage, int plasticity,
                                                 double dilatancy)
{
    struct gsn_material m = {0};
    m.density = 1880.0;
    m.bulk_modulus = PAPER_K;
    m.shear_modulus = PAPER_MU;
    m.has_damage = damage;
    m.damage_e0 = PAPER_E0;
    m.damage_ef = PAPER_EF;
    m.has_plasticity = plasticity;
    m.dp_alpha = PAPER_ALPHA;
    m.dp_R = PAPER_R;
    m.dp_dilatancy = dilatancy;
    return m;
}

/* Creates a model or exits: a test cannot go on without one. */
static inline struct gsn_material_model *
model_make(const char *name, const struct gsn_material *parameters)
{
    struct gsn_material_model *model = NULL;
    if (gsn_material_model_create(name, parameters, &model) != GSN_OK) {
        gsn_error_print(stderr);
        exit(1);
    }
    return model;
}

enum { POINT_STATE_CAPACITY = 32 };

struct point {
    const struct gsn_material_model *model;
    double stress[6]; /* nominal, Pa */
    double state[POINT_STATE_CAPACITY];
};

static inline void point_init(struct point *p,
                              const struct gsn_material_model *model,
                              const double stress0[6])
{
    memset(p, 0, sizeof *p);
    p->model = model;
    if (stress0)
        memcpy(p->stress, stress0, sizeof p->stress);
    if (model->ops->state_size > POINT_STATE_CAPACITY ||
        gsn_material_initialize(model, 1, p->stress, p->state) != GSN_OK) {
        fprintf(stderr, "point_init failed\n");
        exit(1);
    }
}

/* State variable by name (exits if the model lacks it). */
static inline double point_state(const struct point *p, const char *name)
{
    int offset = gsn_material_state_offset(p->model->ops, name);
    if (offset < 0) {
        fprintf(stderr, "model %s has no state '%s'\n", p->model->ops->name,
                name);
        exit(1);
    }
    return p->state[offset];
}

/* Small-strain step: the material update alone. */
static inline void point_strain_step(struct point *p, const double de[6])
{
    if (gsn_material_update(p->model, 1, de, p->stress, p->state) != GSN_OK) {
        gsn_error_print(stderr);
        exit(1);
    }
}

/* Large-deformation step: objective update of Fig. 3 from G. */
static inline void point_gradient_step(struct point *p, const double G[9])
{
    if (gsn_stress_update(p->model, 1, G, p->stress, p->state, NULL) !=
        GSN_OK) {
        gsn_error_print(stderr);
        exit(1);
    }
}

/* Yield function of eq. (8), tension positive (DESIGN.md), on a stress. */
static inline double yield_function(const double s[6], double alpha, double R)
{
    const double tr = gsn_voigt_trace(s), mean = tr / 3.0;
    const double d[6] = {s[0] - mean, s[1] - mean, s[2] - mean,
                         s[3],        s[4],        s[5]};
    return gsn_voigt_norm(d) + alpha * tr - R;
}

static inline double mean_stress(const double s[6])
{
    return gsn_voigt_trace(s) / 3.0;
}

/* Solves the small dense system A x = b (n <= 6) by Gaussian elimination
 * with partial pivoting; returns 0 if singular. */
static inline int dense_solve(int n, double *A, double *b)
{
    for (int k = 0; k < n; ++k) {
        int piv = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(A[n * i + k]) > fabs(A[n * piv + k]))
                piv = i;
        if (A[n * piv + k] == 0.0)
            return 0;
        if (piv != k) {
            for (int j = 0; j < n; ++j) {
                double t = A[n * k + j];
                A[n * k + j] = A[n * piv + j];
                A[n * piv + j] = t;
            }
            double t = b[k];
            b[k] = b[piv];
            b[piv] = t;
        }
        for (int i = k + 1; i < n; ++i) {
            double f = A[n * i + k] / A[n * k + k];
            for (int j = k; j < n; ++j)
                A[n * i + j] -= f * A[n * k + j];
            b[i] -= f * b[k];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        for (int j = i + 1; j < n; ++j)
            b[i] -= A[n * i + j] * b[j];
        b[i] /= A[n * i + i];
    }
    return 1;
}

/* Mixed control: components with stress_controlled[a] get the strain
 * increment that brings the stress component a to target[a] (Newton with a
 * finite-difference Jacobian on copies of the point: the update is pure);
 * the others get de[a]. The point is advanced; de is overwritten with the
 * increment used. Returns the largest stress residual (Pa). */
static inline double point_mixed_step(struct point *p, double de[6],
                                      const int stress_controlled[6],
                                      const double target[6])
{
    const double K = PAPER_K, mu = PAPER_MU;
    int u[6] = {0}, m = 0;
    for (int a = 0; a < 6; ++a)
        if (stress_controlled[a])
            u[m++] = a;
    /* Start from the elastic guess with the other components: a zero
     * increment for the controlled ones. */
    for (int k = 0; k < m; ++k)
        de[u[k]] = 0.0;
    double residual = INFINITY;
    for (int iteration = 0; iteration < 60; ++iteration) {
        struct point trial = *p;
        point_strain_step(&trial, de);
        double r[6];
        residual = 0.0;
        for (int k = 0; k < m; ++k) {
            r[k] = trial.stress[u[k]] - target[u[k]];
            residual = fmax(residual, fabs(r[k]));
        }
        if (residual <= 1e-9) /* Pa: round-off of stresses of 1e5-1e6 Pa */
            break;
        double J[36];
        for (int l = 0; l < m; ++l) {
            const double h = 1e-9; /* strain: stress change ~ 0.03 Pa */
            double dp[6];
            memcpy(dp, de, sizeof dp);
            dp[u[l]] += h;
            struct point plus = *p;
            point_strain_step(&plus, dp);
            for (int k = 0; k < m; ++k)
                J[m * k + l] = (plus.stress[u[k]] - trial.stress[u[k]]) / h;
        }
        if (!dense_solve(m, J, r)) {
            /* singular tangent (e.g. at the apex): elastic compliance */
            for (int k = 0; k < m; ++k)
                r[k] = (trial.stress[u[k]] - target[u[k]]) /
                       (u[k] < 3 ? K + 4.0 * mu / 3.0 : 2.0 * mu);
        }
        for (int k = 0; k < m; ++k)
            de[u[k]] -= r[k];
    }
    point_strain_step(p, de);
    return residual;
}

#endif
