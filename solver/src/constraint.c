/* Exact essential boundary conditions on u(X_J): see constraint.h. */
#include "constraint.h"
#include "geoscni/error.h"

#include <cholmod.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* S_c whose Cholesky factor has (min L_kk / max L_kk)^2 below this (CHOLMOD's
 * cholmod_rcond, a cheap estimate of the reciprocal condition) cannot be
 * trusted to impose the boundary values to 1e-8 relative. */
#define CONSTRAINT_RCOND_LIMIT 1e-12
/* The copied factor must solve S x = b with a componentwise backward
 * error (|S x - b|_i / (|S| |x| + |b|)_i, Oettli-Prager) below
 * this: Cholesky gives a small multiple of n eps; a wrong copy of the
 * factor gives O(1), whatever the conditioning. */
#define CONSTRAINT_SOLVE_CHECK 1e-10
/* Constrained particle components below which the three solves run on one
 * thread (a parallel region costs more than small solves). */
enum { CONSTRAINT_PARALLEL_MIN = 2048 };

struct component_constraint {
    int count;        /* |B_c| */
    int *particle;    /* B_c, ascending */
    double *velocity; /* prescribed velocity of each, m/s (0: fixed) */
    /* C_c: row s = Psi_I(X_J) over all I, J = particle[s] (CSR) */
    int *row_offset;
    int *row_index;
    double *row_value;
    /* C_c^T by the particles its rows touch (ascending), with each touched
     * particle's inverse mass: the correction M^-1 C^T lambda */
    int touched_count;
    int *touched;
    double *touched_inverse_mass;
    int *touched_offset;
    int *touched_row;
    double *touched_value;
    /* S_c = C_c M^-1 C_c^T (rows and columns B_c) in CSR, for the check */
    int *s_offset;
    int *s_column;
    double *s_entry;
    double *rhs; /* right-hand side, then solution */
    /* The supernodal Cholesky factor of S_c from CHOLMOD, P S P^T = L L^T,
     * copied for the solve of every step: per supernode (columns
     * super_column[s] .. super_column[s+1]-1, w of them) its diagonal
     * block's lower triangle by rows (row r holds r + 1 values, the
     * diagonal last, inverted), then its rows below the block, w values
     * each, by rows; their pivots in super_row. Every value is read once
     * forward and once backward, in storage order, in dense runs of w. */
    int *pivot; /* P: pivot k is unknown pivot[k] */
    int super_count;
    int *super_column;          /* super_count + 1 */
    int *super_row_offset;      /* super_count + 1: into super_row */
    int *super_row;             /* the pivots of the rows below each block */
    size_t *super_value_offset; /* super_count + 1: into super_value */
    double *super_value;
    double *pivot_work; /* count */
};

struct gsn_constraints {
    int particle_count;
    int surface_count;
    double ramp;           /* s, time.ramp */
    double epoch;          /* s: displacements are prescribed from then on (the
                              time of the last reference update) */
    int *surface_mask;     /* per model surface: constrained components */
    unsigned *released;    /* particles: entries that let them go, or NULL */
    int *surface_entry;    /* per model surface: the entry naming it, or 0 */
    int *entry_of;         /* particles x 3: the boundary entry whose
                              prescription holds the component, or -1 */
    int *slot[3];          /* slot[c][I]: position of I in B_c, or -1 */
    double *mass;          /* the lumped masses of gsn_constraints_set_mass */
    int factorized;        /* S_c formed and factorized with them */
    int boundary_only;     /* gsn_constraints_set_boundary_only */
    double factor_seconds; /* wall time spent factorizing, s */
    struct component_constraint component[3];
};

static const char component_names[3] = {'x', 'y', 'z'};

static void component_factors_free(struct component_constraint *cc);

void gsn_constraints_destroy(struct gsn_constraints **constraints)
{
    if (!constraints || !*constraints)
        return;
    struct gsn_constraints *k = *constraints;
    for (int c = 0; c < 3; ++c) {
        struct component_constraint *cc = &k->component[c];
        free(cc->particle);
        free(cc->velocity);
        free(cc->rhs);
        component_factors_free(cc);
        int *ints[] = {cc->row_offset, cc->row_index, cc->touched,
                       cc->touched_offset, cc->touched_row};
        double *doubles[] = {cc->row_value, cc->touched_inverse_mass,
                             cc->touched_value};
        for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i)
            free(ints[i]);
        for (size_t i = 0; i < sizeof doubles / sizeof doubles[0]; ++i)
            free(doubles[i]);
        free(k->slot[c]);
    }
    free(k->surface_mask);
    free(k->mass);
    free(k->entry_of);
    free(k->released);
    free(k->surface_entry);
    free(k);
    *constraints = NULL;
}

/* Prescriptions per (particle, component): the first boundary entry in
 * case order that constrains it (-1: none; any later one must prescribe
 * the same value) and its velocity. */
