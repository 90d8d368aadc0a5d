/* Blocks of integration points for the one-pass force computation: see
 * point_blocks.h. */
#include "point_blocks.h"
#include "geoscni/error.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

void gsn_point_blocks_destroy(struct gsn_point_blocks **blocks)
{
    if (!blocks || !*blocks)
        return;
    struct gsn_point_blocks *b = *blocks;
    free(b->block_point);
    free(b->block_slot);
    free(b->slot_particle);
    free(b->row_start);
    free(b->entry_slot);
    free(b->entry_gradient);
    free(b->row_hessian_start);
    free(b->entry_hessian);
    free(b->particle_slot_offset);
    free(b->particle_slot);
    free(b);
    *blocks = NULL;
}

size_t gsn_point_blocks_bytes(const struct gsn_point_blocks *b)
{
    size_t rows = (size_t)b->block_point[b->block_count] *
                  (size_t)gsn_point_blocks_row_stride(b);
    size_t entries = (size_t)b->row_start[rows];
    size_t slots = (size_t)b->block_slot[b->block_count];
    size_t hessian =
        b->fused ? (size_t)b->row_hessian_start[rows] * 6 * sizeof(double) +
                       (rows + 1) * sizeof(int)
                 : 0;
    return entries * (sizeof(uint16_t) + 3 * sizeof(double)) +
           (rows + 1) * sizeof(int) + 2 * slots * sizeof(int) +
           ((size_t)b->block_point[b->block_count] + 1) * sizeof(int) + hessian;
}

/* The stored row of stabilization point p (particle L) into
 * index/gradient: with MSCNI (relative) B_s, from the quadrature's row
 * B_s - B_L and the nodal row B_L (both ascending): (B_s - B_L) + B_L,
 * leaving out the entries that come out exactly zero (those of B_L alone);
 * with NSNI the quadrature's row as it is. Returns the entry count. */
static int subcell_row(const struct gsn_shape_rows *g, int relative, int p,
                       int L, int *index, double *gradient)
{
    int count = 0, l = g->offset[L], l1 = relative ? g->offset[L + 1] : l;
    for (int k = g->offset[p]; k < g->offset[p + 1]; ++k) {
        int particle = g->index[k];
        double v[3] = {g->gradient[3 * (size_t)k],
                       g->gradient[3 * (size_t)k + 1],
                       g->gradient[3 * (size_t)k + 2]};
        while (l < l1 && g->index[l] < particle)
            ++l;
        if (l < l1 && g->index[l] == particle)
            for (int j = 0; j < 3; ++j)
                v[j] += g->gradient[3 * (size_t)l + j];
        if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
            continue;
        if (index) {
            index[count] = particle;
            memcpy(&gradient[3 * (size_t)count], v, sizeof v);
        }
        ++count;
    }
    return count;
}

/* The fused row of nodal point L (NSNI, point_blocks.h) of the n nodal
 * points' rows g: first the particles of its three strain-gradient rows
 * (points n + 3 L + k, the same particles in the same order), in their
 * order, with their main-row gradients (0 where the main row has none) and
 * the second derivatives symmetrized, (d_j row_k + d_k row_j) / 2 (they
 * agree to round-off); then the main row's other particles in its order.
 * index, gradient, hessian NULL: counts only. position: one int per
 * particle, all -1, and left so. Returns the entry count, *hessian_count
 * the first part's. */
static int fused_row(const struct gsn_shape_rows *g, int n, int L,
                     int *position, int *index, double *gradient,
                     double *hessian, int *hessian_count)
{
    int m0 = g->offset[L], m1 = g->offset[L + 1];
    const int *row[3];
    const double *value[3];
    for (int k = 0; k < 3; ++k) {
        int p = n + 3 * L + k;
        row[k] = &g->index[g->offset[p]];
        value[k] = &g->gradient[3 * (size_t)g->offset[p]];
    }
    int h = g->offset[n + 3 * L + 1] - g->offset[n + 3 * L];
    for (int e = m0; e < m1; ++e)
        position[g->index[e]] = e;
    for (int e = 0; e < h; ++e) {
        int particle = row[0][e], at = position[particle];
        if (index) {
            index[e] = particle;
            for (int j = 0; j < 3; ++j)
                gradient[3 * e + j] =
                    at >= 0 ? g->gradient[3 * (size_t)at + j] : 0.0;
            /* d11 d22 d33 d12 d23 d13: row k holds d/dX_k of grad */
            static const int pair[6][2] = {{0, 0}, {1, 1}, {2, 2},
                                           {0, 1}, {1, 2}, {0, 2}};
            for (int c = 0; c < 6; ++c) {
                int j = pair[c][0], k = pair[c][1];
                hessian[6 * e + c] =
                    0.5 * (value[j][3 * e + k] + value[k][3 * e + j]);
            }
        }
        position[particle] = -2; /* taken by the first part */
    }
    int count = h;
    for (int e = m0; e < m1; ++e) {
        int particle = g->index[e];
        if (position[particle] != -2) {
            if (index) {
                index[count] = particle;
                memcpy(&gradient[3 * count], &g->gradient[3 * (size_t)e],
                       3 * sizeof(double));
            }
            ++count;
        }
    }
    for (int e = m0; e < m1; ++e)
        position[g->index[e]] = -1;
    for (int e = 0; e < h; ++e)
        position[row[0][e]] = -1;
    *hessian_count = h;
    return count;
}

