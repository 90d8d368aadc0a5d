/* geoscni solve: reads OUTDIR/model.h5, builds the shape functions and the
 * integration, runs the explicit loop (explicit.h) and writes
 * OUTDIR/results.h5 (frames and a restart checkpoint) and history.csv
 * (DESIGN.md, "What a run leaves"). results.h5 is written as
 * results.h5.part and renamed when the run ends, also when it ends in a
 * numerical failure or is interrupted (SIGINT, SIGTERM: a checkpoint is
 * written first), so the frames written so far stay readable. */
#include "constraint.h"
#include "explicit.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/h5io.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"
#include "geoscni/results.h"
#include "geoscni/solver.h"
#include "geoscni/tensor.h"
#include "material.h"
#include "nonlocal.h"
#include "overburden.h"
#include "reference.h"

#include <errno.h>
#include <math.h>
#include <omp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

/* A run whose energy balance KE + W_int + W_damping - W_ext drifts from its
 * value at step ENERGY_CHECK_FIRST_STEP by more than this fraction of the
 * largest of the three is unstable. Central differences conserve energy to
 * O(dt^2); a stable run stays far below. The balance is taken from that step on
 * because a prescribed velocity starts with a jump, an impact whose work
 * the trapezoidal rule of W_ext does not see (a constant offset). */
#define ENERGY_BALANCE_TOLERANCE 0.05
#define ENERGY_CHECK_FIRST_STEP 10
/* A loading run (a prescribed velocity) is quasi-static while its kinetic
 * energy stays below this fraction of the internal energy (issue 7: 1% of
 * the internal work). Checked from the end of time.ramp, or from
 * QUASI_STATIC_FIRST of the run without one (before, W_int is near 0). */
#define QUASI_STATIC_RATIO 0.01
#define QUASI_STATIC_FIRST 0.05
/* Frames that add up to more than this many bytes are worth a warning. */
#define LARGE_OUTPUT_BYTES 2e9
/* A sudden load is warned of with a suggested time.ramp of this many
 * periods of the body's lowest mode (docs/solver.md, "Quasi-static
 * loads"). */
#define SUDDEN_LOAD_PERIODS 2.0
/* Wall-clock seconds between checkpoints. */
#define CHECKPOINT_INTERVAL 30.0
/* Wall-clock seconds between progress lines written to a file or pipe
 * (besides one at every tenth of the run), unless the options give it. */
#define PROGRESS_INTERVAL 10.0

struct boundary_set {
    int surface; /* index in the model */
    int count;
    int *particle; /* the particles on the entry's surface */
};

struct run {
    const struct gsn_case *c;
    const struct gsn_solve_options *options;
    const char *outdir;
    char model_path[GSN_PATH_SIZE];
    char results_path[GSN_PATH_SIZE];
    char results_temporary[GSN_PATH_SIZE];
    char history_path[GSN_PATH_SIZE];
    char case_name[GSN_PATH_SIZE];
    struct gsn_model model;
    struct gsn_material_set *materials;
    /* the discretization of the present reference configuration and its
     * loop (reference.h) */
    struct gsn_reference *reference;
    struct boundary_set boundary[GSN_MAX_BOUNDARIES];
    struct gsn_frame frame;
    hid_t results;
    FILE *history;
    long total_steps;
    int frame_count;
    double next_frame_time;
    double next_row_time; /* of the next history row between frames */
    int damage_offset, plastic_offset;
    double energy_baseline;    /* J, see ENERGY_CHECK_FIRST_STEP */
    int loading;               /* the case prescribes a nonzero velocity */
    double kinetic_ratio;      /* largest KE / W_int since the check began */
    double kinetic_ratio_time; /* s, when it occurred */
    double last_checkpoint;    /* wall-clock time of the last one, s */
    double frame_bytes;        /* the most the file grew by at a frame */
    int stopped_whole;         /* stopped for want of room, the file whole */
    int body_written; /* the remesh count of the body in the checkpoint */
    /* the full resultant of each traction entry on the present reference
     * configuration, N (the loop applies it times its load factor) */
    double traction_force[GSN_MAX_BOUNDARIES][3];
    /* the geostatic stage of this run (a fresh run of a case with it) */
    long geostatic_steps;
    double geostatic_residual, geostatic_seconds;
    double geostatic_displacement; /* the largest at a particle, m */
    int geostatic_rested;
};

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int build_boundary_sets(struct run *r)
{
    const struct gsn_model *m = &r->model;
    for (int b = 0; b < r->c->boundary_count; ++b) {
        int surface = gsn_model_find_surface(m, r->c->boundaries[b].name);
        GSN_CHECK(surface >= 0, GSN_ERR_INPUT,
                  "%s:%d: boundary '%s' is not a physical surface of %s",
                  r->c->path, r->c->boundaries[b].line,
                  r->c->boundaries[b].name, r->model_path);
        struct boundary_set *set = &r->boundary[b];
        set->surface = surface;
        set->particle = malloc(sizeof(int) * (size_t)(m->particle_count + 1));
        GSN_CHECK(set->particle, GSN_ERR_MEMORY, "out of memory");
        for (int p = 0; p < m->particle_count; ++p)
            if (gsn_model_particle_on_surface(m, p, surface))
                set->particle[set->count++] = p;
    }
    return GSN_OK;
}

/* Fills r->frame from the loop's state at its current time: the fields
 * wanted (bits of schema.h's frame fields: output.fields for a frame, none
 * for a history row alone), and always the displacement and damage, which
 * the history row needs; nothing else is computed. */
static void fill_frame(struct run *r, unsigned wanted)
{
    const struct gsn_explicit *e = r->reference->loop;
    struct gsn_frame *f = &r->frame;
    int n = e->particle_count;
    int stress = (wanted & (1u << GSN_FRAME_STRESS)) != 0;
    int equivalent = (wanted & (1u << GSN_FRAME_EQUIVALENT_STRESS)) != 0;
    int plastic = (wanted & (1u << GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN)) != 0;
    f->time = e->time;
    f->step = (int)e->step;
    f->present = wanted;
    gsn_explicit_particle_displacement(e, f->field[GSN_FRAME_DISPLACEMENT]);
    if (wanted & (1u << GSN_FRAME_VELOCITY))
        gsn_explicit_particle_field(e, e->velocity,
                                    f->field[GSN_FRAME_VELOCITY]);
    if (stress || equivalent)
        gsn_explicit_particle_stress(e, f->field[GSN_FRAME_STRESS]);
    for (int j = 0; equivalent && j < n; ++j) {
        const double *s = &f->field[GSN_FRAME_STRESS][6 * j];
        double mean = gsn_voigt_trace(s) / 3.0, dev[6];
        memcpy(dev, s, sizeof dev);
        for (int k = 0; k < 3; ++k)
            dev[k] -= mean;
        f->field[GSN_FRAME_EQUIVALENT_STRESS][j] =
            sqrt(1.5) * gsn_voigt_norm(dev);
    }
    /* The material state at the particles: their nodal points' (Gauss: the
     * mean over each nodal domain, explicit.h). */
    if (r->damage_offset >= 0)
        gsn_explicit_particle_state(e, r->damage_offset,
                                    f->field[GSN_FRAME_DAMAGE]);
    else
        memset(f->field[GSN_FRAME_DAMAGE], 0, sizeof(double) * (size_t)n);
    if (plastic && r->plastic_offset >= 0)
        gsn_explicit_particle_state(
            e, r->plastic_offset,
            f->field[GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN]);
    else if (plastic)
        memset(f->field[GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN], 0,
               sizeof(double) * (size_t)n);
}

/* Flushes history.csv and reports a failed write (a full disk by name). */
static int history_flush(const struct run *r)
{
    if (fflush(r->history) != 0 || ferror(r->history))
        return GSN_WRITE_ERROR(r->history_path, errno, "cannot write");
    return GSN_OK;
}

/* KE + W_int + W_damping - W_ext less the kinetic energy the reference
 * updates added (not work done), with the kinetic energy central
 * differences conserve (explicit.h): constant on a stable linear body to
 * round-off, J. */
static double energy_balance(const struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    return e->conserved_kinetic_energy + e->internal_energy + e->damping_work -
           e->external_work - gsn_reference_energy(r->reference);
}

/* The header: each column's unit after its name (time_s, NAME_fz_N), so
 * the file stays a plain CSV that carries its units. */
static int write_history_header(struct run *r)
{
    fprintf(r->history, "time_s,step");
    for (int b = 0; b < r->c->boundary_count; ++b) {
        const char *name = r->c->boundaries[b].name;
        fprintf(r->history, ",%s_ux_m,%s_uy_m,%s_uz_m,%s_fx_N,%s_fy_N,%s_fz_N",
                name, name, name, name, name, name);
    }
    fprintf(r->history,
            ",kinetic_energy_J,internal_energy_J,external_work_J,max_damage,"
            "damping_work_J,reference_updates,update_energy_J,"
            "failed_particles,energy_balance_J\n");
    GSN_CALL(history_flush(r));
    return GSN_OK;
}

/* The full resultant of every traction entry on the present reference
 * configuration (t A: the shape functions add up to 1 at every facet
 * point), for its history columns. */
static void traction_resultants(struct run *r)
{
    const struct gsn_case *c = r->c;
    const struct gsn_quadrature *q = r->reference->quadrature;
    const struct gsn_model *m = r->reference->model;
    for (int b = 0; b < c->boundary_count; ++b) {
        const struct gsn_boundary *entry = &c->boundaries[b];
        if (!entry->has_traction[0])
            continue;
        int surface = gsn_model_find_surface(m, entry->name);
        double area = 0.0;
        for (int p = 0; p < q->boundary_point_count; ++p)
            if (m->facet_surface[q->boundary_point_facet[p]] == surface)
                area += q->boundary_point_weight[p];
        for (int k = 0; k < 3; ++k)
            r->traction_force[b][k] = entry->traction[k] * area;
    }
}

/* The factor of the dead loads at time t: with time.ramp they rise as the
 * prescribed velocities do, (1 - cos(pi t / T)) / 2, else 1 (constraint.h,
 * gsn_ramp_factor). */
static double load_factor(const struct run *r, double t)
{
    /* after a geostatic stage the dead loads are on from the start */
    return r->c->geostatic
               ? 1.0
               : gsn_ramp_factor(r->c->time_ramp, GSN_FIELD_VELOCITY, t);
}

/* Sets the loop's f_ext to the dead loads at time t (a no-op once they are
 * at full value). */
static void apply_loads(struct run *r, double t)
{
    gsn_explicit_set_load_factor(r->reference->loop, load_factor(r, t));
}

/* One history row from the frame just filled: the mean u(X_J) over the
 * surface's particles and the force the supports apply through it, the
 * multipliers lambda_J of the components the entry holds
 * (gsn_constraints_multipliers; gsn_constraints_entry: a particle on two
 * surfaces counts once) (DESIGN.md; docs/solver.md, "Boundary values"); on
 * a traction entry, the resultant of the traction it applies; on a rigid
 * body, its prescribed displacement, and the contact force added. */
static int write_history_row(struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    const double *u = r->frame.field[GSN_FRAME_DISPLACEMENT];
    double *multiplier = NULL;
    if (r->reference->constraints) {
        multiplier = malloc(sizeof(double) * 3 * (size_t)e->particle_count);
        GSN_CHECK(multiplier, GSN_ERR_MEMORY, "out of memory");
        int rc = gsn_constraints_multipliers(r->reference->constraints,
                                             e->reaction, multiplier);
        if (rc != GSN_OK) {
            free(multiplier);
            return rc;
        }
    }
    fprintf(r->history, "%.9g,%ld", e->time, e->step);
    for (int b = 0; b < r->c->boundary_count; ++b) {
        const struct boundary_set *set = &r->boundary[b];
        double mean[3] = {0, 0, 0}, force[3] = {0, 0, 0};
        int counted = 0;
        for (int s = 0; s < set->count; ++s) {
            /* a rigid body: the particles it still holds (it lets go of
             * those that slide out past its base, contact.h) */
            if (r->c->boundaries[b].rigid &&
                !gsn_constraints_holds(r->reference->constraints,
                                       set->particle[s], b))
                continue;
            for (int k = 0; k < 3; ++k)
                mean[k] += u[3 * set->particle[s] + k];
            ++counted;
        }
        for (int s = 0; s < set->count && multiplier; ++s)
            for (int k = 0; k < 3; ++k)
                if (gsn_constraints_entry(r->reference->constraints,
                                          set->particle[s], k) == b)
                    force[k] += multiplier[3 * set->particle[s] + k];
        /* a rigid body: the force it puts on the soil by contact too */
        if (e->contact && r->c->boundaries[b].rigid)
            for (int k = 0; k < 3; ++k)
                force[k] += e->contact_resultant[b][k];
        /* a traction entry: the force it applies, ramped as applied */
        for (int k = 0; k < 3; ++k)
            force[k] += e->load_factor * r->traction_force[b][k];
        for (int k = 0; k < 3; ++k)
            mean[k] = counted ? mean[k] / counted : 0.0;
        /* a rigid body moves as prescribed: its own displacement (the
         * particles it takes back under its base keep what they had) */
        const struct gsn_boundary *entry = &r->c->boundaries[b];
        for (int k = 0; k < 3 && entry->rigid; ++k)
            if (entry->has_velocity[k])
                mean[k] = entry->velocity[k] *
                          gsn_ramp_factor(r->c->time_ramp,
                                          GSN_FIELD_DISPLACEMENT, e->time);
        fprintf(r->history, ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", mean[0], mean[1],
                mean[2], force[0], force[1], force[2]);
    }
    double max_damage = 0.0;
    for (int j = 0; j < e->particle_count; ++j)
        if (r->frame.field[GSN_FRAME_DAMAGE][j] > max_damage)
            max_damage = r->frame.field[GSN_FRAME_DAMAGE][j];
    fprintf(r->history, ",%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%d,%.9g\n",
            e->kinetic_energy, e->internal_energy, e->external_work, max_damage,
            e->damping_work, r->reference->update_count,
            gsn_reference_energy(r->reference), e->dead_count,
            energy_balance(r));
    free(multiplier);
    GSN_CALL(history_flush(r));
    return GSN_OK;
}

