/* Reference-configuration updates: see reference.h. */
#include "reference.h"
#include "geoscni/cells.h"
#include "geoscni/error.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The body's tetrahedra are made again when the smallest has less than
 * this share of the mean volume (or is turned inside out): the cells need
 * the union of positive pieces. */
#define GSN_REFERENCE_BODY_QUALITY 1e-6

/* The force an update leaves unbalanced is released over this many steps
 * (gsn_explicit_release_unbalanced), or over a quarter of the steps since
 * the last update where that is fewer, so that it is done well before the
 * next. On the coarse Slope I with updates (14 to 16) the particles with
 * damage above 0.1 at 1 m: 85% applied at once, 67% released over 30
 * steps, 51% over 100, 48% over 500 (31% without updates). Where updates
 * come faster than the release (a footing's corner, 20 to 130 steps
 * apart), what is left of one release is folded into the next and a stale
 * force builds up: the smooth footing at B/5 pushed to 1 B ended with exit
 * 3 at 0.96 B released over 100 steps, 0.875 B over 300, exit 0 at 1 B
 * over 1, 10 or 30 steps and over a quarter of the gap. */
#define RELEASE_STEPS 100

const char *gsn_reference_reason_name(enum gsn_reference_reason reason)
{
    switch (reason) {
    case GSN_REFERENCE_STRAIN:
        return "strain";
    case GSN_REFERENCE_VOLUME:
        return "volume";
    case GSN_REFERENCE_INTERVAL:
        return "interval";
    default:
        return "none";
    }
}

/* The shape functions, integration, constraints (displacements prescribed
 * from epoch on) and the loop at rest on the cells of model m. */
static int build(const struct gsn_model *m, const struct gsn_case *c,
                 const struct gsn_material_set *materials,
                 const struct gsn_contact *contact, double dt, double epoch,
                 struct gsn_quadrature **quadrature,
                 struct gsn_constraints **constraints,
                 struct gsn_explicit **loop,
                 struct gsn_reference_report *report)
{
    unsigned *released = NULL;
    if (contact) {
        released = calloc((size_t)m->particle_count + 1, sizeof *released);
        GSN_CHECK(released, GSN_ERR_MEMORY, "out of memory");
        gsn_contact_release(contact, m, epoch, released);
    }
    struct gsn_kernel_options kernel;
    gsn_kernel_options_from_case(c, &kernel);
    /* a deformed reference (an update, or its restart): every particle
     * covered by its neighbours' kernels */
    kernel.cover_neighbours = epoch > 0.0;
    double seconds[2] = {0.0, 0.0};
    int rc = gsn_constraints_discretize(m, c, &kernel, NULL, 0, released,
                                        quadrature, constraints, seconds);
    free(released);
    GSN_CALL(rc);
    gsn_constraints_set_epoch(*constraints, epoch);
    double t2 = omp_get_wtime();
    GSN_CALL(gsn_explicit_create(m, *quadrature, materials, *constraints, c, dt,
                                 loop));
    if (report) {
        report->seconds_kernels = seconds[0];
        report->support_repairs = (*quadrature)->support_repairs;
        report->held_fallbacks = (*quadrature)->held_fallback_count;
        report->seconds_constraints = seconds[1];
        report->seconds_loop = omp_get_wtime() - t2;
    }
    GSN_CALL(gsn_explicit_set_contact(*loop, contact));
    (*loop)->allow_failure = !c->small_strain;
    (*loop)->track_distortion = c->reference_update;
    /* The loop reads its own packed copy of the gradient rows
     * (point_blocks.h): the quadrature's are freed, 709 MB of the working
     * set on Slope I with MSCNI. */
    gsn_shape_rows_free(&(*quadrature)->gradient);
    return GSN_OK;
}

/* The case's tractions and the water's pressure on the boundary facets of
 * m, into the loop's external force. */
static void add_tractions(struct gsn_explicit *e, const struct gsn_model *m,
                          const struct gsn_case *c)
{
    gsn_explicit_add_water_pressure(e, m, c);
    for (int b = 0; b < c->boundary_count; ++b)
        if (c->boundaries[b].has_traction[0])
            gsn_explicit_add_traction(
                e, m, gsn_model_find_surface(m, c->boundaries[b].name),
                c->boundaries[b].traction);
}

