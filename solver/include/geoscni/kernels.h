/* Reproducing-kernel shape functions and the integration of the weak form
 * (seed paper sections 3 and 4, eqs. (9)-(24)); docs/kernels.md.
 *
 * Everything here is Lagrangian: built once on the reference configuration.
 * Whatever the integration method (SCNI, DNI, Gauss, with or without a
 * stabilization), the result has ONE structure, so the explicit time loop is
 * method-agnostic: integration points with a weight and a position, and for
 * each point a compact row of its neighbours I with the three gradient
 * components dPsi_I/dX_j stored contiguously (CSR). Shape values Psi_I are
 * kept at the particles (mass, body force, u(X_J) = sum_I Psi_I(X_J) d_I)
 * and at the boundary facet quadrature points (tractions).
 *
 * References: Chen, Wu, Yoon, You 2001, IJNME 50:435 (SCNI);
 * Puso, Chen, Zywicz, Elmer 2008, IJNME 74:416 (modified SCNI). */
#ifndef GEOSCNI_KERNELS_H
#define GEOSCNI_KERNELS_H

#include "geoscni/case.h"
#include "geoscni/model.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* More neighbours than this at one point is an input error (support far too
 * large for the particle spacing). */
#define GSN_RK_MAX_NEIGHBOURS 4096

/* Largest accepted 1-norm condition number of the scaled moment matrix
 * M(X) of eq. (15): beyond it more than half of the 16 digits are lost and
 * the reproducing conditions of eq. (18) no longer hold to 1e-8. */
#define GSN_RK_CONDITION_LIMIT 1e8

/* With a window cut, a point whose cut window's moment matrix is
 * conditioned worse than this takes the whole window instead
 * (kernel_evaluate). On Slope I's 530,000 kernel points the cut windows'
 * regular matrices reach 641 (cut 1e-3) and 582 (1e-2) and the starved
 * ones are singular (5.9e17, inf): the limit sits between, well above the
 * whole window's own (641). */
#define GSN_RK_CUT_CONDITION_LIMIT 1e4

/* Sub-cells per nodal domain of modified SCNI: 6 groups the pyramids over
 * the facets by the dominant signed axis of their normal, 2 by the sign
 * only (less than half the storage, slightly weaker: docs/kernels.md). */
#define GSN_DEFAULT_STABILIZATION_SUBCELLS 6

/* Compressed rows: entries offset[r] .. offset[r+1]-1 of row r, sorted by
 * index. value and gradient (3 per entry, d/dX_0..2) may be NULL. */
struct gsn_shape_rows {
    int row_count;
    int *offset;      /* row_count + 1 */
    int *index;       /* particle indices I */
    double *value;    /* Psi_I, - */
    double *gradient; /* dPsi_I/dX_j, 1/m, 3 per entry */
};

/* Frees the arrays and zeroes the struct; accepts a zeroed struct. */
void gsn_shape_rows_free(struct gsn_shape_rows *rows);

/* The RK approximation: particles, their supports and a cell list. The
 * kernel of particle I is the cubic B-spline tensor product with box
 * half-width radius[I] = support * h_I (seed paper eq. (10)). */
struct gsn_rk {
    int particle_count;
    int basis_order; /* 1 linear, 2 quadratic, eq. (11) */
    int basis_size;  /* 4 or 10 */
    double *position;
    double *radius; /* a_I, m */
    double max_radius;
    /* The window is taken as 0 where it is below this fraction of its peak
     * (0: the whole support): a particle covers a point only where its
     * window is at least that. Psi stays exactly linearly complete (an RK
     * correction of the cut window), and SCNI's eq. (24) holds as before,
     * both cells of a facet seeing the same Psi at its points; the tensor
     * product's corners, where the window is tiny, hold 44% of the support
     * box at 1e-3 (docs/kernels.md, "Window cut"). A point whose cut
     * window leaves M ill-conditioned (GSN_RK_CUT_CONDITION_LIMIT) takes
     * the whole window: a function of the point alone, like the cut. */
    double window_cut;
    /* where set (not NULL): kernel_rows_build writes there the position
     * of the ill-conditioned point it reports (the support repair of an
     * updated reference, integration_build.c) */
    double *failure_point;
    /* Cell lists for the neighbour search: grid[0] holds the particles of
     * ordinary support, grid[1] the few much wider than the median (raised
     * to cover a stretched cell or repaired), so that those do not coarsen
     * the search for all. */
    struct gsn_rk_grid {
        int count;          /* particles in it */
        double max_radius;  /* of its particles, m */
        double origin[3];   /* m */
        double cell_size;   /* m */
        int size[3];        /* cells along each axis */
        int *cell_offset;   /* cells + 1 */
        int *cell_particle; /* particles by cell, ascending within a cell */
        double *cell_data;  /* x, y, z, a of cell_particle, in that order */
    } grid[2];
};

