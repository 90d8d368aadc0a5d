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
    char message[256];
    double failed_at[3]; /* the point of a GSN_ERR_NUMERICAL failure */
};

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