/* The arrays of the loop's state, in the order of
 * gsn_checkpoint_datasets, with their row counts. */
static void checkpoint_arrays(struct gsn_explicit *e, double energy[4],
                              void *data[GSN_CHECKPOINT_DATASET_COUNT],
                              size_t rows[GSN_CHECKPOINT_DATASET_COUNT])
{
    size_t n = (size_t)e->particle_count, points = (size_t)e->point_count;
    void *arrays[GSN_CHECKPOINT_DATASET_COUNT] = {
        [GSN_CHECKPOINT_COEFFICIENT_DISPLACEMENT] = e->displacement,
        [GSN_CHECKPOINT_COEFFICIENT_VELOCITY] = e->velocity,
        [GSN_CHECKPOINT_COEFFICIENT_ACCELERATION] = e->acceleration,
        [GSN_CHECKPOINT_DISPLACEMENT_GRADIENT] = e->displacement_gradient,
        [GSN_CHECKPOINT_STRESS] = e->stress,
        [GSN_CHECKPOINT_REACTION] = e->reaction,
        [GSN_CHECKPOINT_ENERGY] = energy,
        [GSN_CHECKPOINT_DAMPING_FORCE] = e->damping_force,
        [GSN_CHECKPOINT_MATERIAL_STATE] = e->state,
        [GSN_CHECKPOINT_REFERENCE_GRADIENT] = e->reference_gradient,
        [GSN_CHECKPOINT_POINT_FAILED] = e->point_dead};
    size_t counts[GSN_CHECKPOINT_DATASET_COUNT] = {
        [GSN_CHECKPOINT_COEFFICIENT_DISPLACEMENT] = n,
        [GSN_CHECKPOINT_COEFFICIENT_VELOCITY] = n,
        [GSN_CHECKPOINT_COEFFICIENT_ACCELERATION] = n,
        [GSN_CHECKPOINT_DISPLACEMENT_GRADIENT] = points,
        [GSN_CHECKPOINT_STRESS] = points,
        [GSN_CHECKPOINT_REACTION] = n,
        [GSN_CHECKPOINT_ENERGY] = 1,
        [GSN_CHECKPOINT_DAMPING_FORCE] = n,
        [GSN_CHECKPOINT_MATERIAL_STATE] = (size_t)e->main_point_count,
        [GSN_CHECKPOINT_REFERENCE_GRADIENT] = (size_t)e->main_point_count,
        [GSN_CHECKPOINT_POINT_FAILED] = (size_t)e->main_point_count};
    memcpy(data, arrays, sizeof arrays);
    memcpy(rows, counts, sizeof counts);
}

/* Writes (write = 1) or reads the checkpoint datasets. */
static int checkpoint_transfer(struct run *r, int write, double energy[4])
{
    struct gsn_explicit *e = r->reference->loop;
    void *data[GSN_CHECKPOINT_DATASET_COUNT];
    size_t rows[GSN_CHECKPOINT_DATASET_COUNT];
    checkpoint_arrays(e, energy, data, rows);
    for (int d = 0; d < GSN_CHECKPOINT_DATASET_COUNT; ++d) {
        struct gsn_dataset_info info = gsn_checkpoint_datasets[d];
        if (d == GSN_CHECKPOINT_MATERIAL_STATE) {
            if (e->state_size == 0)
                continue;
            info.columns = e->state_size;
        }
        if (write)
            GSN_CALL(gsn_h5_write(r->results, &info, rows[d], data[d]));
        else
            GSN_CALL(gsn_h5_read(r->results, &info, rows[d], data[d]));
    }
    return GSN_OK;
}

/* The release of the last update's unbalanced force (explicit.h), in the
 * checkpoint; zeros once released. */
static int write_release(struct run *r, hid_t group)
{
    const struct gsn_explicit *e = r->reference->loop;
    const struct gsn_dataset_info *d =
        &gsn_checkpoint_reference_datasets[GSN_CHECKPOINT_RELEASE_FORCE];
    size_t n = (size_t)e->particle_count;
    double *zeros = e->release_force ? NULL : calloc(3 * n + 1, sizeof(double));
    GSN_CHECK(e->release_force || zeros, GSN_ERR_MEMORY, "out of memory");
    int rc = gsn_h5_write(r->results, d, n,
                          e->release_force ? e->release_force : zeros);
    free(zeros);
    GSN_CALL(rc);
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_RELEASE_START,
                                   (int)e->release_start));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_RELEASE_STEPS,
                                   (int)e->release_steps));
    GSN_CALL(
        gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_RELEASE_FACTOR,
                                 e->release_force ? e->release_factor : 0.0));
    return gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_RELEASE_WORK,
                                    e->release_work);
}

/* Reads what write_release wrote into the loop just restored. */
static int read_release(struct run *r, hid_t group)
{
    struct gsn_explicit *e = r->reference->loop;
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_RELEASE_WORK) <= 0)
        return GSN_OK;
    int start = 0, steps = 0;
    double factor = 0.0;
    GSN_CALL(
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_RELEASE_START, &start));
    GSN_CALL(
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_RELEASE_STEPS, &steps));
    GSN_CALL(gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_RELEASE_FACTOR,
                                     &factor));
    GSN_CALL(gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_RELEASE_WORK,
                                     &e->release_work));
    free(e->release_force);
    e->release_force = NULL;
    if (factor <= 0.0)
        return GSN_OK;
    size_t n = (size_t)e->particle_count;
    e->release_force = malloc(sizeof(double) * 3 * (n ? n : 1));
    GSN_CHECK(e->release_force, GSN_ERR_MEMORY, "out of memory");
    e->release_start = start;
    e->release_steps = steps;
    e->release_factor = e->release_next = factor;
    return gsn_h5_read(
        r->results,
        &gsn_checkpoint_reference_datasets[GSN_CHECKPOINT_RELEASE_FORCE], n,
        e->release_force);
}

/* Writes the reference configuration of the last update into the
 * checkpoint group: its positions and, where the body was made again, its
 * tetrahedra; the update count, time, step and added energy. */
static int write_checkpoint_reference(struct run *r, hid_t group)
{
    const struct gsn_reference *ref = r->reference;
    const struct gsn_dataset_info *d = gsn_checkpoint_reference_datasets;
    GSN_CALL(gsn_h5_write(r->results, &d[GSN_CHECKPOINT_REFERENCE_POSITION],
                          (size_t)ref->model->particle_count,
                          ref->model->position));
    /* the body, when it was made again since the last checkpoint (HDF5
     * does not give back the space of a deleted dataset) */
    if (ref->remesh_count > 0 && ref->remesh_count != r->body_written) {
        for (int k = GSN_CHECKPOINT_BODY_TETRAHEDRA;
             k <= GSN_CHECKPOINT_BODY_FACE; ++k)
            if (gsn_h5_exists(r->results, d[k].path))
                GSN_CHECK(H5Ldelete(r->results, d[k].path, H5P_DEFAULT) >= 0,
                          GSN_ERR_IO, "%s: cannot replace %s",
                          r->results_temporary, d[k].path);
        size_t count = (size_t)ref->body.tetrahedron_count;
        GSN_CALL(gsn_h5_write(r->results, &d[GSN_CHECKPOINT_BODY_TETRAHEDRA],
                              count, ref->body.tetrahedra));
        GSN_CALL(gsn_h5_write(r->results, &d[GSN_CHECKPOINT_BODY_FACE], count,
                              ref->body.face));
        r->body_written = ref->remesh_count;
    }
    GSN_CALL(write_release(r, group));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_UPDATES,
                                   ref->update_count));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_REMESHES,
                                   ref->remesh_count));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_REFERENCE_STEP,
                                   (int)ref->step));
    GSN_CALL(gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_REFERENCE_TIME,
                                      ref->time));
    GSN_CALL(gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_UPDATE_ENERGY,
                                      ref->energy_jump));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_DEFERRED,
                                   ref->deferred_count));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_DEFERRED_RUN,
                                   ref->deferred_run));
    GSN_CALL(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_ATTEMPT_STEP,
                                   (int)ref->attempt_step));
    return GSN_OK;
}

/* Builds the discretization of the checkpoint's reference configuration,
 * when an update made one, before its state is read into the loop. */
static int read_checkpoint_reference(struct run *r, hid_t group)
{
    struct gsn_reference *ref = r->reference;
    const struct gsn_dataset_info *d = gsn_checkpoint_reference_datasets;
    int updates = 0, remeshes = 0, step = 0;
    double time = 0.0, energy = 0.0;
    /* (checkpoints without updates lack nothing that matters) */
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_UPDATES) <= 0)
        return GSN_OK;
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_DEFERRED) > 0) {
        int attempt = 0;
        GSN_CALL(gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_DEFERRED,
                                      &ref->deferred_count));
        GSN_CALL(gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_DEFERRED_RUN,
                                      &ref->deferred_run));
        GSN_CALL(gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_ATTEMPT_STEP,
                                      &attempt));
        ref->attempt_step = attempt;
    }
    GSN_CALL(
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_UPDATES, &updates));
    if (updates == 0)
        return GSN_OK;
    GSN_CALL(
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_REMESHES, &remeshes));
    GSN_CALL(
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_REFERENCE_STEP, &step));
    GSN_CALL(gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_REFERENCE_TIME,
                                     &time));
    GSN_CALL(gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_UPDATE_ENERGY,
                                     &energy));
    size_t n = (size_t)r->model.particle_count;
    double *position = malloc(sizeof(double) * 3 * (n ? n : 1));
    GSN_CHECK(position, GSN_ERR_MEMORY, "out of memory");
    struct gsn_body body;
    memset(&body, 0, sizeof body);
    int rc = GSN_OK;
    GSN_CALL_GOTO(gsn_h5_read(r->results, &d[GSN_CHECKPOINT_REFERENCE_POSITION],
                              n, position),
                  rc, done);
    if (remeshes > 0) {
        size_t count = 0;
        GSN_CALL_GOTO(
            gsn_h5_rows(r->results, &d[GSN_CHECKPOINT_BODY_TETRAHEDRA], &count),
            rc, done);
        body.tetrahedron_count = (int)count;
        body.tetrahedra = malloc(sizeof(int) * 4 * (count ? count : 1));
        body.face = malloc(sizeof(int) * 4 * (count ? count : 1));
        GSN_CHECK_GOTO(body.tetrahedra && body.face, rc, GSN_ERR_MEMORY, done,
                       "out of memory");
        GSN_CALL_GOTO(gsn_h5_read(r->results,
                                  &d[GSN_CHECKPOINT_BODY_TETRAHEDRA], count,
                                  body.tetrahedra),
                      rc, done);
        GSN_CALL_GOTO(gsn_h5_read(r->results, &d[GSN_CHECKPOINT_BODY_FACE],
                                  count, body.face),
                      rc, done);
        for (size_t k = 0; k < 4 * count; ++k)
            GSN_CHECK_GOTO(
                body.tetrahedra[k] >= 0 && (size_t)body.tetrahedra[k] < n &&
                    body.face[k] >= GSN_MODEL_FACE_UNTAGGED &&
                    body.face[k] < r->model.surface_count,
                rc, GSN_ERR_INPUT, done, "%s: %s is damaged",
                r->results_temporary, d[GSN_CHECKPOINT_BODY_TETRAHEDRA].path);
    }
    GSN_CALL_GOTO(gsn_reference_restore(ref, position,
                                        remeshes > 0 ? &body : NULL, time, step,
                                        updates, energy),
                  rc, done);
    ref->remesh_count = remeshes;
    r->body_written = remeshes;
    GSN_CALL_GOTO(read_release(r, group), rc, done);
done:
    free(position);
    gsn_body_free(&body);
    return rc;
}

static int write_checkpoint(struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_group(r->results, GSN_CHECKPOINT_GROUP, &group));
    int rc = GSN_OK;
    double energy[4] = {e->kinetic_energy, e->internal_energy, e->external_work,
                        e->damping_work};
    GSN_CALL_GOTO(checkpoint_transfer(r, 1, energy), rc, done);
    GSN_CALL_GOTO(write_checkpoint_reference(r, group), rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(group, GSN_FRAME_ATTR_TIME, e->time),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(
                      group, GSN_RESULTS_ATTR_KINETIC_RATIO, r->kinetic_ratio),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(group,
                                           GSN_CHECKPOINT_ATTR_RATIO_TIME,
                                           r->kinetic_ratio_time),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(group,
                                           GSN_CHECKPOINT_ATTR_ENERGY_BASELINE,
                                           r->energy_baseline),
                  rc, done);
    GSN_CALL_GOTO(
        gsn_h5_attr_write_int(group, GSN_FRAME_ATTR_STEP, (int)e->step), rc,
        done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(group,
                                           GSN_CHECKPOINT_ATTR_TIME_STEP_FIRST,
                                           r->reference->first_step),
                  rc, done);
    GSN_CALL_GOTO(
        gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_TIME_STEP, e->dt),
        rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_double(group, GSN_CHECKPOINT_ATTR_TIME_BASE,
                                           e->time_base),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_STEP_BASE,
                                        (int)e->step_base),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_BOUNDARIES,
                                        GSN_CHECKPOINT_BOUNDARIES),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_flush(r->results), rc, done);
