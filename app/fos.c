/* geoscni fos: the factor of safety of a body under its own weight by
 * strength reduction: c and tan(phi) divided by a trial factor, the dead
 * loads brought to rest (the geostatic stage alone), the factor bracketed
 * between one at which the body stands and one at which it does not
 * (docs/fos.md). */
#include "app.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/h5io.h"
#include "geoscni/post.h"
#include "geoscni/schema.h"
#include "geoscni/solver.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* The search: the first trial at 1; steps of FOS_STEP (times or over)
 * until the factor is bracketed, within FOS_LOWEST and FOS_HIGHEST; then
 * the bracket narrowed to --tol (default FOS_TOLERANCE, so that two
 * decimals hold). */
#define FOS_START 1.0
#define FOS_STEP 1.5
#define FOS_LOWEST 0.05
#define FOS_HIGHEST 20.0
#define FOS_TOLERANCE 0.01
/* time.mass_scaling where the case sets none: 2.8 times fewer steps on
 * Griffiths & Lane's slope, the same factor and verdicts (docs/fos.md) */
#define FOS_MASS_SCALING 0.01
enum { FOS_MAX_TRIALS = 64 };

struct trial {
    double factor;
    int stands;                 /* 1: at rest; 0: no rest */
    long steps;                 /* of the geostatic stage */
    double unbalanced;          /* over the weight, at the stage's end */
    double displacement;        /* the largest, m */
    double wall;                /* s */
    char folder[GSN_PATH_SIZE]; /* of its run */
    /* the trial's strengths, one per material; reduced[0] is the one the
     * rows and lines show */
    struct gsn_material reduced[GSN_MAX_MATERIALS];
};

struct search {
    struct trial trials[FOS_MAX_TRIALS];
    int count;
    double low, high; /* stands at low, fails at high; 0 / INFINITY: none */
};

/* The case fos can reduce: weight, strength in engineers' terms, no rigid
 * body (the geostatic stage holds none). */
static int fos_check_case(const struct gsn_case *c)
{
    double g =
        sqrt(c->gravity[0] * c->gravity[0] + c->gravity[1] * c->gravity[1] +
             c->gravity[2] * c->gravity[2]);
    GSN_CHECK(g > 0.0, GSN_ERR_INPUT,
              "%s: fos needs the soil's weight: add 'gravity: [0, 0, -9.81]' "
              "(the factor of safety is that of the body under its own "
              "weight)",
              c->path);
    int reducible = 0;
    for (int k = 0; k < c->material_count; ++k) {
        const struct gsn_material *m = &c->materials[k];
        reducible |= m->has_plasticity;
        GSN_CHECK(!m->has_plasticity || m->dp_from_mohr_coulomb, GSN_ERR_INPUT,
                  "%s:%d: fos reduces c and tan(phi): give the strength%s%s "
                  "as 'drucker_prager: {cohesion: PA, friction_angle: DEG, "
                  "dilation_angle: DEG}' (docs/material.md, \"In engineers' "
                  "terms\")",
                  c->path, m->line.entry, m->volume[0] ? " of " : "",
                  m->volume);
    }
    GSN_CHECK(reducible, GSN_ERR_INPUT,
              "%s: fos reduces c and tan(phi), and no soil has them: give "
              "one 'drucker_prager: {cohesion: PA, friction_angle: DEG, "
              "dilation_angle: DEG}' (an elastic one, bedrock, is kept as it "
              "is)",
              c->path);
    for (int b = 0; b < c->boundary_count; ++b)
        GSN_CHECK(!c->boundaries[b].rigid, GSN_ERR_INPUT,
                  "%s:%d: fos brings the body to rest under its dead loads "
                  "alone, which a rigid body ('%s') does not take part in: "
                  "remove it, or give its surface a 'fix' or a 'traction'",
                  c->path, c->boundaries[b].line, c->boundaries[b].name);
    return GSN_OK;
}

/* The line fos.csv starts with: what its rows were made from, so that a
 * later call reuses them only for the same model and strength. */