int gsn_reference_create(const struct gsn_model *original,
                         const struct gsn_case *c,
                         const struct gsn_material_set *materials, double dt,
                         int threads, struct gsn_reference **out)
{
    *out = NULL;
    struct gsn_reference *r = calloc(1, sizeof *r);
    GSN_CHECK(r, GSN_ERR_MEMORY, "out of memory");
    r->original = original;
    r->c = c;
    r->materials = materials;
    r->threads = threads;
    r->model = original;
    const struct gsn_body mesh = {original->tetrahedron_count,
                                  original->tetrahedra,
                                  original->tetrahedron_face};
    int rc = original->tetrahedron_count > 0 ? gsn_body_copy(&mesh, &r->body)
                                             : GSN_OK;
    if (rc == GSN_OK)
        rc = gsn_contact_create(original, c, &r->contact);
    if (rc == GSN_OK)
        rc = build(original, c, materials, r->contact, dt, 0.0, &r->quadrature,
                   &r->constraints, &r->loop, NULL);
    if (rc != GSN_OK) {
        gsn_reference_destroy(&r);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "build(original, ...)");
    }
    add_tractions(r->loop, original, c);
    *out = r;
    return GSN_OK;
}

/* Frees what belongs to one reference configuration (NULL-safe). */
static void discretization_free(struct gsn_model **cells,
                                struct gsn_quadrature **quadrature,
                                struct gsn_constraints **constraints,
                                struct gsn_explicit **loop)
{
    gsn_explicit_destroy(loop);
    gsn_constraints_destroy(constraints);
    gsn_quadrature_destroy(quadrature);
    if (*cells)
        gsn_model_free(*cells);
    free(*cells);
    *cells = NULL;
}

void gsn_reference_destroy(struct gsn_reference **handle)
{
    if (!handle || !*handle)
        return;
    struct gsn_reference *r = *handle;
    discretization_free(&r->cells, &r->quadrature, &r->constraints, &r->loop);
    gsn_contact_destroy(&r->contact);
    gsn_body_free(&r->body);
    free(r);
    *handle = NULL;
}

long gsn_reference_retry_steps(const struct gsn_reference *r)
{
    int run = r->deferred_run < 16 ? r->deferred_run : 16;
    return (long)r->c->reference_min_steps << run;
}

enum gsn_reference_reason gsn_reference_due(const struct gsn_reference *r)
{
    const struct gsn_case *c = r->c;
    const struct gsn_explicit *e = r->loop;
    if (!c->reference_update || e->step - r->step < c->reference_min_steps)
        return GSN_REFERENCE_NOT_DUE;
    if (r->deferred_run > 0 &&
        e->step - r->attempt_step < gsn_reference_retry_steps(r))
        return GSN_REFERENCE_NOT_DUE;
    if (e->distortion_strain > c->reference_strain)
        return GSN_REFERENCE_STRAIN;
    if (e->distortion_jacobian_min < c->reference_volume[0] ||
        e->distortion_jacobian_max > c->reference_volume[1])
        return GSN_REFERENCE_VOLUME;
    if (c->reference_every > 0.0 &&
        e->time - r->time >= c->reference_every - 0.5 * e->dt)
        return GSN_REFERENCE_INTERVAL;
    return GSN_REFERENCE_NOT_DUE;
}

/* Mass and momentum of a loop's lumped masses and velocity coefficients
 * (sum m, sum m v, sum m |v|): the body's, which mass scaling's added mass
 * is not part of. */
