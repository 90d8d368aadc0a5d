/* geoscni: the command-line program. Subcommands pre, solve, post, run,
 * converge, fos and check; exit status 0 ok, 2 bad input, 3 numerical failure
 * (DESIGN.md). */
#include "app.h"
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/h5io.h"
#include "geoscni/post.h"
#include "geoscni/pre.h"
#include "geoscni/solver.h"
#include "geoscni/version.h"

#include <ctype.h>
#include <hdf5.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The options: each command takes -h and -q, and those of its mask. */
enum option_bit {
    OPTION_OUTPUT = 1 << 0,
    OPTION_THREADS = 1 << 1,
    OPTION_FORCE = 1 << 2,
    OPTION_RESTART = 1 << 3,
    OPTION_RERUN = 1 << 4,
    OPTION_NO_PICTURES = 1 << 5,
    OPTION_HELP = 1 << 6,
    OPTION_QUIET = 1 << 7,
    OPTION_VERBOSE = 1 << 8,
    OPTION_LEVELS = 1 << 9,
    OPTION_RATIO = 1 << 10,
    OPTION_QUANTITY = 1 << 11,
    OPTION_TOLERANCE = 1 << 12,
    OPTION_FINEST = 1 << 13,
    OPTION_LAYERS = 1 << 14,
    OPTION_BASE = 1 << 15,
    OPTION_EVERY = 1 << 16,
    OPTION_GENERAL = OPTION_HELP | OPTION_QUIET | OPTION_VERBOSE /* every
                                                                   command's */
};

static const struct option {
    const char *short_name, *long_name; /* short_name may be NULL */
    int bit;
    const char *value; /* what the option takes ("a folder"), NULL: none */
} command_options[] = {
    {"-h", "--help", OPTION_HELP, NULL},
    {"-q", "--quiet", OPTION_QUIET, NULL},
    {"-v", "--verbose", OPTION_VERBOSE, NULL},
    {"-o", "--output", OPTION_OUTPUT, "a folder"},
    {"-j", "--threads", OPTION_THREADS, "a number"},
    {NULL, "--force", OPTION_FORCE, NULL},
    {NULL, "--restart", OPTION_RESTART, NULL},
    {NULL, "--rerun", OPTION_RERUN, NULL},
    {NULL, "--no-pictures", OPTION_NO_PICTURES, NULL},
    {NULL, "--levels", OPTION_LEVELS, "a number"},
    {NULL, "--ratio", OPTION_RATIO, "a number"},
    {NULL, "--quantity", OPTION_QUANTITY, "a quantity"},
    {NULL, "--tol", OPTION_TOLERANCE, "a fraction"},
    {NULL, "--finest", OPTION_FINEST, "a spacing in m"},
    {NULL, "--layers", OPTION_LAYERS, "a list of layers"},
    {NULL, "--base", OPTION_BASE, "an elevation in m"},
    {NULL, "--every", OPTION_EVERY, "a number"},
};
enum { OPTION_COUNT = sizeof command_options / sizeof command_options[0] };

struct command {
    const char *name;
    const char *usage;
    const char *summary;
    const char *options; /* help of the options of the mask but -h, -q */
    int (*run)(const struct arguments *a);
    int min_cases, max_cases;
    const char *operand; /* "file" or "folder" */
    int option_mask;
};

static const char general_options[] =
    "  -h, --help       this help\n"
    "  -q, --quiet      no progress output\n"
    "  -v, --verbose    errors with where they were raised in geoscni\n";

#define THREADS_HELP "  -j, --threads N  OpenMP threads (default: all cores)\n"

static const char *outdir_for(const struct arguments *a, const char *case_path,
                              char *buffer, size_t size)
{
    if (a->outdir && a->case_count <= 1)
        return a->outdir;
    char name[GSN_PATH_SIZE];
    gsn_case_name(case_path, name, sizeof name);
    int n = a->outdir ? snprintf(buffer, size, "%s/%s", a->outdir, name)
                      : snprintf(buffer, size, "%s", name);
    if (n < 0 || (size_t)n >= size)
        buffer[size - 1] = '\0'; /* cut: the folder check reports it */
    return buffer;
}

static int run_pre(const struct gsn_case *c, const char *outdir,
                   const struct arguments *a)
{
    struct gsn_pre_options options = {
        .force = a->force, .threads = a->threads, .quiet = a->quiet};
    GSN_CALL(gsn_pre_run(c, outdir, &options));
    return GSN_OK;
}