static int collect_prescriptions(const struct gsn_model *m,
                                 const struct gsn_case *c,
                                 const unsigned *released, int *entry_of,
                                 double *velocity_of)
{
    int n = m->particle_count;
    for (int i = 0; i < 3 * n; ++i)
        entry_of[i] = -1;
    for (int b = 0; b < c->boundary_count; ++b) {
        const struct gsn_boundary *entry = &c->boundaries[b];
        int surface = gsn_model_find_surface(m, entry->name);
        GSN_CHECK(surface >= 0, GSN_ERR_INPUT,
                  "%s:%d: boundary '%s' is not a physical surface of the "
                  "model; name a surface of the geometry (run pre again if "
                  "the geometry changed)",
                  c->path, entry->line, entry->name);
        for (int p = 0; p < n; ++p) {
            if (!gsn_model_particle_on_surface(m, p, surface) ||
                (released && (released[p] >> b & 1u)))
                continue;
            for (int k = 0; k < 3; ++k) {
                if (!entry->fixed[k] && !entry->has_velocity[k])
                    continue;
                double value = entry->fixed[k] ? 0.0 : entry->velocity[k];
                int previous = entry_of[3 * p + k];
                GSN_CHECK(previous < 0 || velocity_of[3 * p + k] == value,
                          GSN_ERR_INPUT,
                          "%s:%d: particle %d at (%g, %g, %g) lies on '%s' "
                          "and '%s', which prescribe different %c "
                          "velocities (%g and %g m/s); make them agree",
                          c->path, entry->line, p, m->position[3 * p],
                          m->position[3 * p + 1], m->position[3 * p + 2],
                          previous >= 0 ? c->boundaries[previous].name : "",
                          entry->name, component_names[k],
                          velocity_of[3 * p + k], value);
                if (previous < 0)
                    entry_of[3 * p + k] = b;
                velocity_of[3 * p + k] = value;
            }
        }
    }
    return GSN_OK;
}

/* The factor's supernodes into cc (layout above), from CHOLMOD's
 * supernodal L (L(r, c) of supernode s at x[px[s] + r + c nsrow], its rows
 * s[pi[s] ..], the first w of them its columns). */
static int copy_factor(struct component_constraint *cc, const cholmod_factor *L)
{
    int n = cc->count, ns = (int)L->nsuper;
    const int *super = L->super, *pi = L->pi, *px = L->px, *rows = L->s;
    const int *perm = L->Perm;
    const double *x = L->x;
    cc->super_count = ns;
    cc->pivot = malloc(sizeof(int) * (size_t)n);
    cc->super_column = malloc(sizeof(int) * ((size_t)ns + 1));
    cc->super_row_offset = malloc(sizeof(int) * ((size_t)ns + 1));
    cc->super_value_offset = malloc(sizeof(size_t) * ((size_t)ns + 1));
    cc->pivot_work = malloc(sizeof(double) * (size_t)n);
    GSN_CHECK(cc->pivot && cc->super_column && cc->super_row_offset &&
                  cc->super_value_offset && cc->pivot_work,
              GSN_ERR_MEMORY, "out of memory");
    memcpy(cc->pivot, perm, sizeof(int) * (size_t)n);
    size_t values = 0;
    int below = 0;
    cc->super_row_offset[0] = 0;
    cc->super_value_offset[0] = 0;
    for (int k = 0; k < ns; ++k) {
        int w = super[k + 1] - super[k], h = pi[k + 1] - pi[k] - w;
        cc->super_column[k] = super[k];
        below += h;
        values += (size_t)w * (size_t)(w + 1) / 2 + (size_t)h * (size_t)w;
        cc->super_row_offset[k + 1] = below;
        cc->super_value_offset[k + 1] = values;
    }
    cc->super_column[ns] = super[ns];
    cc->super_row = malloc(sizeof(int) * (below ? (size_t)below : 1));
    cc->super_value = malloc(sizeof(double) * (values ? values : 1));
    GSN_CHECK(cc->super_row && cc->super_value, GSN_ERR_MEMORY,
              "out of memory");
    for (int k = 0; k < ns; ++k) {
        int w = super[k + 1] - super[k], nr = pi[k + 1] - pi[k];
        const double *X = x + px[k];
        double *v = cc->super_value + cc->super_value_offset[k];
        for (int r = 0; r < w; ++r) {
            for (int c = 0; c < r; ++c)
                *v++ = X[r + (size_t)c * nr];
            GSN_CHECK(X[r + (size_t)r * nr] > 0.0, GSN_ERR_NUMERICAL,
                      "the boundary factor has a zero pivot");
            *v++ = 1.0 / X[r + (size_t)r * nr];
        }
        for (int r = w; r < nr; ++r) {
            cc->super_row[cc->super_row_offset[k] + r - w] = rows[pi[k] + r];
            for (int c = 0; c < w; ++c)
                *v++ = X[r + (size_t)c * nr];
        }
    }
    return GSN_OK;
}

/* sum_c a[c] b[c], c < w, in four interleaved partial sums (a fixed
 * order: the same bits on every run) so that the multiply-adds do not wait
 * for each other. */
static inline double dot(const double *restrict a, const double *restrict b,
                         int w)
{
    double t0 = 0.0, t1 = 0.0, t2 = 0.0, t3 = 0.0;
    int c = 0;
    for (; c + 3 < w; c += 4) {
        t0 += a[c] * b[c];
        t1 += a[c + 1] * b[c + 1];
        t2 += a[c + 2] * b[c + 2];
        t3 += a[c + 3] * b[c + 3];
    }
    for (; c < w; ++c)
        t0 += a[c] * b[c];
    return (t0 + t1) + (t2 + t3);
}

/* x = S^-1 b in place, with the copied factor: y = P b, L z = y,
 * L^T w = z, x = P^T w; by supernodes, forward then backward, each
 * value read in storage order. The rows below a block are taken four at a
 * time (independent sums forward, one pass over z backward). */