static int fos_signature(const struct gsn_case *c, const char *outdir,
                         char *out, size_t size)
{
    char model[GSN_PATH_SIZE], hash[GSN_FILE_HASH_SIZE];
    GSN_CALL(gsn_path_join(model, sizeof model, outdir, "model.h5"));
    GSN_CALL(gsn_file_hash(model, hash));
    int used =
        snprintf(out, size, "# geoscni fos of %s: model.h5 %s", c->path, hash);
    for (int k = 0; k < c->material_count && used > 0 && (size_t)used < size;
         ++k) {
        const struct gsn_material *m = &c->materials[k];
        int w = snprintf(out + used, size - (size_t)used,
                         ",%s%s c %.17g Pa, phi %.17g, psi %.17g, fit %d",
                         m->volume[0] ? " " : "", m->volume, m->cohesion,
                         m->friction_angle, m->dilation_angle, (int)m->dp_fit);
        used += w > 0 ? w : 0;
    }
    if (used > 0 && (size_t)used < size)
        snprintf(out + used, size - (size_t)used,
                 ", residual %.17g, damping %.17g, max_steps %ld, k0 %.17g, "
                 "mass_scaling %.17g%s",
                 c->geostatic_residual, c->geostatic_damping,
                 c->geostatic_max_steps, c->geostatic_k0, c->time_mass_scaling,
                 c->water.present ? ", with water" : "");
    return GSN_OK;
}

static const char FOS_HEADER[] =
    "factor,cohesion_Pa,friction_angle_deg,dilation_angle_deg,stands,steps,"
    "unbalanced_force,largest_displacement_m,wall_s";

/* The rows of an earlier call made from the same signature. */
static void fos_read_earlier(const char *csv, const char *signature,
                             struct search *earlier)
{
    earlier->count = 0;
    FILE *file = fopen(csv, "r");
    if (!file)
        return;
    char line[2 * GSN_PATH_SIZE + 64];
    if (!fgets(line, sizeof line, file) ||
        strncmp(line, signature, strlen(signature)) != 0 ||
        (line[strlen(signature)] != '\n' && line[strlen(signature)] != '\0')) {
        fclose(file);
        return;
    }
    while (fgets(line, sizeof line, file) && earlier->count < FOS_MAX_TRIALS) {
        struct trial *t = &earlier->trials[earlier->count];
        double c, phi, psi;
        if (sscanf(line, "%lf,%lf,%lf,%lf,%d,%ld,%lf,%lf,%lf", &t->factor, &c,
                   &phi, &psi, &t->stands, &t->steps, &t->unbalanced,
                   &t->displacement, &t->wall) == 9)
            earlier->count++;
    }
    fclose(file);
}

static int fos_csv_write(const char *path, const char *signature,
                         const struct search *s)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    FILE *file = fopen(temporary, "w");
    if (!file)
        return GSN_WRITE_ERROR(temporary, errno, "cannot create");
    fprintf(file, "%s\n%s\n", signature, FOS_HEADER);
    for (int i = 0; i < s->count; ++i) {
        const struct trial *t = &s->trials[i];
        fprintf(file, "%.17g,%.17g,%.17g,%.17g,%d,%ld,%.17g,%.17g,%.3f\n",
                t->factor, t->reduced[0].cohesion, t->reduced[0].friction_angle,
                t->reduced[0].dilation_angle, t->stands, t->steps,
                t->unbalanced, t->displacement, t->wall);
    }
    if (fclose(file) != 0)
        return GSN_WRITE_ERROR(temporary, errno, "cannot write");
    return gsn_file_commit(path);
}

/* The numbers of a trial's geostatic stage from its results.h5. */
static int trial_read_results(struct trial *t)
{
    char path[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, t->folder, "results.h5"));
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file));
    int steps = 0, rested = 0;
    int rc =
        gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_GEOSTATIC_STEPS, &steps);
    if (rc == GSN_OK)
        rc = gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_GEOSTATIC_RESTED,
                                  &rested);
    if (rc == GSN_OK)
        rc = gsn_h5_attr_read_double(file, GSN_RESULTS_ATTR_GEOSTATIC_RESIDUAL,
                                     &t->unbalanced);
    if (rc == GSN_OK)
        rc = gsn_h5_attr_read_double(
            file, GSN_RESULTS_ATTR_GEOSTATIC_DISPLACEMENT, &t->displacement);
    gsn_h5_close(&file);
    t->steps = steps;
    GSN_CALL(rc);
    GSN_CHECK(rested == t->stands, GSN_ERR_INTERNAL,
              "%s: the stage's verdict (%d) is not the solve's (%d)", path,
              rested, t->stands);
    return GSN_OK;
}

