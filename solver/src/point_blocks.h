/* Gradient rows regrouped for one pass per step (issue 5, point 7).
 *
 * The main integration points (the nodal points, one per particle, or the
 * Gauss points) are cut into fixed blocks of consecutive points (the cut
 * does not depend on the thread count). A block holds its main points and,
 * with MSCNI, their stabilization points (S per nodal point). Each block
 * lists the particles its rows touch (its slots), and its rows are
 * copied into one packed stream in block order, every entry with its slot
 * and its three gradient components, so a block gathers the displacement
 * increments of its slots, computes its points' stress, and scatters their
 * forces P g into its own slots, reading its stretch of the stream once. A
 * reduction then adds the slots of every particle in block order: the same
 * sums, bit for bit, on any number of threads.
 *
 * MSCNI's stabilization rows are stored as B_s alone, not as the quadrature's
 * B_s - B_L (which holds the union of both supports, about twice the
 * entries): the solver forms (B_s - B_L) d as B_s d - B_L d with the B_L d
 * of the particle's nodal point, and folds the forces -B_L^T P_s of the
 * sub-cells into the nodal point's P (docs/solver.md, "Speed"). B_s is
 * recovered exactly where B_L has no entry, and to round-off elsewhere, as
 * (B_s - B_L) + B_L; entries that come out exactly zero are left out.
 *
 * NSNI's three rows of a nodal point, d/dX_k grad Psi_I(X_L), have the same
 * particles, all of them (or nearly: zero gradients are added) in the main
 * row's: they ride on the main row (fused). Its entries are ordered with
 * the particles of the NSNI rows first, and those carry the six values of
 * the symmetric second derivatives d^2 Psi_I / dX_j dX_k besides the
 * gradient, so a block gathers each particle's increment once for all four
 * rows and scatters the four points' forces together (issue 17): 73
 * entries a nodal point on Slope I instead of 73 + 3 x 32. */
#ifndef GEOSCNI_POINT_BLOCKS_H
#define GEOSCNI_POINT_BLOCKS_H

#include "geoscni/kernels.h"

#include <stdint.h>

/* Slots of one block at most: entry_slot is 16 bits (2 bytes an entry
 * instead of 4, of the 26 the stream reads per entry). */
#define GSN_POINT_BLOCKS_MAX_SLOTS 65536

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_point_blocks {
    int block_count;
    int subcells;       /* stabilization points per main point, or 0 */
    int relative;       /* 1: MSCNI, the rows act as B_s - B_L (below);
                           0: NSNI, as they are */
    int fused;          /* 1: NSNI, its rows ride on the main rows (above):
                           one packed row per main point */
    int *block_point;   /* block_count + 1: the main points of each block */
    int *block_slot;    /* block_count + 1: the slots of each block */
    int *slot_particle; /* slots: the particle of each */
    /* Packed rows: block k holds the rows of its main points p0..p1-1,
     * then their stabilization rows (S per point, in sub-cell order);
     * row r has entries row_start[r] .. row_start[r+1]-1. */
    int *row_start;         /* main points x (1 + subcells) + 1 */
    uint16_t *entry_slot;   /* the slot of each entry, within its block */
    double *entry_gradient; /* 3 per entry: dPsi_I/dX_j, 1/m */
    /* fused: the first row_hessian_start[r+1] - row_hessian_start[r]
     * entries of row r carry second derivatives, 6 each from
     * entry_hessian[6 row_hessian_start[r]]: d11, d22, d33, d12, d23, d13
     * (1/m^2; NULL unless fused) */
    int *row_hessian_start;
    double *entry_hessian;
    int *particle_slot_offset; /* particles + 1 */
    int *particle_slot;        /* the slots of each particle, ascending */
    int max_block_slots;       /* the most slots of one block */
    int max_block_points;      /* the most main points of one block */
};

/* Packed rows per main point: 1 + subcells, or 1 when fused. */
static inline int gsn_point_blocks_row_stride(const struct gsn_point_blocks *b)
{
    return b->fused ? 1 : 1 + b->subcells;
}

/* The packed row of main point L (block k holds L). */
static inline int gsn_point_blocks_main_row(const struct gsn_point_blocks *b,
                                            int k, int L)
{
    return b->block_point[k] * gsn_point_blocks_row_stride(b) +
           (L - b->block_point[k]);
}

/* The packed row of stabilization point s of nodal point L (block k holds
 * L); not fused. */
static inline int gsn_point_blocks_subcell_row(const struct gsn_point_blocks *b,
                                               int k, int L, int s)
{
    int p0 = b->block_point[k], p1 = b->block_point[k + 1];
    return p0 * (1 + b->subcells) + (p1 - p0) + b->subcells * (L - p0) + s;
}

/* Packs the gradient rows of q (main points [0, main): the nodal points,
 * point L = particle L, or the Gauss points; main + S L + s the
 * stabilization points of nodal point L) into blocks of at most
 * block_points main points; NSNI's rows fused into the main rows. */
int gsn_point_blocks_create(const struct gsn_quadrature *q, int block_points,
                            struct gsn_point_blocks **out);

/* Frees; NULL-safe, nulls the handle. */
void gsn_point_blocks_destroy(struct gsn_point_blocks **blocks);

/* Bytes of the packed rows and slot tables. */
size_t gsn_point_blocks_bytes(const struct gsn_point_blocks *blocks);

/* force_i (3) = sum over the slots of particle i of slot_force (slots x 3),
 * in slot order. */
static inline void gsn_point_blocks_reduce_one(const struct gsn_point_blocks *b,
                                               int i, const double *slot_force,
                                               double force[3])
{
    double f[3] = {0.0, 0.0, 0.0};
    for (int k = b->particle_slot_offset[i]; k < b->particle_slot_offset[i + 1];
         ++k) {
        const double *s = &slot_force[3 * (size_t)b->particle_slot[k]];
        f[0] += s[0];
        f[1] += s[1];
        f[2] += s[2];
    }
    force[0] = f[0];
    force[1] = f[1];
    force[2] = f[2];
}

/* force_I = sum over the slots of I of slot_force (slots x 3), in slot
 * order. OpenMP over particles when worth it. */
void gsn_point_blocks_reduce(const struct gsn_point_blocks *blocks,
                             int particle_count, const double *slot_force,
                             double *force, int parallel);

#ifdef __cplusplus
}
#endif
#endif