/* NSNI's three rows of every nodal point list the same particles in the
 * same order (one kernel evaluation: integration_build.c, nsni_row), which
 * fused_row relies on. */
static int check_fusable(const struct gsn_shape_rows *g, int n)
{
    for (int L = 0; L < n; ++L) {
        int p = n + 3 * L, len = g->offset[p + 1] - g->offset[p];
        for (int k = 1; k < 3; ++k) {
            int q = p + k;
            GSN_CHECK(
                g->offset[q + 1] - g->offset[q] == len &&
                    memcmp(&g->index[g->offset[p]], &g->index[g->offset[q]],
                           sizeof(int) * (size_t)len) == 0,
                GSN_ERR_INTERNAL,
                "the NSNI rows of particle %d list different particles", L);
        }
    }
    return GSN_OK;
}

static int compare_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* The blocks and the length of every packed row. */
static int cut_blocks(struct gsn_point_blocks *b,
                      const struct gsn_quadrature *q, int block_points)
{
    const struct gsn_shape_rows *g = &q->gradient;
    int n = q->main_point_count, S = b->fused ? 0 : b->subcells;
    size_t rows = (size_t)n * (size_t)gsn_point_blocks_row_stride(b);
    b->block_count = (n + block_points - 1) / block_points;
    b->block_point = malloc(sizeof(int) * ((size_t)b->block_count + 1));
    b->block_slot = calloc((size_t)b->block_count + 1, sizeof(int));
    b->row_start = malloc(sizeof(int) * (rows + 1));
    if (b->fused)
        b->row_hessian_start = malloc(sizeof(int) * (rows + 1));
    int *position =
        b->fused ? malloc(sizeof(int) * ((size_t)q->particle_count + 1)) : NULL;
    GSN_CHECK(b->block_point && b->block_slot && b->row_start &&
                  (!b->fused || (b->row_hessian_start && position)),
              GSN_ERR_MEMORY, "out of memory");
    for (int i = 0; position && i < q->particle_count; ++i)
        position[i] = -1;
    for (int k = 0; k <= b->block_count; ++k)
        b->block_point[k] = k * block_points < n ? k * block_points : n;
    int64_t entries = 0, hessian_entries = 0;
    b->row_start[0] = 0;
    if (b->fused)
        b->row_hessian_start[0] = 0;
    for (int k = 0; k < b->block_count; ++k) {
        int p0 = b->block_point[k], p1 = b->block_point[k + 1];
        if (p1 - p0 > b->max_block_points)
            b->max_block_points = p1 - p0;
        for (int L = p0; L < p1; ++L) {
            int r = gsn_point_blocks_main_row(b, k, L);
            if (b->fused) {
                int h;
                entries += fused_row(g, n, L, position, NULL, NULL, NULL, &h);
                hessian_entries += h;
                b->row_hessian_start[r + 1] = (int)hessian_entries;
            } else {
                entries += g->offset[L + 1] - g->offset[L];
            }
            b->row_start[r + 1] = (int)entries;
        }
        for (int L = p0; L < p1; ++L)
            for (int s = 0; s < S; ++s) {
                entries +=
                    subcell_row(g, b->relative, n + S * L + s, L, NULL, NULL);
                b->row_start[gsn_point_blocks_subcell_row(b, k, L, s) + 1] =
                    (int)entries;
            }
        if (entries >= INT32_MAX) {
            free(position);
            GSN_CHECK(0, GSN_ERR_INPUT, "more than %d gradient entries",
                      INT32_MAX);
        }
    }
    free(position);
    return GSN_OK;
}