static void factor_solve(struct component_constraint *cc, double *x)
{
    const int n = cc->count, ns = cc->super_count;
    double *restrict y = cc->pivot_work;
    const double *restrict value = cc->super_value;
    const int *restrict row = cc->super_row;
    for (int k = 0; k < n; ++k)
        y[k] = x[cc->pivot[k]];
    for (int s = 0; s < ns; ++s) {
        const int k0 = cc->super_column[s], w = cc->super_column[s + 1] - k0;
        const double *restrict v = value + cc->super_value_offset[s];
        double *restrict z = y + k0;
        for (int r = 0; r < w; ++r) {
            z[r] = (z[r] - dot(v, z, r)) * v[r];
            v += r + 1;
        }
        int e = cc->super_row_offset[s];
        const int e1 = cc->super_row_offset[s + 1];
        for (; e + 3 < e1; e += 4, v += 4 * w) {
            double t0 = 0.0, t1 = 0.0, t2 = 0.0, t3 = 0.0;
            for (int c = 0; c < w; ++c) {
                t0 += v[c] * z[c];
                t1 += v[w + c] * z[c];
                t2 += v[2 * w + c] * z[c];
                t3 += v[3 * w + c] * z[c];
            }
            y[row[e]] -= t0;
            y[row[e + 1]] -= t1;
            y[row[e + 2]] -= t2;
            y[row[e + 3]] -= t3;
        }
        for (; e < e1; ++e, v += w)
            y[row[e]] -= dot(v, z, w);
    }
    for (int s = ns - 1; s >= 0; --s) {
        const int k0 = cc->super_column[s], w = cc->super_column[s + 1] - k0;
        const int e0 = cc->super_row_offset[s],
                  e1 = cc->super_row_offset[s + 1];
        const double *restrict block = value + cc->super_value_offset[s];
        const double *restrict v = block + (size_t)w * (size_t)(w + 1) / 2;
        double *restrict z = y + k0;
        int e = e0;
        for (; e + 3 < e1; e += 4, v += 4 * w) {
            const double y0 = y[row[e]], y1 = y[row[e + 1]];
            const double y2 = y[row[e + 2]], y3 = y[row[e + 3]];
            for (int c = 0; c < w; ++c)
                z[c] -= (v[c] * y0 + v[w + c] * y1) +
                        (v[2 * w + c] * y2 + v[3 * w + c] * y3);
        }
        for (; e < e1; ++e, v += w) {
            const double ye = y[row[e]];
            for (int c = 0; c < w; ++c)
                z[c] -= v[c] * ye;
        }
        /* L^T of the block: rows from the last, each row's values once */
        v = block + (size_t)w * (size_t)(w + 1) / 2;
        for (int r = w - 1; r >= 0; --r) {
            v -= r + 1;
            const double zr = z[r] * v[r];
            z[r] = zr;
            for (int c = 0; c < r; ++c)
                z[c] -= v[c] * zr;
        }
    }
    for (int k = 0; k < n; ++k)
        x[cc->pivot[k]] = y[k];
}

/* A symmetric matrix of n rows in CSR (offset, column; value, or NULL for
 * the pattern) as CHOLMOD's lower triangle: column j holds row j's entries
 * of column i >= j (the rows' upper halves stand for both, as S's rows are
 * summed in orders that may differ in the last bit); NULL when out of
 * memory. */
static cholmod_sparse *lower_triangle(int n, const int *offset,
                                      const int *column, const double *value,
                                      cholmod_common *cm)
{
    size_t entries = 0;
    for (int j = 0; j < n; ++j)
        for (int e = offset[j]; e < offset[j + 1]; ++e)
            entries += column[e] >= j;
    cholmod_sparse *A =
        cholmod_allocate_sparse((size_t)n, (size_t)n, entries, 0, 1, -1,
                                value ? CHOLMOD_REAL : CHOLMOD_PATTERN, cm);
    if (!A)
        return NULL;
    int *Ap = A->p, *Ai = A->i, at = 0;
    double *Ax = A->x;
    for (int j = 0; j < n; ++j) {
        Ap[j] = at;
        for (int e = offset[j]; e < offset[j + 1]; ++e)
            if (column[e] >= j) {
                if (value)
                    Ax[at] = value[e];
                Ai[at++] = column[e];
            }
    }
    Ap[n] = at;
    return A;
}

/* CHOLMOD, set for a supernodal L L^T factor with its default ordering
 * (AMD, or METIS where AMD fills in much) and no messages. */
static void cholmod_begin(cholmod_common *cm)
{
    cholmod_start(cm);
    cm->supernodal = CHOLMOD_SUPERNODAL;
    cm->final_ll = 1;
    cm->print = 0;
    cm->error_handler = NULL;
}

/* Factorizes S_c (supernodal Cholesky, CHOLMOD), checks its condition,
 * copies the factor for the step's solves and checks it on one right-hand
 * side; CHOLMOD's own objects are freed after. */
static int factorize(struct component_constraint *cc, char name)
{
    int n = cc->count;
    double *b = malloc(sizeof(double) * (size_t)n);
    cholmod_common cm;
    cholmod_begin(&cm);
    /* the least fill of AMD, METIS and CHOLMOD's nested dissection (its
     * suite's methods 1 to 3; by default METIS only where AMD fills in
     * badly): every step reads the factor twice, and on Slope I nested
     * dissection's y factor has 10% fewer values than AMD's, the boundary
     * solves 10% faster (docs/solver.md, "2026-12-07, midnight") */
    cm.nmethods = 4;
    cholmod_sparse *A =
        lower_triangle(n, cc->s_offset, cc->s_column, cc->s_entry, &cm);
    cholmod_factor *L = NULL;
    int rc = GSN_OK;
    GSN_CHECK_GOTO(A && b, rc, GSN_ERR_MEMORY, done, "out of memory");
    L = cholmod_analyze(A, &cm);
    GSN_CHECK_GOTO(L, rc, GSN_ERR_NUMERICAL, done,
                   "the %c boundary matrix (%d particles) could not be "
                   "analysed (CHOLMOD status %d)",
                   name, n, cm.status);
    cholmod_factorize(A, L, &cm);
    GSN_CHECK_GOTO(
        cm.status == CHOLMOD_OK && L->minor == (size_t)n && L->is_super, rc,
        GSN_ERR_NUMERICAL, done,
        "the %c boundary matrix C M^-1 C^T of %d constrained particles "
        "is singular (CHOLMOD status %d); check for duplicate boundary "
        "particles",
        name, n, cm.status);
    double rcond = cholmod_rcond(L, &cm);
    GSN_CHECK_GOTO(rcond > CONSTRAINT_RCOND_LIMIT, rc, GSN_ERR_NUMERICAL, done,
                   "the %c boundary matrix of %d constrained particles is "
                   "too badly conditioned (reciprocal condition %.3g)",
                   name, n, rcond);
    GSN_CALL_GOTO(copy_factor(cc, L), rc, done);
    /* The copy solves S x = b, b_i = 1 + i mod 7. */
    for (int i = 0; i < n; ++i)
        b[i] = 1.0 + i % 7;
    factor_solve(cc, b);
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = -(1.0 + i % 7), scale = 1.0 + i % 7;
        for (int e = cc->s_offset[i]; e < cc->s_offset[i + 1]; ++e) {
            r += cc->s_entry[e] * b[cc->s_column[e]];
            scale += fabs(cc->s_entry[e] * b[cc->s_column[e]]);
        }
        worst = fmax(worst, fabs(r) / scale);
    }
    GSN_CHECK_GOTO(worst <= CONSTRAINT_SOLVE_CHECK, rc, GSN_ERR_INTERNAL, done,
                   "the %c boundary solve has a backward error of %.3g", name,
                   worst);
