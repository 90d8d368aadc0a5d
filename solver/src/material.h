/* Material models behind one table of function pointers (STYLE.md rule 7,
 * after CB-Geo mpm's material interface).
 *
 * A model is a `struct gsn_material_ops` table: its name, its named state
 * variables, and create / initialize / update / destroy. The registry
 * (material_registry.c) finds a table by name; adding a model (for example
 * Mohr-Coulomb) is one new file material_NAME.c that defines
 * `gsn_material_NAME_ops` and one line in GSN_MATERIAL_LIST.
 *
 * Storage, per point (see geoscni/tensor.h for the conventions):
 * - stress: 6 doubles, Voigt xx yy zz xy yz xz, NOMINAL Cauchy stress
 *   sigma (seed paper eq. (6): sigma = (1 - zeta) * effective stress),
 *   tension positive, Pa. This is the stress of the internal force.
 * - state: `state_size` doubles in the order of `state_variables`; a
 *   GSN_STATE_TENSOR variable is 6 consecutive Voigt entries and is rotated
 *   with the stress by the objective update (stress_update.h).
 * - strain increment: 6 doubles, Voigt, TENSOR shear (d eps_xy, not
 *   d gamma_xy), dimensionless.
 * The solver keeps them point-major: point i's stress is stress[6*i + k],
 * its state state[state_size*i + k]. A model's update works on a batch in
 * columns (component k of point i at x[k * column + i]), where its loop
 * over the points vectorizes; gsn_material_update takes point-major arrays.
 *
 * References: seed paper (../shared/paper/seed-paper.txt) eqs. (6)-(8) and
 * Fig. 3; Simo & Ju 1987 (elastic-damage predictor, plastic corrector);
 * de Souza Neto, Peric & Owen 2008, section 8.3 (Drucker-Prager return to
 * the cone and to the apex). */
#ifndef GEOSCNI_MATERIAL_H
#define GEOSCNI_MATERIAL_H

#include "geoscni/case.h"

#include <fenv.h>
#include <stddef.h>
#ifdef __AVX__
#include <immintrin.h>
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The kind of a state variable is the number of doubles it takes. */
enum gsn_state_kind {
    GSN_STATE_SCALAR = 1,
    GSN_STATE_TENSOR = 6 /* symmetric, Voigt; rotated by the update */
};

struct gsn_state_variable {
    const char *name; /* output name, e.g. "damage" */
    enum gsn_state_kind kind;
    const char *units;
    const char *description;
};

struct gsn_material_ops {
    const char *name; /* the registry key, e.g. "elastic" */
    const char *description;
    int state_variable_count;
    const struct gsn_state_variable *state_variables;
    int state_size; /* doubles per point: sum of the kinds */
    /* 1: update() computes the stress from the state alone (the objective
     * update then need not rotate the stress array, only the tensor state);
     * 0: update() reads the (rotated) stress. */
    int stress_from_state;

    /* Checks the parameters and makes the model's context (its resolved
     * parameters). GSN_ERR_INPUT for impossible values. */
    int (*create)(const struct gsn_material *parameters, void **context);

    /* Sets the state of count points that carry the given nominal stress
     * (e.g. a geostatic initial stress) and no history: no damage, no
     * plastic strain. stress is read, state written. */
    int (*initialize)(const void *context, size_t count,
                      const double *restrict stress, double *restrict state);

    /* One strain-driven step of n points: from the stress and state at
     * t_n (already rotated to t_{n+1} by the objective update) and the
     * strain increment, the stress and state at t_{n+1}, in place. The
     * arrays are columns (below): component c of point i at
     * x[c * column + i], i < n <= column, so that the loop over points
     * vectorizes; gsn_material_update takes point-major arrays. Pure: no
     * allocation, I/O or globals; the caller parallelizes over batches and
     * holds the floating-point exceptions (gsn_hold_exceptions). Returns
     * GSN_OK, or GSN_ERR_NUMERICAL (raised, naming the point in the batch)
     * when a point cannot be updated. */
    int (*update)(const void *context, size_t n, size_t column,
                  const double *restrict strain_increment,
                  double *restrict stress, double *restrict state);