/* Copies the positions (n x 3, m) and spacings h_I (m) and builds the cell
 * list. support is a/h (> 0); basis_order 1 or 2. */
int gsn_rk_create(int particle_count, const double *position,
                  const double *spacing, double support, int basis_order,
                  struct gsn_rk **out);

/* Frees; accepts NULL and nulls the handle. */
void gsn_rk_destroy(struct gsn_rk **rk);

/* rk with its whole window (window_cut 0): a shallow copy, sharing rk's
 * arrays, for the searches that must not depend on the cut. */
static inline struct gsn_rk gsn_rk_whole_window(const struct gsn_rk *rk)
{
    struct gsn_rk whole = *rk;
    whole.window_cut = 0.0;
    return whole;
}

/* Local spacing h_I from the nodal domains: the facet-area-weighted mean
 * distance to the particles that share a facet with I (DESIGN.md, "Support
 * size"). Degenerate facets of cospherical lattices have no area and no
 * weight. With cover_support > 0 (the support a/h), h_I is raised where
 * needed for the support to reach every particle that shares a facet of
 * positive area with I: on a deformed configuration a particle beside a
 * sliver or a gap was otherwise covered by too few kernels for the moment
 * matrix (docs/deep_penetration.md). spacing has particle_count entries. */
int gsn_rk_spacing_from_facets(const struct gsn_model *m, double cover_support,
                               double *spacing);

/* The particles whose kernel covers x (|x_k - X_Ik| < a_I for k = 0..2), in
 * ascending order. Returns their number; only the first capacity are
 * written, so a return value above capacity means index was too short. */
int gsn_rk_neighbours(const struct gsn_rk *rk, const double x[3], int capacity,
                      int *index);

/* Sorts n distinct ints ascending (insertion sort on short runs under a
 * quicksort: qsort's calls through a pointer were a tenth of SCNI's rows). */
void gsn_sort_ints(int *a, int n);

/* The particles whose kernel covers some point of the box [lo, hi]
 * (|X_Ik - y_k| < a_I for some lo <= y <= hi), in ascending order: the
 * candidates of gsn_rk_neighbours_among for points in the box. Returns
 * their number; only the first capacity are written. */
int gsn_rk_box_neighbours(const struct gsn_rk *rk, const double lo[3],
                          const double hi[3], int capacity, int *index);

/* gsn_rk_neighbours of x (in the box that gave the candidates) found among
 * them: the same particles in the same order. */
int gsn_rk_neighbours_among(const struct gsn_rk *rk, const double x[3],
                            const int *candidate, int candidate_count,
                            int capacity, int *index);

/* Doubles of workspace gsn_rk_shape_point needs for count neighbours. */
size_t gsn_rk_work_size(const struct gsn_rk *rk, int count);

/* Pure kernel: Psi_I(x) (eq. (16) with M^{-1}) and, if gradient is not
 * NULL, dPsi_I/dX (3 per neighbour) for the count neighbours in index.
 * Returns 0, or 1 if M(x) is singular or its condition number exceeds
 * GSN_RK_CONDITION_LIMIT (the outputs are then undefined). *condition gets
 * the 1-norm condition number of the scaled moment matrix. */
int gsn_rk_shape_point(const struct gsn_rk *rk, const double x[3], int count,
                       const int *index, double *work, double *psi,
                       double *gradient, double *condition);

/* Second derivatives d^2 Psi_I / dX_j dX_k (9 per neighbour, row-major)
 * of the linear basis at x, for the count neighbours in index (NSNI's
 * strain gradients, Hillman & Chen 2016). Returns 0, or 1 if the basis is
 * not linear or M(x) is singular or ill-conditioned (*condition as in
 * gsn_rk_shape_point). */
int gsn_rk_hessian_point(const struct gsn_rk *rk, const double x[3], int count,
                         const int *index, double *work, double *hessian,
                         double *condition);

/* Shape values (and gradients if want_gradient) at point_count points
 * (n x 3, m), one row per point. OpenMP over points; the rows do not depend
 * on the thread count. A point with an ill-conditioned moment matrix is a
 * GSN_ERR_NUMERICAL naming the point and its neighbour count. */
