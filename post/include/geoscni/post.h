/* post: results.h5 -> ParaView files (.pvd + vtu/), plots and pictures
 * (DESIGN.md, "What a run leaves"). */
#ifndef GEOSCNI_POST_H
#define GEOSCNI_POST_H

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_post_options {
    int no_pictures; /* skip the rendered PNGs */
    int quiet;
};

/* Turns OUTDIR/results.h5 and OUTDIR/model.h5 into OUTDIR/CASE.pvd,
 * OUTDIR/vtu/ and the plots. */
int gsn_post_run(const char *outdir, const struct gsn_post_options *options);

/* 1 if OUTDIR/CASE.pvd was written by post from the results.h5 now in
 * OUTDIR (its contents' hash, stored in the .pvd) with the pictures the
 * options ask for; 0 otherwise, and for any problem reading. */
int gsn_post_up_to_date(const char *outdir,
                        const struct gsn_post_options *options);

/* The chart of `geoscni converge` (docs/converge.md): the estimated error
 * of each level's value (percent of the converged value) against its CPU
 * time, both axes logarithmic, with the tolerance as a line and, where
 * predicted_count > 1, the error a study ending at a finer level would have
 * against its time; written to path (a PNG, atomically). Without an X
 * display it writes nothing, says why on stderr and returns GSN_OK. */
int gsn_post_convergence_chart(const char *path, const char *title,
                               int level_count, const double *cpu_seconds,
                               const double *error_percent, int predicted_count,
                               const double *predicted_seconds,
                               const double *predicted_percent,
                               double tolerance_percent);

/* The VTK version loaded at run time, e.g. "9.1.0". */
const char *gsn_post_vtk_version(void);

#ifdef __cplusplus
}
#endif
#endif
