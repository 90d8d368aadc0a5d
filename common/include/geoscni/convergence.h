/* The discretization error of one number computed at several particle
 * spacings: the observed order, the Richardson-extrapolated value and an
 * error estimate. Three levels: the procedure of Celik et al. (2008),
 * "Procedure for estimation and reporting of uncertainty due to
 * discretization in CFD applications", J. Fluids Eng. 130, 078001 (Roache's
 * grid convergence index with the safety factor 1.25). Four or more: the
 * least-squares fit phi = phi_0 + a h^p of Eca and Hoekstra (2014), "A
 * procedure for the estimation of the numerical uncertainty of CFD
 * calculations based on grid refinement studies", J. Comput. Phys. 262,
 * 104-130, whose standard deviation carries the levels' scatter into the
 * error (docs/converge.md). */
#ifndef GEOSCNI_CONVERGENCE_H
#define GEOSCNI_CONVERGENCE_H

#ifdef __cplusplus
extern "C" {
#endif

enum { GSN_CONVERGENCE_REASON_SIZE = 256 };

/* Orders outside this range are taken as a sequence not (yet) in its
 * asymptotic range: a meshfree limit load converges at an order near 1 to
 * 2; much below, the extrapolation reaches far beyond the runs, much above,
 * the differences are mostly noise. */
#define GSN_CONVERGENCE_ORDER_MIN 0.5
#define GSN_CONVERGENCE_ORDER_MAX 4.0
/* Above this order (the linear basis' best, for displacements) the
 * observed order is more likely the levels' scatter than the method's: the
 * error is also taken with this order and the safety factor 3, and the
 * larger kept (Eca and Hoekstra, 2014, J. Comput. Phys. 262, 104-130). */
#define GSN_CONVERGENCE_ORDER_NOMINAL 2.0
/* Safety factors of the grid convergence index: three or more levels
 * converging monotonically (1.25), else (3). */
#define GSN_CONVERGENCE_SAFETY 1.25
#define GSN_CONVERGENCE_SAFETY_UNSURE 3.0

struct gsn_convergence {
    double order;        /* observed p; NaN when it cannot be computed */
    double scatter;      /* four or more levels: the standard deviation of
                            the least-squares fit (units of the values);
                            NaN with three */
    double extrapolated; /* phi_ext: converged value (Richardson, or the
                            cautious value when not trusted) */
    double error;        /* estimated error of `extrapolated`, >= 0, in its
                            units */
    int trusted;         /* 1: monotone, order in range (three levels), or
                            a least-squares order in range (four or more) */
    char reason[GSN_CONVERGENCE_REASON_SIZE]; /* why not, and what is given
                                                 instead, in words, or "" */
};

/* level_count >= 3 values, finest first, with their representative
 * spacings h (m, increasing: (V / N)^(1/3) for N particles in a body of
 * volume V, Celik eq. (1)). GSN_ERR_INPUT for fewer than three levels or
 * spacings not increasing by at least 1%. */
int gsn_convergence_estimate(int level_count, const double *spacing,
                             const double *value, struct gsn_convergence *out);

/* The estimated error of level i's value: |value - extrapolated| +
 * error. */
double gsn_convergence_level_error(const struct gsn_convergence *c,
                                   double value);

/* The spacing at which the error |phi(h) - phi_ext| ~ C h^p falls to
 * `error` (from the finest level's), or NaN when not trusted. */
double gsn_convergence_spacing_for(const struct gsn_convergence *c,
                                   double finest_spacing, double finest_value,
                                   double error);

#ifdef __cplusplus
}
#endif
#endif
