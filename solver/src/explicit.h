/* The explicit central-difference loop of the seed paper, eqs. (26)-(34),
 * in updated-Lagrangian form with Lagrangian (reference) shape functions.
 *
 * Per step, from d_n, v_n, a_n:
 *   d_{n+1} = d_n + dt v_n + dt^2/2 a_n                       eq. (33)
 *   d corrected so u(X_J) holds exactly (constraint.h; every 64 steps)
 *   one pass over the gradient rows, block by block (point_blocks.h):
 *     dH = sum_I (d_I - d_I^n) (x) grad_X Psi_I(X_p), H_{n+1} = H_n + dH,
 *     F = I + H                                              eq. (21)
 *     G = dH (I + H_n + dH/2)^-1, the incremental gradient on the mid-step
 *     configuration; stress by Hughes-Winget + material (Fig. 3)
 *     P_p = det F sigma F^-T w_p  (so that B_I^T sigma det F V_p of eq. (29)
 *     is P_p grad_X Psi_I(X_p), with the chain rule of eq. (25)),
 *     scattered as P_p grad_X Psi_I into the block's slots (a
 *     stabilization point's row B_s - B_L as B_s, with -P_s B_L folded
 *     into its particle's nodal point: point_blocks.h)
 *   the slots of every particle summed in block order (the same bits on
 *   any number of threads):
 *     f_int_I = sum_p P_p grad_X Psi_I(X_p)                   eq. (29)
 *     a_{n+1} = M^-1 (f_ext - f_int)                          eq. (32)
 *   a_{n+1} projected, mass-orthogonally, onto the constraints: the
 *   correction M^-1 C^T lambda, C^T lambda the reaction (constraint.h)
 *   v_{n+1} = v_n + dt/2 (a_n + a_{n+1})                      eq. (34)
 * with the row-sum lumped mass m_I = rho0 sum_p Psi_I(x_p) w_p over the
 * main points (eq. (28); sum_L Psi_I(X_L) V_L with nodal integration) and
 * the body force f_ext_I = m_I g (eq. (27) with the same row sums).
 *
 * Integration points: the main points are the nodal points (point L is
 * particle L) or Gauss points, each with its own stress, H and material
 * state; MSCNI adds stabilization points to nodal points. What a particle
 * reports (stress, damage, plastic strain) is the weighted mean over its nodal
 * domain's points (domain_point below): its own nodal point, bit for bit, with
 * nodal integration.
 *
 * Constrained boundaries: RK test functions do not vanish on a surface whose
 * displacement is prescribed, so the weak form has a boundary term
 * int_{Gamma_u} Psi_I t dS. On the held facets the smoothing integrates
 * the interpolant of Psi_I through the held particles
 * (gsn_kernel_options.held_facet), which makes that term a combination
 * sum_J Psi_I(X_J) lambda_J of the constraints' rows: the mass-orthogonal
 * projection of the accelerations takes it up as the reaction C^T lambda,
 * and the linear patch test is exact with a symmetric operator (the
 * stiffness sum_p B_p^T C B_p w_p on the constrained motions; docs/solver.md,
 * "Boundary values"). The reaction on a surface is the sum of its
 * particles' lambda_J (gsn_constraints_multipliers).
 *
 * Local damping (Cundall 1987, as in FLAC and most MPM codes), optional:
 * on every free component the unbalanced force f = f_ext - f_int gets
 * -a |f| sign(v_{n+1/2}) with v_{n+1/2} = v_n + dt/2 a_n. It removes the
 * ringing of a quasi-static load without changing the equilibrium states
 * (the damping force vanishes with f); its work is reported. */
#ifndef GEOSCNI_EXPLICIT_H
#define GEOSCNI_EXPLICIT_H

