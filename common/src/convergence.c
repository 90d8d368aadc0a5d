/* Observed order and Richardson extrapolation: see convergence.h. */
#include "geoscni/convergence.h"

#include "geoscni/error.h"

#include <math.h>
#include <stdio.h>

/* The observed order of three levels (finest first), Celik et al. (2008)
 * eqs. (3a)-(3c) by fixed-point iteration, without the absolute value of
 * eq. (3a), so that differences that grow under refinement give p <= 0.
 * NaN when a difference is zero, the iteration fails, or the levels
 * oscillate (s < 0: no order describes them). */
static double observed_order(const double *h, const double *phi)
{
    double e21 = phi[1] - phi[0], e32 = phi[2] - phi[1];
    if (e21 == 0.0 || e32 == 0.0 || e32 / e21 < 0.0)
        return NAN;
    double r21 = h[1] / h[0], r32 = h[2] / h[1];
    double ratio = log(fabs(e32 / e21)), p = ratio / log(r21);
    for (int k = 0; k < 200; ++k) {
        double q = 0.0;
        if (p > 0.0) /* eq. (3c), s = 1 */
            q = log((pow(r21, p) - 1.0) / (pow(r32, p) - 1.0));
        double next = (ratio + q) / log(r21);
        if (!isfinite(next))
            return NAN;
        if (fabs(next - p) <= 1e-12 * fmax(1.0, fabs(p)))
            return next;
        p = next;
    }
    return NAN;
}

int gsn_convergence_estimate(int level_count, const double *spacing,
                             const double *value, struct gsn_convergence *out)
{
    GSN_CHECK(level_count >= 3, GSN_ERR_INPUT,
              "a convergence estimate needs at least three levels, got %d",
              level_count);
    for (int i = 0; i < level_count; ++i)
        GSN_CHECK(isfinite(value[i]) && isfinite(spacing[i]) &&
                      spacing[i] > 0.0,
                  GSN_ERR_INPUT, "level %d: value %g at spacing %g m", i + 1,
                  value[i], spacing[i]);
    for (int i = 0; i + 1 < level_count; ++i)
        GSN_CHECK(spacing[i + 1] >= 1.01 * spacing[i], GSN_ERR_INPUT,
                  "the spacings must grow from the finest level by at least "
                  "1%%: %g m then %g m",
                  spacing[i], spacing[i + 1]);
    const double *phi = value, *h = spacing;
    double e21 = phi[1] - phi[0], e32 = phi[2] - phi[1];
    double r21 = h[1] / h[0];
    *out = (struct gsn_convergence){.order = observed_order(h, phi),
                                    .order_coarse = NAN,
                                    .extrapolated = phi[0],
                                    .error = 0.0,
                                    .trusted = 0};
    if (level_count >= 4)
        out->order_coarse = observed_order(h + 1, phi + 1);
    double p = out->order;
    if (e21 == 0.0 && e32 == 0.0) {
        out->trusted = 1; /* the levels agree exactly */
        return GSN_OK;
    }
    if (e21 * e32 < 0.0)
        snprintf(out->reason, sizeof out->reason,
                 "the levels oscillate (%.6g, %.6g, %.6g from the finest): "
                 "no order of convergence describes them",
                 phi[0], phi[1], phi[2]);
    else if (!isfinite(p))
        snprintf(out->reason, sizeof out->reason,
                 "the finest two or coarsest two levels agree exactly but "
                 "the others do not: no order can be observed");
    else if (p <= 0.0)
        snprintf(out->reason, sizeof out->reason,
                 "the differences between levels grow as the spacing "
                 "shrinks (order %.2f): the sequence does not converge",
                 p);
    else if (p < GSN_CONVERGENCE_ORDER_MIN || p > GSN_CONVERGENCE_ORDER_MAX)
        snprintf(out->reason, sizeof out->reason,
                 "the observed order %.2f is outside %.1f to %.1f: the "
                 "levels are not in the asymptotic range",
                 p, GSN_CONVERGENCE_ORDER_MIN, GSN_CONVERGENCE_ORDER_MAX);
    else if (level_count >= 4 && (!isfinite(out->order_coarse) ||
                                  fabs(out->order_coarse - p) >
                                      GSN_CONVERGENCE_ORDER_AGREEMENT * p))
        snprintf(out->reason, sizeof out->reason,
                 "the order changes with the levels (%.2f on the finest "
                 "three, %.2f on the coarser three): not yet in the "
                 "asymptotic range",
                 p, out->order_coarse);
    else
        out->trusted = 1;
    if (out->trusted) {
        /* eq. (4), and the fine-grid convergence index of eq. (7) as the
         * error */
        double rp = pow(r21, p);
        out->extrapolated = (rp * phi[0] - phi[1]) / (rp - 1.0);
        out->error = GSN_CONVERGENCE_SAFETY * fabs(out->extrapolated - phi[0]);
        if (p > GSN_CONVERGENCE_ORDER_NOMINAL)
            out->error =
                fmax(out->error,
                     GSN_CONVERGENCE_SAFETY_UNSURE * fabs(e21) /
                         (pow(r21, GSN_CONVERGENCE_ORDER_NOMINAL) - 1.0));
    } else {
        /* the finest value, with Roache's two-level index at an assumed
         * first order, safety factor 3, on the larger of the two last
         * changes */
        out->error = GSN_CONVERGENCE_SAFETY_UNSURE *
                     fmax(fabs(e21), fabs(e32)) / (r21 - 1.0);
    }
    return GSN_OK;
}

double gsn_convergence_level_error(const struct gsn_convergence *c,
                                   double value)
{
    return fabs(value - c->extrapolated) + c->error;
}

double gsn_convergence_spacing_for(const struct gsn_convergence *c,
                                   double finest_spacing, double finest_value,
                                   double error)
{
    double finest_error = fabs(finest_value - c->extrapolated);
    if (!c->trusted || !isfinite(c->order) || !(error > 0.0))
        return NAN;
    if (finest_error == 0.0)
        return INFINITY;
    return finest_spacing * pow(error / finest_error, 1.0 / c->order);
}