done:
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&A, &cm);
    cholmod_finish(&cm);
    free(b);
    return rc;
}

/* B_c, the rows of C_c (Psi_I(X_J) over every I) and their transpose by
 * the touched particles; S_c is formed and factorized by
 * gsn_constraints_set_mass. */
static int component_build(struct gsn_constraints *k, int c,
                           const struct gsn_model *m,
                           const struct gsn_shape_rows *values,
                           const int *entry_of, const double *velocity_of)
{
    struct component_constraint *cc = &k->component[c];
    int n = m->particle_count;
    k->slot[c] = malloc(sizeof(int) * (size_t)(n ? n : 1));
    GSN_CHECK(k->slot[c], GSN_ERR_MEMORY, "out of memory");
    for (int p = 0; p < n; ++p) {
        k->slot[c][p] = entry_of[3 * p + c] >= 0 ? cc->count : -1;
        cc->count += entry_of[3 * p + c] >= 0;
    }
    if (cc->count == 0)
        return GSN_OK;
    size_t count = (size_t)cc->count;
    cc->particle = malloc(sizeof(int) * count);
    cc->velocity = malloc(sizeof(double) * count);
    cc->row_offset = calloc(count + 1, sizeof(int));
    cc->rhs = malloc(sizeof(double) * count);
    GSN_CHECK(cc->particle && cc->velocity && cc->row_offset && cc->rhs,
              GSN_ERR_MEMORY, "out of memory");
    for (int p = 0; p < n; ++p) {
        int s = k->slot[c][p];
        if (s < 0)
            continue;
        cc->particle[s] = p;
        cc->velocity[s] = velocity_of[3 * p + c];
        cc->row_offset[s + 1] = values->offset[p + 1] - values->offset[p];
    }
    for (size_t s = 0; s < count; ++s)
        cc->row_offset[s + 1] += cc->row_offset[s];
    size_t entries = (size_t)cc->row_offset[count];
    cc->row_index = malloc(sizeof(int) * (entries ? entries : 1));
    cc->row_value = malloc(sizeof(double) * (entries ? entries : 1));
    int *position = calloc((size_t)n + 1, sizeof(int));
    if (!(cc->row_index && cc->row_value && position)) {
        free(position);
        GSN_CHECK(0, GSN_ERR_MEMORY, "out of memory");
    }
    for (size_t s = 0; s < count; ++s) {
        int p = cc->particle[s], e0 = values->offset[p];
        memcpy(cc->row_index + cc->row_offset[s], values->index + e0,
               sizeof(int) * (size_t)(values->offset[p + 1] - e0));
        memcpy(cc->row_value + cc->row_offset[s], values->value + e0,
               sizeof(double) * (size_t)(values->offset[p + 1] - e0));
    }
    /* the transpose: position[I] = 1 + its place among the touched */
    for (size_t e = 0; e < entries; ++e)
        position[cc->row_index[e]] = 1;
    for (int p = 0; p < n; ++p)
        if (position[p])
            position[p] = ++cc->touched_count;
    size_t touched = (size_t)cc->touched_count;
    cc->touched = malloc(sizeof(int) * touched);
    cc->touched_inverse_mass = malloc(sizeof(double) * touched);
    cc->touched_offset = calloc(touched + 1, sizeof(int));
    cc->touched_row = malloc(sizeof(int) * (entries ? entries : 1));
    cc->touched_value = malloc(sizeof(double) * (entries ? entries : 1));
    int *fill = malloc(sizeof(int) * (touched + 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(cc->touched && cc->touched_inverse_mass &&
                       cc->touched_offset && cc->touched_row &&
                       cc->touched_value && fill,
                   rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int p = 0; p < n; ++p)
        if (position[p])
            cc->touched[position[p] - 1] = p;
    for (size_t e = 0; e < entries; ++e)
        cc->touched_offset[position[cc->row_index[e]]]++;
    for (size_t t = 0; t < touched; ++t)
        cc->touched_offset[t + 1] += cc->touched_offset[t];
    memcpy(fill, cc->touched_offset, sizeof(int) * touched);
    for (size_t s = 0; s < count; ++s) /* rows ascending in each column */
        for (int e = cc->row_offset[s]; e < cc->row_offset[s + 1]; ++e) {
            int at = fill[position[cc->row_index[e]] - 1]++;
            cc->touched_row[at] = (int)s;
            cc->touched_value[at] = cc->row_value[e];
        }
done:
    free(fill);
    free(position);
    return rc;
}

/* Frees S_c and its factors (a new mass forms them again). */
static void component_factors_free(struct component_constraint *cc)
{
    int **ints[] = {&cc->s_offset,     &cc->s_column,         &cc->pivot,
                    &cc->super_column, &cc->super_row_offset, &cc->super_row};
    double **doubles[] = {&cc->s_entry, &cc->super_value, &cc->pivot_work};
    free(cc->super_value_offset);
    cc->super_value_offset = NULL;
    cc->super_count = 0;
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i) {
        free(*ints[i]);
        *ints[i] = NULL;
    }
    for (size_t i = 0; i < sizeof doubles / sizeof doubles[0]; ++i) {
        free(*doubles[i]);
        *doubles[i] = NULL;
    }
}

/* S_c = C_c M^-1 C_c^T: row s sums, over the particles I of row s of C,
 * Psi_I(X_J) Psi_I(X_K) / m_I into the columns K that touch I. */
static int component_factorize(struct component_constraint *cc,
                               const double *mass, const int *slot,
                               int boundary_only, char name)
{
    int n = cc->count;
    component_factors_free(cc);
    /* boundary_only: the other particles as if infinitely heavy, so the
     * correction M^-1 C^T lambda reaches B_c alone: Lambda^-1 r */
    for (int t = 0; t < cc->touched_count; ++t)
        cc->touched_inverse_mass[t] = boundary_only && slot[cc->touched[t]] < 0
                                          ? 0.0
                                          : 1.0 / mass[cc->touched[t]];
    double *dense = calloc((size_t)n, sizeof(double));
    int *mark = malloc(sizeof(int) * (size_t)n);
    int *list = malloc(sizeof(int) * (size_t)n);
    /* the touched index of each entry of C, by binary search once */
    size_t entries = (size_t)cc->row_offset[n];
    int *entry_touched = malloc(sizeof(int) * (entries ? entries : 1));
    cc->s_offset = calloc((size_t)n + 1, sizeof(int));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(dense && mark && list && entry_touched && cc->s_offset, rc,
                   GSN_ERR_MEMORY, done, "out of memory");
    for (size_t e = 0; e < entries; ++e) {
        int lo = 0, hi = cc->touched_count - 1, I = cc->row_index[e];
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (cc->touched[mid] < I)
                lo = mid + 1;
            else
                hi = mid;
        }
        entry_touched[e] = lo;
    }
    for (int i = 0; i < n; ++i)
        mark[i] = -1;
    size_t capacity = 0, used = 0;
    for (int pass = 0; pass < 2; ++pass) {
        used = 0;
        for (int s = 0; s < n; ++s) {
            int listed = 0;
            for (int e = cc->row_offset[s]; e < cc->row_offset[s + 1]; ++e) {
                int t = entry_touched[e];
                double a = cc->row_value[e] * cc->touched_inverse_mass[t];
                for (int k = cc->touched_offset[t];
                     k < cc->touched_offset[t + 1]; ++k) {
                    int column = cc->touched_row[k];
                    if (mark[column] != s) {
                        mark[column] = s;
                        list[listed++] = column;
                        dense[column] = 0.0;
                    }
                    dense[column] += a * cc->touched_value[k];
                }
            }
            if (pass == 1)
                for (int l = 0; l < listed; ++l) {
                    cc->s_column[used + (size_t)l] = list[l];
                    cc->s_entry[used + (size_t)l] = dense[list[l]];
                }
            used += (size_t)listed;
            cc->s_offset[s + 1] = (int)used;
        }
        if (pass == 0) {
            capacity = used;
            cc->s_column = malloc(sizeof(int) * (capacity ? capacity : 1));
            cc->s_entry = malloc(sizeof(double) * (capacity ? capacity : 1));
            GSN_CHECK_GOTO(cc->s_column && cc->s_entry, rc, GSN_ERR_MEMORY,
                           done, "out of memory");
            for (int i = 0; i < n; ++i)
                mark[i] = -1;
        }
    }
    rc = factorize(cc, name);
done:
    free(dense);
    free(mark);
    free(list);
    free(entry_touched);
    return rc;
}