done:
    gsn_h5_close(&group);
    return rc;
}

/* The last step of the run: the loop's step plus those of its present time
 * step to time.end (a reference update may change the step). */
static long steps_to_end(const struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    return e->step + (long)ceil((r->c->time_end - e->time) / e->dt - 1e-9);
}

static int read_checkpoint(struct run *r)
{
    struct gsn_explicit *e = r->reference->loop;
    GSN_CHECK(gsn_h5_exists(r->results, GSN_CHECKPOINT_GROUP), GSN_ERR_INPUT,
              "%s: no checkpoint to restart from", r->results_path);
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(
        gsn_h5_group_open(r->results, GSN_CHECKPOINT_GROUP, "group", &group));
    int rc = GSN_OK, step = 0, boundaries = 0;
    double energy[4];
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_BOUNDARIES) > 0)
        GSN_CALL_GOTO(gsn_h5_attr_read_int(
                          group, GSN_CHECKPOINT_ATTR_BOUNDARIES, &boundaries),
                      rc, done);
    GSN_CHECK_GOTO(boundaries == GSN_CHECKPOINT_BOUNDARIES, rc, GSN_ERR_INPUT,
                   done,
                   "%s: its checkpoint was written by a geoscni that imposed "
                   "the essential boundaries otherwise (before 2026-12-02); "
                   "this build cannot continue it: solve again without "
                   "--restart",
                   r->results_path);
    GSN_CALL_GOTO(read_checkpoint_reference(r, group), rc, done);
    e = r->reference->loop;
    GSN_CALL_GOTO(checkpoint_transfer(r, 0, energy), rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_read_int(group, GSN_FRAME_ATTR_STEP, &step), rc,
                  done);
    GSN_CALL_GOTO(gsn_h5_attr_read_double(group, GSN_RESULTS_ATTR_KINETIC_RATIO,
                                          &r->kinetic_ratio),
                  rc, done);
    GSN_CALL_GOTO(gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_RATIO_TIME,
                                          &r->kinetic_ratio_time),
                  rc, done);
    /* (checkpoints written before 2026-12-01 lack it: 0, as they did) */
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_ENERGY_BASELINE) > 0)
        GSN_CALL_GOTO(
            gsn_h5_attr_read_double(group, GSN_CHECKPOINT_ATTR_ENERGY_BASELINE,
                                    &r->energy_baseline),
            rc, done);
    double saved_time = 0.0;
    GSN_CALL_GOTO(
        gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, &saved_time), rc,
        done);
    /* The clock: the step the run started with must be this run's (another
     * would continue the old state on another clock); the step of the
     * checkpoint, which a reference update may have changed, goes on. */
    double first = e->dt, now_step = e->dt, base_time = 0.0;
    int base_step = 0;
    if (H5Aexists(group, GSN_CHECKPOINT_ATTR_TIME_STEP_FIRST) > 0) {
        GSN_CALL_GOTO(gsn_h5_attr_read_double(
                          group, GSN_CHECKPOINT_ATTR_TIME_STEP_FIRST, &first),
                      rc, done);
        GSN_CALL_GOTO(gsn_h5_attr_read_double(
                          group, GSN_CHECKPOINT_ATTR_TIME_STEP, &now_step),
                      rc, done);
        GSN_CALL_GOTO(gsn_h5_attr_read_double(
                          group, GSN_CHECKPOINT_ATTR_TIME_BASE, &base_time),
                      rc, done);
        GSN_CALL_GOTO(gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_STEP_BASE,
                                           &base_step),
                      rc, done);
    }
    double expected = base_time + (double)(step - base_step) * now_step;
    /* With step: auto the step is the solver's: a run begun by a build
     * whose estimate differed (the free body's until 2026-12-07,
     * docs/solver.md "Time step") goes on with its own clock where this
     * build finds that clock's steps stable. */
    double stable = r->reference->first_step / r->c->time_step_safety;
    if (r->c->time_step_auto && first != r->reference->first_step &&
        fmax(first, now_step) <= stable) {
        if (!r->options->quiet)
            printf("restart: the run began with a step of %.4g s, where "
                   "this build's estimate gives %.4g s: it goes on with its "
                   "own (stable for this build up to %.4g s)\n",
                   first, r->reference->first_step, stable);
        r->reference->first_step = first;
    }
    GSN_CHECK_GOTO(
        fabs(first - r->reference->first_step) <= 1e-12 * first &&
            fabs(saved_time - expected) <= 1e-9 * fmax(saved_time, now_step),
        rc, GSN_ERR_INPUT, done,
        "%s: its checkpoint is at step %d, t = %.9g s, of a run "
        "that started with a time step of %.9g s, but this run's "
        "time step is %.9g s: the time step changed; start over "
        "without --restart",
        r->results_path, step, saved_time, first, r->reference->first_step);
    e->step = step;
    e->time = saved_time;
    e->dt = now_step;
    e->time_base = base_time;
    e->step_base = base_step;
    r->total_steps = steps_to_end(r);
    GSN_CHECK_GOTO(saved_time <= r->c->time_end + 0.5 * e->dt, rc,
                   GSN_ERR_INPUT, done,
                   "%s: its checkpoint is at t = %.6g s, after this case's "
                   "time.end %.6g s: a restart can only run further",
                   r->results_path, saved_time, r->c->time_end);
    /* energy[0] is the kinetic energy of the restored v: recomputed with
     * the conserved one (the same sum) */
    gsn_explicit_kinetic_energies(e);
    e->internal_energy = energy[1];
    e->external_work = energy[2];
    e->damping_work = energy[3];
    apply_loads(r, e->time);
    GSN_CALL_GOTO(gsn_explicit_refresh(e), rc, done);
done:
    gsn_h5_close(&group);
    return rc;
}

/* A stop that --restart continues (a signal, a full disk): the checkpoint
 * of this step, and the results marked interrupted. */
static int checkpoint_for_restart(struct run *r)
{
    GSN_CALL(write_checkpoint(r));
    return gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_INTERRUPTED, 1);
}

/* The checkpoint's mark of a frame due at its step but not written (a
 * stop for want of room). */
static int set_frame_due(struct run *r, int due)
{
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_group(r->results, GSN_CHECKPOINT_GROUP, &group));
    int rc = gsn_h5_attr_write_int(group, GSN_CHECKPOINT_ATTR_FRAME_DUE, due);
    gsn_h5_close(&group);
    return rc;
}

static int frame_due_at_checkpoint(struct run *r)
{
    int due = 0;
    hid_t group = H5Gopen2(r->results, GSN_CHECKPOINT_GROUP, H5P_DEFAULT);
    if (group >= 0 && H5Aexists(group, GSN_CHECKPOINT_ATTR_FRAME_DUE) > 0 &&
        gsn_h5_attr_read_int(group, GSN_CHECKPOINT_ATTR_FRAME_DUE, &due) !=
            GSN_OK)
        due = 0;
    if (group >= 0)
        H5Gclose(group);
    return due;
}

static double file_bytes(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (double)st.st_size : 0.0;
}

/* Before a frame: room for it (twice the largest that the file grew by at
 * a frame, and 1 MB), else the run stops as for a signal, its frames whole
 * and a checkpoint of this step written in place, so that --restart goes
 * on once there is room. A disk that another writer fills in between
 * still fails the write itself (the file then stays results.h5.part). */
static int check_room(struct run *r)
{
    struct statvfs disk;
    if (statvfs(r->outdir, &disk) != 0)
        return GSN_OK;
    double room = (double)disk.f_bavail * (double)disk.f_frsize;
    double need = 2.0 * r->frame_bytes + 1e6;
    if (room >= need)
        return GSN_OK;
    const struct gsn_explicit *e = r->reference->loop;
    GSN_CALL(checkpoint_for_restart(r));
    GSN_CALL(set_frame_due(r, 1));
    GSN_CALL(gsn_h5_flush(r->results));
    r->stopped_whole = 1;
    return gsn_error_raise(
        GSN_ERR_NO_SPACE, __FILE__, __LINE__, __func__,
        "%s: %.2f MB free on its disk, the next frame needs about %.2f MB: "
        "the run stops at step %ld, t = %.6g s, with its %d frames whole and "
        "a checkpoint of this step; free some space, then continue with "
        "'geoscni solve %s -o %s --restart'",
        r->outdir, room / 1e6, need / 1e6, e->step, e->time, r->frame_count,
        r->c->path, r->outdir);
}

/* A frame and its history row; a checkpoint with it at the end of the run
 * and when CHECKPOINT_INTERVAL seconds of wall time have passed since the
 * last one (a restart from any checkpoint gives the same bits). */
static int write_output(struct run *r, int final)
{
    GSN_CALL(check_room(r));
    double before = file_bytes(r->results_temporary);
    fill_frame(r, r->c->output_fields);
    GSN_CALL(write_history_row(r));
    GSN_CALL(gsn_results_frame_write(r->results, r->frame_count, &r->frame));
    r->frame_count++;
    double now = now_seconds();
    if (final || now - r->last_checkpoint >= CHECKPOINT_INTERVAL) {
        GSN_CALL(write_checkpoint(r));
        r->last_checkpoint = now;
    }
    r->frame_bytes =
        fmax(r->frame_bytes, file_bytes(r->results_temporary) - before);
    return GSN_OK;
}

/* Whether the step at `time` serves a frame or row time T: the first step
 * with T <= t + dt/2, the step nearest T (docs/economy.md, "Frame
 * times"). */
static int time_served(double target, double time, double dt)
{
    return target <= time + 0.5 * dt;
}

/* The first multiple of `every` that the step at `time` has not served;
 * INFINITY if every is 0. */
static double next_multiple(double every, double time, double dt)
{
    double served = time + 0.5 * dt;
    return every > 0.0 ? (floor(served / every) + 1.0) * every : INFINITY;
}

/* The first frame time of the case, a multiple of output.every or an entry
 * of output.times, that the step at `time` has not served; INFINITY if none
 * is left. A function of the step's time alone, so a restart schedules the
 * frames of the uninterrupted run. */
static double next_frame_time(const struct gsn_case *c, double time, double dt)
{
    double next = next_multiple(c->output_every, time, dt);
    for (int i = 0; i < c->output_time_count; ++i)
        if (!time_served(c->output_times[i], time, dt)) {
            next = fmin(next, c->output_times[i]);
            break;
        }
    return next;
}

/* The next frame and history row after the loop's present step. */
static void schedule_outputs(struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    r->next_frame_time = next_frame_time(r->c, e->time, e->dt);
    r->next_row_time = next_multiple(r->c->history_every, e->time, e->dt);
}

/* The time step: auto (safety x stable) or the case's, refused above the
 * stable one unless forced. */
static int choose_time_step(struct run *r)
{
    struct gsn_explicit *e = r->reference->loop;
    const struct gsn_case *c = r->c;
    double stable = 0.0;
    GSN_CALL(gsn_explicit_stable_step(e, &stable));
    char damped[64] = "";
    if (e->damping_local > 0.0)
        snprintf(damped, sizeof damped, " and the damping (local %g)",
                 e->damping_local);
    if (e->mass_scaled_count > 0 && !r->options->quiet)
        printf("mass scaling: %.3g%% of the body's mass added to %d "
               "particles (%.2g%%), up to %.3g times their own\n",
               100.0 * c->time_mass_scaling, e->mass_scaled_count,
               100.0 * e->mass_scaled_count / e->particle_count,
               e->mass_scaled_largest);
    if (c->time_step_auto) {
        e->dt = c->time_step_safety * stable;
        if (!r->options->quiet)
            printf("time step: %.4g s (auto: %.2f x the stable step %.4g s "
                   "from Lanczos on M^-1 K within the constraints%s)\n",
                   e->dt, c->time_step_safety, stable, damped);
    } else {
        GSN_CHECK(c->time_step <= stable || r->options->force, GSN_ERR_INPUT,
                  "%s: time.step = %.4g s is above the stable step %.4g s of "
                  "this model (Lanczos on M^-1 K within the constraints%s); "
                  "use a smaller step, 'step: auto', or --force",
                  c->path, c->time_step, stable, damped);
        e->dt = c->time_step;
        if (!r->options->quiet)
            printf("time step: %.4g s (the stable step is %.4g s)%s\n", e->dt,
                   stable, c->time_step > stable ? ", forced" : "");
    }
    r->total_steps = steps_to_end(r);
    r->reference->first_step = e->dt;
    return GSN_OK;
}

static void format_duration(double seconds, char *out, size_t size)
{
    if (seconds < 0 || !isfinite(seconds))
        snprintf(out, size, "?");
    else if (seconds < 60)
        snprintf(out, size, "%.0fs", seconds);
    else if (seconds < 3600)
        snprintf(out, size, "%dm%02ds", (int)seconds / 60, (int)seconds % 60);
    else
        snprintf(out, size, "%dh%02dm", (int)seconds / 3600,
                 ((int)seconds % 3600) / 60);
}

