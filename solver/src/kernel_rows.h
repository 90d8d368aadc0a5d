/* Building compressed rows in parallel so that the result does not depend on
 * the thread count: each row is computed whole by one thread into that
 * thread's buffer, then the rows are gathered in row order. */
#ifndef GEOSCNI_KERNEL_ROWS_H
#define GEOSCNI_KERNEL_ROWS_H

#include "geoscni/kernels.h"

#include <stddef.h>

/* Per-thread scratch handed to the row function. */
struct kernel_thread {
    int *index;        /* GSN_RK_MAX_NEIGHBOURS */
    double *psi;       /* GSN_RK_MAX_NEIGHBOURS */
    double *gradient;  /* 3 GSN_RK_MAX_NEIGHBOURS */
    double *hessian;   /* 9 GSN_RK_MAX_NEIGHBOURS */
    int hessian_count; /* neighbours in index/hessian, and the row that */
    int hessian_row;   /* evaluated them (-1 none): for reuse by the next */
    double *work;      /* gsn_rk_work_size for GSN_RK_MAX_NEIGHBOURS */
    double *dense;     /* 3 per particle, zero between rows */
    int *mark;         /* 1 per particle, 0 between rows */
    int *touched;      /* particle_count */
    /* the row being written */
    long count, capacity;
    int *out_index;
    double *out_value;
    double *out_gradient;
    char message[384];
    double failed_at[3]; /* the point of a GSN_ERR_NUMERICAL failure */
    /* Psi at points kept for later rows of the same chunk (kernel_cache_*):
     * per point its slot or -1 (cache_points long, made on first use),
     * per slot its entries in the arena */
    int *cache_slot, cache_points, cache_chunk;
    int *cache_point, *cache_offset, cache_count, cache_capacity;
    int *cache_index;
    double *cache_psi;
    long cache_used, cache_size;
    /* where candidate_count >= 0: kernel_evaluate finds its neighbours
     * among these (gsn_rk_neighbours_among), for points in their box */
    int *candidate, candidate_count;
};

/* Rows per chunk of kernel_rows_build's dynamic schedule: one thread
 * computes rows [k CHUNK, (k + 1) CHUNK) in order. */
enum { KERNEL_ROWS_CHUNK = 256 };

/* The cached Psi of point q (t->cache_*): its entry count with *index and
 * *psi pointing at them, or -1 if not cached for row's chunk (the cache is
 * cleared when a row of a new chunk asks). points: how many points there
 * are (the cache's size). */
int kernel_cache_find(struct kernel_thread *t, int points, int row, int q,
                      const int **index, const double **psi);

/* Keeps t->index, t->psi (count entries, the last kernel_evaluate) as the
 * Psi of point q for the rest of the chunk; 1 if out of memory (the cache
 * is then only not used). */
int kernel_cache_keep(struct kernel_thread *t, int q, int count);

/* Finds the particles covering x and evaluates Psi (and grad Psi if
 * want_gradient is 1) there into t->index, t->psi, t->gradient, or only the
 * second derivatives into t->hessian if it is 2; *count gets
 * their number. On failure returns GSN_ERR_INPUT (too many neighbours) or
 * GSN_ERR_NUMERICAL (moment matrix singular or ill-conditioned) with
 * t->message naming the point ("what which"), its position and its
 * neighbour count. */
int kernel_evaluate(const struct gsn_rk *rk, const double *x, int want_gradient,
                    struct kernel_thread *t, int *count, const char *what,
                    int which);

/* Appends one entry to the current row; 1 if out of memory. */
int kernel_row_push(struct kernel_thread *t, int index, double value,
                    const double *gradient);

/* Computes row r into t with kernel_row_push (indices ascending); returns
 * GSN_OK or an error code with t->message set. */
typedef int (*kernel_row_fn)(void *context, int row, struct kernel_thread *t);

/* Runs fn for every row in parallel and gathers the rows. want_value and
 * want_gradient say which arrays rows gets. */
int kernel_rows_build(const struct gsn_rk *rk, int row_count, kernel_row_fn fn,
                      void *context, int want_value, int want_gradient,
                      struct gsn_shape_rows *rows);

#endif