    /* Frees the context and nulls the handle; NULL-safe. */
    void (*destroy)(void **context);
};

/* A batch's points as columns, for loops over points that the compiler
 * vectorizes (#pragma omp simd; 8 points an instruction with AVX-512):
 * component c of point i of a point-major array with `stride` doubles a
 * point is columns[c * column + i], i < n <= column (GSN_MATERIAL_COLUMN
 * in the updates of point-major arrays, at most GSN_MATERIAL_MAX_COLUMN).
 * Only copies: the bits of an update do not depend on the layout. */
enum { GSN_MATERIAL_COLUMN = 64, GSN_MATERIAL_MAX_COLUMN = 128 };

/* dst[j * D + k] = src[k * S + j] for j, k < 4: a 4 x 4 block transposed,
 * with AVX four loads, four unpacks, four lane swaps and four stores (the
 * copies element by element were a third of main_chunk's time on Zen 3). */
static inline void gsn_copy_transposed_4x4(const double *restrict src, size_t S,
                                           double *restrict dst, size_t D)
{
#ifdef __AVX__
    const __m256d a = _mm256_loadu_pd(src), b = _mm256_loadu_pd(src + S);
    const __m256d c = _mm256_loadu_pd(src + 2 * S);
    const __m256d d = _mm256_loadu_pd(src + 3 * S);
    const __m256d t0 = _mm256_unpacklo_pd(a, b); /* a0 b0 a2 b2 */
    const __m256d t1 = _mm256_unpackhi_pd(a, b); /* a1 b1 a3 b3 */
    const __m256d t2 = _mm256_unpacklo_pd(c, d); /* c0 d0 c2 d2 */
    const __m256d t3 = _mm256_unpackhi_pd(c, d); /* c1 d1 c3 d3 */
    _mm256_storeu_pd(dst, _mm256_permute2f128_pd(t0, t2, 0x20));
    _mm256_storeu_pd(dst + D, _mm256_permute2f128_pd(t1, t3, 0x20));
    _mm256_storeu_pd(dst + 2 * D, _mm256_permute2f128_pd(t0, t2, 0x31));
    _mm256_storeu_pd(dst + 3 * D, _mm256_permute2f128_pd(t1, t3, 0x31));
#else
    for (size_t j = 0; j < 4; ++j)
        for (size_t k = 0; k < 4; ++k)
            dst[j * D + k] = src[k * S + j];
#endif
}

/* dst[j * D + k] = src[k * S + j] for k < K, j < J, by 4 x 4 blocks. */
static inline void gsn_copy_transposed(size_t K, size_t J,
                                       const double *restrict src, size_t S,
                                       double *restrict dst, size_t D)
{
    size_t k = 0;
    for (; k + 4 <= K; k += 4) {
        size_t j = 0;
        for (; j + 4 <= J; j += 4)
            gsn_copy_transposed_4x4(src + k * S + j, S, dst + j * D + k, D);
        for (; j < J; ++j)
            for (size_t q = k; q < k + 4; ++q)
                dst[j * D + q] = src[q * S + j];
    }
    for (; k < K; ++k)
        for (size_t j = 0; j < J; ++j)
            dst[j * D + k] = src[k * S + j];
}

static inline void
gsn_material_to_columns(size_t n, int width, const double *restrict rows,
                        size_t stride, double *restrict columns, size_t column)
{
    gsn_copy_transposed(n, (size_t)width, rows, stride, columns, column);
}

static inline void
gsn_material_from_columns(size_t n, int width, const double *restrict columns,
                          size_t column, double *restrict rows, size_t stride)
{
    gsn_copy_transposed((size_t)width, n, columns, column, rows, stride);
}

