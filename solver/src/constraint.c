/* Exact essential boundary conditions on u(X_J): see constraint.h. */
#include "constraint.h"
#include "geoscni/error.h"

#include <klu.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Lambda_c with a condition estimate worse than this cannot be trusted to
 * impose the boundary values to 1e-8 relative. */
#define CONSTRAINT_RCOND_LIMIT 1e-12
/* The copied factors must solve Lambda x = b with a componentwise backward
 * error (|Lambda x - b|_i / (|Lambda| |x| + |b|)_i, Oettli-Prager) below
 * this: LU with partial pivoting gives a small multiple of n eps; a wrong
 * copy of the factors gives O(1), whatever the conditioning. */
#define CONSTRAINT_SOLVE_CHECK 1e-10
/* Constrained particle components below which the three solves run on one
 * thread (a parallel region costs more than small solves). */
enum { CONSTRAINT_PARALLEL_MIN = 2048 };

struct component_constraint {
    int count;        /* |B_c| */
    int *particle;    /* B_c, ascending */
    double *velocity; /* prescribed velocity of each, m/s (0: fixed) */
    int *row_offset;  /* Lambda_c in CSR (rows J, columns K, both B_c) */
    int *column;
    double *entry;
    double *rhs; /* right-hand side, then solution */
    /* The factors of Lambda_c from KLU (klu_extract, one block):
     * P (R \ Lambda) Q = L U, copied for the solve of every step (each
     * triangle by column in the order the solve reads it; the strict
     * parts, U's diagonal apart). */
    int *pivot_row;    /* P: row pivot_row[k] of Lambda is pivot k */
    int *column_order; /* Q: unknown column_order[k] is pivot k's */
    double *row_scale; /* R: pivot row k was divided by row_scale[k] (KLU
                          keeps the scale factors in pivot order) */
    int *lower_offset; /* count + 1: L's columns 0, 1, ... */
    int *lower_row;
    double *lower_value;
    int *upper_offset; /* count + 1: U's columns count-1, count-2, ... */
    int *upper_row;
    double *upper_value;
    double *upper_diagonal;
    double *pivot_work; /* count */
    /* The entries Psi_I(X_J) of the rows J in B_c with I not in B_c (the
     * right-hand side of a correction), in row order. */
    int *free_offset; /* count + 1 */
    int *free_index;  /* I */
    double *free_value;
};

struct gsn_constraints {
    int particle_count;
    int surface_count;
    double ramp;        /* s, time.ramp */
    double epoch;       /* s: displacements are prescribed from then on (the
                           time of the last reference update) */
    int *surface_mask;  /* per model surface: constrained components */
    unsigned *released; /* particles: entries that let them go, or NULL */
    int *surface_entry; /* per model surface: the entry naming it, or 0 */
    int *entry_of;      /* particles x 3: the boundary entry whose
                           prescription holds the component, or -1 */
    int *slot[3];       /* slot[c][I]: position of I in B_c, or -1 */
    struct component_constraint component[3];
};

static const char component_names[3] = {'x', 'y', 'z'};

void gsn_constraints_destroy(struct gsn_constraints **constraints)
{
    if (!constraints || !*constraints)
        return;
    struct gsn_constraints *k = *constraints;
    for (int c = 0; c < 3; ++c) {
        struct component_constraint *cc = &k->component[c];
        free(cc->particle);
        free(cc->velocity);
        free(cc->row_offset);
        free(cc->column);
        free(cc->entry);
        free(cc->rhs);
        free(cc->free_offset);
        free(cc->free_index);
        free(cc->free_value);
        int *ints[] = {cc->pivot_row, cc->column_order, cc->lower_offset,
                       cc->lower_row, cc->upper_offset, cc->upper_row};
        double *doubles[] = {cc->row_scale, cc->lower_value, cc->upper_value,
                             cc->upper_diagonal, cc->pivot_work};
        for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i)
            free(ints[i]);
        for (size_t i = 0; i < sizeof doubles / sizeof doubles[0]; ++i)
            free(doubles[i]);
        free(k->slot[c]);
    }
    free(k->surface_mask);
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

/* Copies KLU's factors P (R \ Lambda) Q = L U (one block: no BTF) into
 * the arrays of the step's solve (factor_solve). */
