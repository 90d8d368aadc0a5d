/* Essential-boundary patch test: a linear velocity v = A X (A general, with
 * rotation) prescribed on every boundary particle, starting from the same
 * field inside, is an exact solution of the discrete equations (homogeneous
 * deformation, no acceleration), so the interior particles must follow
 * u(X_J) = A X_J t to round-off. On an irregular block and on the gmsh
 * L-shaped body (re-entrant edge). It holds because the held facets
 * integrate the interpolant of Psi_I through the held particles
 * (constraint.h, gsn_kernel_options.held_facet): their boundary integral
 * is then a reaction C^T lambda that the mass-orthogonal projection takes
 * up; with Psi_I itself on them it does not (negative control). */
#include "geoscni/case.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <math.h>

/* Runs the patch test on the case's gmsh body (gmsh 1) or on a jittered
 * box; returns max |u - A X t| / max |A X t|. */
static double patch_error(const char *case_path, int gmsh, int plain_facets)
{
    struct gsn_case c;
    TEST_INT(gsn_case_load(case_path, &c), GSN_OK);
    const int count[3] = {6, 6, 6};
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    struct fixture_solver s;
    fixture_plain_facets = plain_facets;
    int rc = gmsh ? fixture_solver_from_gmsh(&c, 1e-4, &s)
                  : fixture_solver_create(&c, count, lo, hi, 0.25, 1e-4, &s);
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK)
        return 1.0;
    struct gsn_explicit *e = s.loop;
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    e->dt = 0.5 * stable;
    const double A[9] = {2e-3, -1e-3,   0.5e-3, 1.5e-3, -1e-3,
                         2e-3, -0.5e-3, -2e-3,  1e-3}; /* 1/s */
    const double *X = s.quadrature->rk->position;
    for (int i = 0; i < e->particle_count; ++i)
        for (int r = 0; r < 3; ++r) {
            double v = A[3 * r] * X[3 * i] + A[3 * r + 1] * X[3 * i + 1] +
                       A[3 * r + 2] * X[3 * i + 2];
            e->velocity[3 * i + r] = v;
            if (gsn_constraints_is_constrained(s.constraints, i, r))
                TEST_INT(gsn_constraints_set_velocity(s.constraints, i, r, v),
                         GSN_OK);
        }
    const int steps = 200;
    for (int k = 0; k < steps; ++k)
        TEST_INT(gsn_explicit_step(e), GSN_OK);
    double *u = malloc(sizeof(double) * 3 * (size_t)e->particle_count);
    gsn_explicit_particle_field(e, e->displacement, u);
    double worst = 0.0, scale = 0.0;
    int interior = 0;
    for (int i = 0; i < e->particle_count; ++i) {
        for (int r = 0; r < 3; ++r) {
            double exact =
                e->time * (A[3 * r] * X[3 * i] + A[3 * r + 1] * X[3 * i + 1] +
                           A[3 * r + 2] * X[3 * i + 2]);
            scale = fmax(scale, fabs(exact));
            worst = fmax(worst, fabs(u[3 * i + r] - exact));
        }
        interior += s.model.particle_surface_offset[i + 1] ==
                    s.model.particle_surface_offset[i];
    }
    printf("%s, %s: %d particles (%d interior), %d steps to t = %.4g s: "
           "max |u - A X t| / max |A X t| = %.3g\n",
           case_path,
           plain_facets ? "Psi_I on the held facets"
                        : "the interpolant on the held facets",
           e->particle_count, interior, steps, e->time, worst / scale);
    free(u);
    fixture_solver_destroy(&s);
    return worst / scale;
}

int main(void)
{
    test_begin();
    /* 1e-10: the tolerance for an exact solution. */
    TEST_TRUE(patch_error("cases/block_all_fixed.yaml", 0, 0) <= 1e-10);
    TEST_TRUE(patch_error("cases/lshape_all_fixed.yaml", 1, 0) <= 1e-10);
    /* Negative control: with Psi_I itself on the held facets their
     * boundary integral is not a combination of the constraints' rows, and
     * the particles near the constrained faces feel the traction flux. */
    TEST_TRUE(patch_error("cases/block_all_fixed.yaml", 0, 1) > 1e-3);
    return test_end("test_boundary_patch");
}
