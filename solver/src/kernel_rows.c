/* Parallel construction of compressed rows, independent of the thread
 * count (kernel_rows.h). */
#include "kernel_rows.h"

#include "geoscni/error.h"

#include <limits.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The particles covering x under rk and Psi there (kernel_evaluate);
 * returns -1 if they are too many, 1 if M failed, else 0. */
static int evaluate_window(const struct gsn_rk *rk, const double *x,
                           int want_gradient, struct kernel_thread *t,
                           int *count, double *condition)
{
    *count =
        t->candidate_count >= 0
            ? gsn_rk_neighbours_among(rk, x, t->candidate, t->candidate_count,
                                      GSN_RK_MAX_NEIGHBOURS, t->index)
            : gsn_rk_neighbours(rk, x, GSN_RK_MAX_NEIGHBOURS, t->index);
    if (*count > GSN_RK_MAX_NEIGHBOURS)
        return -1;
    return (want_gradient == 2
                ? gsn_rk_hessian_point(rk, x, *count, t->index, t->work,
                                       t->hessian, condition)
                : gsn_rk_shape_point(rk, x, *count, t->index, t->work, t->psi,
                                     want_gradient ? t->gradient : NULL,
                                     condition)) != 0;
}

int kernel_evaluate(const struct gsn_rk *rk, const double *x, int want_gradient,
                    struct kernel_thread *t, int *count, const char *what,
                    int which)
{
    double condition;
    int failed = evaluate_window(rk, x, want_gradient, t, count, &condition);
    /* where the cut leaves a poor set (a corner of a coarse body), the
     * whole window at this point: a function of x alone, so both cells of
     * a facet still see the same Psi (eq. (24)) */
    if (rk->window_cut > 0.0 && failed >= 0 &&
        (failed || condition > GSN_RK_CUT_CONDITION_LIMIT)) {
        const struct gsn_rk whole = gsn_rk_whole_window(rk);
        failed =
            evaluate_window(&whole, x, want_gradient, t, count, &condition);
    }
    if (failed < 0) {
        snprintf(t->message, sizeof t->message,
                 "%s %d at (%g, %g, %g) is covered by %d kernels, more than "
                 "%d: the support is too large",
                 what, which, x[0], x[1], x[2], *count, GSN_RK_MAX_NEIGHBOURS);
        return GSN_ERR_INPUT;
    }
    if (failed) {
        snprintf(t->message, sizeof t->message,
                 "%s %d at (%g, %g, %g): moment matrix singular or "
                 "ill-conditioned (condition number %.3g, limit %.3g) with %d "
                 "particles covering it (the basis has %d terms): enlarge "
                 "the kernel support",
                 what, which, x[0], x[1], x[2], condition,
                 GSN_RK_CONDITION_LIMIT, *count, rk->basis_size);
        memcpy(t->failed_at, x, sizeof t->failed_at);
        return GSN_ERR_NUMERICAL;
    }
    return GSN_OK;
}

int kernel_row_push(struct kernel_thread *t, int index, double value,
                    const double *gradient)
{
    if (t->count == t->capacity) {
        long capacity = t->capacity ? 2 * t->capacity : 4096;
        int *i = realloc(t->out_index, (size_t)capacity * sizeof *i);
        if (!i)
            return 1;
        t->out_index = i;
        double *v = realloc(t->out_value, (size_t)capacity * sizeof *v);
        if (!v)
            return 1;
        t->out_value = v;
        double *g = realloc(t->out_gradient, 3 * (size_t)capacity * sizeof *g);
        if (!g)
            return 1;
        t->out_gradient = g;
        t->capacity = capacity;
    }
    t->out_index[t->count] = index;
    t->out_value[t->count] = value;
    if (gradient)
        memcpy(t->out_gradient + 3 * t->count, gradient, 3 * sizeof *gradient);
    else
        memset(t->out_gradient + 3 * t->count, 0, 3 * sizeof(double));
    t->count++;
    return 0;
}

static void cache_clear(struct kernel_thread *t)
{
    for (int s = 0; s < t->cache_count; ++s)
        t->cache_slot[t->cache_point[s]] = -1;
    t->cache_count = 0;
    t->cache_used = 0;
}