#include "constraint.h"
#include "contact.h"
#include "geoscni/case.h"
#include "geoscni/kernels.h"
#include "material.h"
#include "point_blocks.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Phases of a step, for the wall time spent in each (phase_seconds). */
enum gsn_explicit_phase {
    GSN_PHASE_PASS,        /* the one pass over the rows: F, stress, f_int */
    GSN_PHASE_CONSTRAINTS, /* the boundary solves (constraint.h) */
    GSN_PHASE_UPDATES,     /* d, a, v, reactions, energies */
    GSN_PHASE_COUNT
};

/* Parts of the row pass's blocks (block_step), for their shares of its
 * time (pass_part_ticks). */
enum gsn_pass_part {
    GSN_PASS_GATHER,        /* the increments and the rows' sums */
    GSN_PASS_MATERIAL,      /* the main points' kinematics and stress */
    GSN_PASS_STABILIZATION, /* the stabilization points */
    GSN_PASS_SCATTER,       /* the forces into the slots */
    GSN_PASS_PART_COUNT
};

struct gsn_explicit {
    const struct gsn_model *model;             /* borrowed */
    const struct gsn_quadrature *quadrature;   /* borrowed */
    const struct gsn_material_set *materials;  /* borrowed */
    const struct gsn_material_model *material; /* the first: the kind */
    struct gsn_constraints *constraints;       /* borrowed, may be NULL */
    int particle_count, point_count, main_point_count, state_size;
    unsigned char *point_material; /* main points: index into materials */
    /* K and mu of each material (Pa), for the stabilization points */
    double bulk_modulus[GSN_MAX_MATERIALS], shear_modulus[GSN_MAX_MATERIALS];
    /* the water table's pore pressure u at the main points (Pa, compression
     * positive; water:), NULL without: the force is that of the total
     * stress sigma' - u I, the material's the effective sigma' (stress) */
    double *pore_pressure;
    double pore_factor; /* the load factor the present stress carries u with
                           (u is a dead load: raised with the others) */
    double dt;          /* s */
    long step;
    double time; /* s: time_base + (step - step_base) dt */
    /* where the present step dt began (0, 0 until it changes: a reference
     * update may change it, gsn_explicit_set_time_step) */
    double time_base;
    long step_base;

    double *mass;               /* n, kg: the lumped masses, with the mass that
                                   mass scaling adds (time.mass_scaling) */
    double *lumped_mass;        /* n, kg: the lumped masses alone, which the
                                   body force and the body's mass take */
    double mass_scaling;        /* the fraction of the body's mass that mass
                                   scaling may add (case time.mass_scaling) */
    double *particle_stiffness; /* n, N/m: mass scaling's measure k_I
                                   (explicit.c), NULL without it */
    int mass_scaled_count;      /* particles given added mass */
    double mass_scaled_largest; /* the largest m_I' / m_I */
    double *displacement;       /* n x 3 coefficients d_I, m */
    double *velocity;           /* n x 3, m/s */
    double *acceleration;       /* n x 3, m/s^2 */
    double *f_ext;              /* n x 3 external force of the step, N: the
                                   dead loads times load_factor */
    double *f_ext_full;         /* n x 3 dead loads (body force, tractions) at
                                   full value, N */
    double load_factor;         /* of the dead loads (time.ramp), 1 at full */
    double *f_int;              /* n x 3 internal force, N */
    double *reaction;           /* n x 3: C^T lambda, the force the supports
                                   apply (constraint.h), 0 where they reach not */
    double *stress;             /* points x 6, Pa (nominal Cauchy) */
    double *state;              /* main points x state_size */