static int run_solve(const struct gsn_case *c, const char *outdir,
                     const struct arguments *a, int restart)
{
    /* run --rerun starts over, also over an interrupted run's results;
     * GEOSCNI_PROGRESS_SECONDS sets the interval of the progress lines
     * written to a file (solver.h) */
    const char *interval = getenv("GEOSCNI_PROGRESS_SECONDS");
    struct gsn_solve_options options = {
        .force = a->force,
        .restart = restart,
        .threads = a->threads,
        .quiet = a->quiet,
        .start_over = a->rerun,
        .progress_seconds = interval ? strtod(interval, NULL) : 0.0};
    GSN_CALL(gsn_solve_run(c, outdir, &options));
    return GSN_OK;
}

static int run_post(const char *outdir, const struct arguments *a)
{
    struct gsn_post_options options = {.no_pictures = a->no_pictures,
                                       .quiet = a->quiet};
    GSN_CALL(gsn_post_run(outdir, &options));
    return GSN_OK;
}

/* The resolved case as check shows it: every number outside quotes in the
 * shortest form that reads back to the same double (0.7, not
 * 0.69999999999999996; the files between stages keep all 17 digits). */
static void print_readable(const char *text, FILE *out)
{
    int quoted = 0;
    for (const char *p = text; *p;) {
        int sign = (*p == '-' || *p == '+') && isdigit((unsigned char)p[1]);
        int number = !quoted && (isdigit((unsigned char)*p) || sign) &&
                     (p == text || (!isalnum((unsigned char)p[-1]) &&
                                    p[-1] != '_' && p[-1] != '.'));
        char *end = (char *)p;
        double value = number ? strtod(p, &end) : 0.0;
        if (end > p) {
            char shortest[32];
            for (int digits = 1; digits <= 17; ++digits) {
                if (value == floor(value) && fabs(value) < 1e15)
                    snprintf(shortest, sizeof shortest, "%.0f", value);
                else
                    snprintf(shortest, sizeof shortest, "%.*g", digits, value);
                if (strtod(shortest, NULL) == value)
                    break;
            }
            fputs(shortest, out);
            p = end;
            continue;
        }
        quoted ^= *p == '\'';
        fputc(*p++, out);
    }
}

/* What check found in the geometry, as YAML comments after the case. */
static void print_survey(const struct gsn_pre_survey *s)
{
    double count = s->particle_estimate; /* two digits are what it knows */
    if (count >= 100 && count < 1e6) {
        double unit = pow(10.0, floor(log10(count)) - 1.0);
        count = round(count / unit) * unit;
    }
    printf("# particles: %s %.*g (estimated from a coarse mesh of the %.4g "
           "m^3 body)",
           s->estimate_at_least ? "at least" : "about", count < 1e6 ? 6 : 3,
           count, s->volume);
    if (s->particle_estimate > GSN_DEFAULT_MAX_PARTICLES)
        printf("; more than %d: pre and run need --force",
               GSN_DEFAULT_MAX_PARTICLES);
    printf("\n# free surfaces (no entry under boundary:, traction-free): "
           "%s",
           s->free_surface_count ? s->free_surfaces : "none");
    if (s->unnamed_surface_count)
        printf("; and %d surface%s in no physical group",
               s->unnamed_surface_count,
               s->unnamed_surface_count > 1 ? "s" : "");
    printf("\n");
    if (!s->surfaces_meshed)
        printf("# surfaces not meshed at the spacing (too many particles)\n");
}

/* Checks every case file (each error printed, the first one returned) and
 * prints the resolved parameters of the good ones, with the particle
 * estimate and the surfaces left free. */
static int command_check(const struct arguments *a)
{
    int first_failure = GSN_OK;
    for (int i = 0; i < a->case_count; ++i) {
        struct gsn_case c;
        struct gsn_pre_survey survey;
        char *text = NULL;
        int rc = gsn_case_load(a->cases[i], &c);
        if (rc == GSN_OK)
            gsn_case_warn_implausible(&c, stderr);
        if (rc == GSN_OK)
            rc = gsn_pre_check_geometry(&c, 1, &survey);
        if (rc == GSN_OK && !a->quiet)
            rc = gsn_case_to_yaml_string(&c, &text);
        if (text) {
            print_readable(text, stdout);
            print_survey(&survey);
        }
        free(text);
        if (rc != GSN_OK && a->case_count > 1) {
            fprintf(stderr, "geoscni check: ");
            gsn_error_print_user(stderr, a->verbose);
            gsn_error_clear();
        }
        if (first_failure == GSN_OK)
            first_failure = rc;
        if (rc != GSN_OK && a->case_count == 1)
            return rc;
    }
    GSN_CHECK(first_failure == GSN_OK, first_failure,
              "some case files have errors (see above)");
    return GSN_OK;
}