int kernel_cache_find(struct kernel_thread *t, int points, int row, int q,
                      const int **index, const double **psi)
{
    if (!t->cache_slot) {
        t->cache_slot =
            malloc((size_t)(points > 0 ? points : 1) * sizeof *t->cache_slot);
        if (!t->cache_slot)
            return -1;
        for (int i = 0; i < points; ++i)
            t->cache_slot[i] = -1;
        t->cache_points = points;
        t->cache_chunk = -1;
    }
    int chunk = row / KERNEL_ROWS_CHUNK;
    if (chunk != t->cache_chunk) {
        cache_clear(t);
        t->cache_chunk = chunk;
    }
    int s = q < t->cache_points ? t->cache_slot[q] : -1;
    if (s < 0)
        return -1;
    *index = t->cache_index + t->cache_offset[s];
    *psi = t->cache_psi + t->cache_offset[s];
    return t->cache_offset[s + 1] - t->cache_offset[s];
}

int kernel_cache_keep(struct kernel_thread *t, int q, int count)
{
    if (!t->cache_slot || q >= t->cache_points)
        return 1;
    if (t->cache_count + 1 >= t->cache_capacity) {
        int capacity = t->cache_capacity ? 2 * t->cache_capacity : 1024;
        int *point = realloc(t->cache_point, (size_t)capacity * sizeof *point);
        if (point)
            t->cache_point = point;
        int *offset =
            realloc(t->cache_offset, (size_t)(capacity + 1) * sizeof *offset);
        if (offset)
            t->cache_offset = offset;
        if (!point || !offset)
            return 1;
        t->cache_capacity = capacity;
        if (t->cache_count == 0)
            t->cache_offset[0] = 0;
    }
    if (t->cache_used + count > t->cache_size) {
        long size = 2 * (t->cache_used + count) + 4096;
        int *index = realloc(t->cache_index, (size_t)size * sizeof *index);
        if (index)
            t->cache_index = index;
        double *psi = realloc(t->cache_psi, (size_t)size * sizeof *psi);
        if (psi)
            t->cache_psi = psi;
        if (!index || !psi)
            return 1;
        t->cache_size = size;
    }
    int s = t->cache_count++;
    t->cache_offset[s] = (int)t->cache_used;
    memcpy(t->cache_index + t->cache_used, t->index,
           (size_t)count * sizeof *t->index);
    memcpy(t->cache_psi + t->cache_used, t->psi,
           (size_t)count * sizeof *t->psi);
    t->cache_used += count;
    t->cache_offset[s + 1] = (int)t->cache_used;
    t->cache_point[s] = q;
    t->cache_slot[q] = s;
    return 0;
}

static void thread_free(struct kernel_thread *t)
{
    free(t->candidate);
    free(t->cache_slot);
    free(t->cache_point);
    free(t->cache_offset);
    free(t->cache_index);
    free(t->cache_psi);
    free(t->index);
    free(t->psi);
    free(t->gradient);
    free(t->hessian);
    free(t->work);
    free(t->dense);
    free(t->mark);
    free(t->touched);
    free(t->out_index);
    free(t->out_value);
    free(t->out_gradient);
}

static int thread_allocate(struct kernel_thread *t, const struct gsn_rk *rk)
{
    size_t cap = GSN_RK_MAX_NEIGHBOURS, n = (size_t)rk->particle_count;
    memset(t, 0, sizeof *t);
    t->index = malloc(cap * sizeof *t->index);
    t->psi = malloc(cap * sizeof *t->psi);
    t->gradient = malloc(3 * cap * sizeof *t->gradient);
    t->hessian = malloc(9 * cap * sizeof *t->hessian);
    t->hessian_row = -1;
    t->work = malloc(gsn_rk_work_size(rk, (int)cap) * sizeof *t->work);
    t->dense = calloc(3 * n, sizeof *t->dense);
    t->mark = calloc(n, sizeof *t->mark);
    t->touched = malloc(n * sizeof *t->touched);
    t->candidate = malloc(cap * sizeof *t->candidate);
    t->candidate_count = -1;
    return t->index && t->psi && t->gradient && t->hessian && t->work &&
           t->dense && t->mark && t->touched && t->candidate;
}