int gsn_constraints_set_mass(struct gsn_constraints *constraints,
                             const double *mass)
{
    size_t n = (size_t)constraints->particle_count;
    if (!constraints->mass) {
        constraints->mass = malloc(sizeof(double) * (n ? n : 1));
        GSN_CHECK(constraints->mass, GSN_ERR_MEMORY, "out of memory");
    }
    memcpy(constraints->mass, mass, sizeof(double) * n);
    constraints->factorized = 0;
    return GSN_OK;
}

/* S_c of the masses last set, formed and factorized where they changed
 * (the first correction after gsn_constraints_set_mass: a reference
 * update sets the masses twice, and factorizes once). */
static int ensure_factorized(struct gsn_constraints *constraints)
{
    if (constraints->factorized)
        return GSN_OK;
    GSN_CHECK(constraints->mass, GSN_ERR_INTERNAL,
              "the constraints have no mass (gsn_constraints_set_mass)");
    double start = omp_get_wtime();
    for (int c = 0; c < 3; ++c)
        if (constraints->component[c].count > 0)
            GSN_CALL(component_factorize(
                &constraints->component[c], constraints->mass,
                constraints->slot[c], constraints->boundary_only,
                component_names[c]));
    constraints->factorized = 1;
    constraints->factor_seconds += omp_get_wtime() - start;
    return GSN_OK;
}

double gsn_constraints_factor_seconds(const struct gsn_constraints *constraints)
{
    return constraints->factor_seconds;
}