/* One trial: the geostatic stage alone with the reduced strength, in its
 * own folder beside the shared model.h5 (a hard link). A stage that finds
 * no rest, or any other numerical failure on the way, is a failed trial. */
static int trial_run(const struct arguments *a, const struct gsn_case *base,
                     const char *outdir, int warned, struct trial *t)
{
    struct gsn_case *c = malloc(sizeof *c);
    GSN_CHECK(c, GSN_ERR_MEMORY, "out of memory");
    *c = *base;
    c->geostatic = 1;
    for (int k = 0; k < c->material_count; ++k)
        c->materials[k] = t->reduced[k];
    char model[GSN_PATH_SIZE], link_path[GSN_PATH_SIZE];
    int rc = gsn_folder_prepare(t->folder); /* and trials/ */
    if (rc == GSN_OK)
        rc = gsn_path_join(model, sizeof model, outdir, "model.h5");
    if (rc == GSN_OK)
        rc = gsn_path_join(link_path, sizeof link_path, t->folder, "model.h5");
    if (rc == GSN_OK) {
        unlink(link_path);
        if (link(model, link_path) != 0)
            rc = GSN_WRITE_ERROR(link_path, errno,
                                 "cannot link the model into the trial");
    }
    struct gsn_solve_options options = {.force = a->force,
                                        .threads = a->threads,
                                        .quiet = 1,
                                        .start_over = 1,
                                        .setup_warned = warned,
                                        .geostatic_only = 1};
    double started = app_seconds(CLOCK_MONOTONIC);
    if (rc == GSN_OK) {
        rc = gsn_solve_run(c, t->folder, &options);
        t->stands = rc == GSN_OK;
        if (rc == GSN_ERR_NUMERICAL) {
            if (a->verbose) {
                printf("fos: ");
                gsn_error_print_user(stdout, 0);
            }
            gsn_error_clear();
            rc = GSN_OK;
        }
    }
    t->wall = app_seconds(CLOCK_MONOTONIC) - started;
    if (rc == GSN_OK && trial_read_results(t) != GSN_OK) {
        /* a failure before the stage's numbers were kept */
        gsn_error_clear();
        t->steps = 0;
        t->unbalanced = t->displacement = NAN;
    }
    free(c);
    return rc;
}

static void search_record(struct search *s, const struct trial *t)
{
    s->trials[s->count++] = *t;
    if (t->stands && t->factor > s->low)
        s->low = t->factor;
    if (!t->stands && t->factor < s->high)
        s->high = t->factor;
}

/* The next factor to try, or 0 when the bracket is narrow enough (or the
 * factor lies outside what fos searches): steps of FOS_STEP until a stand
 * and a fail bracket the factor, then bisection. (Extrapolating the failed
 * trials' unbalanced force to zero was tried: it undershoots where the
 * trials lie far above the factor, 1.334 for 1.35 on the 0.29 m slope,
 * and the bracket then closed a tolerance a trial.) */
static double search_next(const struct search *s, double tolerance)
{
    if (s->high == INFINITY)
        return s->low * FOS_STEP > FOS_HIGHEST ? 0.0 : s->low * FOS_STEP;
    if (s->low == 0.0) {
        double next = s->high / FOS_STEP;
        return next < FOS_LOWEST ? 0.0 : next;
    }
    if (s->high - s->low <= tolerance * (1.0 + 1e-9))
        return 0.0;
    return 0.5 * (s->low + s->high);
}

static int fos_earlier_trial(const struct search *earlier, double factor,
                             struct trial *t)
{
    for (int i = 0; i < earlier->count; ++i)
        if (fabs(earlier->trials[i].factor - factor) <= 1e-12 * factor) {
            t->stands = earlier->trials[i].stands;
            t->steps = earlier->trials[i].steps;
            t->unbalanced = earlier->trials[i].unbalanced;
            t->displacement = earlier->trials[i].displacement;
            t->wall = earlier->trials[i].wall;
            return 1;
        }
    return 0;
}