/* Creates outdir and takes its lock (files.h, gsn_folder_lock): a second
 * geoscni that would write it is refused. The lock is held until the
 * process ends, so for the whole command. */
int app_lock_outdir(const char *outdir)
{
    int lock = -1;
    GSN_CALL(gsn_folder_prepare(outdir));
    GSN_CALL(gsn_folder_lock(outdir, &lock));
    return GSN_OK;
}

static int command_pre(const struct arguments *a)
{
    struct gsn_case c;
    char buffer[GSN_PATH_SIZE];
    GSN_CALL(gsn_case_load(a->cases[0], &c));
    gsn_case_warn_implausible(&c, stderr);
    const char *outdir = outdir_for(a, a->cases[0], buffer, sizeof buffer);
    GSN_CALL(app_lock_outdir(outdir));
    GSN_CALL(run_pre(&c, outdir, a));
    return GSN_OK;
}

static int command_solve(const struct arguments *a)
{
    struct gsn_case c;
    char buffer[GSN_PATH_SIZE];
    GSN_CALL(gsn_case_load(a->cases[0], &c));
    gsn_case_warn_implausible(&c, stderr);
    const char *outdir = outdir_for(a, a->cases[0], buffer, sizeof buffer);
    GSN_CALL(app_lock_outdir(outdir));
    GSN_CALL(run_solve(&c, outdir, a, a->restart));
    return GSN_OK;
}

static int command_post(const struct arguments *a)
{
    /* a folder that does not exist is post's own error (no results) */
    struct stat info;
    int lock = -1;
    if (stat(a->cases[0], &info) == 0 && S_ISDIR(info.st_mode))
        GSN_CALL(gsn_folder_lock(a->cases[0], &lock));
    GSN_CALL(run_post(a->cases[0], a));
    return GSN_OK;
}

/* 1 if a string attribute of an HDF5 file of the given kind equals value
 * (and, for an int attribute, if int_name is set, it equals 1). Any problem
 * reading it means "not up to date", never an error. */
static int file_attribute_matches(const char *path, const char *kind,
                                  const char *name, const char *value,
                                  const char *int_name)
{
    hid_t file = H5I_INVALID_HID;
    if (gsn_h5_open(path, kind, 0, &file) != GSN_OK) {
        gsn_error_clear();
        return 0;
    }
    char *stored = NULL;
    int flag = 1;
    int same = gsn_h5_attr_read_string(file, name, &stored) == GSN_OK &&
               strcmp(stored, value) == 0;
    if (same && int_name)
        same =
            gsn_h5_attr_read_int(file, int_name, &flag) == GSN_OK && flag == 1;
    free(stored);
    gsn_h5_close(&file);
    gsn_error_clear();
    return same;
}

/* The hash of path as text, "" if it cannot be read. */
static void hash_or_empty(const char *path, char out[GSN_FILE_HASH_SIZE])
{
    if (gsn_file_hash(path, out) != GSN_OK) {
        gsn_error_clear();
        out[0] = '\0';
    }
}

/* Whether a stage's output was made from the same parameters and from
 * inputs of the same contents (their hashes stored in the output: the
 * geometry's in model.h5, model.h5's in results.h5, results.h5's in the
 * .pvd), so that run can skip it. Modification times play no part: a
 * touched or copied file is not a changed one. */