static void print_progress(const struct run *r, double started, long first,
                           int final)
{
    const struct gsn_explicit *e = r->reference->loop;
    double elapsed = now_seconds() - started;
    long done = e->step - first;
    double rate = elapsed > 0 ? done / elapsed : 0.0;
    double eta = rate > 0 ? (r->total_steps - e->step) / rate : -1.0;
    char eta_text[32], elapsed_text[32];
    format_duration(eta, eta_text, sizeof eta_text);
    format_duration(elapsed, elapsed_text, sizeof elapsed_text);
    int tty = isatty(STDERR_FILENO);
    fprintf(stderr,
            "%sstep %ld/%ld  t = %.4g s  %5.1f%%  %s %s  %.3g particle-steps/s"
            "%s",
            tty ? "\r" : "", e->step, r->total_steps, e->time,
            100.0 * e->step / (double)r->total_steps, final ? "took" : "ETA",
            final ? elapsed_text : eta_text, rate * e->particle_count,
            tty && !final ? "   " : "\n");
    fflush(stderr);
}

static int check_energy(struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    double scale = fmax(fmax(e->kinetic_energy, fabs(e->internal_energy)),
                        fmax(fabs(e->external_work), e->damping_work));
    double balance = energy_balance(r);
    double check_from =
        fmax(r->c->time_ramp, QUASI_STATIC_FIRST * r->c->time_end);
    if (e->time >= check_from && e->internal_energy > 0.0 &&
        e->kinetic_energy > r->kinetic_ratio * e->internal_energy) {
        r->kinetic_ratio = e->kinetic_energy / e->internal_energy;
        r->kinetic_ratio_time = e->time;
    }
    if (e->step <= ENERGY_CHECK_FIRST_STEP)
        r->energy_baseline = balance;
    if (e->step <= ENERGY_CHECK_FIRST_STEP || scale <= 0.0 ||
        fabs(balance - r->energy_baseline) <= ENERGY_BALANCE_TOLERANCE * scale)
        return GSN_OK;
    /* Name the particle where the instability shows most: the fastest. */
    int fastest = 0;
    double speed = -1.0;
    for (int i = 0; i < e->particle_count; ++i) {
        const double *v = &e->velocity[3 * i];
        double s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (s > speed) {
            speed = s;
            fastest = i;
        }
    }
    const double *x = &r->model.position[3 * fastest];
    return gsn_error_raise(
        GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
        "step %ld, t = %.6g s: energy is not conserved (kinetic %.4g J + "
        "internal %.4g J + damping %.4g J - external work %.4g J = %.4g J), "
        "fastest at particle %d (reference position %g, %g, %g; %.3g m/s): "
        "the run is unstable; reduce time.step",
        e->step, e->time, e->kinetic_energy, e->internal_energy,
        e->damping_work, e->external_work, balance, fastest, x[0], x[1], x[2],
        sqrt(speed));
}

/* Where the steps' wall time went (explicit.h, phase_seconds). */
static void print_phases(const struct gsn_explicit *e)
{
    const double *t = e->phase_seconds;
    double total = 0.0;
    for (int k = 0; k < GSN_PHASE_COUNT; ++k)
        total += t[k];
    if (!(total > 0.0))
        return;
    printf("step time: row pass %.0f%%, boundary solves %.0f%%, updates "
           "%.0f%% of %.3g s",
           100.0 * t[GSN_PHASE_PASS] / total,
           100.0 * t[GSN_PHASE_CONSTRAINTS] / total,
           100.0 * t[GSN_PHASE_UPDATES] / total, total);
    const double *part = e->pass_part_ticks;
    double blocks = 0.0;
    for (int k = 0; k < GSN_PASS_PART_COUNT; ++k)
        blocks += part[k];
    if (blocks > 0.0)
        printf("; the pass's blocks: gather %.0f%%, material %.0f%%, "
               "stabilization %.0f%%, scatter %.0f%%",
               100.0 * part[GSN_PASS_GATHER] / blocks,
               100.0 * part[GSN_PASS_MATERIAL] / blocks,
               100.0 * part[GSN_PASS_STABILIZATION] / blocks,
               100.0 * part[GSN_PASS_SCATTER] / blocks);
    if (e->factor_seconds > 0.0)
        printf("; besides, %.3g s factorizing the boundary matrices",
               e->factor_seconds);
    printf("\n");
    printf("step data: %.2f kB a particle-step at the least (the rows and "
           "slot tables %.2f kB; gsn_explicit_step_bytes)\n",
           1e-3 * gsn_explicit_step_bytes(e) / e->particle_count,
           1e-3 * (double)gsn_point_blocks_bytes(e->blocks) /
               e->particle_count);
}

/* The signal that asked the loop to stop (SIGINT, SIGTERM), or 0. */
static volatile sig_atomic_t stop_signal;

static void request_stop(int signal_number)
{
    stop_signal = signal_number;
}

/* Catches SIGINT and SIGTERM once (install = 1; a second one ends the
 * process at once), or gives the handlers back (install = 0). A signal
 * ignored on entry (SIGINT of a background job in a script) stays
 * ignored. */
static void catch_stop_signals(int install, struct sigaction previous[2])
{
    static const int signals[2] = {SIGINT, SIGTERM};
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = request_stop;
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    for (int k = 0; k < 2; ++k) {
        if (install) {
            sigaction(signals[k], NULL, &previous[k]);
            if (previous[k].sa_handler != SIG_IGN)
                sigaction(signals[k], &action, NULL);
        } else {
            sigaction(signals[k], &previous[k], NULL);
        }
    }
    stop_signal = 0;
}

static const char *stopped_by(int signal_number)
{
    return signal_number == SIGTERM ? "terminated" : "interrupted";
}

/* After a stop signal: the checkpoint of the step just done, so that
 * --restart continues from it (the frames so far are kept as they are). */
static int stop_for_signal(struct run *r)
{
    const struct gsn_explicit *e = r->reference->loop;
    int signal_number = stop_signal;
    GSN_CALL(checkpoint_for_restart(r));
    return gsn_error_raise(
        GSN_ERR_INTERRUPTED, __FILE__, __LINE__, __func__,
        "%s at step %ld of %ld, t = %.6g s: the checkpoint of this step is "
        "written; continue with 'geoscni solve %s -o %s --restart' (or run "
        "--restart)",
        stopped_by(signal_number), e->step, r->total_steps, e->time, r->c->path,
        r->outdir);
}

/* What the reference updates did and cost, and the failed particles. */
static void print_updates(const struct run *r, double seconds)
{
    const struct gsn_reference *ref = r->reference;
    if (ref->update_count > 0)
        printf("reference updates: %d (%d with the body's tetrahedra made "
               "again), %.3g s, %.1f%% of the solve; the energy they "
               "added: %.4g J (kinetic %.4g J, released forces' work "
               "%.4g J)\n",
               ref->update_count, ref->remesh_count, ref->seconds,
               seconds > 0.0 ? 100.0 * ref->seconds / seconds : 0.0,
               gsn_reference_energy(ref), ref->energy_jump,
               ref->loop->release_work);
    if (ref->deferred_count > 0)
        printf("reference updates deferred: %d (the new discretization "
               "failed its checks%s%s)\n",
               ref->deferred_count, ref->last_deferral[0] ? "; the last: " : "",
               ref->last_deferral);
    if (ref->loop->dead_count > 0)
        printf("failed particles: %d (turned inside out; they carry no "
               "stress and keep their mass)\n",
               ref->loop->dead_count);
}

/* A reference-configuration update when the last step calls for one
 * (reference.h), with a line saying why and what it cost. */
static int update_reference(struct run *r)
{
    enum gsn_reference_reason reason = gsn_reference_due(r->reference);
    if (reason == GSN_REFERENCE_NOT_DUE)
        return GSN_OK;
    struct gsn_reference_report report;
    GSN_CALL(gsn_reference_update(r->reference, &report));
    if (report.deferred) {
        const struct gsn_reference *ref = r->reference;
        const struct gsn_explicit *e = ref->loop;
        if (!r->options->quiet) {
            fprintf(stderr,
                    "%swarning: reference update at step %ld, t = %.4g s "
                    "(%s) deferred: %s; the run goes on with the reference "
                    "of step %ld and tries again after %ld steps\n",
                    isatty(STDERR_FILENO) ? "\r" : "", e->step, e->time,
                    gsn_reference_reason_name(reason), report.cause, ref->step,
                    gsn_reference_retry_steps(ref));
            fflush(stderr);
        }
        return GSN_OK;
    }
    traction_resultants(r);
    const struct gsn_explicit *e = r->reference->loop;
    r->total_steps = steps_to_end(r);
    if (!r->options->quiet) {
        const double *x = &r->model.position[3 * report.particle];
        char repairs[128] = "";
        if (report.support_repairs > 0 || report.held_fallbacks > 0)
            snprintf(repairs, sizeof repairs,
                     " (%d supports repaired, %d points of held facets keep "
                     "Psi_I)",
                     report.support_repairs, report.held_fallbacks);
        fprintf(stderr,
                "%sreference update %d at step %ld, t = %.4g s (%s: |E| %.3g, "
                "det F %.3g..%.3g, at particle %d, first at %g, %g, %g): "
                "%.2f s (cells %.2f, kernels %.2f, constraints %.2f, loop "
                "%.2f, state %.2f, stable step %.2f)%s%s, step %.4g s of a "
                "stable %.4g s, kinetic energy %.4g -> %.4g J, mass "
                "%.1e, momentum %.1e, %d failed particles\n",
                isatty(STDERR_FILENO) ? "\r" : "", r->reference->update_count,
                e->step, e->time, gsn_reference_reason_name(reason),
                report.strain, report.volume[0], report.volume[1],
                report.particle, x[0], x[1], x[2], report.seconds,
                report.seconds_cells, report.seconds_kernels,
                report.seconds_constraints, report.seconds_loop,
                report.seconds_state, report.seconds_stable,
                report.remeshed ? " (body's tetrahedra made again)" : "",
                repairs, report.time_step, report.stable_step,
                report.kinetic_before, report.kinetic_after, report.mass_error,
                report.momentum_error, e->dead_count);
        fflush(stderr);
    }
    return GSN_OK;
}

static int run_loop(struct run *r)
{
    double started = now_seconds(), last_print = started;
    long first = r->reference->loop->step;
    int quiet = r->options->quiet, tty = isatty(STDERR_FILENO);
    double interval = r->options->progress_seconds > 0.0
                          ? r->options->progress_seconds
                          : PROGRESS_INTERVAL;
    while (r->reference->loop->step < r->total_steps) {
        if (stop_signal)
            return stop_for_signal(r);
        struct gsn_explicit *e = r->reference->loop;
        apply_loads(r, gsn_explicit_time_of(e, e->step + 1));
        GSN_CALL(gsn_explicit_step(e));
        GSN_CALL(check_energy(r));
        /* before the outputs of the step, so that its checkpoint holds the
         * new reference (a restart then continues on it; also at the last
         * step, which a longer run continues) */
        GSN_CALL(update_reference(r));
        e = r->reference->loop;
        /* Frames at the steps nearest the frame times before the end, and
         * one at the last step (not also one a step before it). */
        int last = e->step == r->total_steps;
        int due = time_served(r->next_frame_time, e->time, e->dt) &&
                  r->next_frame_time < r->c->time_end - 0.5 * e->dt;
        /* History rows between the frames at the steps nearest the
         * multiples of output.history_every, scheduled the same way. */
        int row_due = time_served(r->next_row_time, e->time, e->dt);
        if (due || last) {
            GSN_CALL(write_output(r, last));
            r->next_frame_time = next_frame_time(r->c, e->time, e->dt);
        } else if (row_due) {
            fill_frame(r, 0);
            GSN_CALL(write_history_row(r));
        }
        if (due || last || row_due)
            r->next_row_time =
                next_multiple(r->c->history_every, e->time, e->dt);
        /* On a terminal a line rewritten twice a second; into a file, a
         * line at every tenth of the run and every progress interval. */
        double t = now_seconds();
        int tenth = (e->step * 10) / r->total_steps !=
                    ((e->step - 1) * 10) / r->total_steps;
        int print =
            tty ? t - last_print > 0.5
                : (tenth && t - last_print > 0.5) || t - last_print >= interval;
        if (!quiet && (last || print)) {
            print_progress(r, started, first, last);
            last_print = t;
        }
    }
    if (!quiet) {
        print_phases(r->reference->loop);
        print_updates(r, now_seconds() - started);
    }
    return GSN_OK;
}

/* The text after `key` at the start of a line of text, or NULL. */
static const char *line_value(const char *text, const char *key)
{
    size_t n = strlen(key);
    for (const char *line = text; line && *line;) {
        if (!strncmp(line, key, n))
            return line + n;
        line = strchr(line, '\n');
        line = line ? line + 1 : NULL;
    }
    return NULL;
}

/* A resolved case without its header comment (the case file's path). */
static const char *without_header(const char *text)
{
    const char *newline = text[0] == '#' ? strchr(text, '\n') : NULL;
    return text[0] == '#' ? (newline ? newline + 1 : "") : text;
}