static void print_trial(const struct trial *t, int reused)
{
    printf("fos: factor %.4f (%s%sc %.4g kPa, phi %.2f, psi %.2f deg): %s",
           t->factor, t->reduced[0].volume, t->reduced[0].volume[0] ? ": " : "",
           1e-3 * t->reduced[0].cohesion, t->reduced[0].friction_angle,
           t->reduced[0].dilation_angle, t->stands ? "stands" : "fails");
    if (t->stands)
        printf(" (at rest after %ld steps, largest displacement %.3g m",
               t->steps, t->displacement);
    else if (isfinite(t->unbalanced))
        printf(" (no rest after %ld steps: unbalanced force %.3g of the "
               "weight, largest displacement %.3g m",
               t->steps, t->unbalanced, t->displacement);
    else
        printf(" (the stage failed before its end");
    printf(", %.1f s%s)\n", t->wall, reused ? ", from fos.csv" : "");
}

/* OUTDIR/mechanism: a link to the folder of the lowest failed factor, with
 * its ParaView files and pictures. */
static int fos_mechanism(const struct arguments *a, const char *outdir,
                         const struct trial *t)
{
    struct gsn_post_options options = {.no_pictures = a->no_pictures,
                                       .quiet = 1};
    GSN_CALL(gsn_post_run(t->folder, &options));
    char link_path[GSN_PATH_SIZE], temporary[GSN_PATH_SIZE], target[128];
    GSN_CALL(gsn_path_join(link_path, sizeof link_path, outdir, "mechanism"));
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, link_path));
    snprintf(target, sizeof target, "trials/factor_%.4f", t->factor);
    unlink(temporary);
    if (symlink(target, temporary) != 0)
        return GSN_WRITE_ERROR(temporary, errno, "cannot create the link");
    if (rename(temporary, link_path) != 0)
        return GSN_WRITE_ERROR(link_path, errno, "cannot rename the link");
    return GSN_OK;
}