static int stage_up_to_date(const char *stage, const struct gsn_case *c,
                            const char *outdir, const struct arguments *a)
{
    char model[GSN_PATH_SIZE + 16], results[GSN_PATH_SIZE + 16];
    char history[GSN_PATH_SIZE + 16], hash[GSN_FILE_HASH_SIZE];
    snprintf(model, sizeof model, "%s/model.h5", outdir);
    snprintf(results, sizeof results, "%s/results.h5", outdir);
    snprintf(history, sizeof history, "%s/history.csv", outdir);
    if (!strcmp(stage, "pre")) {
        char signature[GSN_PRE_SIGNATURE_SIZE];
        if (gsn_case_pre_signature(c, signature, sizeof signature) != GSN_OK) {
            gsn_error_clear();
            return 0;
        }
        hash_or_empty(c->geometry, hash);
        return hash[0] &&
               file_attribute_matches(model, GSN_FILE_KIND_MODEL,
                                      GSN_ATTR_PRE_SIGNATURE, signature,
                                      NULL) &&
               file_attribute_matches(model, GSN_FILE_KIND_MODEL,
                                      GSN_ATTR_GEOMETRY_HASH, hash, NULL);
    }
    if (!strcmp(stage, "solve")) {
        char *yaml = NULL;
        if (gsn_case_to_yaml_string(c, &yaml) != GSN_OK) {
            gsn_error_clear();
            return 0;
        }
        hash_or_empty(model, hash);
        int same =
            hash[0] && access(history, R_OK) == 0 &&
            file_attribute_matches(results, GSN_FILE_KIND_RESULTS,
                                   GSN_ATTR_CASE, yaml,
                                   GSN_RESULTS_ATTR_COMPLETE) &&
            file_attribute_matches(results, GSN_FILE_KIND_RESULTS,
                                   GSN_RESULTS_ATTR_MODEL_HASH, hash, NULL);
        free(yaml);
        return same;
    }
    struct gsn_post_options options = {.no_pictures = a->no_pictures};
    return gsn_post_up_to_date(outdir, &options);
}

static int run_skipped(const struct arguments *a, const char *stage,
                       const struct gsn_case *c, const char *outdir)
{
    if (a->rerun || !stage_up_to_date(stage, c, outdir, a))
        return 0;
    if (!a->quiet)
        printf("run: %s skipped: its output in %s was made from the same "
               "parameters and inputs of the same contents (--rerun to "
               "redo)\n",
               stage, outdir);
    return 1;
}

int app_pre(const struct arguments *a, const struct gsn_case *c,
            const char *outdir)
{
    if (!run_skipped(a, "pre", c, outdir))
        GSN_CALL(run_pre(c, outdir, a));
    return GSN_OK;
}

int app_run_case(const struct arguments *a, const struct gsn_case *c,
                 const char *outdir, int with_post, int *solved)
{
    GSN_CALL(app_pre(a, c, outdir));
    /* --restart over several cases: those an interrupt kept from starting
     * have no results to continue and start from the beginning */
    char results[GSN_PATH_SIZE], part[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(results, sizeof results, outdir, "results.h5"));
    GSN_CALL(gsn_path_temporary(part, sizeof part, results));
    int restart =
        a->restart && (access(results, F_OK) == 0 || access(part, F_OK) == 0);
    if (a->restart && !restart && !a->quiet)
        printf("run: %s has no run to restart in %s: solving from the start\n",
               c->path, outdir);
    int skipped = run_skipped(a, "solve", c, outdir);
    if (solved)
        *solved = !skipped;
    int rc = skipped ? GSN_OK : run_solve(c, outdir, a, restart);
    if (rc == GSN_ERR_NUMERICAL && with_post) {
        /* Show what the run reached before it failed, then fail. */
        fprintf(stderr, "geoscni run: ");
        gsn_error_print_user(stderr, a->verbose);
        fprintf(stderr, "geoscni run: post-processing the frames "
                        "written before the failure\n");
        gsn_error_clear();
        if (run_post(outdir, a) != GSN_OK) {
            gsn_error_print_user(stderr, a->verbose);
            gsn_error_clear();
        }
        GSN_CHECK(0, GSN_ERR_NUMERICAL,
                  "%s: the solver failed (see above); the frames before "
                  "the failure are in %s",
                  c->path, outdir);
    }
    GSN_CALL(rc);
    if (with_post && !run_skipped(a, "post", c, outdir))
        GSN_CALL(run_post(outdir, a));
    return GSN_OK;
}