int kernel_rows_build(const struct gsn_rk *rk, int row_count, kernel_row_fn fn,
                      void *context, int want_value, int want_gradient,
                      struct gsn_shape_rows *rows)
{
    memset(rows, 0, sizeof *rows);
    int threads = omp_get_max_threads();
    size_t nr = (size_t)row_count;
    struct kernel_thread *team = calloc((size_t)threads, sizeof *team);
    int *row_thread = malloc((nr ? nr : 1) * sizeof *row_thread);
    long *row_start = malloc((nr ? nr : 1) * sizeof *row_start);
    long *row_length = malloc((nr ? nr : 1) * sizeof *row_length);
    int *fail_row = malloc((size_t)threads * sizeof *fail_row);
    int *fail_code = malloc((size_t)threads * sizeof *fail_code);
    int rc = GSN_OK;
    GSN_CHECK_GOTO(
        team && row_thread && row_start && row_length && fail_row && fail_code,
        rc, GSN_ERR_MEMORY, done, "cannot allocate %d rows", row_count);
    int allocated = 1;
    for (int i = 0; i < threads; ++i) {
        allocated &= thread_allocate(&team[i], rk);
        fail_row[i] = INT_MAX;
        fail_code[i] = GSN_OK;
    }
    GSN_CHECK_GOTO(allocated, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate the scratch of %d threads", threads);

#pragma omp parallel num_threads(threads)
    {
        int tid = omp_get_thread_num();
        struct kernel_thread *t = &team[tid];
#pragma omp for schedule(dynamic, KERNEL_ROWS_CHUNK)
        for (int r = 0; r < row_count; ++r) {
            row_thread[r] = tid;
            row_start[r] = t->count;
            row_length[r] = 0;
            if (fail_code[tid] != GSN_OK)
                continue;
            int code = fn(context, r, t);
            row_length[r] = t->count - row_start[r];
            if (code != GSN_OK) {
                fail_code[tid] = code;
                fail_row[tid] = r;
            }
        }
    }
    /* Report the failure of the lowest row among the threads. */
    int worst = -1;
    for (int i = 0; i < threads; ++i)
        if (fail_code[i] != GSN_OK &&
            (worst < 0 || fail_row[i] < fail_row[worst]))
            worst = i;
    if (worst >= 0 && fail_code[worst] == GSN_ERR_NUMERICAL &&
        rk->failure_point)
        memcpy(rk->failure_point, team[worst].failed_at,
               sizeof team[worst].failed_at);
    GSN_CHECK_GOTO(worst < 0, rc, worst >= 0 ? fail_code[worst] : GSN_OK, done,
                   "%s", worst >= 0 ? team[worst].message : "");

    rows->row_count = row_count;
    rows->offset = malloc((nr + 1) * sizeof *rows->offset);
    GSN_CHECK_GOTO(rows->offset, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate row offsets");
    long total = 0;
    rows->offset[0] = 0;
    for (size_t r = 0; r < nr; ++r) {
        total += row_length[r];
        GSN_CHECK_GOTO(total <= INT_MAX, rc, GSN_ERR_INPUT, done,
                       "more than %d row entries", INT_MAX);
        rows->offset[r + 1] = (int)total;
    }
    size_t nt = (size_t)total;
    rows->index = malloc((nt ? nt : 1) * sizeof *rows->index);
    if (want_value)
        rows->value = malloc((nt ? nt : 1) * sizeof *rows->value);
    if (want_gradient)
        rows->gradient = malloc(3 * (nt ? nt : 1) * sizeof *rows->gradient);
    GSN_CHECK_GOTO(rows->index && (!want_value || rows->value) &&
                       (!want_gradient || rows->gradient),
                   rc, GSN_ERR_MEMORY, done, "cannot allocate %ld row entries",
                   total);
#pragma omp parallel for schedule(static)
    for (int r = 0; r < row_count; ++r) {
        const struct kernel_thread *t = &team[row_thread[r]];
        size_t src = (size_t)row_start[r], dst = (size_t)rows->offset[r];
        size_t len = (size_t)row_length[r];
        if (len == 0)
            continue;
        memcpy(rows->index + dst, t->out_index + src, len * sizeof(int));
        if (want_value)
            memcpy(rows->value + dst, t->out_value + src, len * sizeof(double));
        if (want_gradient)
            memcpy(rows->gradient + 3 * dst, t->out_gradient + 3 * src,
                   3 * len * sizeof(double));
    }
done:
    if (team)
        for (int i = 0; i < threads; ++i)
            thread_free(&team[i]);
    free(team);
    free(row_thread);
    free(row_start);
    free(row_length);
    free(fail_row);
    free(fail_code);
    if (rc != GSN_OK)
        gsn_shape_rows_free(rows);
    return rc;
}