static const char *file_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* A restart continues the case its results were started with: refused when
 * it differs in anything but what a continuation may change (another
 * material or step would continue the old state with the new case,
 * unnoticed): time.end (a run may go further; with it output.every where
 * that follows time.end by default) and the geometry's folder (a moved
 * project). Nothing is written here. */
static int check_restart_case(struct run *r)
{
    char *then = NULL, *now = NULL;
    GSN_CALL(gsn_h5_attr_read_string(r->results, GSN_ATTR_CASE, &then));
    gsn_case_yaml_upgrade(&then);
    struct gsn_case *same = malloc(sizeof *same);
    int rc = same ? GSN_OK
                  : gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__,
                                    __func__, "out of memory");
    if (rc == GSN_OK) {
        *same = *r->c;
        const char *end = line_value(then, "time: {end: ");
        if (end) {
            same->time_end = strtod(end, NULL);
            if (same->output_every_default)
                same->output_every = same->time_end / GSN_DEFAULT_FRAMES;
        }
        const char *geometry = line_value(then, "geometry: '");
        const char *close = geometry ? strchr(geometry, '\'') : NULL;
        char stored[GSN_PATH_SIZE];
        if (close && (size_t)(close - geometry) < sizeof stored) {
            memcpy(stored, geometry, (size_t)(close - geometry));
            stored[close - geometry] = '\0';
            if (!strcmp(file_name(stored), file_name(same->geometry)))
                memcpy(same->geometry, stored, strlen(stored) + 1);
        }
        rc = gsn_case_to_yaml_string(same, &now);
    }
    const char *a = rc == GSN_OK ? without_header(then) : "";
    const char *b = rc == GSN_OK ? without_header(now) : "";
    if (rc == GSN_OK && strcmp(a, b) != 0) {
        /* the first line that differs, each cut to 200 characters */
        size_t at = 0, line = 0;
        for (; a[at] && a[at] == b[at]; ++at)
            if (a[at] == '\n')
                line = at + 1;
        const char *then_line = a + line + strspn(a + line, " ");
        const char *now_line = b + line + strspn(b + line, " ");
        int la = (int)strcspn(then_line, "\n");
        int lb = (int)strcspn(now_line, "\n");
        rc = gsn_error_raise(
            GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
            "%s: --restart continues the run in %s, which was started from "
            "another case: it had '%.*s' where this case has '%.*s'; only "
            "time.end may change for a restart: restart with the case it was "
            "started with, or start over without --restart",
            r->c->path, r->results_path, la < 200 ? la : 200, then_line,
            lb < 200 ? lb : 200, now_line);
    }
    free(same);
    free(now);
    free(then);
    return rc;
}

/* The checkpoint step of a results file if it is waiting for --restart: a
 * results.h5.part (a run killed, or running now) or a results.h5 that a
 * signal stopped; 0 otherwise (a numerical failure may be started over). */
static int waiting_step(const char *path, int part, double *time)
{
    hid_t file = H5I_INVALID_HID, group = H5I_INVALID_HID;
    int step = 0, complete = 1, interrupted = 0;
    if (access(path, F_OK) != 0 ||
        gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file) != GSN_OK) {
        gsn_error_clear();
        return 0;
    }
    if (H5Aexists(file, GSN_RESULTS_ATTR_INTERRUPTED) > 0)
        gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_INTERRUPTED, &interrupted);
    gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_COMPLETE, &complete);
    if ((part || (interrupted && !complete)) &&
        gsn_h5_exists(file, GSN_CHECKPOINT_GROUP)) {
        group = H5Gopen2(file, GSN_CHECKPOINT_GROUP, H5P_DEFAULT);
        if (group < 0 ||
            gsn_h5_attr_read_int(group, GSN_FRAME_ATTR_STEP, &step) != GSN_OK ||
            gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, time) != GSN_OK)
            step = 0;
    }
    if (group >= 0)
        H5Gclose(group);
    gsn_h5_close(&file);
    gsn_error_clear();
    return step;
}

/* A fresh run would replace results that wait for --restart: refused unless
 * options->start_over, since the history they need is rewritten at once. */
static int check_not_interrupted(const struct run *r)
{
    if (r->options->start_over)
        return GSN_OK;
    double time = 0.0;
    const char *path = r->results_temporary;
    int step = waiting_step(path, 1, &time);
    if (step == 0) {
        path = r->results_path;
        step = waiting_step(path, 0, &time);
    }
    GSN_CHECK(step == 0, GSN_ERR_INPUT,
              "%s holds a run stopped at step %d, t = %.6g s, before its end: "
              "continue it with --restart, or start over with 'geoscni run "
              "--rerun' (or delete %s and solve again)",
              path, step, time, path);
    return GSN_OK;
}

/* What a restart needs of the results it continues (open, read-only):
 * the same model.h5, the same case (check_restart_case) and a checkpoint
 * it can continue from, which is read. */
static int check_restart(struct run *r, const char *model_hash,
                         int *was_complete)
{
    char *stored = NULL;
    if (H5Aexists(r->results, GSN_RESULTS_ATTR_MODEL_HASH) > 0)
        GSN_CALL(gsn_h5_attr_read_string(r->results,
                                         GSN_RESULTS_ATTR_MODEL_HASH, &stored));
    int same = !stored || strcmp(stored, model_hash) == 0;
    free(stored);
    GSN_CHECK(same, GSN_ERR_INPUT,
              "%s: --restart continues the run in %s, but %s changed since "
              "it started (pre ran again?): its particles are not the "
              "checkpoint's; start over without --restart",
              r->c->path, r->results_path, r->model_path);
    *was_complete = 0; /* a run killed before its first flush lacks it */
    if (H5Aexists(r->results, GSN_RESULTS_ATTR_COMPLETE) > 0)
        GSN_CALL(gsn_h5_attr_read_int(r->results, GSN_RESULTS_ATTR_COMPLETE,
                                      was_complete));
    GSN_CALL(check_restart_case(r));
    GSN_CALL(read_checkpoint(r));
    GSN_CHECK(access(r->history_path, R_OK) == 0, GSN_ERR_INPUT,
              "%s: missing; cannot restart (start over without --restart)",
              r->history_path);
    return GSN_OK;
}

/* Opens results and history for a fresh run, or for a restart from the
 * checkpoint of an earlier run's results (complete or cut short). */
static int open_outputs(struct run *r)
{
    struct gsn_explicit *e = r->reference->loop;
    char *case_yaml = NULL, model_hash[GSN_FILE_HASH_SIZE];
    GSN_CALL(gsn_file_hash(r->model_path, model_hash));
    if (!r->options->restart) {
        GSN_CALL(check_not_interrupted(r));
        GSN_CALL(gsn_case_to_yaml_string(r->c, &case_yaml));
        int rc = gsn_h5_create(r->results_temporary, GSN_FILE_KIND_RESULTS,
                               case_yaml, &r->results);
        free(case_yaml);
        GSN_CALL(rc);
        GSN_CALL(gsn_h5_attr_write_string(
            r->results, GSN_RESULTS_ATTR_CASE_NAME, r->case_name));
        GSN_CALL(gsn_h5_attr_write_string(
            r->results, GSN_RESULTS_ATTR_MODEL_HASH, model_hash));
        /* before the first frame's flush: a run killed after it has it */
        GSN_CALL(
            gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_COMPLETE, 0));
        r->history = fopen(r->history_path, "w");
        if (!r->history)
            return GSN_WRITE_ERROR(r->history_path, errno, "cannot create");
        GSN_CALL(write_history_header(r));
        GSN_CALL(write_output(r, 0)); /* the frame at t = 0 */
        schedule_outputs(r);
        return GSN_OK;
    }
    /* A results.h5.part is the newest (a run killed while writing it);
     * else results.h5 becomes the .part it is written as. */
    int part = access(r->results_temporary, F_OK) == 0;
    GSN_CHECK(part || access(r->results_path, F_OK) == 0, GSN_ERR_INPUT,
              "%s: not found: there is no run to restart in %s; solve "
              "without --restart",
              r->results_path, r->outdir);
    /* Checked where they are, read-only, so that a refused restart leaves
     * the files as they were; then written under the temporary name. */
    GSN_CALL(gsn_h5_open(part ? r->results_temporary : r->results_path,
                         GSN_FILE_KIND_RESULTS, 0, &r->results));
    int was_complete = 0;
    int rc = check_restart(r, model_hash, &was_complete);
    gsn_h5_close(&r->results);
    GSN_CALL(rc);
    /* the checkpoint's state; with reference updates a new loop (the one
     * taken above is gone): its step decides which frames and history
     * rows are kept */
    e = r->reference->loop;
    if (!part)
        GSN_CHECK(rename(r->results_path, r->results_temporary) == 0,
                  GSN_ERR_IO, "cannot rename %s for the restart",
                  r->results_path);
    GSN_CALL(gsn_h5_open(r->results_temporary, GSN_FILE_KIND_RESULTS, 1,
                         &r->results));
    /* The case may have a later time.end: it is the case of the results. */
    GSN_CALL(gsn_case_to_yaml_string(r->c, &case_yaml));
    int written =
        gsn_h5_attr_write_string(r->results, GSN_ATTR_CASE, case_yaml);
    free(case_yaml);
    GSN_CALL(written);
    GSN_CALL(
        gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_INTERRUPTED, 0));
    if (!r->options->quiet)
        printf("restart: from the checkpoint at step %ld of %ld, t = %.6g s\n",
               e->step, r->total_steps, e->time);
    fflush(stdout);
    /* The checkpoint's step wrote a frame, unless a signal wrote it; later
     * ones are written again. */
    int last_frame_step = -1;
    GSN_CALL(gsn_results_frames_drop_after(r->results, (int)e->step,
                                           &r->frame_count, &last_frame_step));
    schedule_outputs(r);
    /* Keep the history rows up to the checkpoint, drop any later ones. */
    char temporary[GSN_PATH_SIZE + 8], line[65536];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, r->history_path));
    FILE *old = fopen(r->history_path, "r");
    GSN_CHECK(old, GSN_ERR_INPUT, "%s: missing; cannot restart",
              r->history_path);
    r->history = fopen(temporary, "w");
    GSN_CHECK_GOTO(r->history, rc, GSN_ERR_IO, fail, "%s: cannot create",
                   temporary);
    int header = 1;
    while (fgets(line, sizeof line, old)) {
        if (!header && strtol(strchr(line, ',') ? strchr(line, ',') + 1 : line,
                              NULL, 10) > e->step)
            break;
        fputs(line, r->history);
        header = 0;
    }
    fflush(r->history);
    GSN_CHECK_GOTO(rename(temporary, r->history_path) == 0, rc, GSN_ERR_IO,
                   fail, "cannot replace %s", r->history_path);
    /* Stopped by a signal at what is now the last step: its final frame. */
    if (e->step == r->total_steps && !was_complete &&
        last_frame_step != (int)e->step)
        rc = write_output(r, 1);
    /* Stopped for want of room before the frame (and row) of its step:
     * written now, as the run would have */
    else if (frame_due_at_checkpoint(r) && last_frame_step != (int)e->step) {
        rc = write_output(r, e->step == r->total_steps);
        if (rc == GSN_OK)
            rc = set_frame_due(r, 0);
        schedule_outputs(r);
    }
fail:
    fclose(old);
    return rc;
}

static void run_free(struct run *r)
{
    gsn_reference_destroy(&r->reference);
    gsn_material_set_destroy(&r->materials);
    gsn_model_free(&r->model);
    gsn_frame_free(&r->frame);
    for (int b = 0; b < GSN_MAX_BOUNDARIES; ++b)
        free(r->boundary[b].particle);
    if (r->history)
        fclose(r->history);
    gsn_h5_close(&r->results);
}

/* The pre signature (gsn_case_pre_signature) with the geometry's folder
 * left out, so that a project moved elsewhere still matches its model. */
static void signature_without_folder(const char *signature, char *out,
                                     size_t size)
{
    static const char key[] = "geometry=";
    const char *end = strchr(signature, ';');
    const char *name = signature + sizeof key - 1;
    for (const char *c = name; end && c < end; ++c)
        if (*c == '/')
            name = c + 1;
    size_t used = 0;
    if (strncmp(signature, key, sizeof key - 1) != 0 || !end)
        name = signature;
    else
        for (const char *c = key; *c && used + 1 < size; ++c)
            out[used++] = *c;
    for (const char *c = name; *c && used + 1 < size; ++c)
        out[used++] = *c;
    out[used] = '\0';
}

/* model.h5 must have been made by pre from this case's geometry, spacing,
 * facet points and refinements (a model made without pre, by a test, has
 * no signature and is taken as it is). */
static int check_model_source(const struct run *r)
{
    char wanted[GSN_PRE_SIGNATURE_SIZE], a[GSN_PRE_SIGNATURE_SIZE];
    char b[GSN_PRE_SIGNATURE_SIZE];
    GSN_CALL(gsn_case_pre_signature(r->c, wanted, sizeof wanted));
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(r->model_path, GSN_FILE_KIND_MODEL, 0, &file));
    char *stored = NULL;
    int rc = GSN_OK;
    if (H5Aexists(file, GSN_ATTR_PRE_SIGNATURE) > 0)
        rc = gsn_h5_attr_read_string(file, GSN_ATTR_PRE_SIGNATURE, &stored);
    gsn_h5_close(&file);
    if (rc == GSN_OK && stored) {
        signature_without_folder(stored, a, sizeof a);
        signature_without_folder(wanted, b, sizeof b);
        if (strcmp(a, b) != 0)
            rc = gsn_error_raise(
                GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                "%s: %s was made by pre from other inputs (%s), not from "
                "this case's (%s): run 'geoscni pre %s -o %s' first, or "
                "'geoscni run', which does",
                r->c->path, r->model_path, a, b, r->c->path, r->outdir);
    }
    free(stored);
    return rc;
}

