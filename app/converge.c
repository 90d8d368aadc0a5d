/* geoscni converge: the case at several spacings refined by a fixed ratio,
 * and the converged value of one number with its estimated error
 * (docs/converge.md; convergence.h for the arithmetic). */
#include "app.h"
#include "geoscni/convergence.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/model.h"
#include "geoscni/post.h"
#include "geoscni/quantity.h"
#include "geoscni/schema.h"

#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Defaults: three levels (the least an order can be observed from), each
 * 1.5 times finer (Celik et al. ask for more than 1.3; 1.5 costs 5 times
 * more per level, spacing^-4: particles and steps), the case's spacing the
 * finest, so the study costs about 1.25 times the case's own run. */
#define CONVERGE_LEVELS 3
#define CONVERGE_RATIO 1.5
#define CONVERGE_TOLERANCE 0.02
#define CONVERGE_FOS_BRACKET 0.0025
enum { CONVERGE_MAX_LEVELS = 8, PREDICTED_POINTS = 8 };

struct level {
    double spacing;                   /* particles.spacing of the level, m */
    double earlier_wall, earlier_cpu; /* s, of an earlier call of the study
                                         that finished it; NaN: none */
    double representative; /* (V / N)^(1/3), m (Celik et al. eq. (1)) */
    int particles;
    double value;
    double wall, cpu; /* s; NaN where not measured (a level done before) */
    char folder[GSN_PATH_SIZE];
};

double app_seconds(clockid_t clock)
{
    struct timespec t;
    clock_gettime(clock, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Particles and body volume of a level's model.h5. */
static int level_size(struct level *l)
{
    char path[GSN_PATH_SIZE];
    struct gsn_model m = {0};
    GSN_CALL(gsn_path_join(path, sizeof path, l->folder, "model.h5"));
    GSN_CALL(gsn_model_read(path, &m));
    double volume = 0.0;
    for (int p = 0; p < m.particle_count; ++p)
        volume += m.volume[p];
    l->particles = m.particle_count;
    l->representative = cbrt(volume / m.particle_count);
    gsn_model_free(&m);
    return GSN_OK;
}

/* The times of a level finished by an earlier call of the study, from its
 * converge.csv row of the same spacing; NaN if there is none. */
static void earlier_times(const char *csv, struct level *l)
{
    l->earlier_wall = l->earlier_cpu = NAN;
    FILE *file = fopen(csv, "r");
    if (!file)
        return;
    char line[1024];
    while (fgets(line, sizeof line, file)) {
        double spacing, representative, value, wall, cpu;
        int level, particles;
        if (sscanf(line, "%d,%lf,%lf,%d,%lf,%lf,%lf", &level, &spacing,
                   &representative, &particles, &value, &wall, &cpu) == 7 &&
            fabs(spacing - l->spacing) <= 1e-9 * l->spacing) {
            l->earlier_wall = wall;
            l->earlier_cpu = cpu;
        }
    }
    fclose(file);
}

/* converge.csv: one row per level done (coarsest first), then the
 * converged value when there are three or more; written whole each time
 * (temporary name, renamed). */
static int csv_write(const char *path, const struct level *levels, int done,
                     const struct gsn_convergence *estimate, double tolerance)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    FILE *file = fopen(temporary, "w");
    GSN_CHECK(file, GSN_ERR_IO, "%s: cannot write", temporary);
    fprintf(file, "level,spacing_m,representative_spacing_m,particles,value,"
                  "wall_s,cpu_s,estimated_error,within_tolerance,order,"
                  "trusted\n");
    for (int i = 0; i < done; ++i) {
        const struct level *l = &levels[i];
        fprintf(file, "%d,%.9g,%.9g,%d,%.9g,%.3f,%.3f,", i + 1, l->spacing,
                l->representative, l->particles, l->value, l->wall, l->cpu);
        if (estimate) {
            double error = gsn_convergence_level_error(estimate, l->value);
            fprintf(file, "%.6g,%d,,\n", error,
                    error <= tolerance * fabs(estimate->extrapolated));
        } else {
            fprintf(file, ",,,\n");
        }
    }
    if (estimate)
        fprintf(file, "converged,,,,%.9g,,,%.6g,%d,%.4g,%d\n",
                estimate->extrapolated, estimate->error,
                estimate->error <= tolerance * fabs(estimate->extrapolated),
                estimate->order, estimate->trusted);
    int ok = !ferror(file);
    ok = (fclose(file) == 0) && ok;
    if (!ok) {
        gsn_file_discard(path);
        GSN_CHECK(0, GSN_ERR_IO, "%s: write failed (disk full?)", temporary);
    }
    GSN_CALL(gsn_file_commit(path));
    return GSN_OK;
}

/* 1 if a level's solve stopped before its end and can be continued: a
 * results.h5 not marked complete (an interrupt, a full disk) or a
 * results.h5.part (a killed run). */
static int level_interrupted(const char *results, const char *part)
{
    if (access(part, F_OK) == 0)
        return 1;
    hid_t file = H5I_INVALID_HID;
    int complete = 1;
    if (access(results, F_OK) == 0 &&
        gsn_h5_open(results, GSN_FILE_KIND_RESULTS, 0, &file) == GSN_OK &&
        H5Aexists(file, GSN_RESULTS_ATTR_COMPLETE) > 0 &&
        gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_COMPLETE, &complete) !=
            GSN_OK)
        complete = 1;
    gsn_h5_close(&file);
    gsn_error_clear(); /* a damaged file is solve's to report */
    return complete == 0;
}