static int command_run(const struct arguments *a)
{
    /* Every case file is checked before any work starts, and every output
     * folder locked: cases whose files have the same name would write one
     * folder, the second over the first, so they are refused. */
    static struct gsn_case cases[MAX_CASES];
    static char outdirs[MAX_CASES][GSN_PATH_SIZE];
    for (int i = 0; i < a->case_count; ++i) {
        GSN_CALL(gsn_case_load(a->cases[i], &cases[i]));
        gsn_case_warn_implausible(&cases[i], stderr);
        GSN_CALL(gsn_pre_check_geometry(&cases[i], 0, NULL));
        const char *outdir =
            outdir_for(a, a->cases[i], outdirs[i], sizeof outdirs[i]);
        if (outdir != outdirs[i])
            snprintf(outdirs[i], sizeof outdirs[i], "%s", outdir);
        for (int j = 0; j < i; ++j)
            GSN_CHECK(strcmp(outdirs[i], outdirs[j]) != 0, GSN_ERR_INPUT,
                      "%s and %s would both write to %s (the files have the "
                      "same name): rename one, or run them with separate "
                      "-o folders",
                      a->cases[j], a->cases[i], outdirs[i]);
    }
    for (int i = 0; i < a->case_count; ++i)
        GSN_CALL(app_lock_outdir(outdirs[i]));
    /* A case that fails does not stop the others, except an interrupt. */
    int first_failure = GSN_OK, failed = 0, ran = 0;
    for (int i = 0; i < a->case_count; ++i, ++ran) {
        const char *outdir = outdirs[i];
        int rc = app_run_case(a, &cases[i], outdir, 1, NULL);
        if (rc == GSN_OK)
            continue;
        if (a->case_count == 1)
            return rc;
        fprintf(stderr, "geoscni run: ");
        gsn_error_print_user(stderr, a->verbose);
        gsn_error_clear();
        failed++;
        if (first_failure == GSN_OK || rc == GSN_ERR_INTERRUPTED)
            first_failure = rc; /* an interrupt ends the batch with 130 */
        if (rc == GSN_ERR_INTERRUPTED) {
            ++ran;
            break;
        }
    }
    char not_run[64] = "";
    if (ran < a->case_count)
        snprintf(not_run, sizeof not_run, "; %d not run after the interrupt",
                 a->case_count - ran);
    GSN_CHECK(failed == 0, first_failure, "%d of %d cases failed (see above)%s",
              failed, a->case_count, not_run);
    return GSN_OK;
}