/* Copies the rows of block k into the stream, their particle indices into
 * particle (one per entry). */
static void fill_block(struct gsn_point_blocks *b,
                       const struct gsn_quadrature *q, int k, int *particle,
                       int *position)
{
    const struct gsn_shape_rows *g = &q->gradient;
    int n = q->main_point_count, S = b->subcells;
    int p0 = b->block_point[k], p1 = b->block_point[k + 1];
    if (b->fused) {
        for (int L = p0; L < p1; ++L) {
            int r = gsn_point_blocks_main_row(b, k, L), h;
            size_t at = (size_t)b->row_start[r];
            fused_row(
                g, n, L, position, &particle[at], &b->entry_gradient[3 * at],
                &b->entry_hessian[6 * (size_t)b->row_hessian_start[r]], &h);
        }
        return;
    }
    for (int L = p0; L < p1; ++L) {
        int r = gsn_point_blocks_main_row(b, k, L);
        size_t at = (size_t)b->row_start[r],
               count = (size_t)(g->offset[L + 1] - g->offset[L]);
        memcpy(&particle[at], &g->index[g->offset[L]], count * sizeof(int));
        memcpy(&b->entry_gradient[3 * at],
               &g->gradient[3 * (size_t)g->offset[L]],
               3 * count * sizeof(double));
    }
    for (int L = p0; L < p1; ++L)
        for (int s = 0; s < S; ++s) {
            size_t at =
                (size_t)b->row_start[gsn_point_blocks_subcell_row(b, k, L, s)];
            subcell_row(g, b->relative, n + S * L + s, L, &particle[at],
                        &b->entry_gradient[3 * at]);
        }
}

/* Slots of every block: the distinct particles of its rows, ascending; the
 * entries get their slot (GSN_ERR_INPUT if a block has more slots than
 * entry_slot can hold). */
