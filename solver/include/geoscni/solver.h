/* solver: model.h5 -> explicit large-deformation dynamics -> results.h5 and
 * history.csv (DESIGN.md, "Pipeline"). */
#ifndef GEOSCNI_SOLVER_H
#define GEOSCNI_SOLVER_H

#include "geoscni/case.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_solve_options {
    int force;      /* accept a time step above the stable one, and a
                       memory need above what is available */
    int restart;    /* continue from the checkpoint in results.h5 */
    int threads;    /* 0: OpenMP's default */
    int quiet;      /* no progress line */
    int start_over; /* replace an interrupted run's results (else refused) */
    double progress_seconds; /* between progress lines into a file (0: the
                                default, 10 s) */
    int setup_warned;   /* the set-up's warnings were given by an earlier run
                           of the same model: not again */
    int geostatic_only; /* the geostatic stage alone: results.h5 holds its
                           end state (displacements not reset) as the one
                           frame; exit 3 if it found no rest (geoscni fos) */
};

/* Reads OUTDIR/model.h5, runs the case, writes OUTDIR/results.h5 and
 * OUTDIR/history.csv. */
int gsn_solve_run(const struct gsn_case *c, const char *outdir,
                  const struct gsn_solve_options *options);

#ifdef __cplusplus
}
#endif
#endif
