/* Essential boundary conditions imposed exactly on the displacement of the
 * boundary particles, u_c(X_J) = sum_I Psi_I(X_J) d_Ic (DESIGN.md,
 * "Essential boundary conditions"): RK shape functions do not interpolate,
 * so fixing d_J would not fix u(X_J).
 *
 * For each component c, B_c is the set of particles with c constrained and
 * Lambda_c[J][K] = Psi_K(X_J) for J, K in B_c, factorized once (KLU; its
 * factors copied into plain arrays, so the solve of every step reads each
 * factor once in storage order: 2.5x faster than klu_solve). After
 * each unconstrained update, the coefficients of B_c alone are corrected so
 * that sum_I Psi_I(X_J) f_Ic equals the prescribed value at every J in B_c:
 * the mixed transformation of Chen & Wang (2000) restricted to the boundary.
 * The same correction is applied to displacements, velocities and
 * accelerations. */
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
    GSN_FIELD_ACCELERATION
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
 * holds the component normal to its plane, gsn_case_resolve_symmetry), and
 * factorizes Lambda_c. values: Psi_I(X_J), one row per particle J.
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
 * has left its base is free there, and so is the boundary term). */
int gsn_constraints_facet_mask(const struct gsn_constraints *constraints,
                               int surface, int owner);

/* Frees; NULL-safe, nulls the handle. */
void gsn_constraints_destroy(struct gsn_constraints **constraints);

/* Corrects field (n x 3 coefficients) in place so that the prescribed
 * values hold at time t at every constrained particle. values: the rows
 * given to gsn_constraints_create (whose entries were taken from them
 * once, at create). */
int gsn_constraints_apply(struct gsn_constraints *constraints,
                          const struct gsn_shape_rows *values,
                          enum gsn_constraint_field kind, double time,
                          double *field);

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
