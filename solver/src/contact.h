/* Rigid bodies the soil cannot enter (issue 15; docs/solver.md, "Rigid
 * bodies"): a boundary entry with `rigid: true` and a velocity is the face
 * of a rigid body, the surface swept against its motion (a footing's base
 * and, rising from its edges, its side walls). Its own particles keep their
 * prescribed velocity (constraint.h) while they lie under the base: one
 * that has slid out past the base's edge (a smooth footing squeezes soil
 * out) is released from it at the next reference update, as soil is not
 * under the footing any more (gsn_contact_release). Every other particle
 * that enters the body is pushed out by a penalty force, through the
 * nearer of the base and the walls: without it the soil beside a footing
 * that sinks deeper than its spacing flows over the base's edge and
 * between the base's particles.
 *
 * The body, at time t, is its surface on model.h5 moved by the prescribed
 * displacement v D(t) (constraint.h, gsn_ramp_factor; components without a
 * velocity stay). In its frame (a, b across the motion, c against it) the
 * surface's triangles project to a footprint; a point at (p, s) is inside
 * when p lies in the footprint and s above the base there. Its depth is the
 * smaller of the height above the base (along the base triangle's normal)
 * and the distance to the footprint's exits: its edges, except those along
 * a surface whose particles are held in the direction of the exit (a
 * symmetry plane, a roller side, the plane_strain axis), which soil cannot
 * cross anyway. The walls are frictionless.
 *
 * The force on a particle at depth g is k g along the way out, with
 * k = CONTACT_STIFFNESS m_I / dt^2 (m_I its lumped mass), applied at the
 * particle's position: f_J += Psi_J(X_I) k g n on the coefficients. It is
 * an external force on the soil: it enters the external work, and minus it
 * is the force the soil puts on the body (the entry's history columns). */
#ifndef GEOSCNI_CONTACT_H
#define GEOSCNI_CONTACT_H

#include "constraint.h"
#include "geoscni/case.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_contact;

/* The rigid bodies of the case's boundary entries with rigid: true, on the
 * model of the first reference configuration (its tetrahedra's faces give
 * the surfaces). *out is NULL when the case has none. GSN_ERR_INPUT, with
 * the case file's line, for a rigid surface with no faces. */
int gsn_contact_create(const struct gsn_model *original,
                       const struct gsn_case *c, struct gsn_contact **out);

/* Frees; NULL-safe, nulls the handle. */
void gsn_contact_destroy(struct gsn_contact **contact);

/* Marks in released (one bit mask of boundary entries per particle, |=)
 * the particles of each rigid surface of m (a reference configuration:
 * its positions, its particles' surfaces) that lie outside the body's
 * footprint at time t (s): no longer under the base. */
void gsn_contact_release(const struct gsn_contact *contact,
                         const struct gsn_model *m, double time,
                         unsigned *released);

/* The penalty forces at time t (s) with step dt (s): position the reference
 * positions X_I (n x 3, m), values Psi_J(X_I) (one row per particle),
 * displacement the coefficients d_J (n x 3, m), mass the lumped masses
 * (kg), margin an upper bound of |u(X_I) - d_I| (m; the largest support
 * serves); a particle that constraints hold to a body's own prescription
 * moves with it and feels no force from it. force (n x 3, N) is
 * overwritten; resultant[entry] (N) gets the
 * total force on the soil of each rigid entry (0 for the others); inside
 * the number of particles inside a body. */
int gsn_contact_forces(const struct gsn_contact *contact,
                       const struct gsn_constraints *constraints,
                       const double *position,
                       const struct gsn_shape_rows *values,
                       const double *displacement, const double *mass,
                       double dt, double time, double margin, double *force,
                       double resultant[][3], int *inside);

#ifdef __cplusplus
}
#endif
#endif