/* The frames the run will write (run_loop's schedule: t = 0, the steps
 * nearest the frame times before the end, the last step) and the bytes of
 * one in results.h5. */
static long planned_frames(const struct run *r, double *frame_bytes)
{
    const struct gsn_explicit *e = r->reference->loop;
    const struct gsn_case *c = r->c;
    unsigned present = c->output_fields | (1u << GSN_FRAME_DISPLACEMENT) |
                       (1u << GSN_FRAME_DAMAGE);
    int columns = 0;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        if (present & (1u << f))
            columns += gsn_frame_fields[f].columns;
    *frame_bytes = 8.0 * columns * (double)r->model.particle_count;
    long frames = 2, step = 0;
    for (;;) {
        double next = next_frame_time(c, (double)step * e->dt, e->dt);
        if (!(next < c->time_end - 0.5 * e->dt))
            break;
        /* the first later step that serves it, in run_loop's arithmetic */
        long k = (long)floor((next - 0.5 * e->dt) / e->dt);
        if (k <= step)
            k = step + 1;
        while (!time_served(next, (double)k * e->dt, e->dt))
            ++k;
        step = k;
        frames++;
    }
    return frames;
}

/* The body's extent along gravity (with_gravity and gravity given), or its
 * largest extent along the axes, m. */
static double body_height(const struct run *r, int with_gravity)
{
    const struct gsn_case *c = r->c;
    const struct gsn_model *m = &r->model;
    double g =
        sqrt(c->gravity[0] * c->gravity[0] + c->gravity[1] * c->gravity[1] +
             c->gravity[2] * c->gravity[2]);
    int gravity = with_gravity && g > 0.0;
    double height = 0.0;
    for (int axis = gravity ? -1 : 0; axis < (gravity ? 0 : 3); ++axis) {
        double low = INFINITY, high = -INFINITY;
        for (int i = 0; i < m->particle_count; ++i) {
            const double *x = &m->position[3 * i];
            double along = axis >= 0
                               ? x[axis]
                               : (x[0] * c->gravity[0] + x[1] * c->gravity[1] +
                                  x[2] * c->gravity[2]) /
                                     g;
            low = fmin(low, along);
            high = fmax(high, along);
        }
        height = fmax(height, high - low);
    }
    return height;
}

static int any_damage(const struct gsn_case *c)
{
    int damage = 0;
    for (int k = 0; k < c->material_count; ++k)
        damage |= c->materials[k].has_damage;
    return damage;
}

/* A warning for gravity or tractions applied at full value at t = 0, with
 * a ramp to suggest: SUDDEN_LOAD_PERIODS periods of the body's lowest mode,
 * taken as a layer of height H on a fixed base, 4 H / c_s (H the body's
 * extent along gravity, or its largest extent for tractions alone). */
static void warn_sudden_load(const struct run *r, int gravity, int traction)
{
    const struct gsn_case *c = r->c;
    double height = body_height(r, gravity);
    double period = 4.0 * height / gsn_case_slowest_wave(c, 1);
    double ramp = SUDDEN_LOAD_PERIODS * period;
    double unit = pow(10.0, floor(log10(ramp))); /* one significant digit up */
    ramp = ceil(ramp / unit) * unit;
    char end[96] = "";
    if (ramp > c->time_end)
        snprintf(end, sizeof end, " (and time.end %g s at least)", ramp);
    fprintf(stderr,
            "warning: %s: %s applied at full value at t = 0 (time.ramp is "
            "0): a sudden load makes the body oscillate about its static "
            "deformation, up to twice it%s; 'time: {ramp: %g}'%s raises the "
            "loads smoothly over %g periods of the body's lowest mode (4 H / "
            "c_s = %.2g s with H = %.3g m), and prescribed velocities with "
            "them\n",
            c->path,
            gravity && traction ? "gravity and tractions are"
            : gravity           ? "gravity is"
                                : "tractions are",
            any_damage(c)
                ? ", and damage, which counts every oscillation, grows"
                : "",
            ramp, end, SUDDEN_LOAD_PERIODS, period, height);
}

/* The dead loads: each traction added to f_ext (its resultant kept for
 * history.csv), and f_ext kept at full value to be ramped with time.ramp
 * (apply_loads); warnings for a case that nothing loads and for loads
 * applied at once. */
static int setup_loads(struct run *r)
{
    const struct gsn_case *c = r->c;
    int traction = 0;
    for (int b = 0; b < c->boundary_count; ++b) {
        const struct gsn_boundary *entry = &c->boundaries[b];
        for (int k = 0; k < 3; ++k) {
            r->loading |= entry->has_velocity[k] && entry->velocity[k] != 0.0;
            traction |= entry->traction[k] != 0.0;
        }
    }
    traction_resultants(r);
    int gravity =
        c->gravity[0] != 0.0 || c->gravity[1] != 0.0 || c->gravity[2] != 0.0;
    if (!r->loading && !traction && !gravity)
        fprintf(stderr,
                "warning: %s: nothing loads the body (no gravity, no nonzero "
                "velocity or traction on a boundary): it stays at rest\n",
                c->path);
    if (!gravity && !traction)
        return GSN_OK;
    if (!(c->time_ramp > 0.0) && !c->geostatic) {
        warn_sudden_load(r, gravity, traction);
        return GSN_OK;
    }
    apply_loads(r, 0.0);
    GSN_CALL(gsn_explicit_refresh(r->reference->loop));
    return GSN_OK;
}

/* The integration as the messages name it: "scni", "scni + nsni", ... */
static const char *method_text(const struct gsn_case *c, char *text,
                               size_t size)
{
    snprintf(text, size, "%s%s%s", gsn_integration_name(c->integration),
             c->stabilization != GSN_STABILIZATION_NONE ? " + " : "",
             c->stabilization != GSN_STABILIZATION_NONE
                 ? gsn_stabilization_name(c->stabilization)
                 : "");
    return text;
}

/* The solve's peak memory (bytes), before it allocates: a fit to the peak
 * resident size of 8 bodies (402 to 52,054 particles, slabs, slopes, a box;
 * docs/solver.md, "Memory"; within 7% with SCNI): 80 MB, per particle
 * 3.5 KB with SCNI or DNI, 8.4 KB with NSNI, 26.5 KB with MSCNI, or per
 * Gauss point 2.5 KB; and the exact boundary values' matrices, 24 bytes per
 * entry of S_c = C M^-1 C^T (two copies) and 20 per value of its
 * supernodal Cholesky factor (CHOLMOD's, the copy the steps read, and
 * their row lists), both counted on their pattern
 * (gsn_constraints_size_estimate): a slab whose faces are all held has
 * most of its memory there. The rows of the shape functions grow with the
 * support's volume (and, taken as twice, with the quadratic basis). Of the
 * first reference: an update holds two at once (check_memory). */
/* The kernels that cover each particle, summed over the particles: the
 * length of the shape-function rows at the particles, which the smoothed
 * gradients' rows follow (a thin slab has more of them per particle than
 * a body of the same spacing); *entries with the case's window cut,
 * *whole with the whole window. */
