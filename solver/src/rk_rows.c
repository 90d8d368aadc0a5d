/* Shape values and gradients of the RK approximation at many points, one
 * compressed row per point (geoscni/kernels.h). */
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "kernel_rows.h"

#include <stdio.h>

struct shape_context {
    const struct gsn_rk *rk;
    const double *points;
    int want_gradient;
};

static int shape_row(void *context, int r, struct kernel_thread *t)
{
    const struct shape_context *c = context;
    const double *x = c->points + 3 * (size_t)r;
    int count = gsn_rk_neighbours(c->rk, x, GSN_RK_MAX_NEIGHBOURS, t->index);
    if (count > GSN_RK_MAX_NEIGHBOURS) {
        snprintf(t->message, sizeof t->message,
                 "point %d at (%g, %g, %g) is covered by %d kernels, more "
                 "than %d: the support is too large",
                 r, x[0], x[1], x[2], count, GSN_RK_MAX_NEIGHBOURS);
        return GSN_ERR_INPUT;
    }
    double condition;
    if (gsn_rk_shape_point(c->rk, x, count, t->index, t->work, t->psi,
                           c->want_gradient ? t->gradient : NULL, &condition)) {
        snprintf(t->message, sizeof t->message,
                 "point %d at (%g, %g, %g): moment matrix singular or "
                 "ill-conditioned (condition number %.3g, limit %.3g) with %d "
                 "particles covering it (the basis has %d terms): enlarge "
                 "the kernel support",
                 r, x[0], x[1], x[2], condition, GSN_RK_CONDITION_LIMIT, count,
                 c->rk->basis_size);
        return GSN_ERR_NUMERICAL;
    }
    for (int n = 0; n < count; ++n)
        if (kernel_row_push(t, t->index[n], t->psi[n],
                            c->want_gradient ? t->gradient + 3 * n : NULL)) {
            snprintf(t->message, sizeof t->message, "out of memory at point %d",
                     r);
            return GSN_ERR_MEMORY;
        }
    return GSN_OK;
}

int gsn_rk_shape_rows(const struct gsn_rk *rk, int point_count,
                      const double *points, int want_gradient,
                      struct gsn_shape_rows *rows)
{
    struct shape_context c = {rk, points, want_gradient};
    GSN_CALL(kernel_rows_build(rk, point_count, shape_row, &c, 1, want_gradient,
                               rows));
    return GSN_OK;
}
