/* Essential boundary conditions imposed exactly on the displacement of the
 * boundary particles, u_c(X_J) = sum_I Psi_I(X_J) d_Ic (DESIGN.md,
 * "Essential boundary conditions"): RK shape functions do not interpolate,
 * so fixing d_J would not fix u(X_J).
 *
 * For each component c, B_c is the set of particles with c constrained and
 * C_c the rows Psi_I(X_J), J in B_c, over all I: the constraints read
 * C_c f_c = prescribed. Every correction is the mass-orthogonal projection
 * onto them, f += M^-1 C^T lambda with (C M^-1 C^T) lambda = prescribed -
 * C f (S_c = C M^-1 C^T factorized once, CHOLMOD's supernodal Cholesky;
 * its factor copied into dense runs that the solve of every step reads
 * once forward and once backward in storage order). On
 * the accelerations, C^T lambda is the force the supports apply: it does
 * no work on a motion the constraints allow, so the discrete system keeps
 * the symmetry of its stiffness and mass (docs/solver.md, "Boundary
 * values"). The same correction is applied to displacements, velocities
 * and accelerations. */
#ifndef GEOSCNI_CONSTRAINT_H
#define GEOSCNI_CONSTRAINT_H

#include "geoscni/case.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_constraints;

/* What a field is, for the prescribed value of a velocity boundary at time
 * t: displacement v t, velocity v, acceleration 0; fixed components are 0
 * for all three. */
enum gsn_constraint_field {
    GSN_FIELD_DISPLACEMENT,
    GSN_FIELD_VELOCITY,
    GSN_FIELD_ACCELERATION,
    GSN_FIELD_HOMOGENEOUS /* 0 everywhere: the projection onto the motions
                             the constraints allow (the stable step) */
};

/* The prescribed value of field `kind` at time t per unit prescribed
 * velocity, with the velocity rising over `ramp` seconds as
 * (1 - cos(pi t / ramp)) / 2 (continuous velocity and acceleration at t = 0
 * and t = ramp, so the load starts without an impact), then constant:
 * displacement t/2 - ramp/(2 pi) sin(pi t/ramp), then t - ramp/2. */
double gsn_ramp_factor(double ramp, enum gsn_constraint_field kind, double t);

/* Displacements are prescribed from `time` on (s): the value at t is
 * v (D(t) - D(time)) with D the displacement factor of gsn_ramp_factor, so
 * a reference configuration taken at `time` holds d = 0 (issue 15). */
void gsn_constraints_set_epoch(struct gsn_constraints *constraints,
                               double time);

/* 1 while the prescribed velocities still rise (t < time.ramp): their
 * accelerations are then nonzero, so d and v are corrected every step. */
int gsn_constraints_ramping(const struct gsn_constraints *constraints,
                            double time);

/* Collects the constrained particles of every boundary entry of the case
 * (each entry must name a surface of the model), checks that no particle
 * gets two different prescriptions for one component (a symmetry entry
 * holds the component normal to its plane, gsn_case_resolve_symmetry) and
 * the rows C_c. values: Psi_I(X_J), one row per particle J.
 * released (NULL: none): per particle, a bit mask of the entries that do
 * not hold it although it lies on their surface (a rigid body's particle
 * that has left its base, contact.h). */
int gsn_constraints_create(const struct gsn_model *m, const struct gsn_case *c,
                           const struct gsn_shape_rows *values,
                           const unsigned *released,
                           struct gsn_constraints **out);

/* The components constrained on a facet of model surface `surface` owned
 * by particle `owner`: gsn_constraints_surface_mask, or 0 where the
 * surface's entry has released the owner (a rigid body's particle that
 * has left its base is free there). */
int gsn_constraints_facet_mask(const struct gsn_constraints *constraints,
                               int surface, int owner);

/* The quadrature of model m with the held facets of case c
 * (gsn_constraints_held, into a copy of options), then the constraints on
 * its shape values: the build every solver of a case goes through.
 * seconds (NULL: not wanted): the wall time of the two (s). */
int gsn_constraints_discretize(
    const struct gsn_model *m, const struct gsn_case *c,
    const struct gsn_kernel_options *options, const double *background_cells,
    int background_cell_count, const unsigned *released,
    struct gsn_quadrature **quadrature, struct gsn_constraints **constraints,
    double seconds[2]);