static int kernel_entries(const struct gsn_case *c, const struct gsn_model *m,
                          double *entries, double *whole)
{
    int n = m->particle_count;
    double *spacing = malloc(sizeof(double) * ((size_t)n + 1));
    struct gsn_rk *rk = NULL;
    int rc = GSN_OK;
    GSN_CHECK_GOTO(spacing, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CALL_GOTO(gsn_rk_spacing_from_facets(m, 0.0, spacing), rc, done);
    GSN_CALL_GOTO(
        gsn_rk_create(n, m->position, spacing, c->kernel_support, 1, &rk), rc,
        done);
    rk->window_cut = c->kernel_window_cut;
    const struct gsn_rk uncut = gsn_rk_whole_window(rk);
    const int cut = rk->window_cut > 0.0;
    double sum = 0.0, sum_whole = 0.0;
#pragma omp parallel for reduction(+ : sum, sum_whole) schedule(static)
    for (int i = 0; i < n; ++i) {
        const double *x = m->position + 3 * (size_t)i;
        sum += gsn_rk_neighbours(rk, x, 0, NULL);
        if (cut)
            sum_whole += gsn_rk_neighbours(&uncut, x, 0, NULL);
    }
    *entries = sum;
    *whole = cut ? sum_whole : sum;
done:
    gsn_rk_destroy(&rk);
    free(spacing);
    return rc;
}

static int memory_estimate(const struct gsn_case *c, const struct gsn_model *m,
                           double *bytes)
{
    double row_entries = 0.0, whole_entries = 0.0;
    GSN_CALL(kernel_entries(c, m, &row_entries, &whole_entries));
    double points = 0.0, per_point = 3.5e3;
    if (c->integration == GSN_INTEGRATION_GAUSS) {
        points = (double)m->tetrahedron_count * c->gauss_points *
                 c->gauss_points * c->gauss_points;
        per_point = 2.5e3;
    } else {
        points = m->particle_count;
        if (c->stabilization == GSN_STABILIZATION_NSNI)
            per_point = 8.4e3;
        else if (c->stabilization == GSN_STABILIZATION_MSCNI)
            per_point = 26.5e3;
    }
    double entries[3], factor_entries[3], held = 0.0;
    GSN_CALL(gsn_constraints_size_estimate(m, c, entries, factor_entries));
    for (int k = 0; k < 3; ++k)
        held += 24.0 * entries[k] + 20.0 * factor_entries[k];
    double support = c->kernel_support / 1.5;
    double scale = fmax(1.0, support * support * support) *
                   (c->kernel_basis_order == 2 ? 2.0 : 1.0);
    /* while the rows are built, the facet points' rows of Psi_I (an index,
     * a value and a gradient, 36 B an entry, as long as a particle's) are
     * held at once beside the model: the peak of bodies whose boundary
     * matrices are small (the deep-penetration slab: 46 MB of 48 MB of
     * heap, heaptrack 2026-12-03) */
    double facet_points = m->facet_point_offset[m->facet_count];
    double building = facet_points * row_entries /
                          fmax(1.0, (double)m->particle_count) * 36.0 * scale +
                      700.0 * m->particle_count;
    /* per_point was measured with the whole window; the window cut
     * shortens the rows, which hold most of it (Slope I at 1e-3: 0.63 of
     * the entries, 0.72 (SCNI) and 0.66 (NSNI) of the memory above the
     * base) */
    double cut = 0.2 + 0.8 * row_entries / fmax(1.0, whole_entries);
    double running = points * per_point * scale * cut + held;
    /* nonlocal damage: each particle's ball of the longest damage.length
     * (nonlocal.h), 12 bytes a neighbour */
    double length = 0.0, balls = 0.0;
    for (int k = 0; k < c->material_count; ++k)
        if (c->materials[k].has_damage)
            length = fmax(length, c->materials[k].damage_length);
    for (int p = 0; length > 0.0 && p < m->particle_count; ++p)
        balls += fmin((double)m->particle_count,
                      4.18879 * length * length * length / m->volume[p]);
    running += gsn_nonlocal_bytes(m->particle_count, balls);
    *bytes = 80e6 + fmax(building, running);
    return GSN_OK;
}

/* States the memory need and refuses a case that would not fit. */
static int check_memory(const struct run *r)
{
    const char *source = NULL;
    char method[64];
    double first = 0.0;
    GSN_CALL(memory_estimate(r->c, &r->model, &first));
    /* an update holds two discretizations at once (1.93 times measured) */
    double need = r->c->reference_update ? 2.0 * first : first;
    double available = gsn_memory_available(&source);
    if (!r->options->quiet && need > first)
        printf("solver: about %.0f MB of memory needed, %.0f MB while the "
               "reference is updated (%.0f MB available: %s)\n",
               first / 1e6, need / 1e6, available / 1e6, source);
    else if (!r->options->quiet)
        printf("solver: about %.0f MB of memory needed (%.0f MB available: "
               "%s)\n",
               need / 1e6, available / 1e6, source);
    GSN_CHECK(available <= 0.0 || need <= available || r->options->force,
              GSN_ERR_INPUT,
              "%s: this case needs about %.0f MB of memory (%d particles, "
              "%s%s), but %.0f MB are available (%s): use a larger "
              "particles.spacing or a cheaper integration, free memory, or "
              "--force to try anyway",
              r->c->path, need / 1e6, r->model.particle_count,
              method_text(r->c, method, sizeof method),
              r->c->reference_update ? ", reference updates" : "",
              available / 1e6, source);
    return GSN_OK;
}

/* Whether the reference follows the body, and what triggers an update
 * (docs/solver.md, "Reference-configuration updates"). */
static void print_update_setting(const struct gsn_case *c)
{
    const char *given = c->reference_update_line ? "" : ", the default";
    if (c->small_strain || c->integration == GSN_INTEGRATION_GAUSS)
        return;
    if (!c->reference_update) {
        printf("reference updates: off%s%s\n", given,
               c->reference_update_line ? ""
               : c->stabilization == GSN_STABILIZATION_MSCNI
                   ? " with MSCNI (its sub-cells stiffen under plastic flow "
                     "on an updated reference)"
                   : " with damage (it sums |d eps|, and with it the noise "
                     "of each new discretization)");
        return;
    }
    printf("reference updates: on%s: when a particle's |E| since the last "
           "passes %g or det F leaves [%g, %g]",
           given, c->reference_strain, c->reference_volume[0],
           c->reference_volume[1]);
    if (c->reference_every > 0.0)
        printf(", or every %g s", c->reference_every);
    printf(", %d steps apart at least ('reference_update: off' keeps the "
           "first reference)\n",
           c->reference_min_steps);
}

/* The soils on the particles and the water's pore pressure, a line each
 * (docs/site.md). */
static void print_site(const struct run *r)
{
    const struct gsn_case *c = r->c;
    const struct gsn_material_set *set = r->materials;
    if (c->materials_by_volume) {
        printf("soils:");
        for (int k = 0; k < set->case_count; ++k) {
            int count = 0; /* an interface soil is its majority's volume */
            for (int i = 0; i < set->particle_count; ++i)
                count += !strcmp(set->soil[set->particle_material[i]].volume,
                                 c->materials[k].volume);
            printf("%s %s %d particles", k ? "," : "", c->materials[k].volume,
                   count);
        }
        if (set->interface_count > 0)
            printf("; %d on interfaces carry the weaker soil's strength",
                   set->interface_count);
        printf("\n");
    }
    if (c->water.present) {
        double largest = 0.0;
        for (int i = 0; i < r->model.particle_count; ++i)
            largest =
                fmax(largest,
                     gsn_water_pressure(c, &r->model.position[3 * (size_t)i]));
        printf("water: %s, gamma_w %.4g kN/m^3: pore pressure up to %.4g kPa "
               "(the material sees the effective stress)\n",
               c->water.point_count == 1 ? "a level table"
               : c->water.triangle_count ? "a table spread over the site"
                                         : "a section's table",
               1e-3 * c->water.unit_weight, 1e-3 * largest);
    }
    const struct gsn_nonlocal *nl = r->reference->loop->nonlocal;
    if (nl) {
        double length = 0.0;
        for (int k = 0; k < set->count; ++k)
            length = fmax(length, set->parameters[k]->damage_length);
        double mean = (double)nl->offset[nl->point_count] / nl->point_count;
        printf("damage: nonlocal, e_t averaged over %.4g m: %.0f points a "
               "ball on average, %d at most%s\n",
               length, mean, nl->max_row,
               mean < 8.0 ? " (fewer than 8: the law is nearly local at this "
                            "spacing; refine, or give a longer length)"
                          : "");
    }
}

static int run_setup(struct run *r)
{
    const struct gsn_case *c = r->c;
    double t0 = now_seconds();
    GSN_CHECK(access(r->model_path, R_OK) == 0, GSN_ERR_INPUT,
              "%s: not found; run 'geoscni pre %s -o OUTDIR' first",
              r->model_path, c->path);
    GSN_CALL(check_model_source(r));
    GSN_CALL(gsn_model_read(r->model_path, &r->model));
    GSN_CALL(check_memory(r));
    r->frame_bytes = 320.0 * r->model.particle_count; /* 40 doubles each */
    GSN_CALL(build_boundary_sets(r));
    GSN_CALL(gsn_material_set_create(c, &r->model, &r->materials));
    GSN_CALL(gsn_reference_create(&r->model, c, r->materials, c->time_step,
                                  r->options->threads, &r->reference));
    GSN_CALL(setup_loads(r));
    const struct gsn_material_ops *ops = r->materials->model[0]->ops;
    r->damage_offset = gsn_material_state_offset(ops, "damage");
    r->plastic_offset =
        gsn_material_state_offset(ops, "equivalent_plastic_strain");
    GSN_CALL(gsn_frame_allocate(&r->frame, r->model.particle_count));
    GSN_CALL(choose_time_step(r));
    char method[64];
    if (!r->options->quiet)
        printf("solver: %d particles (gmsh's %s mesh), %d integration "
               "points, %s, %.1f MB of shape functions, set up in %.2f s, "
               "%ld steps\n",
               r->model.particle_count, gsn_mesher_name(c->mesher),
               r->reference->quadrature->point_count,
               method_text(c, method, sizeof method),
               gsn_quadrature_bytes(r->reference->quadrature) / 1e6,
               now_seconds() - t0, r->total_steps);
    if (!r->options->quiet && !r->options->setup_warned) {
        print_update_setting(c);
        print_site(r);
    }
    if (r->reference->quadrature->held_fallback_count > 0 &&
        !r->options->setup_warned)
        fprintf(stderr,
                "warning: %d of %d quadrature points on held surfaces keep "
                "Psi_I: the held particles near them do not span them (a "
                "held surface one particle wide?); the patch test is not "
                "exact there (docs/solver.md, \"Boundary values\")\n",
                r->reference->quadrature->held_fallback_count,
                r->reference->quadrature->held_point_count +
                    r->reference->quadrature->held_fallback_count);
    double frame_bytes = 0.0;
    long frames = planned_frames(r, &frame_bytes);
    if (!r->options->quiet)
        printf("output: %ld frames of %.3g MB\n", frames, frame_bytes / 1e6);
    fflush(stdout); /* before the progress and any error, on stderr */
    if ((double)frames * frame_bytes > LARGE_OUTPUT_BYTES)
        fprintf(stderr,
                "warning: %s: %ld frames of %.3g MB make %.3g GB of results "
                "(and about as much in the .vtu files); a larger "
                "output.every writes fewer\n",
                c->path, frames, frame_bytes / 1e6,
                (double)frames * frame_bytes / 1e9);
    return GSN_OK;
}

/* The quasi-static check of a loading run: the largest KE / W_int, stored
 * in results.h5 and printed, with a warning above QUASI_STATIC_RATIO. */
static int report_quasi_static(struct run *r)
{
    if (!r->loading)
        return GSN_OK;
    GSN_CALL(gsn_h5_attr_write_double(
        r->results, GSN_RESULTS_ATTR_KINETIC_RATIO, r->kinetic_ratio));
    if (r->kinetic_ratio > QUASI_STATIC_RATIO)
        fprintf(stderr,
                "warning: the load was not quasi-static: the kinetic energy "
                "reached %.3g%% of the internal energy at t = %.4g s (limit "
                "%g%%) in %s; a sudden failure does this; otherwise slow "
                "the load (a smaller velocity or a longer time.ramp) or %s "
                "damping.local\n",
                100.0 * r->kinetic_ratio, r->kinetic_ratio_time,
                100.0 * QUASI_STATIC_RATIO, r->c->path,
                r->c->damping_local > 0.0 ? "raise" : "add");
    else if (!r->options->quiet)
        printf("quasi-static: the kinetic energy stayed below %.3g%% of the "
               "internal energy (largest at t = %.4g s)\n",
               100.0 * r->kinetic_ratio, r->kinetic_ratio_time);
    return GSN_OK;
}

static int write_geostatic_attributes(struct run *r)
{
    GSN_CALL(gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_GEOSTATIC_STEPS,
                                   (int)r->geostatic_steps));
    GSN_CALL(gsn_h5_attr_write_double(r->results,
                                      GSN_RESULTS_ATTR_GEOSTATIC_RESIDUAL,
                                      r->geostatic_residual));
    GSN_CALL(gsn_h5_attr_write_double(
        r->results, GSN_RESULTS_ATTR_GEOSTATIC_SECONDS, r->geostatic_seconds));
    GSN_CALL(gsn_h5_attr_write_double(r->results,
                                      GSN_RESULTS_ATTR_GEOSTATIC_DISPLACEMENT,
                                      r->geostatic_displacement));
    GSN_CALL(gsn_h5_attr_write_int(
        r->results, GSN_RESULTS_ATTR_GEOSTATIC_RESTED, r->geostatic_rested));
    return GSN_OK;
}

/* The unbalanced force of the body over its load, |M a| / |f_ext|, with a
 * = M^-1 (f_ext - f_int) projected onto the constraints (the supports'
 * reaction included, the local damping not: the loop's damping acts on the
 * force before the reaction, so near held faces it does not vanish at
 * rest), over the components the loop moves, with the constraints it
 * imposes now; work: 3 n doubles. */
static int unbalanced_force(const struct run *r, double *work, double *residual)
{
    const struct gsn_explicit *e = r->reference->loop;
    size_t n3 = 3 * (size_t)e->particle_count;
    for (size_t at = 0; at < n3; ++at)
        work[at] = (int)(at % 3) == e->held_axis
                       ? 0.0
                       : (e->f_ext[at] - e->f_int[at]) / e->mass[at / 3];
    if (e->constraints)
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &r->reference->quadrature->particle_values,
            GSN_FIELD_ACCELERATION, e->time, work, NULL));
    double unbalanced = 0.0, load = 0.0;
    for (size_t at = 0; at < n3; ++at) {
        double f = e->mass[at / 3] * work[at];
        unbalanced += f * f;
        load += e->f_ext[at] * e->f_ext[at];
    }
    *residual = load > 0.0 ? sqrt(unbalanced / load) : 0.0;
    return GSN_OK;
}

/* geostatic.k0: the stress of the soil's weight set at every point before
 * the stage: sigma_v the weight of the column above (gsn_overburden:
 * layers, the water table's saturated densities, slopes), the effective
 * sigma'_v = sigma_v + u, sigma'_h = K0 sigma'_v (compression negative),
 * and the material state set from it; the stage then starts with the dead
 * loads at full value. */
static int set_level_ground_stress(struct run *r)
{
    const struct gsn_case *c = r->c;
    struct gsn_explicit *e = r->reference->loop;
    const struct gsn_quadrature *q = r->reference->quadrature;
    double g =
        sqrt(c->gravity[0] * c->gravity[0] + c->gravity[1] * c->gravity[1] +
             c->gravity[2] * c->gravity[2]);
    GSN_CHECK(g > 0.0, GSN_ERR_INPUT,
              "%s:%d: 'geostatic.k0' sets the stresses of the soil's weight: "
              "give gravity",
              c->path, c->geostatic_line);
    double down[3] = {c->gravity[0] / g, c->gravity[1] / g, c->gravity[2] / g};
    double *vertical = malloc(sizeof(double) * ((size_t)q->point_count + 1));
    GSN_CHECK(vertical, GSN_ERR_MEMORY, "out of memory");
    int rc = gsn_overburden(&r->model, c, q->point_count, q->point_position,
                            vertical);
    for (int p = 0; rc == GSN_OK && p < q->point_count; ++p) {
        double v = vertical[p] +
                   gsn_water_pressure(c, &q->point_position[3 * (size_t)p]);
        double h = c->geostatic_k0 * v;
        /* h (I - n n) + v n n, Voigt xx yy zz xy yz xz */
        static const int row[6] = {0, 1, 2, 0, 1, 0},
                         col[6] = {0, 1, 2, 1, 2, 2};
        for (int a = 0; a < 6; ++a)
            e->stress[6 * (size_t)p + a] =
                (row[a] == col[a] ? h : 0.0) +
                (v - h) * down[row[a]] * down[col[a]];
    }
    free(vertical);
    GSN_CALL(rc);
    GSN_CALL(gsn_explicit_initialize_material(e));
    GSN_CALL(gsn_explicit_refresh(e));
    return GSN_OK;
}

