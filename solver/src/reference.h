/* The reference configuration and its updates (issue 15; docs/solver.md,
 * "Large deformation").
 *
 * The seed paper builds its shape functions, nodal domains and smoothed
 * gradients once, on the initial configuration (eqs. (10), (19)-(20)).
 * Once a sliding mass has moved a support radius against its neighbours
 * they no longer describe the body. An update takes the current positions
 * x = X_ref + u(X_ref) as the new reference: the cells are built again on
 * them (the cells library, with the pre mesh's tetrahedra, their nodes
 * moved, as the body's pieces, so the boundary facets keep their surfaces),
 * then the shape functions, the integration and the boundary constraints
 * (displacements prescribed from the update's time on), and the state is
 * carried over (gsn_explicit_carry_over: stress, material state,
 * F = F_inc F_ref, the particles' masses and velocities, the clock and the
 * work). The discrete operator changes, the state does not; the kinetic
 * energy of the lumped masses may jump, and each jump is reported and
 * counted in the energy balance. Mass is kept exactly (the lumped masses
 * are partitions of the particles' masses) and so is momentum (the new
 * velocity coefficients interpolate the old velocity at every particle), to
 * the interpolation's tolerance. */
#ifndef GEOSCNI_REFERENCE_H
#define GEOSCNI_REFERENCE_H

#include "constraint.h"
#include "contact.h"
#include "explicit.h"
#include "geoscni/case.h"
#include "geoscni/cells.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"
#include "material.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Why an update is due (gsn_reference_due). */
enum gsn_reference_reason {
    GSN_REFERENCE_NOT_DUE = 0,
    GSN_REFERENCE_STRAIN,  /* |E| since the last update over the limit */
    GSN_REFERENCE_VOLUME,  /* det F since the last update out of range */
    GSN_REFERENCE_INTERVAL /* reference_update.every has passed */
};

/* What one update did. */
struct gsn_reference_report {
    enum gsn_reference_reason reason;
    int particle;             /* where the trigger was measured */
    double strain, volume[2]; /* |E| and det F extremes that triggered */
    double seconds;           /* wall time of the update */
    /* of it: the body and its cells, the shape functions and integration,
     * the constraints, the loop (blocks, masses), the state carried over
     * and settled */
    double seconds_cells, seconds_kernels, seconds_constraints, seconds_loop,
        seconds_state;
    double kinetic_before, kinetic_after; /* J, conserved (explicit.h) */
    double mass_error;                    /* |sum m' - sum m| / sum m */
    double momentum_error;                /* |sum m'v' - sum m v| / sum m |v| */
    int interpolation_iterations;
    double stable_step, time_step; /* s: of the new reference, and the
                                      step taken from it on */
    double seconds_stable;         /* wall time of the stable step */
    int remeshed;        /* 1: the body's tetrahedra were made again */
    int tetrahedra_only; /* 1: the cells needed the tetrahedra throughout */
    double body_quality; /* smallest tetrahedron volume / mean before */
    int support_repairs; /* points whose supports were repaired */
    int held_fallbacks;  /* points of held facets that keep Psi_I */
    int deferred;        /* 1: the new discretization failed its checks;
                            the run goes on with the present one */
    char cause[512];     /* why, when deferred */
};

struct gsn_reference {
    const struct gsn_model *original;         /* model.h5 (borrowed) */
    const struct gsn_case *c;                 /* borrowed */
    const struct gsn_material_set *materials; /* borrowed */
    int threads;                              /* 0: OpenMP's default */
    struct gsn_body body;    /* the body's tetrahedra: the pre mesh's, moved
                                with the particles, until some turn inside
                                out and it is made again (gsn_body_remesh) */
    int remesh_count;        /* times the body was made again */
    struct gsn_model *cells; /* the cells of the present reference after an
                                update (NULL before: `original` has them) */
    const struct gsn_model *model; /* original or cells */
    struct gsn_quadrature *quadrature;
    struct gsn_constraints *constraints;
    struct gsn_contact *contact; /* the rigid bodies, NULL without: built
                                    once on `original`, kept by updates */
    struct gsn_explicit *loop;
    int update_count;
    /* Updates whose new discretization failed (a negative lumped mass, a
     * point no kernel covers, cells that do not fit): the present one is
     * kept and the next attempt waits min_steps times 2^deferred_run steps
     * from attempt_step, so that a run that cannot be followed any further
     * does not spend itself on attempts. */
    int deferred_count, deferred_run;
    long attempt_step;
    double time;        /* s, of the present reference */
    long step;          /* of the present reference */
    double energy_jump; /* J, the kinetic energy the updates added */
    double seconds;     /* wall time of the updates */
    double first_step;  /* s: the run's time step at its start; an update
                           takes the new reference's stable step times
                           time.safety where that is smaller, else this */
    struct gsn_reference_report last;
    char last_deferral[512]; /* the cause of the last deferred update */
};

/* The discretization of the first reference configuration (model.h5's
 * particles and cells) with the loop at rest, step dt (s; the caller may
 * change it before the first step). */
int gsn_reference_create(const struct gsn_model *original,
                         const struct gsn_case *c,
                         const struct gsn_material_set *materials, double dt,
                         int threads, struct gsn_reference **out);

/* Frees; NULL-safe, nulls the handle. */
void gsn_reference_destroy(struct gsn_reference **r);

/* Whether the loop's last step calls for an update (the case's
 * reference_update), and why. */
enum gsn_reference_reason gsn_reference_due(const struct gsn_reference *r);

/* Steps from the last deferred attempt to the next: min_steps times
 * 2^(deferred updates in a row), the power at most 16. */
long gsn_reference_retry_steps(const struct gsn_reference *r);

/* Takes the current configuration as the reference (see above); report
 * (may be NULL) gets what it did. Where the new discretization fails its
 * checks the update is deferred (report->deferred, with the cause): the
 * old discretization is kept as it was and GSN_OK returned; other
 * failures (memory, a body that cannot be followed) are errors. */
int gsn_reference_update(struct gsn_reference *r,
                         struct gsn_reference_report *report);

/* For a restart: the discretization built on the reference positions of a
 * checkpoint (n x 3, m) taken at time (s) and step, with its body (NULL:
 * the pre mesh's) and the first reference's masses; the caller then loads
 * the checkpoint's state. */
/* The energy the updates added (J): the kinetic energy of their jumps and
 * the work of the forces they left unbalanced while those are released
 * (gsn_explicit_release_unbalanced); the energy balance takes it out. */
double gsn_reference_energy(const struct gsn_reference *r);

int gsn_reference_restore(struct gsn_reference *r, const double *position,
                          const struct gsn_body *body, double time, long step,
                          int update_count, double energy_jump);

/* Short name of a reason, for messages. */
const char *gsn_reference_reason_name(enum gsn_reference_reason reason);

#ifdef __cplusplus
}
#endif
#endif