    double kinetic_energy, internal_energy, external_work; /* J */
    /* 1/2 v_{n-1/2} M v_{n+1/2} = 1/2 v M v - dt^2/8 a M a: with W_int what
     * central differences conserve exactly on a linear body, where
     * 1/2 v M v swings by (omega dt / 2)^2 of each mode's energy; the
     * energy balance's kinetic term (solve.c, check_energy), J */
    double conserved_kinetic_energy;
    double phase_seconds[GSN_PHASE_COUNT]; /* wall time of the steps, s */
    /* the blocks' parts summed over the threads, in clock ticks (the time
     * stamp counter on x86-64): their shares, not seconds */
    double pass_part_ticks[GSN_PASS_PART_COUNT];
    double *thread_part_ticks; /* threads x 8: one cache line each */
    /* of it, spent factorizing the boundary matrices (the first solve
     * after a restart or new masses), taken out of
     * phase_seconds[GSN_PHASE_CONSTRAINTS], s */
    double factor_seconds;
    double damping_work;   /* J dissipated by the local damping */
    double damping_local;  /* Cundall's coefficient (case damping.local) */
    int damping_net;       /* 1: the damping acts on f_ext - f_int plus the
                              last step's reaction C^T lambda, which vanishes
                              at rest also beside held faces (the geostatic
                              stage); 0: on f_ext - f_int, which there does
                              not (the loading stage, as measured so far) */
    double *damping_force; /* n x 3, N: the local damping force of the last
                              step (its work is a trapezoid like W_ext) */

    /* Work arrays, owned. */
    double *previous_displacement, *previous_external, *new_acceleration;
    /* n x 4: d - d_n of the step (the 4th zero), the pass's input */
    double *increment;
    double *piola;        /* points x 9: P_p w_p of the main points (the pass
                             keeps the stabilization points' P in registers) */
    double *point_energy; /* points: internal energy increment, J */
    int *point_failed;    /* points: 1 where pass 1 failed */
    double *thread_work;
    int thread_count;
    /* The pass's blocks in contiguous ranges, one a thread (for
     * block_range_threads threads): each thread takes its own from the
     * front and then others' from the back (block_deque: 8 words a thread,
     * one cache line, the first holding front << 32 | back), and the next
     * pass's ranges are as long as the blocks each took (block_taken). A
     * block's points then stay in one core's caches from step to step,
     * where OpenMP's dynamic schedule moved them between the cores every
     * step. */
    int block_range_threads;
    int *block_taken;
    uint64_t *block_deque;
    struct gsn_point_blocks *blocks; /* the rows cut for one pass a step */
    double *slot_force;              /* slots x 3: forces of each block */
    double *displacement_gradient;   /* points x 9: H = F - I at t_n at the
                                        main points (the rows of the
                                        stabilization points stay zero: their
                                        stress is integrated as a rate) */
    int small_strain;                /* kinematics: small: F = I in the
                                        forces, G = sym dH (case.h) */
    int held_axis;                   /* plane_strain: the component that is
                                        zero at every coefficient, -1 none */
    int plastic_offset;              /* equivalent_plastic_strain in the
                                        state, -1 without plasticity */
    /* damage.length (nonlocal.h): the averaging rows of the main points,
     * NULL without a length; the state offsets of e_t and its average */
    struct gsn_nonlocal *nonlocal;
    int strain_offset, nonlocal_offset;
    /* The main points of each particle's nodal domain (offset particles
     * + 1), what the particle reports of the points' stress and state (and
     * the tractions of gsn_explicit_surface_force): nodal integration, the
     * particle's own nodal point; Gauss, the points nearest to the particle
     * (among those its kernel covers, so the points of its nodal domain) or,
     * where there are none, the one point nearest to it. domain_weight: the sum
     * of their weights, m^3. */
    int *domain_offset, *domain_point;
    double *domain_weight;
    int *point_owner; /* main points: the particle whose domain holds it */
    unsigned char *constrained; /* particles: constrained components (bit k:
                                   component k), copied once from the
                                   constraints for the step's loops */
    struct gsn_step_sums *step_partial; /* the sums of each piece of the
                                           step's loops (explicit.c) */