/* One level: the scaled case through pre and solve (an interrupted solve
 * continued from its checkpoint, a finished one kept), then its number. */
static int level_run(const struct arguments *a, const struct gsn_case *base,
                     const struct gsn_quantity *q, struct level *l)
{
    struct gsn_case c = *base;
    gsn_case_scale_spacing(&c, l->spacing / base->particle_spacing);
    char results[GSN_PATH_SIZE], part[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(results, sizeof results, l->folder, "results.h5"));
    GSN_CALL(gsn_path_temporary(part, sizeof part, results));
    struct arguments level_arguments = *a;
    level_arguments.restart = level_interrupted(results, part);
    level_arguments.rerun = 0;
    /* converge's --tol is not fos's: a level's factor is bracketed to
     * 0.0025 (fos: 0.01), so the steps of the bisection do not pass for
     * the spacing's effect (two more trials a level) */
    level_arguments.tolerance = CONVERGE_FOS_BRACKET;
    double wall = app_seconds(CLOCK_MONOTONIC);
    double cpu = app_seconds(CLOCK_PROCESS_CPUTIME_ID);
    GSN_CALL(app_lock_outdir(l->folder));
    int solved = 0;
    if (q->kind == GSN_QUANTITY_FACTOR_OF_SAFETY) {
        /* a fos study of the level (trials of an earlier call kept) */
        int trials = 0;
        GSN_CALL(
            app_fos_study(&level_arguments, &c, l->folder, &l->value, &trials));
        solved = trials > 0;
        l->wall =
            solved ? app_seconds(CLOCK_MONOTONIC) - wall : l->earlier_wall;
        l->cpu = solved ? app_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu
                        : l->earlier_cpu;
        GSN_CALL(level_size(l));
        return GSN_OK;
    }
    GSN_CALL(app_run_case(&level_arguments, &c, l->folder, 0, &solved));
    /* a level found done: its time is the earlier call's (NaN if unknown);
     * a continued one counts this call's part only */
    l->wall = solved ? app_seconds(CLOCK_MONOTONIC) - wall : l->earlier_wall;
    l->cpu =
        solved ? app_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu : l->earlier_cpu;
    GSN_CALL(level_size(l));
    GSN_CALL(gsn_quantity_measure(l->folder, &c, q, &l->value));
    return GSN_OK;
}

/* The levels' numbers (coarsest first) as the estimate wants them: finest
 * first. */
static int estimate_levels(const struct level *levels, int count,
                           struct gsn_convergence *estimate)
{
    double h[CONVERGE_MAX_LEVELS], phi[CONVERGE_MAX_LEVELS];
    for (int i = 0; i < count; ++i) {
        h[i] = levels[count - 1 - i].representative;
        phi[i] = levels[count - 1 - i].value;
    }
    GSN_CALL(gsn_convergence_estimate(count, h, phi, estimate));
    return GSN_OK;
}

