/* Gradient rows regrouped for one pass per step (issue 5, point 7).
 *
 * The points are cut into fixed blocks of consecutive points (the cut does
 * not depend on the thread count). Each block lists the particles its rows
 * touch (its slots), and every row entry carries its slot, so a block can
 * gather the displacement increments of its slots, compute its points'
 * stress, and scatter their forces P g into its own slots, reading the
 * gradients once. A reduction then adds the slots of every particle in
 * block order: the same sums, bit for bit, on any number of threads. */
#ifndef GEOSCNI_POINT_BLOCKS_H
#define GEOSCNI_POINT_BLOCKS_H

#include "geoscni/kernels.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_point_blocks {
    int block_count;
    int main_block_count; /* blocks [0, this) hold the points before split */
    int *block_point;     /* block_count + 1: the points of each block */
    int *block_slot;      /* block_count + 1: the slots of each block */
    int *slot_particle;   /* slots: the particle of each */
    int *entry_slot;      /* gradient entries: the slot of each, in its block */
    int *particle_slot_offset; /* particles + 1 */
    int *particle_slot;        /* the slots of each particle, ascending */
    int max_block_slots;       /* the most slots of one block */
};

/* Cuts points [0, point_count) of the rows into blocks of at most
 * block_size points, with a cut also at split (main and stabilization
 * points apart). */
int gsn_point_blocks_create(const struct gsn_shape_rows *rows,
                            int particle_count, int block_size, int split,
                            struct gsn_point_blocks **out);

/* Frees; NULL-safe, nulls the handle. */
void gsn_point_blocks_destroy(struct gsn_point_blocks **blocks);

/* force_I = sum over the slots of I of slot_force (slots x 3), in slot
 * order. OpenMP over particles when worth it. */
void gsn_point_blocks_reduce(const struct gsn_point_blocks *blocks,
                             int particle_count, const double *slot_force,
                             double *force, int parallel);

#ifdef __cplusplus
}
#endif
#endif
