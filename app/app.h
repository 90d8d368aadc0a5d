/* What the commands of app/ share: the parsed command line, and one case
 * through the stages. */
#ifndef GEOSCNI_APP_H
#define GEOSCNI_APP_H

#include "geoscni/case.h"

#include <time.h>

enum { MAX_CASES = 64 };

struct arguments {
    const char *cases[MAX_CASES];
    int case_count;
    const char *outdir;
    int force, restart, quiet, no_pictures, threads, rerun, verbose;
    /* converge */
    int levels;           /* 0: the default */
    double ratio;         /* 0: the default */
    double tolerance;     /* relative; 0: the default */
    double finest;        /* m; 0: the case's particles.spacing */
    const char *quantity; /* NULL: the default */
    /* ground */
    const char *layers; /* --layers */
    double base;        /* --base, m */
    int has_base, every;
};

/* Prepares and locks an output folder for this process. */
int app_lock_outdir(const char *outdir);

/* One case through pre, solve and (with_post) post, each skipped where its
 * output is up to date; after a numerical failure the frames written before
 * it are post-processed (with_post), then the failure returned. *solved
 * (may be NULL): 1 if the solve ran, 0 if it was skipped. */
int app_run_case(const struct arguments *a, const struct gsn_case *c,
                 const char *outdir, int with_post, int *solved);

/* The time of a clock (CLOCK_MONOTONIC: wall; CLOCK_PROCESS_CPUTIME_ID:
 * CPU), s. */
double app_seconds(clockid_t clock);

/* pre of one case into outdir, skipped where its model.h5 is up to date */
int app_pre(const struct arguments *a, const struct gsn_case *c,
            const char *outdir);

/* geoscni converge (app/converge.c) */
int command_converge(const struct arguments *a);

/* geoscni fos (app/fos.c) */
int command_fos(const struct arguments *a);

/* The factor of safety of case c (its strength reduced by trial factors,
 * c left as it was) into outdir (locked by the caller): pre where needed, the
 * trials (those of an earlier study of the same model and strength kept), the
 * mechanism's post; prints 'factor of safety: X.XX'. *result: the bracket's
 * middle; *trials_run: the trials this call ran. */
int app_fos_study(const struct arguments *a, struct gsn_case *c,
                  const char *outdir, double *result, int *trials_run);

/* geoscni ground (app/ground.c) */
int command_ground(const struct arguments *a);

#endif