static const struct command commands[] = {
    {"pre", "geoscni pre CASE.yaml [-o OUTDIR] [--force]",
     "mesh the geometry and build the nodal domains: OUTDIR/model.h5",
     "  -o, --output DIR output folder (default: the case file's name)\n"
     "  --force          allow more than 5 million particles\n" THREADS_HELP,
     command_pre, 1, 1, "file", OPTION_OUTPUT | OPTION_FORCE | OPTION_THREADS},
    {"solve", "geoscni solve CASE.yaml [-o OUTDIR] [--restart] [--force]",
     "run the explicit dynamics: OUTDIR/results.h5 and history.csv",
     "  -o, --output DIR output folder holding model.h5\n"
     "  --restart        continue an interrupted solve from the checkpoint "
     "in results.h5\n"
     "  --force          accept a time step above the stable "
     "one\n" THREADS_HELP,
     command_solve, 1, 1, "file",
     OPTION_OUTPUT | OPTION_RESTART | OPTION_FORCE | OPTION_THREADS},
    {"post", "geoscni post OUTDIR [--no-pictures]",
     "write ParaView files (CASE.pvd, vtu/), plots and pictures",
     "  --no-pictures    skip the rendered PNG pictures\n", command_post, 1, 1,
     "folder", OPTION_NO_PICTURES},
    {"run", "geoscni run CASE.yaml [CASE2.yaml ...] [-o OUTDIR] [--restart]",
     "pre, solve and post for each case, each into its own folder, skipping "
     "a stage whose output was made from the same parameters and inputs of "
     "the same contents",
     "  -o, --output DIR output folder (with several cases: a folder per "
     "case inside it)\n"
     "  --restart        resume an interrupted solve from the checkpoint in "
     "results.h5 (as for solve)\n"
     "  --force          as for pre and solve\n"
     "  --no-pictures    as for post\n"
     "  --rerun          run every stage, also those whose output is up to "
     "date\n" THREADS_HELP,
     command_run, 1, MAX_CASES, "file",
     OPTION_OUTPUT | OPTION_RESTART | OPTION_FORCE | OPTION_NO_PICTURES |
         OPTION_RERUN | OPTION_THREADS},
    {"converge",
     "geoscni converge CASE.yaml [-o OUTDIR] [--levels N] [--ratio R] "
     "[--finest H] [--quantity Q] [--tol T]",
     "run the case at several spacings and give one number's converged "
     "value with its estimated error (Richardson), the order, and the "
     "coarsest spacing within a tolerance: OUTDIR/converge.csv and "
     "converge.png",
     "  -o, --output DIR output folder, a folder per level inside (default: "
     "CASE_converge)\n"
     "  --levels N       number of spacings, 3 to 8 (default 3)\n"
     "  --ratio R        each level's spacing over the next finer one's "
     "(default 1.5)\n"
     "  --finest H       the finest level's particles.spacing in m (default: "
     "the case's; refinement zones scale with it)\n"
     "  --quantity Q     peak_force[:SURFACE] (default: on the entry the "
     "case moves; its pressure where the surface's area follows the "
     "spacing), force_at:SETTLEMENT[:SURFACE] (m), peak_pressure or "
     "pressure_at (the force over the surface's area), "
     "displacement_at:X,Y,Z (m, at the end)\n"
     "  --tol T          the error asked for: a fraction or a percentage "
     "(default 2%)\n"
     "  --force          as for pre and solve\n"
     "  --no-pictures    no chart\n" THREADS_HELP,
     command_converge, 1, 1, "file",
     OPTION_OUTPUT | OPTION_FORCE | OPTION_NO_PICTURES | OPTION_THREADS |
         OPTION_LEVELS | OPTION_RATIO | OPTION_QUANTITY | OPTION_TOLERANCE |
         OPTION_FINEST},
    {"fos", "geoscni fos CASE.yaml [-o OUTDIR] [--tol T] [--rerun]",
     "the factor of safety of the body under its own weight by strength "
     "reduction (c and tan(phi) divided by trial factors): a line 'factor "
     "of safety: X.XX', OUTDIR/fos.csv and the mechanism's pictures in "
     "OUTDIR/mechanism",
     "  -o, --output DIR output folder, a folder per trial in trials/ "
     "(default: CASE_fos)\n"
     "  --tol T          the width of the final bracket: the factor the body "
     "stands at and the one it fails at lie T apart at most (default "
     "0.01)\n"
     "  --rerun          run every trial again (else those in fos.csv made "
     "from the same model and strength are kept)\n"
     "  --force          as for pre and solve\n"
     "  --no-pictures    no pictures of the mechanism\n" THREADS_HELP,
     command_fos, 1, 1, "file",
     OPTION_OUTPUT | OPTION_FORCE | OPTION_NO_PICTURES | OPTION_THREADS |
         OPTION_TOLERANCE | OPTION_RERUN},
    {"ground",
     "geoscni ground GRID.xyz --layers NAME:T,...,NAME --base Z [-o SITE.geo] "
     "[--every N]",
     "a gmsh geometry of layered ground from survey data: a grid of "
     "elevations (lines 'x y z'), the layers under it and a level base; "
     "named surfaces (ground, base, xmin, xmax, ymin, ymax) and a volume per "
     "layer (docs/site.md)",
     "  --layers LIST    the layers top down, comma-separated: NAME:T (T m "
     "thick under the one above), NAME:FILE.xyz (down to the elevations of "
     "that grid), and last a NAME alone (down to the base)\n"
     "  --base Z         the elevation of the level bottom, m\n"
     "  -o, --output F   the .geo to write (default: GRID.geo)\n"
     "  --every N        every N-th grid line only (a coarser ground: the "
     "grid's spacing bounds the particle spacing near it)\n",
     command_ground, 1, 1, "file",
     OPTION_OUTPUT | OPTION_LAYERS | OPTION_BASE | OPTION_EVERY},
    {"check", "geoscni check CASE.yaml [CASE2.yaml ...]",
     "check case files (also against their geometries, meshing their "
     "surfaces) and print their resolved parameters, the particle estimate "
     "and the surfaces left free",
     "", command_check, 1, MAX_CASES, "file", 0},
};
enum { COMMAND_COUNT = sizeof commands / sizeof commands[0] };

static void print_usage(FILE *out)
{
    fprintf(out,
            "geoscni %s: 3D meshfree (RK + SCNI) simulation of soil slope "
            "failure\n\nusage: geoscni COMMAND [options]\n\ncommands:\n",
            gsn_code_version());
    for (int i = 0; i < COMMAND_COUNT; ++i)
        fprintf(out, "  %-8s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n  geoscni COMMAND --help   options of a command\n"
                 "  geoscni --version        versions of geoscni and its "
                 "libraries\n\nexit status: 0 success, 2 bad input, 3 "
                 "numerical failure, 1 other failure\n");
}

