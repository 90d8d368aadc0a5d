/* Blocks of points for the one-pass force computation: see point_blocks.h. */
#include "point_blocks.h"
#include "geoscni/error.h"

#include <stdlib.h>
#include <string.h>

void gsn_point_blocks_destroy(struct gsn_point_blocks **blocks)
{
    if (!blocks || !*blocks)
        return;
    struct gsn_point_blocks *b = *blocks;
    free(b->block_point);
    free(b->block_slot);
    free(b->slot_particle);
    free(b->entry_slot);
    free(b->particle_slot_offset);
    free(b->particle_slot);
    free(b);
    *blocks = NULL;
}

/* The number of blocks and where each starts. */
static int cut_blocks(struct gsn_point_blocks *b, int point_count,
                      int block_size, int split)
{
    int count = 0;
    for (int start = 0; start < point_count; ++count) {
        int end = start + block_size;
        if (start < split && end > split)
            end = split;
        start = end < point_count ? end : point_count;
    }
    b->block_count = count;
    b->block_point = malloc(sizeof(int) * (size_t)(count + 1));
    b->block_slot = calloc((size_t)count + 1, sizeof(int));
    GSN_CHECK(b->block_point && b->block_slot, GSN_ERR_MEMORY, "out of memory");
    int at = 0;
    for (int start = 0; start < point_count; ++at) {
        int end = start + block_size;
        if (start < split && end > split)
            end = split;
        b->block_point[at] = start;
        if (start < split)
            b->main_block_count = at + 1;
        start = end < point_count ? end : point_count;
    }
    b->block_point[count] = point_count;
    return GSN_OK;
}

/* Slots of every block: the distinct particles of its rows, ascending. */
static int build_slots(struct gsn_point_blocks *b,
                       const struct gsn_shape_rows *rows, int particle_count)
{
    size_t entries = (size_t)rows->offset[rows->row_count];
    int *mark = malloc(sizeof(int) * (size_t)(particle_count + 1));
    int *slot_of = malloc(sizeof(int) * (size_t)(particle_count + 1));
    b->entry_slot = malloc(sizeof(int) * (entries ? entries : 1));
    b->slot_particle = malloc(sizeof(int) * (entries ? entries : 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(mark && slot_of && b->entry_slot && b->slot_particle, rc,
                   GSN_ERR_MEMORY, done, "out of memory");
    for (int i = 0; i < particle_count; ++i)
        mark[i] = -1;
    int slots = 0;
    for (int k = 0; k < b->block_count; ++k) {
        int first = slots;
        int e0 = rows->offset[b->block_point[k]];
        int e1 = rows->offset[b->block_point[k + 1]];
        for (int e = e0; e < e1; ++e) {
            int particle = rows->index[e];
            if (mark[particle] != k) {
                mark[particle] = k;
                b->slot_particle[slots++] = particle;
            }
        }
        /* Ascending particles within the block, for a predictable gather. */
        int count = slots - first;
        for (int i = 1; i < count; ++i) {
            int value = b->slot_particle[first + i], j = i;
            while (j > 0 && b->slot_particle[first + j - 1] > value) {
                b->slot_particle[first + j] = b->slot_particle[first + j - 1];
                --j;
            }
            b->slot_particle[first + j] = value;
        }
        for (int s = first; s < slots; ++s)
            slot_of[b->slot_particle[s]] = s - first;
        for (int e = e0; e < e1; ++e)
            b->entry_slot[e] = slot_of[rows->index[e]];
        b->block_slot[k + 1] = slots;
        if (count > b->max_block_slots)
            b->max_block_slots = count;
    }
done:
    free(mark);
    free(slot_of);
    return rc;
}

/* For every particle, its slots in ascending order (that is, block order). */
static int build_particle_slots(struct gsn_point_blocks *b, int particle_count)
{
    int slots = b->block_slot[b->block_count];
    b->particle_slot_offset = calloc((size_t)particle_count + 1, sizeof(int));
    b->particle_slot = malloc(sizeof(int) * (size_t)(slots ? slots : 1));
    GSN_CHECK(b->particle_slot_offset && b->particle_slot, GSN_ERR_MEMORY,
              "out of memory");
    for (int s = 0; s < slots; ++s)
        b->particle_slot_offset[b->slot_particle[s] + 1]++;
    for (int i = 0; i < particle_count; ++i)
        b->particle_slot_offset[i + 1] += b->particle_slot_offset[i];
    int *fill = malloc(sizeof(int) * (size_t)(particle_count + 1));
    GSN_CHECK(fill, GSN_ERR_MEMORY, "out of memory");
    memcpy(fill, b->particle_slot_offset, sizeof(int) * (size_t)particle_count);
    for (int s = 0; s < slots; ++s)
        b->particle_slot[fill[b->slot_particle[s]]++] = s;
    free(fill);
    return GSN_OK;
}

int gsn_point_blocks_create(const struct gsn_shape_rows *rows,
                            int particle_count, int block_size, int split,
                            struct gsn_point_blocks **out)
{
    *out = NULL;
    GSN_CHECK(block_size > 0, GSN_ERR_INTERNAL, "block size %d", block_size);
    struct gsn_point_blocks *b = calloc(1, sizeof *b);
    GSN_CHECK(b, GSN_ERR_MEMORY, "out of memory");
    int rc = GSN_OK;
    GSN_CALL_GOTO(cut_blocks(b, rows->row_count, block_size, split), rc, fail);
    GSN_CALL_GOTO(build_slots(b, rows, particle_count), rc, fail);
    GSN_CALL_GOTO(build_particle_slots(b, particle_count), rc, fail);
    *out = b;
    return GSN_OK;
fail:
    gsn_point_blocks_destroy(&b);
    return rc;
}

void gsn_point_blocks_reduce(const struct gsn_point_blocks *blocks,
                             int particle_count, const double *slot_force,
                             double *force, int parallel)
{
#pragma omp parallel for if (parallel)
    for (int i = 0; i < particle_count; ++i) {
        double f[3] = {0.0, 0.0, 0.0};
        for (int k = blocks->particle_slot_offset[i];
             k < blocks->particle_slot_offset[i + 1]; ++k) {
            const double *s = &slot_force[3 * blocks->particle_slot[k]];
            f[0] += s[0];
            f[1] += s[1];
            f[2] += s[2];
        }
        memcpy(&force[3 * i], f, sizeof f);
    }
}
