/* results.h5: frames written by the solver as it runs (each frame a group,
 * flushed when written, so the frames of a run that stops stay readable)
 * and read one at a time by post, so memory stays bounded by one frame. */
#ifndef GEOSCNI_RESULTS_H
#define GEOSCNI_RESULTS_H

#include "geoscni/h5io.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One frame: field[f] is particle_count x gsn_frame_fields[f].columns. */
struct gsn_frame {
    double time; /* s */
    int step;
    int particle_count;
    double *field[GSN_FRAME_FIELD_COUNT];
    /* bit f: field f is written (output.fields) or was read; the others
     * are left out of the file (their arrays stay allocated) */
    unsigned present;
};

/* Allocates the fields of a frame of particle_count particles (zeroed),
 * every field present. */
int gsn_frame_allocate(struct gsn_frame *frame, int particle_count);

/* Frees the fields and zeroes the struct; accepts a zeroed struct. */
void gsn_frame_free(struct gsn_frame *frame);

/* Appends frame number index (0, 1, 2, ... in order) with its present
 * fields and flushes the file. */
int gsn_results_frame_write(hid_t file, int index,
                            const struct gsn_frame *frame);

/* Number of complete frames in the file. */
int gsn_results_frame_count(hid_t file, int *count);

/* Deletes the frames written after the given step and sets *count to the
 * frames left: a restart from a checkpoint at that step writes them again
 * (a run stopped between checkpoints leaves such frames behind); *last_step
 * (may be NULL) is the step of the last frame left, -1 if none. */
int gsn_results_frames_drop_after(hid_t file, int step, int *count,
                                  int *last_step);

/* Reads frame index into a frame allocated for the file's particle count;
 * frame->present says which fields the file holds (the others are zeroed). */
int gsn_results_frame_read(hid_t file, int index, struct gsn_frame *frame);

#ifdef __cplusplus
}
#endif
#endif