/* Frees; NULL-safe, nulls the handle. */
void gsn_constraints_destroy(struct gsn_constraints **constraints);

/* The lumped masses (n, kg; copied) of S_c = C_c M^-1 C_c^T, which the
 * next correction forms and factorizes; before any gsn_constraints_apply. */
int gsn_constraints_set_mass(struct gsn_constraints *constraints,
                             const double *mass);

/* Wall time spent forming and factorizing S_c so far (s). */
double
gsn_constraints_factor_seconds(const struct gsn_constraints *constraints);

/* The correction of before 2026-12-02 evening, for a negative control
 * only: the coefficients of B_c alone, Lambda_c^-1 (prescribed - C f), not
 * mass-orthogonal (its force is M times the correction); from the next
 * correction on. */
void gsn_constraints_set_boundary_only(struct gsn_constraints *constraints);

/* Corrects field (n x 3 coefficients) in place, by the mass-orthogonal
 * projection, so that the prescribed values hold at time t at every
 * constrained particle. force (NULL: not wanted): where the correction
 * reaches, M times it, C^T lambda (for accelerations, the reaction in N);
 * left as it was elsewhere. values: the rows given to
 * gsn_constraints_create (whose entries were taken from them once). */
int gsn_constraints_apply(struct gsn_constraints *constraints,
                          const struct gsn_shape_rows *values,
                          enum gsn_constraint_field kind, double time,
                          double *field, double *force);

/* The multipliers lambda (n x 3, 0 where not constrained) whose C^T lambda
 * is force (n x 3): the force each constrained particle's prescription
 * applies (N, for a reaction force); they add up to the resultant of
 * force by the partition of unity. */
int gsn_constraints_multipliers(struct gsn_constraints *constraints,
                                const double *force, double *multiplier);

/* What the boundary entries of case c hold on model m, before any shape
 * function exists: per facet the components held on it (a boundary facet
 * of a surface with an essential entry, unless its owner is released
 * there; 0 elsewhere) and per particle the components held at it (bit k:
 * component k). Both arrays allocated, the caller frees them; they go to
 * gsn_kernel_options.held_facet / held_particle. */
int gsn_constraints_held(const struct gsn_model *m, const struct gsn_case *c,
                         const unsigned *released, int **facet_mask,
                         int **particle_mask);

/* The sizes of S_c = C_c M^-1 C_c^T and of its Cholesky factor, estimated
 * before any shape function exists (for the memory the solve states):
 * per component, entries[k] counts the pairs of held particles J, K with
 * |X_J - X_K|_inf < 2 a (their kernels may share a particle: the pattern
 * of S_c), and factor_entries[k] the values of its supernodal factor. */
int gsn_constraints_size_estimate(const struct gsn_model *m,
                                  const struct gsn_case *c, double entries[3],
                                  double factor_entries[3]);

/* 1 if component k of particle I is constrained. */
int gsn_constraints_is_constrained(const struct gsn_constraints *constraints,
                                   int particle, int component);

/* Replaces the prescribed velocity (m/s) of a constrained component of one
 * particle, e.g. for a linear field v = A X on every boundary particle;
 * GSN_ERR_INTERNAL if that component is not constrained. */
int gsn_constraints_set_velocity(struct gsn_constraints *constraints,
                                 int particle, int component, double velocity);

/* The boundary entry (index in the case's boundaries) whose prescription
 * holds component k of particle I: the first in case order that constrains
 * it (any later one must prescribe the same value), or -1. The history
 * reports the component's constraint reaction under that entry. */
int gsn_constraints_entry(const struct gsn_constraints *constraints,
                          int particle, int component);

/* 1 if boundary entry `entry` holds some component of the particle. */
int gsn_constraints_holds(const struct gsn_constraints *constraints,
                          int particle, int entry);

/* Components constrained on model surface `surface` by the case's
 * boundary entries, as a bit mask (bit k: component k); 0 if none. */
int gsn_constraints_surface_mask(const struct gsn_constraints *constraints,
                                 int surface);

#ifdef __cplusplus
}
#endif
#endif
