/* Observed order and Richardson extrapolation: see convergence.h. */
#include "geoscni/convergence.h"

#include "geoscni/error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

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

/* The least-squares fit of phi_0 + a h^p at a fixed p; the sum of the
 * squared residuals. */
static double fit_at_order(int n, const double *h, const double *phi, double p,
                           double *phi0, double *a)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
        double x = pow(h[i], p);
        sx += x;
        sy += phi[i];
        sxx += x * x;
        sxy += x * phi[i];
    }
    double det = n * sxx - sx * sx;
    *a = det != 0.0 ? (n * sxy - sx * sy) / det : 0.0;
    *phi0 = (sy - *a * sx) / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = phi[i] - (*phi0 + *a * pow(h[i], p));
        sum += r * r;
    }
    return sum;
}

/* Eca and Hoekstra (2014), simplified: the order that fits best (a scan of
 * 0.05 to 8 refined by golden sections), its standard deviation sigma, and
 * the error 1.25 |delta| + sigma + |phi_1 - fit(h_1)| (delta = phi_1 -
 * phi_0) in the range 0.5 to 2; above 2, also at p = 2 with safety 3,
 * keeping the larger; outside 0.5 to 4 the value at order 1 with safety 3,
 * not trusted; levels that scatter more than they change are not trusted
 * and get 3 times their range. */
static void least_squares_estimate(int n, const double *h, const double *phi,
                                   struct gsn_convergence *out)
{
    double best = INFINITY, p = NAN, phi0 = 0.0, a = 0.0;
    for (int k = 0; k <= 795; ++k) { /* p = 0.05 to 8 by 0.01 */
        double q = 0.05 + 0.01 * k, f0, fa;
        double sum = fit_at_order(n, h, phi, q, &f0, &fa);
        if (sum < best) {
            best = sum;
            p = q;
        }
    }
    double lo = fmax(0.05, p - 0.01), hi = fmin(8.0, p + 0.01);
    const double golden = 0.5 * (sqrt(5.0) - 1.0);
    for (int k = 0; k < 60; ++k) {
        double m1 = hi - golden * (hi - lo), m2 = lo + golden * (hi - lo);
        if (fit_at_order(n, h, phi, m1, &phi0, &a) <
            fit_at_order(n, h, phi, m2, &phi0, &a))
            hi = m2;
        else
            lo = m1;
    }
    p = 0.5 * (lo + hi);
    best = fit_at_order(n, h, phi, p, &phi0, &a);
    double sigma = sqrt(best / (n - 3));
    double low = phi[0], high = phi[0];
    for (int i = 1; i < n; ++i) {
        low = fmin(low, phi[i]);
        high = fmax(high, phi[i]);
    }
    double range = high - low;
    out->order = p;
    out->scatter = sigma;
    if (range == 0.0) {
        out->extrapolated = phi[0];
        out->error = 0.0;
        out->trusted = 1; /* the levels agree exactly */
        return;
    }
    if (sigma >= range) {
        out->extrapolated = phi[0];
        out->error = GSN_CONVERGENCE_SAFETY_UNSURE * range;
        snprintf(out->reason, sizeof out->reason,
                 "the levels scatter (standard deviation %.3g) as much as "
                 "they change (%.3g): the finest value, with 3 times the "
                 "range of the levels as its error",
                 sigma, range);
        return;
    }
    double fit1 = phi0 + a * pow(h[0], p);
    if (p >= GSN_CONVERGENCE_ORDER_MIN && p <= GSN_CONVERGENCE_ORDER_MAX) {
        out->extrapolated = phi0;
        out->error = GSN_CONVERGENCE_SAFETY * fabs(phi[0] - phi0) + sigma +
                     fabs(phi[0] - fit1);
        if (p > GSN_CONVERGENCE_ORDER_NOMINAL) {
            double f0, fa;
            double sum = fit_at_order(n, h, phi, GSN_CONVERGENCE_ORDER_NOMINAL,
                                      &f0, &fa);
            double fit2 = f0 + fa * pow(h[0], GSN_CONVERGENCE_ORDER_NOMINAL);
            out->error = fmax(
                out->error, GSN_CONVERGENCE_SAFETY_UNSURE * fabs(phi[0] - f0) +
                                sqrt(sum / (n - 2)) + fabs(phi[0] - fit2));
        }
        out->trusted = 1;
        return;
    }
    double f1, a1;
    double sum = fit_at_order(n, h, phi, 1.0, &f1, &a1);
    out->extrapolated = f1;
    out->error = GSN_CONVERGENCE_SAFETY_UNSURE * fabs(phi[0] - f1) +
                 sqrt(sum / (n - 2)) + fabs(phi[0] - (f1 + a1 * h[0]));
    snprintf(out->reason, sizeof out->reason,
             "the order that fits the levels best, %.2f, is outside %.1f to "
             "%.1f; the value is extrapolated at order 1, with a safety "
             "factor of 3",
             p, GSN_CONVERGENCE_ORDER_MIN, GSN_CONVERGENCE_ORDER_MAX);
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
                                    .scatter = NAN,
                                    .extrapolated = phi[0],
                                    .error = 0.0,
                                    .trusted = 0};
    if (level_count >= 4) {
        least_squares_estimate(level_count, h, phi, out);
        return GSN_OK;
    }
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
        size_t used = strlen(out->reason);
        snprintf(out->reason + used, sizeof out->reason - used,
                 "; the finest value, with 3 times the larger of the last "
                 "two changes over the ratio - 1 as its error");
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