/* The prescriptions of case `given` on model m (symmetry entries resolved):
 * entry_of and velocity_of per particle and component (collect_
 * prescriptions), and per model surface the components its entry holds
 * and that entry's index (both arrays surface_count + 1, zeroed). For the
 * rows of the constraints (rows 1) the rollers along a plane_strain axis
 * are left out: the key holds that component at every particle already
 * (explicit.c), and on a slab nearly every particle lies on one of its two
 * faces, so they made most of S and its factors (docs/solver.md, "Plane
 * strain"); the held facets keep them (the same gradients as with them). */
static int prescribe(const struct gsn_model *m, const struct gsn_case *given,
                     const unsigned *released, int rows, int *entry_of,
                     double *velocity_of, int *surface_mask, int *surface_entry)
{
    /* symmetry planes hold their normal component: a copy with it fixed */
    struct gsn_case *c = malloc(sizeof *c);
    GSN_CHECK(c, GSN_ERR_MEMORY, "out of memory");
    *c = *given;
    int rc = gsn_case_resolve_symmetry(c, m);
    int axis = rows ? c->plane_strain_axis : -1;
    unsigned axis_held = 0; /* bit b: entry b held the axis */
    for (int b = 0; axis >= 0 && b < c->boundary_count; ++b) {
        struct gsn_boundary *entry = &c->boundaries[b];
        if (entry->fixed[axis] || entry->has_velocity[axis])
            axis_held |= 1u << b;
        entry->fixed[axis] = entry->has_velocity[axis] = 0;
        entry->velocity[axis] = 0.0;
    }
    if (rc == GSN_OK)
        rc = collect_prescriptions(m, c, released, entry_of, velocity_of);
    for (int b = 0; rc == GSN_OK && b < c->boundary_count; ++b) {
        int surface = gsn_model_find_surface(m, c->boundaries[b].name);
        surface_entry[surface] = b;
        for (int comp = 0; comp < 3; ++comp)
            if (c->boundaries[b].fixed[comp] ||
                c->boundaries[b].has_velocity[comp] ||
                (comp == axis && axis_held >> b & 1u))
                surface_mask[surface] |= 1 << comp;
    }
    free(c);
    return rc;
}