static int copy_factors(struct component_constraint *cc, klu_symbolic *symbolic,
                        klu_numeric *numeric, klu_common *common)
{
    int n = cc->count, lnz = numeric->lnz, unz = numeric->unz;
    int *Lp = malloc(sizeof(int) * ((size_t)n + 1));
    int *Up = malloc(sizeof(int) * ((size_t)n + 1));
    int *Li = malloc(sizeof(int) * (size_t)lnz);
    int *Ui = malloc(sizeof(int) * (size_t)unz);
    double *Lx = malloc(sizeof(double) * (size_t)lnz);
    double *Ux = malloc(sizeof(double) * (size_t)unz);
    cc->pivot_row = malloc(sizeof(int) * (size_t)n);
    cc->column_order = malloc(sizeof(int) * (size_t)n);
    cc->row_scale = malloc(sizeof(double) * (size_t)n);
    cc->lower_offset = calloc((size_t)n + 1, sizeof(int));
    cc->upper_offset = calloc((size_t)n + 1, sizeof(int));
    cc->lower_row = malloc(sizeof(int) * (size_t)lnz);
    cc->lower_value = malloc(sizeof(double) * (size_t)lnz);
    cc->upper_row = malloc(sizeof(int) * (size_t)unz);
    cc->upper_value = malloc(sizeof(double) * (size_t)unz);
    cc->upper_diagonal = calloc((size_t)n, sizeof(double));
    cc->pivot_work = malloc(sizeof(double) * (size_t)n);
    int rc = GSN_OK;
    GSN_CHECK_GOTO(Lp && Up && Li && Ui && Lx && Ux && cc->pivot_row &&
                       cc->column_order && cc->row_scale && cc->lower_offset &&
                       cc->upper_offset && cc->lower_row && cc->lower_value &&
                       cc->upper_row && cc->upper_value && cc->upper_diagonal &&
                       cc->pivot_work,
                   rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CHECK_GOTO(klu_extract(numeric, symbolic, Lp, Li, Lx, Up, Ui, Ux, NULL,
                               NULL, NULL, cc->pivot_row, cc->column_order,
                               cc->row_scale, NULL, common),
                   rc, GSN_ERR_NUMERICAL, done,
                   "the boundary factors could not be read (KLU status %d)",
                   common->status);
    /* L: columns ascending, the unit diagonal left out. */
    for (int k = 0; k < n; ++k) {
        int at = cc->lower_offset[k];
        for (int p = Lp[k]; p < Lp[k + 1]; ++p)
            if (Li[p] != k) {
                cc->lower_row[at] = Li[p];
                cc->lower_value[at++] = Lx[p];
            }
        cc->lower_offset[k + 1] = at;
    }
    /* U: columns descending (the order of the backward solve), the
     * diagonal apart. */
    for (int j = 0; j < n; ++j) {
        int k = n - 1 - j, at = cc->upper_offset[j];
        for (int p = Up[k]; p < Up[k + 1]; ++p) {
            if (Ui[p] == k) {
                cc->upper_diagonal[k] = Ux[p];
                continue;
            }
            cc->upper_row[at] = Ui[p];
            cc->upper_value[at++] = Ux[p];
        }
        cc->upper_offset[j + 1] = at;
        GSN_CHECK_GOTO(cc->upper_diagonal[k] != 0.0, rc, GSN_ERR_NUMERICAL,
                       done, "the boundary factor U has a zero pivot");
    }
done:
    free(Lp);
    free(Up);
    free(Li);
    free(Ui);
    free(Lx);
    free(Ux);
    return rc;
}

/* x = Lambda^-1 b in place, with the copied factors: y = P (R \ b),
 * L U z = y, x = Q z. Columns of L then of U (last first), each read once
 * in storage order. */
static void factor_solve(struct component_constraint *cc, double *x)
{
    const int n = cc->count;
    double *restrict y = cc->pivot_work;
    for (int k = 0; k < n; ++k)
        y[k] = x[cc->pivot_row[k]] / cc->row_scale[k];
    for (int k = 0; k < n; ++k) {
        const double yk = y[k];
        for (int p = cc->lower_offset[k]; p < cc->lower_offset[k + 1]; ++p)
            y[cc->lower_row[p]] -= cc->lower_value[p] * yk;
    }
    for (int j = 0; j < n; ++j) {
        const int k = n - 1 - j;
        const double zk = y[k] / cc->upper_diagonal[k];
        y[k] = zk;
        for (int p = cc->upper_offset[j]; p < cc->upper_offset[j + 1]; ++p)
            y[cc->upper_row[p]] -= cc->upper_value[p] * zk;
    }
    for (int k = 0; k < n; ++k)
        x[cc->column_order[k]] = y[k];
}

/* Factorizes Lambda_c (KLU with AMD, partial pivoting, no BTF), checks its
 * condition, copies the factors for the step's solves and checks them on
 * one right-hand side; KLU's own objects are freed after. */
static int factorize(struct component_constraint *cc, char name)
{
    int n = cc->count, entries = cc->row_offset[n];
    /* Lambda in CSC (the transpose of the CSR rows) */
    int *column_offset = calloc((size_t)n + 1, sizeof(int));
    int *row = malloc(sizeof(int) * (size_t)(entries ? entries : 1));
    double *value = malloc(sizeof(double) * (size_t)(entries ? entries : 1));
    double *b = malloc(sizeof(double) * (size_t)n);
    klu_common common;
    klu_symbolic *symbolic = NULL;
    klu_numeric *numeric = NULL;
    int rc = GSN_OK;
    GSN_CHECK_GOTO(column_offset && row && value && b, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    for (int e = 0; e < entries; ++e)
        column_offset[cc->column[e] + 1]++;
    for (int k = 0; k < n; ++k)
        column_offset[k + 1] += column_offset[k];
    for (int i = 0; i < n; ++i)
        for (int e = cc->row_offset[i]; e < cc->row_offset[i + 1]; ++e) {
            int at = column_offset[cc->column[e]]++;
            row[at] = i;
            value[at] = cc->entry[e];
        }
    for (int k = n; k > 0; --k)
        column_offset[k] = column_offset[k - 1];
    column_offset[0] = 0;
    klu_defaults(&common);
    common.btf = 0; /* one block: the copied factors need no F */
    symbolic = klu_analyze(n, column_offset, row, &common);
    GSN_CHECK_GOTO(symbolic, rc, GSN_ERR_NUMERICAL, done,
                   "the %c boundary matrix (%d particles) could not be "
                   "analysed (KLU status %d)",
                   name, n, common.status);
    numeric = klu_factor(column_offset, row, value, symbolic, &common);
    GSN_CHECK_GOTO(
        numeric && common.status == KLU_OK, rc, GSN_ERR_NUMERICAL, done,
        "the %c boundary matrix Psi_K(X_J) of %d constrained particles "
        "is singular (KLU status %d); check for duplicate boundary "
        "particles",
        name, n, common.status);
    klu_rcond(symbolic, numeric, &common);
    GSN_CHECK_GOTO(common.rcond > CONSTRAINT_RCOND_LIMIT, rc, GSN_ERR_NUMERICAL,
                   done,
                   "the %c boundary matrix of %d constrained particles is "
                   "too badly conditioned (reciprocal condition %.3g)",
                   name, n, common.rcond);
    GSN_CALL_GOTO(copy_factors(cc, symbolic, numeric, &common), rc, done);
    /* The copy solves Lambda x = b, b_i = 1 + i mod 7. */
    for (int i = 0; i < n; ++i)
        b[i] = 1.0 + i % 7;
    factor_solve(cc, b);
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = -(1.0 + i % 7), scale = 1.0 + i % 7;
        for (int e = cc->row_offset[i]; e < cc->row_offset[i + 1]; ++e) {
            r += cc->entry[e] * b[cc->column[e]];
            scale += fabs(cc->entry[e] * b[cc->column[e]]);
        }
        worst = fmax(worst, fabs(r) / scale);
    }
    GSN_CHECK_GOTO(worst <= CONSTRAINT_SOLVE_CHECK, rc, GSN_ERR_INTERNAL, done,
                   "the %c boundary solve has a backward error of %.3g", name,
                   worst);
done:
    if (numeric)
        klu_free_numeric(&numeric, &common);
    if (symbolic)
        klu_free_symbolic(&symbolic, &common);
    free(column_offset);
    free(row);
    free(value);
    free(b);
    return rc;
}

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
        for (int e = values->offset[p]; e < values->offset[p + 1]; ++e)
            cc->row_offset[s + 1] += k->slot[c][values->index[e]] >= 0;
    }
    for (size_t s = 0; s < count; ++s)
        cc->row_offset[s + 1] += cc->row_offset[s];
    size_t entries = (size_t)cc->row_offset[count];
    cc->column = malloc(sizeof(int) * (entries ? entries : 1));
    cc->entry = malloc(sizeof(double) * (entries ? entries : 1));
    GSN_CHECK(cc->column && cc->entry, GSN_ERR_MEMORY, "out of memory");
    for (size_t s = 0; s < count; ++s) {
        int p = cc->particle[s], at = cc->row_offset[s];
        for (int e = values->offset[p]; e < values->offset[p + 1]; ++e) {
            int column = k->slot[c][values->index[e]];
            if (column < 0)
                continue;
            cc->column[at] = column;
            cc->entry[at] = values->value[e];
            at++;
        }
    }
    cc->free_offset = calloc(count + 1, sizeof(int));
    GSN_CHECK(cc->free_offset, GSN_ERR_MEMORY, "out of memory");
    for (size_t s = 0; s < count; ++s) {
        int p = cc->particle[s];
        cc->free_offset[s + 1] = cc->free_offset[s] +
                                 (values->offset[p + 1] - values->offset[p]) -
                                 (cc->row_offset[s + 1] - cc->row_offset[s]);
    }
    size_t free_entries = (size_t)cc->free_offset[count];
    cc->free_index = malloc(sizeof(int) * (free_entries ? free_entries : 1));
    cc->free_value = malloc(sizeof(double) * (free_entries ? free_entries : 1));
    GSN_CHECK(cc->free_index && cc->free_value, GSN_ERR_MEMORY,
              "out of memory");
    for (size_t s = 0; s < count; ++s) {
        int p = cc->particle[s], at = cc->free_offset[s];
        for (int e = values->offset[p]; e < values->offset[p + 1]; ++e) {
            if (k->slot[c][values->index[e]] >= 0)
                continue;
            cc->free_index[at] = values->index[e];
            cc->free_value[at] = values->value[e];
            at++;
        }
    }
    GSN_CALL(factorize(cc, component_names[c]));
    return GSN_OK;
}