int gsn_rk_shape_rows(const struct gsn_rk *rk, int point_count,
                      const double *points, int want_gradient,
                      struct gsn_shape_rows *rows);

/* Options of the kernel and integration build, usually from the case. */
struct gsn_kernel_options {
    double support;  /* a/h */
    int basis_order; /* 1 or 2 */
    enum gsn_integration integration;
    int gauss_points; /* per direction per background cell, GAUSS */
    enum gsn_stabilization stabilization;
    double stabilization_coefficient; /* MSCNI: weight of the sub-cells */
    int stabilization_subcells;       /* MSCNI: 6 (+-x, +-y, +-z) or 2 */
    int cover_neighbours;             /* supports reach every facet neighbour (a
                                         reference-configuration update's build) */
    /* Essential boundaries (gsn_constraints_held; NULL: none): the
     * components held on each facet and at each particle. On a held
     * boundary facet, Psi_I at the quadrature points is replaced by its
     * linear interpolant through the held particles of the facet's surface
     * (in the smoothed gradients and boundary_values), so that the facet's
     * boundary integral is a combination of the constraints' rows
     * (docs/solver.md, "Boundary values"). */
    const int *held_facet;
    const int *held_particle;
    double window_cut; /* gsn_rk.window_cut */
};

void gsn_kernel_options_from_case(const struct gsn_case *c,
                                  struct gsn_kernel_options *options);

/* The integrated weak form, one structure for every method:
 *   f_int_I = sum_p B_pI^T sigma_p weight_p,  B_pI from gradient row p.
 * Points [0, main_point_count) are the nodal points (SCNI: smoothed
 * gradient eq. (20), DNI: gradient at the particle; point p is particle p,
 * weight V_L) or the Gauss points (weight = Gauss weight x Jacobian, no
 * particle). Points [main_point_count, point_count) are MSCNI stabilization
 * points: row = B_s - B_L of a sub-cell s of particle L, weight
 * = coefficient x V_s; their stress is the elastic C : (B_s - B_L) d (Puso
 * et al. 2008), which vanishes for every linear field. Stabilization point
 * main_point_count + S L + s belongs to sub-cell s of particle L (S = the
 * sub-cell count); a sub-cell with no volume has weight 0 and no entries. */
struct gsn_quadrature {
    enum gsn_integration method;
    enum gsn_stabilization stabilization;
    int particle_count;
    int point_count;
    int main_point_count;
    double *point_weight;   /* m^3 */
    double *point_position; /* point_count x 3, m */
    int *point_particle;    /* nodal and stabilization points: L; Gauss: -1 */
    /* Rows = points. value: Psi_I at the Gauss points (their lumped mass,
     * eq. (28)); NULL for nodal integration (particle_values has it). */
    struct gsn_shape_rows gradient;
    /* Psi_I(X_J), rows = particles J: lumped mass eq. (28), body force,
     * u(X_J) = sum_I Psi_I(X_J) d_I. */
    struct gsn_shape_rows particle_values;
    /* The quadrature points of the boundary facets (neighbour -1), in facet
     * order, with Psi_I at each: tractions use the smoothing's quadrature. */
    int boundary_point_count;
    int *boundary_point_facet;
    double *boundary_point_position; /* x 3, m */
    double *boundary_point_weight;   /* m^2 */
    struct gsn_shape_rows boundary_values;
    /* points of held facets (gsn_kernel_options.held_facet) that integrate
     * the interpolant through the held particles, and those that keep
     * Psi_I because their held particles do not span them */
    int held_point_count, held_fallback_count;
    /* points whose supports were repaired (gsn_quadrature_create) */
    int support_repairs;
    struct gsn_rk *rk; /* the shape functions (owned) */
};

/* Builds the shape functions and the integration of model m. Gauss uses
 * background cells: background_cell_count hexahedra of 8 vertices each
 * (x 3, vertex (i,j,k) at i + 2j + 4k, trilinear map), or, when
 * background_cells is NULL, the tetrahedra of the model (each collapsed to
 * a hexahedron, n^3 points per tetrahedron). */
int gsn_quadrature_create(const struct gsn_model *m,
                          const struct gsn_kernel_options *options,
                          const double *background_cells,
                          int background_cell_count,
                          struct gsn_quadrature **out);

/* Frees; accepts NULL and nulls the handle. */
void gsn_quadrature_destroy(struct gsn_quadrature **q);

/* Bytes of the arrays the time loop reads (points, rows, values). */
size_t gsn_quadrature_bytes(const struct gsn_quadrature *q);

#ifdef __cplusplus
}
#endif
#endif