int app_fos_study(const struct arguments *a, struct gsn_case *c,
                  const char *outdir, double *result, int *trials_run)
{
    double tolerance = a->tolerance > 0.0 ? a->tolerance : FOS_TOLERANCE;
    char csv[GSN_PATH_SIZE], signature[2 * GSN_PATH_SIZE];
    int rc = GSN_OK;
    GSN_CALL(fos_check_case(c));
    /* Each trial's answer is an equilibrium, which the masses do not move:
     * mass scaling by default (docs/fos.md) */
    if (!c->time_mass_scaling_given)
        c->time_mass_scaling = FOS_MASS_SCALING;
    struct search *s = calloc(2, sizeof *s), *earlier = s + 1;
    GSN_CHECK_GOTO(s, rc, GSN_ERR_MEMORY, done, "out of memory");
    s->high = INFINITY;
    GSN_CALL_GOTO(app_pre(a, c, outdir), rc, done);
    GSN_CALL_GOTO(gsn_path_join(csv, sizeof csv, outdir, "fos.csv"), rc, done);
    GSN_CALL_GOTO(fos_signature(c, outdir, signature, sizeof signature), rc,
                  done);
    if (!a->rerun)
        fos_read_earlier(csv, signature, earlier);
    if (!a->quiet) {
        if (c->material_count > 1)
            printf("fos: %s: c and tan(phi) of its %d soils", c->path,
                   c->material_count);
        else
            printf("fos: %s: c %.4g kPa and tan(phi) %.4g", c->path,
                   1e-3 * c->material.cohesion,
                   tan(c->material.friction_angle * acos(-1.0) / 180.0));
        printf(" divided by trial factors until one the body stands at and "
               "one it does not lie %.3g apart; the trials in %s/trials",
               tolerance, outdir);
        if (earlier->count)
            printf(" (%d done before, kept in fos.csv)", earlier->count);
        printf("\n");
        if (!c->time_mass_scaling_given)
            printf("fos: %g%% of the body's mass added where the stable step "
                   "is set (fos's default; 'time: {mass_scaling: 0}' in the "
                   "case turns it off)\n",
                   100.0 * c->time_mass_scaling);
        int damage = 0;
        for (int k = 0; k < c->material_count; ++k)
            damage |= c->materials[k].has_damage;
        for (int k = 0; k < c->material_count; ++k)
            if (!c->materials[k].has_plasticity)
                printf("fos: note: %s%s has no strength given: it stays "
                       "elastic, not reduced\n",
                       c->materials[k].volume[0] ? c->materials[k].volume
                                                 : "the material",
                       "");
        if (damage)
            printf("fos: note: the damage of the case is left out: the "
                   "factor reduces the peak strength c, phi\n");
    }
    if (c->stabilization != GSN_STABILIZATION_NONE) {
        fprintf(stderr,
                "fos: warning: %s integrates with a stabilization, which "
                "stiffens collapse: Griffiths & Lane's slope gave 1.61 with "
                "NSNI 0.1, 1.40 with plain SCNI (1.38 published; "
                "docs/fos.md); for a factor of safety use 'integration: "
                "{method: scni}'\n",
                c->path);
    }
    double factor = FOS_START;
    int ran = 0; /* trials run by this call */
    while (factor > 0.0) {
        GSN_CHECK_GOTO(s->count < FOS_MAX_TRIALS, rc, GSN_ERR_NUMERICAL, done,
                       "fos: no bracket after %d trials", s->count);
        struct trial t = {.factor = factor};
        for (int k = 0; k < c->material_count; ++k)
            gsn_material_reduce_strength(&c->materials[k], factor,
                                         &t.reduced[k]);
        char folder[64];
        snprintf(folder, sizeof folder, "trials/factor_%.4f", factor);
        GSN_CALL_GOTO(gsn_path_join(t.folder, sizeof t.folder, outdir, folder),
                      rc, done);
        int reused = fos_earlier_trial(earlier, factor, &t);
        if (!reused)
            GSN_CALL_GOTO(trial_run(a, c, outdir, ran++ > 0, &t), rc, done);
        search_record(s, &t);
        GSN_CALL_GOTO(fos_csv_write(csv, signature, s), rc, done);
        if (!a->quiet) {
            print_trial(&t, reused);
            fflush(stdout); /* progress also into a file */
        }
        factor = search_next(s, tolerance);
    }
    GSN_CHECK_GOTO(s->high < INFINITY, rc, GSN_ERR_NUMERICAL, done,
                   "%s: the body still stands with c and tan(phi) divided by "
                   "%.3g: its factor of safety is above that (is it held on "
                   "every side?)",
                   c->path, s->low);
    GSN_CHECK_GOTO(s->low > 0.0, rc, GSN_ERR_NUMERICAL, done,
                   "%s: the body does not stand even with c and tan(phi) "
                   "multiplied by %.3g: look at the mechanism in %s/trials "
                   "(is it held at all?)",
                   c->path, 1.0 / s->high, outdir);
    const struct trial *failed = NULL;
    for (int i = 0; i < s->count; ++i)
        if (s->trials[i].factor == s->high)
            failed = &s->trials[i];
    GSN_CALL_GOTO(fos_mechanism(a, outdir, failed), rc, done);
    *result = 0.5 * (s->low + s->high);
    *trials_run = ran;
    printf("factor of safety: %.2f\n", *result);
    if (!a->quiet)
        printf("fos: the body stands at %.4f and fails at %.4f (%d trials); "
               "the mechanism at %.4f: %s/mechanism (pictures/, the .pvd); "
               "the trials: %s\n",
               s->low, s->high, s->count, s->high, outdir, csv);
done:
    free(s);
    return rc;
}

int command_fos(const struct arguments *a)
{
    struct gsn_case *c = malloc(sizeof *c);
    GSN_CHECK(c, GSN_ERR_MEMORY, "out of memory");
    int rc = gsn_case_load(a->cases[0], c);
    if (rc == GSN_OK)
        rc = fos_check_case(c);
    if (rc != GSN_OK) {
        free(c);
        return rc;
    }
    gsn_case_warn_implausible(c, stderr);
    char outdir[GSN_PATH_SIZE], name[256];
    gsn_case_name(c->path, name, sizeof name);
    if (a->outdir)
        snprintf(outdir, sizeof outdir, "%s", a->outdir);
    else
        snprintf(outdir, sizeof outdir, "%s_fos", name);
    double factor = 0.0;
    int trials = 0;
    rc = app_lock_outdir(outdir);
    if (rc == GSN_OK)
        rc = app_fos_study(a, c, outdir, &factor, &trials);
    free(c);
    return rc;
}