static int build_slots(struct gsn_point_blocks *b, const int *particle,
                       int particle_count)
{
    int rows = b->block_point[b->block_count] * gsn_point_blocks_row_stride(b);
    size_t entries = (size_t)b->row_start[rows];
    int *mark = malloc(sizeof(int) * (size_t)(particle_count + 1));
    int *slot_of = malloc(sizeof(int) * (size_t)(particle_count + 1));
    b->slot_particle = malloc(sizeof(int) * (entries ? entries : 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(mark && slot_of && b->slot_particle, rc, GSN_ERR_MEMORY,
                   done, "out of memory");
    for (int i = 0; i < particle_count; ++i)
        mark[i] = -1;
    int slots = 0;
    for (int k = 0; k < b->block_count; ++k) {
        int first = slots;
        int r0 = b->block_point[k] * gsn_point_blocks_row_stride(b);
        int r1 = b->block_point[k + 1] * gsn_point_blocks_row_stride(b);
        int e0 = b->row_start[r0], e1 = b->row_start[r1];
        for (int e = e0; e < e1; ++e) {
            if (mark[particle[e]] != k) {
                mark[particle[e]] = k;
                b->slot_particle[slots++] = particle[e];
            }
        }
        /* Ascending particles within the block, for a predictable gather. */
        int count = slots - first;
        GSN_CHECK_GOTO(count <= GSN_POINT_BLOCKS_MAX_SLOTS, rc, GSN_ERR_INPUT,
                       done, "block %d touches %d particles, more than %d", k,
                       count, GSN_POINT_BLOCKS_MAX_SLOTS);
        qsort(&b->slot_particle[first], (size_t)count, sizeof(int),
              compare_int);
        for (int s = first; s < slots; ++s)
            slot_of[b->slot_particle[s]] = s - first;
        for (int e = e0; e < e1; ++e)
            b->entry_slot[e] = (uint16_t)slot_of[particle[e]];
        b->block_slot[k + 1] = slots;
        if (count > b->max_block_slots)
            b->max_block_slots = count;
    }
    /* allocated for one slot an entry: keep what the slots use */
    int *shrunk =
        realloc(b->slot_particle, sizeof(int) * (size_t)(slots ? slots : 1));
    if (shrunk)
        b->slot_particle = shrunk;
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

/* Memory for the packed stream, which the pass reads front to back every
 * step: on 2 MB pages where the system allows it (Linux transparent huge
 * pages on request), so that the hardware prefetcher, which stops at page
 * boundaries, runs on and the pages' translations stay cached (measured on
 * Slope I: MSCNI's 343 MB stream +3%, SCNI's 91 MB unchanged). */
static void *stream_alloc(size_t bytes)
{
    enum { HUGE_PAGE = 2 << 20 };
    if (bytes < HUGE_PAGE)
        return malloc(bytes);
    void *p = NULL;
    size_t rounded = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    if (posix_memalign(&p, HUGE_PAGE, rounded) != 0)
        return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, rounded, MADV_HUGEPAGE); /* a hint: 4 kB pages if refused */
#endif
    return p;
}

/* The blocks of at most block_points main points. */
static int blocks_build(const struct gsn_quadrature *q, int block_points,
                        struct gsn_point_blocks *b)
{
    int n = q->main_point_count;
    b->subcells = n > 0 ? (q->point_count - n) / n : 0;
    b->relative = q->stabilization == GSN_STABILIZATION_MSCNI;
    b->fused = q->stabilization == GSN_STABILIZATION_NSNI && b->subcells == 3;
    if (b->fused)
        GSN_CALL(check_fusable(&q->gradient, n));
    GSN_CALL(cut_blocks(b, q, block_points));
    size_t rows = (size_t)n * (size_t)gsn_point_blocks_row_stride(b);
    size_t entries = (size_t)b->row_start[rows];
    size_t hessian = b->fused ? (size_t)b->row_hessian_start[rows] : 0;
    int *particle = malloc(sizeof(int) * (entries ? entries : 1));
    b->entry_slot = stream_alloc(sizeof(uint16_t) * (entries ? entries : 1));
    b->entry_gradient =
        stream_alloc(3 * sizeof(double) * (entries ? entries : 1));
    if (b->fused)
        b->entry_hessian =
            stream_alloc(6 * sizeof(double) * (hessian ? hessian : 1));
    int rc = GSN_OK, failed = 0;
    GSN_CHECK_GOTO(particle && b->entry_slot && b->entry_gradient &&
                       (!b->fused || b->entry_hessian),
                   rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu packed gradient entries", entries);
#pragma omp parallel reduction(| : failed)
    {
        int *position = NULL;
        if (b->fused) {
            position = malloc(sizeof(int) * ((size_t)q->particle_count + 1));
            for (int i = 0; position && i < q->particle_count; ++i)
                position[i] = -1;
        }
        failed = b->fused && !position;
#pragma omp for schedule(dynamic, 16)
        for (int k = 0; k < b->block_count; ++k)
            if (!failed)
                fill_block(b, q, k, particle, position);
        free(position);
    }
    GSN_CHECK_GOTO(!failed, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CALL_GOTO(build_slots(b, particle, q->particle_count), rc, done);
    GSN_CALL_GOTO(build_particle_slots(b, q->particle_count), rc, done);
done:
    free(particle);
    return rc;
}

int gsn_point_blocks_create(const struct gsn_quadrature *q, int block_points,
                            struct gsn_point_blocks **out)
{
    *out = NULL;
    int n = q->main_point_count, stabilization = q->point_count - n;
    GSN_CHECK(block_points > 0, GSN_ERR_INTERNAL, "block size %d",
              block_points);
    GSN_CHECK(stabilization == 0 || (n == q->particle_count &&
                                     stabilization % (n > 0 ? n : 1) == 0),
              GSN_ERR_INTERNAL,
              "%d points, %d main points, %d particles: stabilization "
              "points need one nodal point per particle and the same "
              "number of them per nodal point",
              q->point_count, n, q->particle_count);
    /* Halve the blocks until every block fits the 16-bit slots (a block of
     * one point always does: 7 rows of at most GSN_RK_MAX_NEIGHBOURS). */
    for (;;) {
        struct gsn_point_blocks *b = calloc(1, sizeof *b);
        GSN_CHECK(b, GSN_ERR_MEMORY, "out of memory");
        int rc = blocks_build(q, block_points, b);
        if (rc == GSN_OK) {
            *out = b;
            return GSN_OK;
        }
        gsn_point_blocks_destroy(&b);
        if (rc != GSN_ERR_INPUT || block_points == 1)
            GSN_CALL(rc);
        gsn_error_clear();
        block_points /= 2;
    }
}

void gsn_point_blocks_reduce(const struct gsn_point_blocks *blocks,
                             int particle_count, const double *slot_force,
                             double *force, int parallel)
{
#pragma omp parallel for if (parallel)
    for (int i = 0; i < particle_count; ++i)
        gsn_point_blocks_reduce_one(blocks, i, slot_force,
                                    &force[3 * (size_t)i]);
}