/* A force on a surface whose area follows the spacing (a slab two spacings
 * thick) does not converge to anything: *changed says so, and the message
 * whether the study turns to the pressure (switching) or warns. */
static int area_changes(const struct level *levels, int count,
                        const char *surface, int switching, int *changed)
{
    double first = 0.0, area = 0.0;
    *changed = 0;
    for (int i = 0; i < count && !*changed; ++i) {
        GSN_CALL(gsn_quantity_surface_area(levels[i].folder, surface, &area));
        if (i == 0)
            first = area;
        else if (fabs(area - first) > 0.01 * first) {
            fprintf(stderr,
                    "%s: the area of '%s' changes with the spacing (%.4g m^2 "
                    "at level 1, %.4g m^2 at level %d): its force follows "
                    "the area, not the discretization; %s\n",
                    switching ? "converge" : "warning", surface, first, area,
                    i + 1,
                    switching ? "following the pressure on it instead"
                              : "follow the pressure instead (--quantity "
                                "peak_pressure)");
            *changed = 1;
        }
    }
    return GSN_OK;
}

static void print_report(const struct level *levels, int count,
                         const struct gsn_convergence *e, double tolerance,
                         const char *description, const char *unit)
{
    const struct level *last = &levels[count - 1];
    printf("\nconverge: %s, by level:\n", description);
    printf("  level  spacing [m]  particles  value [%s]      CPU [s]  "
           "estimated error\n",
           unit);
    for (int i = 0; i < count; ++i) {
        const struct level *l = &levels[i];
        double error = gsn_convergence_level_error(e, l->value);
        printf("  %5d  %11.4g  %9d  %-15.6g %8.1f  %.2g %s (%.2f%%)\n", i + 1,
               l->spacing, l->particles, l->value, l->cpu, error, unit,
               100.0 * error / fabs(e->extrapolated));
    }
    if (isfinite(e->order))
        printf("converge: observed order %.2f", e->order);
    else
        printf("converge: no observed order");
    if (isfinite(e->scatter))
        printf(" (least squares over the %d levels, standard deviation %.3g "
               "%s)",
               count, e->scatter, unit);
    printf("\n");
    if (!e->trusted)
        printf("converge: NOT IN THE ASYMPTOTIC RANGE: %s. Do not trust the "
               "extrapolation; refine further (--levels %d) or start finer\n",
               e->reason, count + 1);
    const char *space = unit[0] ? " " : ""; /* none before no unit */
    printf("converged value: %.6g%s%s (estimated error %.2g%s%s, %.2f%%)\n",
           e->extrapolated, space, unit, e->error, space, unit,
           100.0 * e->error / fabs(e->extrapolated));
    int coarsest = -1;
    for (int i = count - 1; i >= 0; --i)
        if (gsn_convergence_level_error(e, levels[i].value) <=
            tolerance * fabs(e->extrapolated))
            coarsest = i;
    if (coarsest >= 0) {
        printf("converge: the coarsest spacing within %.3g%%: %.4g m (level "
               "%d, %d particles, %.1f s CPU)\n",
               100.0 * tolerance, levels[coarsest].spacing, coarsest + 1,
               levels[coarsest].particles, levels[coarsest].cpu);
        return;
    }
    /* A level's error is |phi - phi_ext| + 1.25 |phi_f - phi_ext| with phi_f
     * the finest of its study: a study ending at spacing h puts its finest
     * level within the tolerance where 2.25 C h^p <= tol |phi_ext|. */
    double room =
        tolerance * fabs(e->extrapolated) / (1.0 + GSN_CONVERGENCE_SAFETY);
    double h =
        gsn_convergence_spacing_for(e, last->representative, last->value, room);
    if (isfinite(h) && h > 0.0) {
        double scale = h / last->representative;
        printf("converge: no level is within %.3g%%; the observed order puts "
               "a study ending near a spacing of %.3g m within it (%.2g times "
               "the finest; about %.3g times its particles and %.3g times its "
               "time)\n",
               100.0 * tolerance, last->spacing * scale, scale,
               pow(scale, -3.0), pow(scale, -4.0));
    } else {
        printf("converge: no level is within %.3g%%%s\n", 100.0 * tolerance,
               e->trusted ? ""
                          : ", and without an observed order no spacing "
                            "can be predicted");
    }
}