/* Loops over columns compute every case of a select in every lane and
 * keep one (solver/CMakeLists.txt, -fno-trapping-math), so an untaken case
 * may divide by zero in its lane. They run between these two: the
 * floating-point exceptions are held (traps off, the flags raised then
 * dropped) and the caller's environment is given back after; the callers
 * check the results themselves (non-finite stresses, inverted points). */
static inline void gsn_hold_exceptions(fenv_t *caller)
{
    feholdexcept(caller);
}

static inline void gsn_release_exceptions(const fenv_t *caller)
{
    fesetenv(caller);
}

/* A model with its parameters: what the solver holds. */
struct gsn_material_model {
    const struct gsn_material_ops *ops;
    void *context;
};

/* The soils of a case on its particles (issue 22): one model per soil,
 * all of one kind so that every point's state has one layout, and each
 * particle's. The soils are the case's (material: one; materials: one per
 * physical volume), then those of the interfaces: a particle where soils
 * meet has a nodal domain on both sides, and it carries the density and
 * stiffness of the soil with most of its tetrahedra but the strength of the
 * weakest soil there (at the effective vertical stress of its weight), as
 * a slip surface along the interface would find it. */
enum { GSN_MAX_SOILS = 4 * GSN_MAX_MATERIALS };
struct gsn_material_set {
    int count;      /* soils */
    int case_count; /* the first case_count are the case's materials */
    struct gsn_material_model *model[GSN_MAX_SOILS]; /* owned */
    struct gsn_material soil[GSN_MAX_SOILS];
    const struct gsn_material *parameters[GSN_MAX_SOILS]; /* &soil[k] */
    int particle_count;
    int *particle_material; /* index into model, per particle */
    int interface_count;    /* particles with an interface soil */
};

/* The set of case c on model m's particles: each particle's material from
 * its physical volume (materials:), or 0 (material:). GSN_ERR_INPUT naming
 * the volume when a particle's volume has no material. */
struct gsn_model;
int gsn_material_set_create(const struct gsn_case *c, const struct gsn_model *m,
                            struct gsn_material_set **out);

/* Frees and nulls the handle; NULL-safe. */
void gsn_material_set_destroy(struct gsn_material_set **set);

/* The table of a registered model, or NULL. */
const struct gsn_material_ops *gsn_material_find(const char *name);

/* Number of registered models and the i-th one (for listings and tests). */
int gsn_material_count(void);
const struct gsn_material_ops *gsn_material_at(int index);

/* The model a case's material block asks for: "damage_drucker_prager" when
 * it has damage or plasticity, "elastic" otherwise. (The case file has no
 * model key yet; this is the one place that maps it.) */
const char *gsn_material_name_for_case(const struct gsn_material *parameters);

/* Creates the named model (GSN_ERR_INPUT naming the known models if the name
 * is unknown). The caller owns *model and frees it with
 * gsn_material_model_destroy. */
int gsn_material_model_create(const char *name,
                              const struct gsn_material *parameters,
                              struct gsn_material_model **model);

/* Frees a model and nulls the handle; NULL-safe. */
void gsn_material_model_destroy(struct gsn_material_model **model);

/* Offset of a named state variable within a point's state, or -1 if the
 * model has no such variable (e.g. "damage" of the elastic model). */
int gsn_material_state_offset(const struct gsn_material_ops *ops,
                              const char *name);

/* Calls through the table; gsn_material_update on point-major arrays
 * (strain increment count x 6, stress count x 6, state count x state_size),
 * copied into columns GSN_MATERIAL_COLUMN points at a time. */
int gsn_material_initialize(const struct gsn_material_model *model,
                            size_t count, const double *restrict stress,
                            double *restrict state);
int gsn_material_update(const struct gsn_material_model *model, size_t count,
                        const double *restrict strain_increment,
                        double *restrict stress, double *restrict state);

#ifdef __cplusplus
}
#endif
#endif