/* The largest displacement at a particle, m; work: 3 n doubles. */
static double largest_displacement(const struct gsn_explicit *e, double *work)
{
    gsn_explicit_particle_displacement(e, work);
    double largest = 0.0;
    for (int i = 0; i < e->particle_count; ++i) {
        const double *u = work + 3 * (size_t)i;
        largest = fmax(largest, sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    }
    return largest;
}

/* A body that does not settle: measured over windows of
 * MECHANISM_WINDOW_TRANSITS transits of a pressure wave, the unbalanced
 * force fell by less than a tenth and the largest displacement grew at
 * least as fast as in the window before, MECHANISM_WINDOWS windows in a row
 * (docs/solver.md, "The soil's own weight"). A body settling under strong
 * damping slows down; a mechanism keeps its unbalanced force and speeds up. */
enum { MECHANISM_WINDOW_TRANSITS = 5, MECHANISM_WINDOWS = 3 };
/* ... or that moved more than this share of its height along gravity:
 * what held it then is not the soil's strength (the NSNI stabilization's
 * elastic part held Griffiths & Lane's slope after 16 m; docs/fos.md) */
#define MECHANISM_MOVE 0.1

struct mechanism_watch {
    double residual, displacement, growth; /* at the last window's end */
    int windows;                           /* in a row so far */
};

static int mechanism_found(struct mechanism_watch *w, double residual,
                           double displacement)
{
    double growth = displacement - w->displacement;
    int moving = residual > 0.9 * w->residual && w->growth > 0.0 &&
                 growth >= 0.98 * w->growth;
    w->windows = moving ? w->windows + 1 : 0;
    w->residual = residual;
    w->displacement = displacement;
    w->growth = growth;
    return w->windows >= MECHANISM_WINDOWS;
}

/* The geostatic stage (docs/solver.md, "The soil's own weight"): the dead
 * loads raised smoothly over four transits of a pressure wave across the
 * body, then the body relaxed with strong local damping, the surfaces
 * that will move free (only the fixed components held), until the
 * unbalanced force falls to geostatic.residual of the load. It fails (exit
 * 3) when the step budget runs out or the body moves as a mechanism
 * (mechanism_found). */
static int geostatic_stage(struct run *r)
{
    const struct gsn_case *c = r->c;
    struct gsn_explicit *e = r->reference->loop;
    double started = now_seconds(), last_print = started;
    double damping = e->damping_local, run_step = e->dt, residual = INFINITY;
    long step = 0, ramp = 0, window = 0;
    int rc = GSN_OK, mechanism = 0;
    double move_limit = MECHANISM_MOVE * body_height(r, 1);
    struct mechanism_watch watch = {INFINITY, 0.0, 0.0, 0};
    double *work = malloc(3 * sizeof(double) * ((size_t)e->particle_count + 1));
    /* the surfaces that will move are free while the body settles: the
     * constraints of the fixed components alone */
    struct gsn_case *fixed_only = malloc(sizeof *fixed_only);
    struct gsn_constraints *stage = NULL;
    GSN_CHECK_GOTO(work && fixed_only, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    *fixed_only = *c;
    for (int b = 0; b < fixed_only->boundary_count; ++b)
        for (int k = 0; k < 3; ++k) {
            fixed_only->boundaries[b].has_velocity[k] = 0;
            fixed_only->boundaries[b].velocity[k] = 0.0;
        }
    GSN_CALL_GOTO(gsn_constraints_create(
                      r->reference->model, fixed_only,
                      &r->reference->quadrature->particle_values, NULL, &stage),
                  rc, done);
    GSN_CALL_GOTO(gsn_constraints_set_mass(stage, e->mass), rc, done);
    gsn_explicit_set_constraints(e, stage);
    e->damping_local = c->geostatic_damping;
    e->damping_net = 1;
    /* The stage's own step: its fewer constraints and strong damping
     * lower the stable step (explicit.h); never above the run's. */
    double stable = 0.0;
    GSN_CALL_GOTO(gsn_explicit_stable_step(e, &stable), rc, done);
    gsn_explicit_set_time_step(e, fmin(run_step, c->time_step_safety * stable));
    double extent = body_height(r, 0); /* the largest along the axes */
    double wave = gsn_case_slowest_wave(c, 0);
    long transit = (long)ceil(extent / (wave * e->dt));
    ramp = 4 * transit < 50 ? 50 : 4 * transit;
    window = MECHANISM_WINDOW_TRANSITS * transit;
    if (window < 50)
        window = 50;
    if (c->geostatic_k0 > 0.0) {
        GSN_CALL_GOTO(set_level_ground_stress(r), rc, done);
        ramp = 0; /* the stress is there: the loads too */
    }
    while (step < c->geostatic_max_steps) {
        GSN_CHECK_GOTO(!stop_signal, rc, GSN_ERR_INTERRUPTED, done,
                       "%s during the geostatic stage (step %ld): nothing "
                       "was written; solve again from the start",
                       stopped_by(stop_signal), step);
        double pi = acos(-1.0);
        gsn_explicit_set_load_factor(
            e, step < ramp ? 0.5 * (1.0 - cos(pi * (step + 1) / ramp)) : 1.0);
        GSN_CALL_GOTO(gsn_explicit_step(e), rc, done);
        ++step;
        if (step >= ramp && step % 10 == 0) {
            GSN_CALL_GOTO(unbalanced_force(r, work, &residual), rc, done);
            if (residual <= c->geostatic_residual)
                break;
        }
        if (step > ramp && (step - ramp) % window == 0) {
            GSN_CALL_GOTO(unbalanced_force(r, work, &residual), rc, done);
            double moved = largest_displacement(e, work);
            mechanism =
                mechanism_found(&watch, residual, moved) || moved > move_limit;
            if (mechanism)
                break;
        }
        if (!r->options->quiet && now_seconds() - last_print >= 10.0) {
            fprintf(stderr,
                    "geostatic: step %ld, unbalanced force %.3g of the load "
                    "(to reach %.3g)\n",
                    step, residual, c->geostatic_residual);
            last_print = now_seconds();
        }
    }
    if (!(residual <= c->geostatic_residual) && !mechanism)
        GSN_CALL_GOTO(unbalanced_force(r, work, &residual), rc, done);
    r->geostatic_steps = step;
    r->geostatic_residual = residual;
    r->geostatic_seconds = now_seconds() - started;
    r->geostatic_displacement = largest_displacement(e, work);
    GSN_CHECK_GOTO(
        r->geostatic_displacement <= move_limit, rc, GSN_ERR_NUMERICAL, done,
        "%s: the body moved %.3g m under its dead loads by step %ld, more "
        "than a tenth of its height (%.3g m): a mechanism, whatever held it "
        "after (a factor of safety below 1)",
        c->path, r->geostatic_displacement, step, body_height(r, 1));
    r->geostatic_rested = residual <= c->geostatic_residual;
    GSN_CHECK_GOTO(
        !mechanism, rc, GSN_ERR_NUMERICAL, done,
        "%s: the body does not come to rest under its dead loads: over the "
        "last %ld steps its unbalanced force stayed near %.3g of the load and "
        "its displacements grew ever faster (%.3g m at step %ld): a mechanism "
        "(a factor of safety below 1)",
        c->path, MECHANISM_WINDOWS * window, residual,
        r->geostatic_displacement, step);
    GSN_CHECK_GOTO(
        r->geostatic_rested, rc, GSN_ERR_NUMERICAL, done,
        "%s: the body found no rest under its dead loads within %ld steps "
        "(geostatic.max_steps): the unbalanced force is still %.3g of the "
        "load (geostatic.residual %.3g); it may not stand (a factor of "
        "safety below 1), or it needs more steps",
        c->path, step, residual, c->geostatic_residual);
    if (!r->options->quiet) {
        char how[96];
        if (c->geostatic_k0 > 0.0)
            snprintf(how, sizeof how,
                     "the stresses of level ground set "
                     "first, K0 = %g",
                     c->geostatic_k0);
        else
            snprintf(how, sizeof how, "the dead loads raised over %ld", ramp);
        printf("geostatic: at rest after %ld steps of %.3g s (%s): "
               "unbalanced force %.3g of the load (limit %.3g), largest "
               "displacement %.3g m, %.1f s%s\n",
               step, e->dt, how, residual, c->geostatic_residual,
               r->geostatic_displacement, r->geostatic_seconds,
               r->options->geostatic_only
                   ? ""
                   : "; the loading starts from this state with zero "
                     "displacements");
    }
done:
    gsn_explicit_set_constraints(e, r->reference->constraints);
    gsn_explicit_set_time_step(e, run_step);
    gsn_constraints_destroy(&stage);
    free(fixed_only);
    free(work);
    e->damping_local = damping;
    e->damping_net = 0;
    return rc;
}

/* The loading stage after a geostatic one starts from its stress and
 * material state with d = v = a = 0, at t = 0, its energies at zero. */
static void start_loading_stage(struct gsn_explicit *e)
{
    size_t n3 = 3 * (size_t)e->particle_count;
    memset(e->displacement, 0, n3 * sizeof(double));
    memset(e->previous_displacement, 0, n3 * sizeof(double));
    memset(e->velocity, 0, n3 * sizeof(double));
    memset(e->acceleration, 0, n3 * sizeof(double));
    e->kinetic_energy = e->internal_energy = e->external_work = 0.0;
    e->damping_work = 0.0;
    e->step = e->step_base = 0;
    e->time = e->time_base = 0.0;
}

/* A geostatic stage that found no rest keeps the state it reached: results.h5
 * with that state as its one frame (the stage's time and step, its
 * displacements: the mechanism), not complete, and the stage's numbers. */
static int keep_failed_stage(struct run *r)
{
    char failure[1024]; /* a copy: writing may raise over the message */
    snprintf(failure, sizeof failure, "%s", gsn_error_message());
    gsn_error_clear();
    GSN_CALL(open_outputs(r));
    GSN_CALL(write_geostatic_attributes(r));
    return gsn_error_raise(GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
                           "in the geostatic stage: %s; the state it reached "
                           "is the one frame of %s (its displacements show "
                           "the mechanism)",
                           failure, r->results_path);
}

/* The geostatic stage alone (gsn_solve_options.geostatic_only), at rest:
 * results.h5 complete with its end state as the one frame. */
static int keep_stage_alone(struct run *r)
{
    GSN_CALL(open_outputs(r));
    GSN_CALL(write_geostatic_attributes(r));
    GSN_CALL(gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_COMPLETE, 1));
    return GSN_OK;
}

int gsn_solve_run(const struct gsn_case *c, const char *outdir,
                  const struct gsn_solve_options *options)
{
    struct run *r = calloc(1, sizeof *r);
    GSN_CHECK(r, GSN_ERR_MEMORY, "out of memory");
    r->c = c;
    r->options = options;
    r->outdir = outdir;
    r->results = H5I_INVALID_HID;
    if (options->threads > 0)
        omp_set_num_threads(options->threads);
    int rc = GSN_OK;
    GSN_CALL_GOTO(gsn_folder_prepare(outdir), rc, done);
    GSN_CALL_GOTO(
        gsn_path_join(r->model_path, sizeof r->model_path, outdir, "model.h5"),
        rc, done);
    GSN_CALL_GOTO(gsn_path_join(r->results_path, sizeof r->results_path, outdir,
                                "results.h5"),
                  rc, done);
    GSN_CALL_GOTO(gsn_path_temporary(r->results_temporary,
                                     sizeof r->results_temporary,
                                     r->results_path),
                  rc, done);
    GSN_CALL_GOTO(gsn_path_join(r->history_path, sizeof r->history_path, outdir,
                                "history.csv"),
                  rc, done);
    gsn_case_name(c->path, r->case_name, sizeof r->case_name);
    GSN_CHECK_GOTO(!options->geostatic_only ||
                       (c->geostatic && !options->restart),
                   rc, GSN_ERR_INPUT, done,
                   "%s: the geostatic stage alone needs the case's geostatic "
                   "key and a fresh run",
                   c->path);
    GSN_CALL_GOTO(run_setup(r), rc, done);
    struct sigaction previous[2];
    catch_stop_signals(1, previous);
    if (c->geostatic && !options->restart)
        rc = geostatic_stage(r);
    if (rc == GSN_ERR_NUMERICAL) {
        rc = keep_failed_stage(r);
        catch_stop_signals(0, previous);
        goto done;
    }
    if (rc == GSN_OK && options->geostatic_only) {
        rc = keep_stage_alone(r);
        catch_stop_signals(0, previous);
        goto done;
    }
    if (rc == GSN_OK && c->geostatic && !options->restart)
        start_loading_stage(r->reference->loop);
    if (rc == GSN_OK)
        rc = open_outputs(r);
    if (rc == GSN_OK)
        rc = gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_COMPLETE, 0);
    if (rc == GSN_OK && c->geostatic && !options->restart)
        rc = write_geostatic_attributes(r);
    if (rc != GSN_OK) {
        catch_stop_signals(0, previous);
        goto done;
    }
    rc = run_loop(r);
    int late_signal = stop_signal; /* during the last step or its output */
    catch_stop_signals(0, previous);
    if (rc != GSN_OK) /* keep what was written: the frames so far */
        gsn_error_pass(rc, __FILE__, __LINE__, __func__, "run_loop(r)");
    else
        rc = gsn_h5_attr_write_int(r->results, GSN_RESULTS_ATTR_COMPLETE, 1);
    if (rc == GSN_OK)
        rc = report_quasi_static(r);
    if (rc == GSN_OK && late_signal) /* complete, but the user asked to stop */
        rc = gsn_error_raise(GSN_ERR_INTERRUPTED, __FILE__, __LINE__, __func__,
                             "%s after the last step: the run in %s is "
                             "complete",
                             stopped_by(late_signal), r->outdir);
done:
    if (r->results >= 0) {
        char first[1024]; /* the failure of the run, not of the close (a
                             copy: a raise writes over the message) */
        snprintf(first, sizeof first, "%s", gsn_error_message());
        int closed = gsn_h5_close(&r->results);
        if (rc == GSN_OK)
            rc = closed;
        /* A write that failed (a full disk) may have left the last frame
         * cut short: the file stays results.h5.part, which --restart
         * continues from its last checkpoint once there is room; a
         * complete file, or one that a numerical failure, a signal or a
         * lack of memory stopped (its frames all whole), takes its final
         * name; any other failure (a .part that a restart could not read)
         * leaves it as it was. */
        if (rc == GSN_ERR_NO_SPACE && !r->stopped_whole)
            rc = gsn_error_raise(
                rc, __FILE__, __LINE__, __func__,
                "%s; the results so far stay in %s (not renamed: its last "
                "frame may be cut short): once there is room, continue with "
                "'geoscni solve %s -o %s --restart' (or start over with "
                "--rerun where the restart cannot mend it)",
                first, r->results_temporary, c->path, r->outdir);
        else if ((rc == GSN_OK || rc == GSN_ERR_NUMERICAL ||
                  rc == GSN_ERR_INTERRUPTED || rc == GSN_ERR_MEMORY ||
                  rc == GSN_ERR_NO_SPACE) &&
                 rename(r->results_temporary, r->results_path) != 0 &&
                 rc == GSN_OK)
            rc = gsn_error_raise(GSN_ERR_IO, __FILE__, __LINE__, __func__,
                                 "cannot rename %s to %s", r->results_temporary,
                                 r->results_path);
    }
    run_free(r);
    free(r);
    return rc;
}