    /* The reference configuration (issue 15). The shape functions, cells
     * and gradients are built on it; an update builds them again on the
     * current positions and carries the state over
     * (gsn_explicit_carry_over). */
    double gravity[3];          /* m/s^2, f_ext = m g */
    double *point_mass;         /* main points: the mass each carries, kg
                                   (rho0 w_p at the first reference; kept
                                   through updates, so the lumped masses
                                   always add up to the body's) */
    double *reference_offset;   /* n x 3: X_ref - X_0, m (0 until an update) */
    double *reference_gradient; /* main points x 9: F of the reference
                                   configuration, F = (I + H) F_ref */
    int allow_failure;          /* 1: a point whose F turns inside out fails
                                   (no stress from then on) instead of
                                   stopping the run */
    int *point_dead;            /* main points: 1 once failed */
    int dead_count;             /* main points failed so far */
    int legacy_boundary_term;   /* 1: take the boundary term of before
                                   2026-12-02 evening off f_int, sum_q
                                   Psi_I(x_q) t w_q on the held facets
                                   (non-symmetric; the negative control of
                                   test_long_energy, with Psi_I itself on
                                   the held facets) */
    int track_distortion;       /* 1: measure the distortion below (reference
                                   updates need it; the step skips it else) */
    /* Distortion of the step just done over the live main points, from
     * F_inc = I + H: the largest |E|, E = (F^T F - I) / 2 (Frobenius), the
     * extremes of det F_inc, and where the largest strain is. */
    double distortion_strain, distortion_jacobian_min, distortion_jacobian_max;
    int distortion_point;
    double *block_distortion;     /* blocks x 6: the same per block, with
                                     the points failed in the step and the
                                     first of them */
    int interpolation_iterations; /* of the velocity at the last carry-over */

    /* Rigid bodies (contact.h), borrowed, NULL without: their penalty
     * forces on the coefficients at the present step (n x 3, N; an
     * external force: in a, the reactions and W_ext), their total on the
     * soil by boundary entry, and the particles inside a body. */
    const struct gsn_contact *contact;
    double *contact_force;
    double contact_resultant[GSN_MAX_BOUNDARIES][3];
    int contact_count;

    /* The force a reference update leaves unbalanced, released gradually
     * (gsn_explicit_release_unbalanced): applied at release_factor times
     * its full value, which falls linearly to 0 over release_steps steps;
     * NULL once released. Its work (J, since the first reference) is the
     * update's, not the loads'. */
    double *release_force; /* n x 3, N */
    long release_start, release_steps;
    double release_factor, release_next; /* of the present and next step */
    double release_work;
};

/* Sets up the loop at rest (d = v = a = 0, zero stress, F = I). The lumped
 * mass must be positive at every particle. A point carries the material of
 * its particle (the one whose nodal domain holds it), the density of it
 * (saturated below the water table) and the pore pressure where it is. */
int gsn_explicit_create(const struct gsn_model *m,
                        const struct gsn_quadrature *quadrature,
                        const struct gsn_material_set *materials,
                        struct gsn_constraints *constraints,
                        const struct gsn_case *c, double dt,
                        struct gsn_explicit **out);

/* Frees; NULL-safe, nulls the handle. */
void gsn_explicit_destroy(struct gsn_explicit **e);

/* The constraints the loop imposes from now on (borrowed, may be NULL; their
 * masses set by the caller), with the components they hold: the geostatic
 * stage swaps in those of the fixed components alone (solve.c). */
void gsn_explicit_set_constraints(struct gsn_explicit *e,
                                  struct gsn_constraints *constraints);

/* Gives the loop its rigid bodies (NULL: none) and their forces on the
 * present state. */
int gsn_explicit_set_contact(struct gsn_explicit *e,
                             const struct gsn_contact *contact);

