/* Nonlocal damage (damage.length; docs/material.md, "A length for the
 * damage"): the damage of seed paper eq. (7) at a point is driven by the
 * equivalent strain e_t averaged over a ball of its soil's length L
 * (Pijaudier-Cabot & Bazant 1987; Bazant & Jirasek 2002, eq. (11)):
 *
 *   ebar_p = sum_q w(|x_p - x_q|) V_q e_q / sum_q w(|x_p - x_q|) V_q,
 *   w(r) = (1 - r^2 / L^2)^2 for r < L (the bell function),
 *
 * over the integration points q with volume V_q, on the reference
 * configuration (rebuilt with it at a reference update). Without it, a
 * strain threshold at a footing's corner is reached sooner the finer the
 * particles and a softening band is one particle wide: the peak load
 * falls with the spacing and does not converge (docs/convergence.md).
 *
 * The averages are taken once a step, after the material update, and
 * drive the next step's damage: a lag of one step of the explicit scheme.
 * Each row is summed in one order by one thread: the same bits for any
 * thread count. */
#ifndef GEOSCNI_NONLOCAL_H
#define GEOSCNI_NONLOCAL_H

#include <stddef.h>

struct gsn_nonlocal {
    int point_count;
    int *offset;    /* point_count + 1; a point without a length: no row */
    int *index;     /* points q of each row, ascending */
    double *weight; /* w V_q / sum w V: a row sums to 1 */
    int max_row;    /* entries of the longest row */
};

/* The averaging rows of point_count points (positions n x 3, m; volumes,
 * m^3; radius L per point, m, 0 for a point of local damage). A ball that
 * holds more than GSN_RK_MAX_NEIGHBOURS points is a GSN_ERR_INPUT naming
 * the length. */
int gsn_nonlocal_create(int point_count, const double *position,
                        const double *volume, const double *radius,
                        struct gsn_nonlocal **out);

/* Frees and nulls the handle; NULL-safe. */
void gsn_nonlocal_destroy(struct gsn_nonlocal **nonlocal);

/* Point p's average of the strains (value of point q at strain[q * stride]),
 * written at *average; nothing for a point without a row. */
static inline void gsn_nonlocal_average(const struct gsn_nonlocal *n, int p,
                                        const double *strain, size_t stride,
                                        double *average)
{
    int k0 = n->offset[p], k1 = n->offset[p + 1];
    if (k0 == k1)
        return;
    double sum = 0.0;
    for (int k = k0; k < k1; ++k)
        sum += n->weight[k] * strain[stride * (size_t)n->index[k]];
    *average = sum;
}

/* Bytes the rows of point_count points take with `entries` entries. */
double gsn_nonlocal_bytes(double point_count, double entries);

#endif