static void print_command_help(const struct command *command)
{
    printf("usage: %s\n\n%s\n\noptions:\n%s%s", command->usage,
           command->summary, command->options, general_options);
    if (command->option_mask & (OPTION_OUTPUT | OPTION_THREADS))
        printf("a value may also follow '=' or the letter: --output=DIR, "
               "-oDIR, --threads=2, -j2\n");
}

static int print_version(void)
{
    char gmsh_version[64] = "unknown";
    unsigned major = 0, minor = 0, release = 0;
    H5get_libversion(&major, &minor, &release);
    printf("geoscni %s\nbuilt with: %s\n", gsn_code_version(),
           gsn_library_versions());
    int rc = gsn_pre_gmsh_version(gmsh_version, sizeof gmsh_version);
    if (rc != GSN_OK)
        gsn_error_clear();
    printf("loaded: gmsh %s, HDF5 %u.%u.%u, VTK %s\n", gmsh_version, major,
           minor, release, gsn_post_vtk_version());
    return 0;
}

static int usage_error(const struct command *command, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static int usage_error(const struct command *command, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fprintf(stderr, "geoscni: ");
    vfprintf(stderr, format, args);
    va_end(args);
    if (command)
        fprintf(stderr, "\nusage: %s\n(see geoscni %s --help)\n",
                command->usage, command->name);
    else
        fprintf(stderr, "\nusage: geoscni COMMAND [options]\n(see geoscni "
                        "--help)\n");
    return 2;
}

/* The option arg names, or NULL; *value is what follows '=' in
 * --name=value or the letter in -jN, NULL if nothing does. */
static const struct option *find_option(const char *arg, const char **value)
{
    *value = NULL;
    for (int k = 0; k < OPTION_COUNT; ++k) {
        const struct option *o = &command_options[k];
        size_t n = strlen(o->long_name);
        if (!strncmp(arg, o->long_name, n) &&
            (arg[n] == '\0' || arg[n] == '=')) {
            *value = arg[n] == '=' ? arg + n + 1 : NULL;
            return o;
        }
        if (o->short_name && !strncmp(arg, o->short_name, 2) &&
            (arg[2] == '\0' || o->value)) {
            *value = arg[2] != '\0' ? arg + 2 : NULL;
            return o;
        }
    }
    return NULL;
}

static int parse_arguments(const struct command *command, int argc, char **argv,
                           struct arguments *a, int *help)
{
    for (int i = 2; i < argc; ++i) {
        const char *arg = argv[i], *value = NULL;
        if (arg[0] != '-' || arg[1] == '\0') {
            if (a->case_count >= MAX_CASES)
                return usage_error(command, "too many %ss (%s)",
                                   command->operand, arg);
            a->cases[a->case_count++] = arg;
            continue;
        }
        const struct option *o = find_option(arg, &value);
        if (!o)
            return usage_error(command, "unknown option '%s'", arg);
        if (!(o->bit & (command->option_mask | OPTION_GENERAL))) {
            if (arg[1] == '-')
                return usage_error(command, "%s does not take %s",
                                   command->name, o->long_name);
            return usage_error(command, "%s does not take %s (%s)",
                               command->name, o->short_name, o->long_name);
        }
        if (!o->value && value)
            return usage_error(command, "%s takes no value ('%s')",
                               o->long_name, arg);
        if (o->value && !value) {
            if (i + 1 >= argc)
                return usage_error(command, "%s needs %s", arg, o->value);
            value = argv[++i];
        }
        if (o->bit == OPTION_HELP) {
            *help = 1;
        } else if (o->bit == OPTION_QUIET) {
            a->quiet = 1;
        } else if (o->bit == OPTION_VERBOSE) {
            a->verbose = 1;
        } else if (o->bit == OPTION_OUTPUT) {
            if (!value[0])
                return usage_error(command, "%s needs a folder", arg);
            a->outdir = value;
        } else if (o->bit == OPTION_THREADS) {
            char *end = NULL;
            long threads = strtol(value, &end, 10);
            if (end == value || *end != '\0' || threads < 1 ||
                threads > 1 << 20)
                return usage_error(command,
                                   "bad thread count '%s': give a whole "
                                   "number of at least 1",
                                   value);
            a->threads = (int)threads;
        } else if (o->bit == OPTION_FORCE) {
            a->force = 1;
        } else if (o->bit == OPTION_RESTART) {
            a->restart = 1;
        } else if (o->bit == OPTION_RERUN) {
            a->rerun = 1;
        } else if (o->bit == OPTION_NO_PICTURES) {
            a->no_pictures = 1;
        } else if (o->bit == OPTION_QUANTITY) {
            a->quantity = value;
        } else if (o->bit == OPTION_LAYERS) {
            a->layers = value;
        } else if (o->bit == OPTION_BASE || o->bit == OPTION_EVERY) {
            char *end = NULL;
            double number = strtod(value, &end);
            if (end == value || *end != '\0' || !isfinite(number) ||
                (o->bit == OPTION_EVERY &&
                 (number < 1 || number > 1e6 || number != floor(number))))
                return usage_error(command, "bad value '%s' of %s", value,
                                   o->long_name);
            if (o->bit == OPTION_BASE) {
                a->base = number;
                a->has_base = 1;
            } else
                a->every = (int)number;
        } else if (o->bit & (OPTION_LEVELS | OPTION_RATIO | OPTION_TOLERANCE |
                             OPTION_FINEST)) {
            char *end = NULL;
            double number = strtod(value, &end);
            int percent = o->bit == OPTION_TOLERANCE && end && *end == '%';
            if (end == value ||
                (*end != '\0' && !(percent && end[1] == '\0')) ||
                !(number > 0.0) || !isfinite(number) ||
                (o->bit == OPTION_LEVELS && number != floor(number)))
                return usage_error(command, "bad value '%s' of %s", value,
                                   o->long_name);
            if (o->bit == OPTION_LEVELS)
                a->levels = number > 1e6 ? 1000000 : (int)number;
            else if (o->bit == OPTION_RATIO)
                a->ratio = number;
            else if (o->bit == OPTION_FINEST)
                a->finest = number;
            else
                a->tolerance = percent ? number / 100.0 : number;
        }
    }
    return 0;
}

/* OpenMP threads that wait at a barrier spin first (libgomp: 300,000 turns)
 * and starve each other when other work holds the cores: 386 steps of the
 * coarse slope on 2 threads beside two busy processes took 39 s, against 6 s
 * on one thread and 4.8 s with a spin of 3,000 turns, which costs nothing on
 * idle cores (7.72 s against 7.67 s, medians of 5). libgomp reads its
 * environment when it loads, so geoscni runs itself again with
 * GOMP_SPINCOUNT=3000, unless the user set the wait policy. */
static void exec_with_short_spin(char **argv)
{
    /* Under valgrind /proc/self/exe is valgrind's tool, not geoscni. */
    const char *preload = getenv("LD_PRELOAD");
    if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT") ||
        (preload && strstr(preload, "vgpreload")) ||
        setenv("GOMP_SPINCOUNT", "3000", 1) != 0)
        return;
    execv("/proc/self/exe", argv);
    /* exec failed: go on with libgomp's default spin */
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
        print_usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version"))
        return print_version();

    const struct command *command = NULL;
    for (int i = 0; i < COMMAND_COUNT; ++i)
        if (!strcmp(argv[1], commands[i].name))
            command = &commands[i];
    if (!command)
        return usage_error(NULL, "unknown command '%s'", argv[1]);

    struct arguments a = {0};
    int help = 0;
    int status = parse_arguments(command, argc, argv, &a, &help);
    if (status != 0)
        return status;
    if (help) {
        print_command_help(command);
        return 0;
    }
    if (a.case_count < command->min_cases)
        return usage_error(command, "%s needs a %s", command->name,
                           command->operand);
    if (a.case_count > command->max_cases)
        return usage_error(command, "%s takes one %s", command->name,
                           command->operand);

    /* every command: fos and converge solve too (the tests of fos and
     * fos_site beside each other on 2 cores: 203 s with libgomp's default
     * spin, 94 s with this one, measured 2026-12-04) */
    exec_with_short_spin(argv);
    int rc = command->run(&a);
    if (rc != GSN_OK) {
        fprintf(stderr, "geoscni %s: ", command->name);
        gsn_error_print_user(stderr, a.verbose);
        /* HDF5 1.10 crashes at exit (H5F__close_cb) on a file whose close
         * failed, as on a full disk: end without its exit handlers */
        if (rc == GSN_ERR_NO_SPACE) {
            fflush(NULL);
            _exit(gsn_error_exit_status(rc));
        }
        return gsn_error_exit_status(rc);
    }
    return 0;
}