/* Releases gradually the force by which `to`, just carried over from
 * `from` and settled, is out of balance: the particles' acceleration from
 * the loads and the internal force (no damping, no supports) on from's
 * discretization, interpolated onto to's coefficients, less to's own, times
 * the masses, added to to's force and faded out over `steps` steps. An
 * update changes the discrete operator, not the state: on a nonuniform
 * stress the new cells' forces differ from the old ones by a noise of the
 * particles' scale, which applied at once kicks every particle (measured
 * on the coarse Slope I: the acceleration's rms 5 to 40 times its value
 * before) and the damage, which sums |d eps| (eq. (7)), spreads with the
 * ringing. Then settles `to` again with that force. */
int gsn_explicit_release_unbalanced(struct gsn_explicit *to,
                                    const struct gsn_explicit *from,
                                    long steps);

/* Carries the state of `from` onto `to`, a loop built (gsn_explicit_create)
 * on the current positions of from's particles, X_ref + u(X_ref): the
 * particles' masses, velocities (the coefficients of `to` that carry
 * from's velocity at every particle, gsn_explicit_interpolate), the stress
 * and material state of every point, F = (I + H) F_ref as to's F_ref, the
 * failed points, the clock and the work done; d = 0 and H = 0 on the new
 * reference. The body force is m g with the carried masses; tractions are
 * the caller's to add, then gsn_explicit_settle. Nodal integration only
 * (the points are the particles' own). */
int gsn_explicit_carry_over(struct gsn_explicit *to,
                            const struct gsn_explicit *from);

/* f_ext = factor x the dead loads (the ramp of gravity and tractions). */
void gsn_explicit_set_load_factor(struct gsn_explicit *e, double factor);

/* Sets the masses the main points carry (kg, one per main point) and
 * builds the lumped masses and the body force from them. */
int gsn_explicit_set_point_mass(struct gsn_explicit *e, const double *mass);

/* The forces, accelerations, reactions and kinetic energy of the present
 * state (stress, d, v) without moving it: after set-up from a state (a
 * checkpoint or gsn_explicit_carry_over). The prescribed velocities are
 * imposed on v first. */
int gsn_explicit_settle(struct gsn_explicit *e);

/* The weight eps of the interpolation's regularization below. */
#define GSN_INTERPOLATE_REGULARIZATION 0.01

/* The coefficients c (n x 3) whose field takes the given values v (n x 3)
 * at the particles, regularized: c minimizes
 * |Lambda c - v|_W^2 + eps |c - v|_M^2 with Lambda_JI = Psi_I(X_J), W the
 * particles' masses and M the lumped ones, keeping the momentum
 * (sum_I M_I c_I = sum_J W_J v_J). A linear field is kept exactly (c = v);
 * smooth ones nearly (eps of the exact interpolation's correction is left
 * out); a field near Lambda's null space is not amplified more than
 * 1 / (2 sqrt(eps)) = 5 times, where the exact interpolation blew the
 * velocity of a distorted corner up 127 times (kinetic energy 68 J ->
 * 43 kJ, docs/solver.md). Conjugate gradients on the normal equations with
 * the diagonal as preconditioner, to 1e-12 of the right-hand side;
 * GSN_ERR_NUMERICAL if it does not get there. Needs the masses set
 * (gsn_explicit_set_point_mass). *iterations gets the count (may be
 * NULL). */
int gsn_explicit_interpolate(const struct gsn_explicit *e, const double *values,
                             double *c, int *iterations);

/* u(X_J) at the particles from the first reference, X_ref - X_0 +
 * sum_I Psi_I(X_J) d_I (n x 3, m): what frames show. */
void gsn_explicit_particle_displacement(const struct gsn_explicit *e,
                                        double *out);

/* The material state of every main point set from its stress (the
 * materials' initialize: no history), e.g. after a geostatic stress. */
int gsn_explicit_initialize_material(struct gsn_explicit *e);

/* Adds the water's pressure on the boundary facets below the table of
 * c (water:), t = -u n, to f_ext, with the facet quadrature as tractions
 * (nothing without water). */
void gsn_explicit_add_water_pressure(struct gsn_explicit *e,
                                     const struct gsn_model *m,
                                     const struct gsn_case *c);