int gsn_constraints_create(const struct gsn_model *m,
                           const struct gsn_case *given,
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
    /* symmetry planes hold their normal component: a copy with it fixed */
    struct gsn_case *c = malloc(sizeof *c);
    int rc = GSN_OK;
    GSN_CHECK_GOTO(k && entry_of && velocity_of && c, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    *c = *given;
    GSN_CALL_GOTO(gsn_case_resolve_symmetry(c, m), rc, done);
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
    GSN_CALL_GOTO(collect_prescriptions(m, c, released, entry_of, velocity_of),
                  rc, done);
    for (int b = 0; b < c->boundary_count; ++b) {
        int surface = gsn_model_find_surface(m, c->boundaries[b].name);
        k->surface_entry[surface] = b;
        for (int comp = 0; comp < 3; ++comp)
            if (c->boundaries[b].fixed[comp] ||
                c->boundaries[b].has_velocity[comp])
                k->surface_mask[surface] |= 1 << comp;
    }
    for (int comp = 0; comp < 3; ++comp)
        GSN_CALL_GOTO(
            component_build(k, comp, m, values, entry_of, velocity_of), rc,
            done);
done:
    if (!k)
        free(entry_of);
    free(velocity_of);
    free(c);
    if (rc != GSN_OK)
        gsn_constraints_destroy(&k);
    *out = k;
    return rc;
}

double gsn_ramp_factor(double ramp, enum gsn_constraint_field kind, double t)
{
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

/* Component c of gsn_constraints_apply. */
static void component_apply(struct gsn_constraints *constraints, int c,
                            double factor, double *field)
{
    struct component_constraint *cc = &constraints->component[c];
    for (int s = 0; s < cc->count; ++s) {
        double target = cc->velocity[s] * factor;
        for (int e = cc->free_offset[s]; e < cc->free_offset[s + 1]; ++e)
            target -= cc->free_value[e] * field[3 * cc->free_index[e] + c];
        cc->rhs[s] = target;
    }
    factor_solve(cc, cc->rhs);
    for (int s = 0; s < cc->count; ++s)
        field[3 * cc->particle[s] + c] = cc->rhs[s];
}

int gsn_constraints_apply(struct gsn_constraints *constraints,
                          const struct gsn_shape_rows *values,
                          enum gsn_constraint_field kind, double time,
                          double *field)
{
    /* The components read and write only their own column of field, and
     * each has its own work array: they run in parallel, the same bits on
     * any thread count. */
    GSN_CHECK(values->row_count == constraints->particle_count,
              GSN_ERR_INTERNAL, "shape values are not one row per particle");
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
            component_apply(constraints, c, factor, field);
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
