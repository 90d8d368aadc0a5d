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
    int count;
    int rc = kernel_evaluate(c->rk, c->points + 3 * (size_t)r, c->want_gradient,
                             t, &count, "point", r);
    if (rc != GSN_OK)
        return rc;
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