/* Adds a dead-load traction t (Pa, per reference area) on the boundary
 * facets of model surface `surface` to f_ext, integrated with the facet
 * quadrature of the smoothing (eq. (27); DESIGN.md: the same points keep
 * the patch test exact). */
void gsn_explicit_add_traction(struct gsn_explicit *e,
                               const struct gsn_model *m, int surface,
                               const double traction[3]);

/* Recomputes what is derived from the state (the external force of the
 * last step) after the state was loaded from a checkpoint. */
int gsn_explicit_refresh(struct gsn_explicit *e);

/* The pass alone: F, the objective stress update, P at every point and
 * f_int for the increment from
 * previous_displacement to displacement (both set by the caller).
 * gsn_explicit_step calls it; tests drive it with prescribed motions. */
int gsn_explicit_update_stress(struct gsn_explicit *e);

/* kinetic_energy and conserved_kinetic_energy of the present v and a (a
 * step sets them; a restart's restored state calls it). */
void gsn_explicit_kinetic_energies(struct gsn_explicit *e);

/* The bytes a step must move at the least (the roofline's data, issue 17):
 * every array it reads once and every array it changes written once: the
 * packed rows and slot tables; the slot forces (written, then read by the
 * reduction); per particle d, v, a (read and written), m and f_ext (read),
 * f_int (written and read); per point H, the stress and the state (read
 * and written), P w (written) and w (read). The code moves more (d_n kept,
 * damping, the boundary solves); caches may hold some of it between steps. */
double gsn_explicit_step_bytes(const struct gsn_explicit *e);

/* The time of a step at the present time step (s). */
double gsn_explicit_time_of(const struct gsn_explicit *e, long step);

/* The time step from the present step on (s): steps before keep their
 * times. */
void gsn_explicit_set_time_step(struct gsn_explicit *e, double dt);

/* One step from t_n to t_{n+1}. GSN_ERR_NUMERICAL names the step, the time
 * and the particle when a point inverts (det F <= 0), a value is not finite
 * or the material fails. */
int gsn_explicit_step(struct gsn_explicit *e);

/* The largest stable step of the linear elastic system at the reference
 * configuration under the present constraints and local damping:
 * 2 / sqrt((1 + damping_local) lambda_max), lambda_max of P M^-1 K P (P the
 * constraints' projection, which the loop applies to a every step) from
 * Lanczos in the mass inner product (deterministic start; the largest Ritz
 * value plus its residual bound). The local damping scales each
 * component's unbalanced force by a factor in [1 - a, 1 + a], the
 * stiffness by up to 1 + a (docs/solver.md, "Time step"). */
int gsn_explicit_stable_step(struct gsn_explicit *e, double *dt);

/* Resultant of the tractions on the boundary facets of model surface
 * `surface` for the components in mask (N), in the current state: on a
 * constrained surface, the force the supports apply to the body (the
 * facets of particles a rigid body has released left out). */
void gsn_explicit_surface_force(const struct gsn_explicit *e, int surface,
                                int mask, double force[3]);

/* Field values at the particles from coefficients (n x 3 each):
 * out_J = sum_I Psi_I(X_J) c_I. */
void gsn_explicit_particle_field(const struct gsn_explicit *e,
                                 const double *coefficients, double *out);

/* Stress at the particles (n x 6, Pa): the weighted mean stress of the
 * points of each particle's nodal domain (explicit.h, domain_point): the
 * nodal point's own stress with nodal integration. */
void gsn_explicit_particle_stress(const struct gsn_explicit *e, double *out);

/* Material state variable `offset` at the particles (n), the same weighted
 * mean over each nodal domain as the stress (damage, equivalent plastic
 * strain: a convex combination, so it stays in their ranges). */
void gsn_explicit_particle_state(const struct gsn_explicit *e, int offset,
                                 double *out);

#ifdef __cplusplus
}
#endif
#endif