int gsn_constraints_create(const struct gsn_model *m, const struct gsn_case *c,
                           const struct gsn_shape_rows *values,
                           const unsigned *released,
                           struct gsn_constraints **out)
{
    *out = NULL;
    GSN_CHECK(values->row_count == m->particle_count && values->value,
              GSN_ERR_INTERNAL, "shape values are not one row per particle");
    size_t n = (size_t)m->particle_count;
    struct gsn_constraints *k = calloc(1, sizeof *k);
    int *entry_of = malloc(sizeof(int) * 3 * (n ? n : 1));
    if (k)
        k->entry_of = entry_of;
    double *velocity_of = malloc(sizeof(double) * 3 * (n ? n : 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(k && entry_of && velocity_of, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    k->particle_count = m->particle_count;
    k->ramp = c->time_ramp;
    k->surface_count = m->surface_count;
    k->surface_mask = calloc((size_t)m->surface_count + 1, sizeof(int));
    k->surface_entry = calloc((size_t)m->surface_count + 1, sizeof(int));
    GSN_CHECK_GOTO(k->surface_mask && k->surface_entry, rc, GSN_ERR_MEMORY,
                   done, "out of memory");
    if (released) {
        k->released = malloc(sizeof(unsigned) * (n ? n : 1));
        GSN_CHECK_GOTO(k->released, rc, GSN_ERR_MEMORY, done, "out of memory");
        memcpy(k->released, released, sizeof(unsigned) * n);
    }
    GSN_CALL_GOTO(prescribe(m, c, released, 1, entry_of, velocity_of,
                            k->surface_mask, k->surface_entry),
                  rc, done);
    for (int comp = 0; comp < 3; ++comp)
        GSN_CALL_GOTO(
            component_build(k, comp, m, values, entry_of, velocity_of), rc,
            done);
done:
    if (!k)
        free(entry_of);
    free(velocity_of);
    if (rc != GSN_OK)
        gsn_constraints_destroy(&k);
    *out = k;
    return rc;
}

int gsn_constraints_held(const struct gsn_model *m, const struct gsn_case *c,
                         const unsigned *released, int **facet_mask,
                         int **particle_mask)
{
    size_t n = (size_t)m->particle_count;
    *facet_mask = calloc((size_t)m->facet_count + 1, sizeof(int));
    *particle_mask = calloc(n + 1, sizeof(int));
    int *entry_of = malloc(sizeof(int) * 3 * (n + 1));
    double *velocity_of = malloc(sizeof(double) * 3 * (n + 1));
    int *surface_mask = calloc((size_t)m->surface_count + 1, sizeof(int));
    int *surface_entry = calloc((size_t)m->surface_count + 1, sizeof(int));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(*facet_mask && *particle_mask && entry_of && velocity_of &&
                       surface_mask && surface_entry,
                   rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CALL_GOTO(prescribe(m, c, released, 0, entry_of, velocity_of,
                            surface_mask, surface_entry),
                  rc, done);
    for (size_t p = 0; p < n; ++p)
        for (int k = 0; k < 3; ++k)
            if (entry_of[3 * p + k] >= 0)
                (*particle_mask)[p] |= 1 << k;
    for (int f = 0; f < m->facet_count; ++f) {
        int s = m->facet_surface[f], owner = m->facet_owner[f];
        if (m->facet_neighbour[f] >= 0 || s < 0 || s >= m->surface_count)
            continue;
        /* a released owner's facets hold nothing (gsn_constraints_facet_
         * mask) */
        if (released && released[owner] >> surface_entry[s] & 1u)
            continue;
        (*facet_mask)[f] = surface_mask[s];
    }
done:
    free(entry_of);
    free(velocity_of);
    free(surface_mask);
    free(surface_entry);
    if (rc != GSN_OK) {
        free(*facet_mask);
        free(*particle_mask);
        *facet_mask = *particle_mask = NULL;
    }
    return rc;
}

/* The pattern of S_c for the n held particles of one component: J and K
 * couple where |X_J - X_K|_inf < 2 a_K, the held particles' kernels grown
 * twice (gsn_rk_neighbours); its entries and CHOLMOD's symbolic count of
 * the supernodal factor's values (the ordering factorize uses). */
static int pattern_size_estimate(int n, const double *position,
                                 const double *spacing, double support,
                                 double *entries, double *factor_entries)
{
    struct gsn_rk *rk = NULL;
    int *offset = calloc((size_t)n + 1, sizeof(int)), *index = NULL;
    int rc = GSN_OK;
    GSN_CHECK_GOTO(offset, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CALL_GOTO(gsn_rk_create(n, position, spacing, 2.0 * support, 1, &rk),
                  rc, done);
    for (int j = 0; j < n; ++j)
        offset[j + 1] = offset[j] + gsn_rk_neighbours(
                                        rk, position + 3 * (size_t)j, 0, NULL);
    index = malloc(sizeof(int) * ((size_t)offset[n] + 1));
    GSN_CHECK_GOTO(index, rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int j = 0; j < n; ++j)
        gsn_rk_neighbours(rk, position + 3 * (size_t)j,
                          offset[j + 1] - offset[j], index + offset[j]);
    cholmod_common cm;
    cholmod_begin(&cm);
    cholmod_factor *L = NULL;
    /* the pattern's lower triangle, as S's (values do not matter) */
    cholmod_sparse *A = lower_triangle(n, offset, index, NULL, &cm);
    GSN_CHECK_GOTO(A, rc, GSN_ERR_MEMORY, done_cholmod, "out of memory");
    L = cholmod_analyze(A, &cm);
    GSN_CHECK_GOTO(L, rc, GSN_ERR_MEMORY, done_cholmod,
                   "the boundary matrix's pattern (%d particles) could not "
                   "be analysed (CHOLMOD status %d)",
                   n, cm.status);
    *entries = offset[n];
    *factor_entries = (double)L->xsize;
done_cholmod:
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&A, &cm);
    cholmod_finish(&cm);
done:
    gsn_rk_destroy(&rk);
    free(offset);
    free(index);
    return rc;
}

int gsn_constraints_size_estimate(const struct gsn_model *m,
                                  const struct gsn_case *c, double entries[3],
                                  double factor_entries[3])
{
    size_t n = (size_t)m->particle_count;
    int *facet_mask = NULL, *particle_mask = NULL;
    double *spacing = malloc(sizeof(double) * (n + 1));
    double *held_spacing = malloc(sizeof(double) * (n + 1));
    double *held_position = malloc(sizeof(double) * 3 * (n + 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(spacing && held_spacing && held_position, rc, GSN_ERR_MEMORY,
                   done, "out of memory");
    GSN_CALL_GOTO(gsn_constraints_held(m, c, NULL, &facet_mask, &particle_mask),
                  rc, done);
    GSN_CALL_GOTO(gsn_rk_spacing_from_facets(m, 0.0, spacing), rc, done);
    for (int k = 0; k < 3; ++k) {
        int count = 0;
        for (size_t p = 0; p < n; ++p)
            if (particle_mask[p] >> k & 1) {
                held_spacing[count] = spacing[p];
                memcpy(held_position + 3 * (size_t)count, m->position + 3 * p,
                       3 * sizeof(double));
                ++count;
            }
        entries[k] = factor_entries[k] = 0.0;
        if (count > 0 && k != c->plane_strain_axis) /* no rows: prescribe */
            GSN_CALL_GOTO(pattern_size_estimate(count, held_position,
                                                held_spacing, c->kernel_support,
                                                &entries[k],
                                                &factor_entries[k]),
                          rc, done);
    }
done:
    free(facet_mask);
    free(particle_mask);
    free(spacing);
    free(held_spacing);
    free(held_position);
    return rc;
}

double gsn_ramp_factor(double ramp, enum gsn_constraint_field kind, double t)
{
    if (kind == GSN_FIELD_HOMOGENEOUS)
        return 0.0;
    if (ramp <= 0.0 || t >= ramp)
        return kind == GSN_FIELD_DISPLACEMENT ? t - 0.5 * ramp
               : kind == GSN_FIELD_VELOCITY   ? 1.0
                                              : 0.0;
    const double pi = acos(-1.0), s = pi * t / ramp;
    return kind == GSN_FIELD_DISPLACEMENT ? 0.5 * t - 0.5 * ramp / pi * sin(s)
           : kind == GSN_FIELD_VELOCITY   ? 0.5 * (1.0 - cos(s))
                                          : 0.5 * pi / ramp * sin(s);
}

void gsn_constraints_set_epoch(struct gsn_constraints *constraints, double time)
{
    constraints->epoch = time;
}

int gsn_constraints_ramping(const struct gsn_constraints *constraints,
                            double time)
{
    return time < constraints->ramp;
}

/* Component c of gsn_constraints_apply: S lambda = target - C f, then
 * f += M^-1 C^T lambda (and force = C^T lambda where asked). */
static void component_apply(struct gsn_constraints *constraints, int c,
                            double factor, double *field, double *force)
{
    struct component_constraint *cc = &constraints->component[c];
    for (int s = 0; s < cc->count; ++s) {
        double target = cc->velocity[s] * factor;
        for (int e = cc->row_offset[s]; e < cc->row_offset[s + 1]; ++e)
            target -= cc->row_value[e] * field[3 * cc->row_index[e] + c];
        cc->rhs[s] = target;
    }
    factor_solve(cc, cc->rhs);
    for (int t = 0; t < cc->touched_count; ++t) {
        double f = 0.0;
        for (int k = cc->touched_offset[t]; k < cc->touched_offset[t + 1]; ++k)
            f += cc->touched_value[k] * cc->rhs[cc->touched_row[k]];
        size_t at = 3 * (size_t)cc->touched[t] + (size_t)c;
        field[at] += f * cc->touched_inverse_mass[t];
        if (force) /* M times the correction */
            force[at] = cc->touched_inverse_mass[t] != 0.0 ? f : 0.0;
    }
}

int gsn_constraints_apply(struct gsn_constraints *constraints,
                          const struct gsn_shape_rows *values,
                          enum gsn_constraint_field kind, double time,
                          double *field, double *force)
{
    /* The components read and write only their own column of field and
     * force, and each has its own work array: they run in parallel, the
     * same bits on any thread count. */
    GSN_CHECK(values->row_count == constraints->particle_count,
              GSN_ERR_INTERNAL, "shape values are not one row per particle");
    GSN_CALL(ensure_factorized(constraints));
    double factor = gsn_ramp_factor(constraints->ramp, kind, time);
    if (kind == GSN_FIELD_DISPLACEMENT)
        factor -= gsn_ramp_factor(constraints->ramp, kind, constraints->epoch);
    int work = 0;
    for (int c = 0; c < 3; ++c)
        work += constraints->component[c].count;
#pragma omp parallel for schedule(dynamic,                                     \
                                  1) if (work >= CONSTRAINT_PARALLEL_MIN)
    for (int c = 0; c < 3; ++c)
        if (constraints->component[c].count > 0)
            component_apply(constraints, c, factor, field, force);
    return GSN_OK;
}

int gsn_constraints_multipliers(struct gsn_constraints *constraints,
                                const double *force, double *multiplier)
{
    GSN_CALL(ensure_factorized(constraints));
    memset(multiplier, 0,
           sizeof(double) * 3 * (size_t)constraints->particle_count);
    for (int c = 0; c < 3; ++c) {
        struct component_constraint *cc = &constraints->component[c];
        if (cc->count == 0)
            continue;
        /* S lambda = C M^-1 (C^T lambda) */
        for (int s = 0; s < cc->count; ++s)
            cc->rhs[s] = 0.0;
        for (int t = 0; t < cc->touched_count; ++t) {
            double g = force[3 * (size_t)cc->touched[t] + (size_t)c] *
                       cc->touched_inverse_mass[t];
            for (int k = cc->touched_offset[t]; k < cc->touched_offset[t + 1];
                 ++k)
                cc->rhs[cc->touched_row[k]] += cc->touched_value[k] * g;
        }
        factor_solve(cc, cc->rhs);
        for (int s = 0; s < cc->count; ++s)
            multiplier[3 * (size_t)cc->particle[s] + (size_t)c] = cc->rhs[s];
    }
    return GSN_OK;
}

int gsn_constraints_is_constrained(const struct gsn_constraints *constraints,
                                   int particle, int component)
{
    return constraints->slot[component] &&
           constraints->slot[component][particle] >= 0;
}

int gsn_constraints_set_velocity(struct gsn_constraints *constraints,
                                 int particle, int component, double velocity)
{
    GSN_CHECK(gsn_constraints_is_constrained(constraints, particle, component),
              GSN_ERR_INTERNAL,
              "component %d of particle %d is not constrained", component,
              particle);
    struct component_constraint *cc = &constraints->component[component];
    cc->velocity[constraints->slot[component][particle]] = velocity;
    return GSN_OK;
}

int gsn_constraints_facet_mask(const struct gsn_constraints *constraints,
                               int surface, int owner)
{
    int mask = gsn_constraints_surface_mask(constraints, surface);
    if (mask && constraints->released &&
        constraints->released[owner] >> constraints->surface_entry[surface] &
            1u)
        return 0;
    return mask;
}

int gsn_constraints_entry(const struct gsn_constraints *constraints,
                          int particle, int component)
{
    return constraints->entry_of[3 * (size_t)particle + component];
}

int gsn_constraints_holds(const struct gsn_constraints *constraints,
                          int particle, int entry)
{
    for (int k = 0; k < 3; ++k)
        if (gsn_constraints_entry(constraints, particle, k) == entry)
            return 1;
    return 0;
}

int gsn_constraints_surface_mask(const struct gsn_constraints *constraints,
                                 int surface)
{
    if (surface < 0 || surface >= constraints->surface_count)
        return 0;
    return constraints->surface_mask[surface];
}

int gsn_constraints_discretize(
    const struct gsn_model *m, const struct gsn_case *c,
    const struct gsn_kernel_options *options, const double *background_cells,
    int background_cell_count, const unsigned *released,
    struct gsn_quadrature **quadrature, struct gsn_constraints **constraints,
    double seconds[2])
{
    *quadrature = NULL;
    *constraints = NULL;
    double start = omp_get_wtime();
    struct gsn_kernel_options kernel = *options;
    int *held_facet = NULL, *held_particle = NULL;
    int rc = gsn_constraints_held(m, c, released, &held_facet, &held_particle);
    kernel.held_facet = held_facet;
    kernel.held_particle = held_particle;
    if (rc == GSN_OK)
        rc = gsn_quadrature_create(m, &kernel, background_cells,
                                   background_cell_count, quadrature);
    free(held_facet);
    free(held_particle);
    double built = omp_get_wtime();
    if (rc == GSN_OK)
        rc = gsn_constraints_create(m, c, &(*quadrature)->particle_values,
                                    released, constraints);
    if (seconds) {
        seconds[0] = built - start;
        seconds[1] = omp_get_wtime() - built;
    }
    if (rc != GSN_OK)
        gsn_quadrature_destroy(quadrature);
    return rc;
}

void gsn_constraints_set_boundary_only(struct gsn_constraints *constraints)
{
    constraints->boundary_only = 1;
    constraints->factorized = 0;
}
