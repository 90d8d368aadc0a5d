/* geoscni: the command-line program. Subcommands pre, solve, post, run and
 * check; exit status 0 ok, 2 bad input, 3 numerical failure (DESIGN.md). */
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/h5io.h"
#include "geoscni/post.h"
#include "geoscni/pre.h"
#include "geoscni/solver.h"
#include "geoscni/version.h"

#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { MAX_CASES = 64 };

struct arguments {
    const char *cases[MAX_CASES];
    int case_count;
    const char *outdir;
    int force, restart, quiet, no_pictures, threads, rerun;
};

struct command {
    const char *name;
    const char *usage;
    const char *summary;
    const char *options;
    int (*run)(const struct arguments *a);
    int min_cases, max_cases;
};

static const char general_options[] =
    "  -h, --help       this help\n"
    "  -q, --quiet      no progress output\n"
    "  -j, --threads N  OpenMP threads (default: all cores)\n";

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
                     const struct arguments *a)
{
    struct gsn_solve_options options = {.force = a->force,
                                        .restart = a->restart,
                                        .threads = a->threads,
                                        .quiet = a->quiet};
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

static int command_check(const struct arguments *a)
{
    for (int i = 0; i < a->case_count; ++i) {
        struct gsn_case c;
        GSN_CALL(gsn_case_load(a->cases[i], &c));
        GSN_CALL(gsn_pre_check_geometry(&c));
        if (!a->quiet)
            GSN_CALL(gsn_case_write_yaml(&c, stdout));
    }
    return GSN_OK;
}

static int command_pre(const struct arguments *a)
{
    struct gsn_case c;
    char buffer[GSN_PATH_SIZE];
    GSN_CALL(gsn_case_load(a->cases[0], &c));
    GSN_CALL(run_pre(&c, outdir_for(a, a->cases[0], buffer, sizeof buffer), a));
    return GSN_OK;
}

static int command_solve(const struct arguments *a)
{
    struct gsn_case c;
    char buffer[GSN_PATH_SIZE];
    GSN_CALL(gsn_case_load(a->cases[0], &c));
    GSN_CALL(
        run_solve(&c, outdir_for(a, a->cases[0], buffer, sizeof buffer), a));
    return GSN_OK;
}

static int command_post(const struct arguments *a)
{
    GSN_CALL(run_post(a->cases[0], a));
    return GSN_OK;
}

/* 1 if path exists and was modified no earlier than reference (which must
 * exist too). */
static int newer_than(const char *path, const char *reference)
{
    struct stat a, b;
    if (stat(path, &a) != 0 || stat(reference, &b) != 0)
        return 0;
    if (a.st_mtim.tv_sec != b.st_mtim.tv_sec)
        return a.st_mtim.tv_sec > b.st_mtim.tv_sec;
    return a.st_mtim.tv_nsec >= b.st_mtim.tv_nsec;
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

/* Whether a stage's output is newer than its inputs and was made from the
 * same parameters, so that run can skip it. */
static int stage_up_to_date(const char *stage, const struct gsn_case *c,
                            const char *outdir)
{
    char model[GSN_PATH_SIZE + 16], results[GSN_PATH_SIZE + 16];
    char pvd[2 * GSN_PATH_SIZE + 8], name[GSN_PATH_SIZE];
    snprintf(model, sizeof model, "%s/model.h5", outdir);
    snprintf(results, sizeof results, "%s/results.h5", outdir);
    if (!strcmp(stage, "pre")) {
        char signature[GSN_PRE_SIGNATURE_SIZE];
        if (gsn_case_pre_signature(c, signature, sizeof signature) != GSN_OK) {
            gsn_error_clear();
            return 0;
        }
        return newer_than(model, c->geometry) &&
               file_attribute_matches(model, GSN_FILE_KIND_MODEL,
                                      GSN_ATTR_PRE_SIGNATURE, signature, NULL);
    }
    if (!strcmp(stage, "solve")) {
        char *yaml = NULL;
        if (gsn_case_to_yaml_string(c, &yaml) != GSN_OK) {
            gsn_error_clear();
            return 0;
        }
        int same = newer_than(results, model) &&
                   file_attribute_matches(results, GSN_FILE_KIND_RESULTS,
                                          GSN_ATTR_CASE, yaml,
                                          GSN_RESULTS_ATTR_COMPLETE);
        free(yaml);
        return same;
    }
    gsn_case_name(c->path, name, sizeof name);
    snprintf(pvd, sizeof pvd, "%s/%s.pvd", outdir, name);
    return newer_than(pvd, results);
}

static int run_skipped(const struct arguments *a, const char *stage,
                       const struct gsn_case *c, const char *outdir)
{
    if (a->rerun || !stage_up_to_date(stage, c, outdir))
        return 0;
    if (!a->quiet)
        printf("run: %s skipped: its output in %s is newer than its inputs "
               "and was made from the same parameters (--rerun to redo)\n",
               stage, outdir);
    return 1;
}

static int command_run(const struct arguments *a)
{
    /* Every case file is checked before any work starts. */
    static struct gsn_case cases[MAX_CASES];
    for (int i = 0; i < a->case_count; ++i) {
        GSN_CALL(gsn_case_load(a->cases[i], &cases[i]));
        GSN_CALL(gsn_pre_check_geometry(&cases[i]));
    }
    for (int i = 0; i < a->case_count; ++i) {
        char buffer[GSN_PATH_SIZE];
        const char *outdir = outdir_for(a, a->cases[i], buffer, sizeof buffer);
        if (!run_skipped(a, "pre", &cases[i], outdir))
            GSN_CALL(run_pre(&cases[i], outdir, a));
        int rc = run_skipped(a, "solve", &cases[i], outdir)
                     ? GSN_OK
                     : run_solve(&cases[i], outdir, a);
        if (rc == GSN_ERR_NUMERICAL) {
            /* Show what the run reached before it failed, then fail. */
            fprintf(stderr, "geoscni run: ");
            gsn_error_print(stderr);
            fprintf(stderr, "geoscni run: post-processing the frames "
                            "written before the failure\n");
            gsn_error_clear();
            if (run_post(outdir, a) != GSN_OK) {
                gsn_error_print(stderr);
                gsn_error_clear();
            }
            GSN_CHECK(0, GSN_ERR_NUMERICAL,
                      "%s: the solver failed (see above); the frames before "
                      "the failure are in %s",
                      cases[i].path, outdir);
        }
        GSN_CALL(rc);
        if (!run_skipped(a, "post", &cases[i], outdir))
            GSN_CALL(run_post(outdir, a));
    }
    return GSN_OK;
}

static const struct command commands[] = {
    {"pre", "geoscni pre CASE.yaml [-o OUTDIR] [--force]",
     "mesh the geometry and build the nodal domains: OUTDIR/model.h5",
     "  -o, --output DIR output folder (default: the case file's name)\n"
     "  --force          allow more than 5 million particles\n",
     command_pre, 1, 1},
    {"solve", "geoscni solve CASE.yaml [-o OUTDIR] [--restart] [--force]",
     "run the explicit dynamics: OUTDIR/results.h5 and history.csv",
     "  -o, --output DIR output folder holding model.h5\n"
     "  --restart        continue from the checkpoint in results.h5\n"
     "  --force          accept a time step above the stable one\n",
     command_solve, 1, 1},
    {"post", "geoscni post OUTDIR [--no-pictures]",
     "write ParaView files (CASE.pvd, vtu/), plots and pictures",
     "  --no-pictures    skip the rendered PNG pictures\n", command_post, 1, 1},
    {"run", "geoscni run CASE.yaml [CASE2.yaml ...] [-o OUTDIR]",
     "pre, solve and post for each case, each into its own folder, skipping "
     "a stage whose output is newer than its inputs and made from the same "
     "parameters",
     "  -o, --output DIR output folder (with several cases: a folder per "
     "case inside it)\n"
     "  --force          as for pre and solve\n"
     "  --no-pictures    as for post\n"
     "  --rerun          run every stage, also those whose output is up to "
     "date\n",
     command_run, 1, MAX_CASES},
    {"check", "geoscni check CASE.yaml [CASE2.yaml ...]",
     "check case files (also against their geometries, without meshing) "
     "and print their resolved parameters",
     "", command_check, 1, MAX_CASES},
};
enum { COMMAND_COUNT = sizeof commands / sizeof commands[0] };

static void print_usage(FILE *out)
{
    fprintf(out,
            "geoscni %s: 3D meshfree (RK + SCNI) simulation of soil slope "
            "failure\n\nusage: geoscni COMMAND [options]\n\ncommands:\n",
            gsn_code_version());
    for (int i = 0; i < COMMAND_COUNT; ++i)
        fprintf(out, "  %-6s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n  geoscni COMMAND --help   options of a command\n"
                 "  geoscni --version        versions of geoscni and its "
                 "libraries\n\nexit status: 0 success, 2 bad input, 3 "
                 "numerical failure, 1 other failure\n");
}

static void print_command_help(const struct command *command)
{
    printf("usage: %s\n\n%s\n\noptions:\n%s%s", command->usage,
           command->summary, command->options, general_options);
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

static int usage_error(const char *format, const char *detail,
                       const struct command *command)
{
    fprintf(stderr, "geoscni: ");
    fprintf(stderr, format, detail);
    fprintf(stderr, "\nusage: %s\n(see geoscni %s --help)\n",
            command ? command->usage : "geoscni COMMAND [options]",
            command ? command->name : "");
    return 2;
}

static int parse_arguments(const struct command *command, int argc, char **argv,
                           struct arguments *a, int *help)
{
    for (int i = 2; i < argc; ++i) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            *help = 1;
        } else if (!strcmp(arg, "-o") || !strcmp(arg, "--output")) {
            if (i + 1 >= argc)
                return usage_error("%s needs a folder", arg, command);
            a->outdir = argv[++i];
        } else if (!strcmp(arg, "-j") || !strcmp(arg, "--threads")) {
            char *end = NULL;
            if (i + 1 >= argc)
                return usage_error("%s needs a number", arg, command);
            a->threads = (int)strtol(argv[++i], &end, 10);
            if (*end != '\0' || a->threads < 1)
                return usage_error("bad thread count '%s'", argv[i], command);
        } else if (!strcmp(arg, "--force")) {
            a->force = 1;
        } else if (!strcmp(arg, "--restart")) {
            a->restart = 1;
        } else if (!strcmp(arg, "-q") || !strcmp(arg, "--quiet")) {
            a->quiet = 1;
        } else if (!strcmp(arg, "--rerun")) {
            a->rerun = 1;
        } else if (!strcmp(arg, "--no-pictures")) {
            a->no_pictures = 1;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            return usage_error("unknown option '%s'", arg, command);
        } else {
            if (a->case_count >= MAX_CASES)
                return usage_error("too many files (%s)", arg, command);
            a->cases[a->case_count++] = arg;
        }
    }
    return 0;
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
        return usage_error("unknown command '%s'", argv[1], NULL);

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
        return usage_error("%s needs a file", command->name, command);
    if (a.case_count > command->max_cases)
        return usage_error("%s takes one file", command->name, command);

    int rc = command->run(&a);
    if (rc != GSN_OK) {
        fprintf(stderr, "geoscni %s: ", command->name);
        gsn_error_print(stderr);
        return gsn_error_exit_status(rc);
    }
    return 0;
}