int command_converge(const struct arguments *a)
{
    struct gsn_case c;
    GSN_CALL(gsn_case_load(a->cases[0], &c));
    gsn_case_warn_implausible(&c, stderr);
    int count = a->levels ? a->levels : CONVERGE_LEVELS;
    double ratio = a->ratio > 0.0 ? a->ratio : CONVERGE_RATIO;
    double tolerance = a->tolerance > 0.0 ? a->tolerance : CONVERGE_TOLERANCE;
    GSN_CHECK(count >= 3 && count <= CONVERGE_MAX_LEVELS, GSN_ERR_INPUT,
              "--levels %d: give 3 to %d", count, CONVERGE_MAX_LEVELS);
    GSN_CHECK(ratio >= 1.1 && ratio <= 4.0, GSN_ERR_INPUT,
              "--ratio %g: give 1.1 to 4 (the spacing of each level over the "
              "next finer one)",
              ratio);
    double finest = a->finest > 0.0 ? a->finest : c.particle_spacing;
    GSN_CHECK(tolerance < 1.0, GSN_ERR_INPUT,
              "--tol %g: give a fraction below 1 (0.02 or 2%% for 2%%)",
              tolerance);
    struct gsn_quantity q;
    char description[256];
    const char *unit = "";
    GSN_CALL(gsn_quantity_parse(a->quantity ? a->quantity : "peak_force", &q));
    GSN_CALL(
        gsn_quantity_resolve(&c, &q, description, sizeof description, &unit));
    char outdir[GSN_PATH_SIZE], name[256], csv[GSN_PATH_SIZE];
    gsn_case_name(c.path, name, sizeof name);
    if (a->outdir)
        snprintf(outdir, sizeof outdir, "%s", a->outdir);
    else
        snprintf(outdir, sizeof outdir, "%s_converge", name);
    GSN_CALL(app_lock_outdir(outdir));
    GSN_CALL(gsn_path_join(csv, sizeof csv, outdir, "converge.csv"));

    struct level levels[CONVERGE_MAX_LEVELS];
    memset(levels, 0, sizeof levels);
    for (int i = 0; i < count; ++i) {
        struct level *l = &levels[i];
        l->spacing = finest * pow(ratio, count - 1 - i);
        char folder[32];
        snprintf(folder, sizeof folder, "level_%d", i + 1);
        GSN_CALL(gsn_path_join(l->folder, sizeof l->folder, outdir, folder));
        earlier_times(csv, l);
    }
    if (!a->quiet)
        printf("converge: %s of %s at %d spacings from %.4g m to %.4g m "
               "(ratio %g) into %s; an interrupted study continues where it "
               "stopped when run again\n",
               description, c.path, count, levels[0].spacing,
               levels[count - 1].spacing, ratio, outdir);
    /* a softening law without a length has no converged peak */
    for (int k = 0; k < c.material_count; ++k)
        if (c.materials[k].has_damage &&
            !(c.materials[k].damage_length > 0.0) &&
            q.kind != GSN_QUANTITY_FACTOR_OF_SAFETY)
            fprintf(stderr,
                    "warning: %s:%d: the damage has no length: a softening "
                    "band narrows with the spacing and the peak load may not "
                    "converge (docs/converge.md); add 'length: L' (m) to "
                    "damage: for damage that averages e_t over a ball of "
                    "radius L, kept through the levels\n",
                    c.path, c.materials[k].line.entry);
    for (int i = 0; i < count; ++i) {
        struct level *l = &levels[i];
        if (!a->quiet)
            printf("\nconverge: level %d of %d: spacing %.4g m, in %s\n", i + 1,
                   count, l->spacing, l->folder);
        GSN_CALL(level_run(a, &c, &q, l));
        GSN_CALL(csv_write(csv, levels, i + 1, NULL, tolerance));
        if (!a->quiet) {
            printf("converge: level %d: %s = %.6g %s (%d particles, %.1f s "
                   "CPU)",
                   i + 1, description, l->value, unit, l->particles, l->cpu);
            /* particles grow as h^-3, steps as h^-1 */
            if (i + 1 < count && isfinite(l->wall))
                printf("; level %d should take about %.0f s", i + 2,
                       l->wall * pow(ratio, 4.0));
            printf("\n");
        }
    }
    if (q.kind != GSN_QUANTITY_DISPLACEMENT_AT &&
        q.kind != GSN_QUANTITY_FACTOR_OF_SAFETY && !q.per_area) {
        /* the default quantity turns into the pressure; one asked for is
         * kept, with the warning */
        int changed = 0;
        GSN_CALL(
            area_changes(levels, count, q.surface, !a->quantity, &changed));
        q.per_area = changed && !a->quantity;
        if (q.per_area) {
            GSN_CALL(gsn_quantity_resolve(&c, &q, description,
                                          sizeof description, &unit));
            for (int i = 0; i < count; ++i)
                GSN_CALL(gsn_quantity_measure(levels[i].folder, &c, &q,
                                              &levels[i].value));
        }
    }
    struct gsn_convergence estimate;
    GSN_CALL(estimate_levels(levels, count, &estimate));
    GSN_CALL(csv_write(csv, levels, count, &estimate, tolerance));
    if (!a->quiet)
        print_report(levels, count, &estimate, tolerance, description, unit);
    else
        printf("converged value: %.6g%s%s (estimated error %.2g%s%s)%s%s\n",
               estimate.extrapolated, unit[0] ? " " : "", unit, estimate.error,
               unit[0] ? " " : "", unit,
               estimate.trusted ? "" : "; not in the asymptotic range: ",
               estimate.reason);

    double cpu[CONVERGE_MAX_LEVELS], error[CONVERGE_MAX_LEVELS];
    int measured = 0;
    for (int i = 0; i < count; ++i)
        if (isfinite(levels[i].cpu) && levels[i].cpu > 0.0) {
            cpu[measured] = levels[i].cpu;
            /* floored for the logarithmic axis: levels that agree */
            error[measured++] = fmax(1e-6, 100.0 *
                                               gsn_convergence_level_error(
                                                   &estimate, levels[i].value) /
                                               fabs(estimate.extrapolated));
        }
    char chart[GSN_PATH_SIZE], title[1024];
    GSN_CALL(gsn_path_join(chart, sizeof chart, outdir, "converge.png"));
    snprintf(title, sizeof title, "%s: %s, error against CPU time%s", name,
             description, estimate.trusted ? "" : " (not asymptotic)");
    /* a study ending finer: 2.25 C h^p at CPU time ~ h^-4, from the finest
     * level down to the tolerance (at most 10^4 times its time) */
    double predicted_cpu[PREDICTED_POINTS], predicted_error[PREDICTED_POINTS];
    int predicted = 0;
    const struct level *last = &levels[count - 1];
    if (estimate.trusted && isfinite(estimate.order) && estimate.order > 0.0 &&
        isfinite(last->cpu) && last->cpu > 0.0 &&
        last->value != estimate.extrapolated) {
        double start = (1.0 + GSN_CONVERGENCE_SAFETY) *
                       fabs(last->value - estimate.extrapolated) /
                       fabs(estimate.extrapolated);
        double end = fmax(tolerance, start * pow(1e4, -estimate.order / 4.0));
        for (; predicted < PREDICTED_POINTS; ++predicted) {
            double e =
                start * pow(end / start, predicted / (PREDICTED_POINTS - 1.0));
            predicted_error[predicted] = 100.0 * e;
            predicted_cpu[predicted] =
                last->cpu * pow(start / e, 4.0 / estimate.order);
        }
    }
    if (measured >= 2 && !a->no_pictures)
        GSN_CALL(gsn_post_convergence_chart(
            chart, title, measured, cpu, error, predicted, predicted_cpu,
            predicted_error, 100.0 * tolerance));
    if (!a->quiet)
        printf("converge: %s and converge.png in %s\n", "converge.csv", outdir);
    return GSN_OK;
}