static void mass_momentum(const struct gsn_explicit *e, double *mass,
                          double momentum[3], double *scale)
{
    *mass = *scale = 0.0;
    momentum[0] = momentum[1] = momentum[2] = 0.0;
    for (int i = 0; i < e->particle_count; ++i) {
        const double *v = &e->velocity[3 * i];
        const double m = e->lumped_mass[i];
        *mass += m;
        for (int k = 0; k < 3; ++k)
            momentum[k] += m * v[k];
        *scale += m * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
}

/* Replaces r's discretization by the one built on the cells at x within
 * body (NULL: r's own, made again if it no longer fits x), with the state
 * carried over from r's loop (carry = 1) or the first reference's masses
 * for a checkpoint to fill (carry = 0). */
static int rebuild(struct gsn_reference *r, const double *x,
                   const struct gsn_body *given, double time, int carry,
                   struct gsn_reference_report *report)
{
    const struct gsn_model *X0 = r->original;
    const int n = X0->particle_count;
    struct gsn_explicit *old = r->loop;
    struct gsn_body body;
    memset(&body, 0, sizeof body);
    struct gsn_model *cells = calloc(1, sizeof *cells);
    GSN_CHECK(cells, GSN_ERR_MEMORY, "out of memory");
    struct gsn_quadrature *quadrature = NULL;
    struct gsn_constraints *constraints = NULL;
    struct gsn_explicit *loop = NULL;
    double t0 = omp_get_wtime();
    struct gsn_cells_options options = {r->c->facet_points, r->threads, 0};
    int rc = GSN_OK;
    if (given)
        GSN_CALL_GOTO(gsn_body_copy(given, &body), rc, fail);
    else {
        gsn_body_worst(&r->body, x, &report->body_quality);
        if (report->body_quality > GSN_REFERENCE_BODY_QUALITY)
            GSN_CALL_GOTO(gsn_body_copy(&r->body, &body), rc, fail);
        else {
            GSN_CALL_GOTO(gsn_body_remesh(&r->body, x, n, &body), rc, fail);
            report->remeshed = 1;
        }
    }
    /* The cells, checked. Where the deformed boundary fools the fast path
     * (a cell cut by the planes of boundary triangles that are not the body
     * there) the checks fail: then every boundary cell is intersected with
     * the tetrahedra, the brute force (docs/pre.md); where the moved
     * tetrahedra fail too, the body is made again. A restart builds what
     * the run built: the checkpoint's body, the same path. */
    int attempts = given || report->remeshed ? 2 : 4;
    for (int attempt = 0; attempt < attempts; ++attempt) {
        if (attempt > 0)
            gsn_error_clear(); /* the last failure's message is kept */
        if (attempt == 2) {
            struct gsn_body made;
            GSN_CALL_GOTO(gsn_body_remesh(&body, x, n, &made), rc, fail);
            gsn_body_free(&body);
            body = made;
            report->remeshed = 1;
        }
        options.tetrahedra_only = attempt % 2;
        rc = gsn_cells_model_at(X0, x, &body, &options, cells, NULL);
        if (rc == GSN_OK)
            break;
    }
    report->tetrahedra_only = options.tetrahedra_only;
    GSN_CALL_GOTO(rc, rc, fail);
    report->seconds_cells = omp_get_wtime() - t0;
    GSN_CALL_GOTO(build(cells, r->c, r->materials, r->contact, old->dt, time,
                        &quadrature, &constraints, &loop, report),
                  rc, fail);
    double t_state = omp_get_wtime();
    for (size_t i = 0; i < 3 * (size_t)n; ++i)
        loop->reference_offset[i] = x[i] - X0->position[i];
    if (carry) {
        GSN_CALL_GOTO(gsn_explicit_carry_over(loop, old), rc, fail);
        report->interpolation_iterations = loop->interpolation_iterations;
    } else
        GSN_CALL_GOTO(gsn_explicit_set_point_mass(loop, old->point_mass), rc,
                      fail);
    add_tractions(loop, cells, r->c);
    if (carry) {
        GSN_CALL_GOTO(gsn_explicit_settle(loop), rc, fail);
        long quarter = (old->step - r->step) / 4; /* of the last gap */
        GSN_CALL_GOTO(
            gsn_explicit_release_unbalanced(
                loop, old, quarter < RELEASE_STEPS ? quarter : RELEASE_STEPS),
            rc, fail);
    }
    report->seconds_state = omp_get_wtime() - t_state;
    /* S = C M^-1 C^T is factorized at the first correction, in the settle:
     * counted with the constraints */
    double factor = gsn_constraints_factor_seconds(constraints);
    report->seconds_constraints += factor;
    report->seconds_state -= factor;
    discretization_free(&r->cells, &r->quadrature, &r->constraints, &r->loop);
    gsn_body_free(&r->body);
    r->body = body;
    r->remesh_count += report->remeshed;
    r->cells = cells;
    r->model = cells;
    r->quadrature = quadrature;
    r->constraints = constraints;
    r->loop = loop;
    r->time = time;
    report->seconds = omp_get_wtime() - t0;
    return GSN_OK;
fail:
    gsn_body_free(&body);
    discretization_free(&cells, &quadrature, &constraints, &loop);
    return rc;
}

int gsn_reference_update(struct gsn_reference *r,
                         struct gsn_reference_report *out)
{
    struct gsn_reference_report report;
    memset(&report, 0, sizeof report);
    struct gsn_explicit *old = r->loop;
    const int n = old->particle_count;
    report.reason = gsn_reference_due(r);
    report.particle = old->distortion_point;
    report.strain = old->distortion_strain;
    report.volume[0] = old->distortion_jacobian_min;
    report.volume[1] = old->distortion_jacobian_max;
    report.kinetic_before = old->conserved_kinetic_energy;
    GSN_CHECK(r->body.tetrahedron_count > 0, GSN_ERR_INPUT,
              "the model has no tetrahedra: the body cannot be followed "
              "(reference_update: off)");
    double t0 = omp_get_wtime();
    double mass0, momentum0[3], scale0;
    mass_momentum(old, &mass0, momentum0, &scale0);
    /* the current positions x = X_ref + u(X_ref) */
    double *x = malloc(sizeof(double) * 3 * (size_t)(n ? n : 1));
    GSN_CHECK(x, GSN_ERR_MEMORY, "cannot allocate %d positions", n);
    gsn_explicit_particle_field(old, old->displacement, x);
    for (size_t i = 0; i < 3 * (size_t)n; ++i)
        x[i] += r->model->position[i];
    long step = old->step;
    double time = old->time;
    int rc = rebuild(r, x, NULL, time, 1, &report);
    free(x);
    if (rc == GSN_ERR_MEMORY)
        return rc;
    if (rc != GSN_OK) {
        /* a failure of the discretization is the computation's, whatever
         * its library called it: the present reference, which the last
         * step passed every check on, goes on, and the update is tried
         * again later (the energy check still watches the run) */
        snprintf(report.cause, sizeof report.cause, "%s", gsn_error_message());
        memcpy(r->last_deferral, report.cause, sizeof r->last_deferral);
        gsn_error_clear();
        report.deferred = 1;
        r->deferred_count++;
        r->deferred_run++;
        r->attempt_step = step;
        r->seconds += report.seconds = omp_get_wtime() - t0;
        r->last = report;
        if (out)
            *out = report;
        return GSN_OK;
    }
    r->deferred_run = 0;
    /* The new reference's cells may be smaller for their particles' masses
     * than the first (a compressed zone, a remade body) and its stable step
     * shorter: the step follows it. */
    double t_stable = omp_get_wtime();
    GSN_CALL(gsn_explicit_stable_step(r->loop, &report.stable_step));
    report.seconds_stable = omp_get_wtime() - t_stable;
    report.seconds += report.seconds_stable;
    report.time_step = fmin(r->first_step ? r->first_step : r->loop->dt,
                            r->c->time_step_safety * report.stable_step);
    if (report.time_step != r->loop->dt) {
        gsn_explicit_set_time_step(r->loop, report.time_step);
        gsn_explicit_kinetic_energies(r->loop); /* of the new step */
    }
    double mass1, momentum1[3], scale1;
    mass_momentum(r->loop, &mass1, momentum1, &scale1);
    report.kinetic_after = r->loop->conserved_kinetic_energy;
    report.mass_error = fabs(mass1 - mass0) / mass0;
    double dp = 0.0;
    for (int k = 0; k < 3; ++k)
        dp += (momentum1[k] - momentum0[k]) * (momentum1[k] - momentum0[k]);
    report.momentum_error = scale0 > 0.0 ? sqrt(dp) / scale0 : 0.0;
    r->update_count++;
    r->step = step;
    r->energy_jump += report.kinetic_after - report.kinetic_before;
    r->seconds += report.seconds;
    r->last = report;
    if (out)
        *out = report;
    return GSN_OK;
}

double gsn_reference_energy(const struct gsn_reference *r)
{
    return r->energy_jump + r->loop->release_work;
}

int gsn_reference_restore(struct gsn_reference *r, const double *position,
                          const struct gsn_body *body, double time, long step,
                          int update_count, double energy_jump)
{
    struct gsn_reference_report report;
    memset(&report, 0, sizeof report);
    GSN_CALL(rebuild(r, position, body ? body : &r->body, time, 0, &report));
    r->update_count = update_count;
    r->step = step;
    r->energy_jump = energy_jump;
    return GSN_OK;
}
