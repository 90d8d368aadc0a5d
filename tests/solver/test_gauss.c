/* Gauss points through the explicit loop (explicit.h): what holds exactly
 * although RK shape functions are not integrated exactly by Gauss
 * quadrature (docs/kernels.md: the patch test fails), and the standing
 * wave of the column.
 * - The lumped mass, eq. (28) summed over the Gauss points, adds up to
 *   rho times the volume of the cells (partition of unity): a jittered box
 *   on its lattice cells, and the gmsh L-shape on its tetrahedra.
 * - A rigid translation gives no strain, no stress and no force; the
 *   internal forces of any motion add up to zero (sum_I grad Psi_I = 0 at
 *   every point), so a free body keeps its momentum.
 * - Under a linear field every Gauss point has the same stress; the
 *   particles report it (the mean over their nodal domains) and the
 *   traction resultant on a face is sigma n times its area.
 * - Each Gauss point belongs to the nearest particle (brute force over all
 *   particles), and a particle's stress is the weighted mean of its points.
 * - Gauss 3x3x3: the first longitudinal mode of the 10 m column,
 *   f1 = c_p / (4 H), the base fixed (the mass-orthogonal projection;
 *   Gauss points do not smooth over the held facets, so their boundary
 *   integral is not a reaction as SCNI's is: Gauss fails the patch test
 *   anyway, docs/kernels.md). */
#include "geoscni/case.h"
#include "geoscni/tensor.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <math.h>

static const int COUNT[3] = {6, 5, 4};
static const double LO[3] = {0, 0, 0}, HI[3] = {1.0, 0.8, 0.6};
#define JITTER 0.2

static double squared_distance(const double x[3], const double y[3])
{
    double d = 0.0;
    for (int a = 0; a < 3; ++a)
        d += (x[a] - y[a]) * (x[a] - y[a]);
    return d;
}

static double total_mass(const struct gsn_explicit *e)
{
    double sum = 0.0;
    for (int i = 0; i < e->particle_count; ++i)
        sum += e->mass[i];
    return sum;
}

/* Sum of the masses against rho V: the box, V of its lattice cells. */
static void test_mass_box(void)
{
    struct gsn_case c;
    struct fixture_solver s;
    TEST_INT(fixture_solver_case("cases/block_elastic.yaml", 2, COUNT, LO, HI,
                                 JITTER, 1e-3, &c, &s),
             GSN_OK);
    double volume = (HI[0] - LO[0]) * (HI[1] - LO[1]) * (HI[2] - LO[2]);
    double error = fabs(total_mass(s.loop) / (c.material.density * volume) - 1);
    printf("jittered box, %d particles, %d Gauss points: sum m_I / (rho V) "
           "- 1 = %.3g\n",
           s.loop->particle_count, s.loop->main_point_count, error);
    /* 1e-13: round-off of a few thousand products and sums (2x2x2 Gauss
     * integrates the trilinear cells' det J exactly, so the weights add up
     * to V). */
    TEST_TRUE(error <= 1e-13);
    fixture_solver_destroy(&s);
}

/* The gmsh L-shape on its tetrahedra (n^3 points per tetrahedron, Duffy):
 * sum m_I = rho sum_t V_t, the tetrahedra's volume from their vertices. */
static void test_mass_tetrahedra(int gauss_points)
{
    struct gsn_case c;
    TEST_INT(fixture_case_load("cases/lshape_all_fixed.yaml", gauss_points, &c),
             GSN_OK);
    struct fixture_solver s;
    TEST_INT(fixture_solver_from_gmsh(&c, 1e-4, &s), GSN_OK);
    const struct gsn_model *m = &s.model;
    double volume = 0.0;
    for (int t = 0; t < m->tetrahedron_count; ++t) {
        const double *x[4];
        for (int a = 0; a < 4; ++a)
            x[a] = &m->position[3 * (size_t)m->tetrahedra[4 * t + a]];
        double d[9];
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < 3; ++k)
                d[3 * a + k] = x[a + 1][k] - x[0][k];
        volume += fabs(gsn_matrix_determinant(d)) / 6.0;
    }
    struct gsn_explicit *e = s.loop;
    double error = fabs(total_mass(e) / (c.material.density * volume) - 1);
    printf("gmsh L-shape, %d particles, %d tetrahedra, %d Gauss points: sum "
           "m_I / (rho V) - 1 = %.3g\n",
           e->particle_count, m->tetrahedron_count, e->main_point_count, error);
    /* 1e-13, as for the box: the Duffy map's det J is quadratic along one
     * axis, integrated exactly from 2 points on. */
    TEST_TRUE(error <= 1e-13);
    /* One point per direction would integrate 3/4 of the volume: refused. */
    struct gsn_kernel_options one;
    struct gsn_quadrature *q = NULL;
    c.gauss_points = 1;
    gsn_kernel_options_from_case(&c, &one);
    TEST_INT(gsn_quadrature_create(m, &one, NULL, 0, &q), GSN_ERR_INPUT);
    gsn_error_clear();
    fixture_solver_destroy(&s);
}

/* Rigid translation: no stress, no force. Any motion: the forces add up
 * to zero, so a free body started with random velocities keeps its
 * momentum. */
static void test_translation_and_momentum(void)
{
    struct gsn_case c;
    struct fixture_solver s;
    TEST_INT(fixture_solver_case("cases/block_elastic.yaml", 3, COUNT, LO, HI,
                                 JITTER, 1e-3, &c, &s),
             GSN_OK);
    struct gsn_explicit *e = s.loop;
    const int n = e->particle_count;
    const double shift[3] = {0.3, -0.2, 0.1}, h = 0.2; /* m */
    const double mu = c.material.shear_modulus;
    for (int i = 0; i < n; ++i)
        memcpy(&e->displacement[3 * i], shift, sizeof shift);
    TEST_INT(gsn_explicit_update_stress(e), GSN_OK);
    double stress = 0.0, force = 0.0;
    for (int p = 0; p < e->main_point_count; ++p)
        stress = fmax(stress, gsn_voigt_norm(&e->stress[6 * p]));
    for (int i = 0; i < 3 * n; ++i)
        force = fmax(force, fabs(e->f_int[i]));
    /* The scale: the stress of a strain |shift| / h, the force of that
     * stress on a face of h^2. */
    double length =
        sqrt(shift[0] * shift[0] + shift[1] * shift[1] + shift[2] * shift[2]);
    double sigma_scale = mu * length / h, force_scale = sigma_scale * h * h;
    printf("rigid translation: max |sigma| / (mu |c| / h) = %.3g, max "
           "|f_int| / (that h^2) = %.3g\n",
           stress / sigma_scale, force / force_scale);
    /* 1e-12: sum_I grad Psi_I is zero to round-off, about 1e-14 / h. */
    TEST_TRUE(stress <= 1e-12 * sigma_scale);
    TEST_TRUE(force <= 1e-12 * force_scale);

    /* Free body, random velocities of 0.01 m/s, 200 steps at the stable
     * step x 0.8. */
    memset(e->displacement, 0, sizeof(double) * 3 * (size_t)n);
    memset(e->stress, 0, sizeof(double) * 6 * (size_t)e->point_count);
    memset(e->displacement_gradient, 0,
           sizeof(double) * 9 * (size_t)e->point_count);
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    e->dt = 0.8 * stable;
    unsigned state = 7u;
    for (int i = 0; i < 3 * n; ++i) {
        state = state * 1664525u + 1013904223u;
        e->velocity[i] = 0.02 * ((double)(state >> 8) / 16777216.0 - 0.5);
    }
    double p0[3] = {0, 0, 0}, scale = 0.0, drift = 0.0, imbalance = 0.0;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            p0[k] += e->mass[i] * e->velocity[3 * i + k];
            scale += e->mass[i] * fabs(e->velocity[3 * i + k]);
        }
    for (int step = 0; step < 200; ++step) {
        TEST_INT(gsn_explicit_step(e), GSN_OK);
        double p[3] = {0, 0, 0}, f[3] = {0, 0, 0}, f_abs = 0.0;
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                p[k] += e->mass[i] * e->velocity[3 * i + k];
                f[k] += e->f_int[3 * i + k];
                f_abs += fabs(e->f_int[3 * i + k]);
            }
        for (int k = 0; k < 3; ++k) {
            drift = fmax(drift, fabs(p[k] - p0[k]) / scale);
            imbalance = fmax(imbalance, fabs(f[k]) / f_abs);
        }
    }
    printf("free body, 200 steps: max |sum f_int| / sum |f_int| = %.3g, "
           "momentum drift / sum m |v| = %.3g\n",
           imbalance, drift);
    /* 1e-12 for both: round-off of sum_I grad Psi_I = 0 at every point and
     * of the sums over some 500 force components. */
    TEST_TRUE(imbalance <= 1e-12);
    TEST_TRUE(drift <= 1e-12);
    fixture_solver_destroy(&s);
}

/* A linear field d_I = A X_I: every Gauss point gets the same stress; the
 * particles report it, and the traction resultant on the face x = 1
 * (surface xmax) is sigma e_x times its area. */
static void test_linear_field(void)
{
    struct gsn_case c;
    struct fixture_solver s;
    TEST_INT(fixture_solver_case("cases/block_elastic.yaml", 2, COUNT, LO, HI,
                                 JITTER, 1e-3, &c, &s),
             GSN_OK);
    struct gsn_explicit *e = s.loop;
    const double A[9] = {1e-3, 2e-4, -3e-4, -1e-4, -5e-4,
                         4e-4, 2e-4, 3e-4,  7e-4};
    fixture_set_linear_field(e, A);
    TEST_INT(gsn_explicit_update_stress(e), GSN_OK);
    const double *sigma0 = &e->stress[0];
    double norm = gsn_voigt_norm(sigma0), spread = 0.0, reported = 0.0;
    for (int p = 0; p < e->main_point_count; ++p)
        for (int a = 0; a < 6; ++a)
            spread = fmax(spread, fabs(e->stress[6 * p + a] - sigma0[a]));
    double *particle = malloc(sizeof(double) * 6 * (size_t)e->particle_count);
    TEST_TRUE(particle != NULL);
    gsn_explicit_particle_stress(e, particle);
    for (int i = 0; i < 6 * e->particle_count; ++i)
        reported = fmax(reported, fabs(particle[i] - sigma0[i % 6]));
    free(particle);
    /* The face x = 1 (surface 1, xmax) of area 0.8 x 0.6, at the
     * reference configuration: the nominal traction is P e_x. */
    double F[9], Finv[9], S[9], force[3], expected[3];
    for (int a = 0; a < 9; ++a)
        F[a] = (a % 4 == 0 ? 1.0 : 0.0) + A[a];
    double J = gsn_matrix_inverse(F, Finv);
    gsn_voigt_to_matrix(sigma0, S);
    for (int i = 0; i < 3; ++i)
        expected[i] = J *
                      (S[3 * i] * Finv[0] + S[3 * i + 1] * Finv[1] +
                       S[3 * i + 2] * Finv[2]) *
                      0.8 * 0.6;
    gsn_explicit_surface_force(e, 1, 7, force);
    double face = 0.0;
    for (int i = 0; i < 3; ++i)
        face = fmax(face, fabs(force[i] - expected[i]));
    printf("linear field: max |sigma_p - sigma_0| / |sigma| = %.3g at the "
           "Gauss points, %.3g at the particles; face resultant error / "
           "(|sigma| A) = %.3g\n",
           spread / norm, reported / norm, face / (norm * 0.48));
    /* 1e-12: the points' F differ by the round-off of eq. (18), 1e-15. */
    TEST_TRUE(spread <= 1e-12 * norm);
    TEST_TRUE(reported <= 1e-12 * norm);
    TEST_TRUE(face <= 1e-12 * norm * 0.48);
    fixture_solver_destroy(&s);
}

/* The nodal domains against brute force: each Gauss point's owner is its
 * nearest particle of all; a particle's stress is the weighted mean of
 * its points (here a stress that differs from point to point), or, with
 * none, the stress of its nearest point (one point at the centre of each
 * cell of a regular lattice: the corner particles of the lattice own no
 * point). */
static void test_domains(int gauss_points, double jitter)
{
    struct gsn_case c;
    struct fixture_solver s;
    TEST_INT(fixture_solver_case("cases/block_elastic.yaml", gauss_points,
                                 COUNT, LO, HI, jitter, 1e-3, &c, &s),
             GSN_OK);
    struct gsn_explicit *e = s.loop;
    const struct gsn_quadrature *q = s.quadrature;
    const int n = e->particle_count, points = e->main_point_count;
    int *owner = malloc(sizeof(int) * (size_t)points);
    double *sum = calloc(7 * (size_t)n, sizeof(double));
    double *particle = malloc(sizeof(double) * 6 * (size_t)n);
    TEST_TRUE(owner && sum && particle);
    int mismatched = 0;
    for (int p = 0; p < points; ++p) {
        double best = INFINITY;
        for (int i = 0; i < n; ++i) {
            double d = squared_distance(&q->point_position[3 * p],
                                        &q->rk->position[3 * i]);
            if (d < best) {
                best = d;
                owner[p] = i;
            }
        }
        mismatched += owner[p] != e->point_owner[p];
        for (int a = 0; a < 6; ++a)
            e->stress[6 * p + a] = sin(0.37 * p + a) * 1e5;
        double w = q->point_weight[p];
        sum[7 * owner[p] + 6] += w;
        for (int a = 0; a < 6; ++a)
            sum[7 * owner[p] + a] += w * e->stress[6 * p + a];
    }
    gsn_explicit_particle_stress(e, particle);
    double error = 0.0;
    int empty = 0;
    for (int i = 0; i < n; ++i) {
        double expected[6] = {0};
        if (sum[7 * i + 6] > 0.0) {
            for (int a = 0; a < 6; ++a)
                expected[a] = sum[7 * i + a] / sum[7 * i + 6];
        } else { /* the nearest point of all */
            empty++;
            double best = INFINITY;
            for (int p = 0; p < points; ++p) {
                double d = squared_distance(&q->point_position[3 * p],
                                            &q->rk->position[3 * i]);
                if (d < best) {
                    best = d;
                    memcpy(expected, &e->stress[6 * p], sizeof expected);
                }
            }
        }
        for (int a = 0; a < 6; ++a)
            error = fmax(error, fabs(particle[6 * i + a] - expected[a]) / 1e5);
    }
    printf("nodal domains, %d^3 Gauss points a cell, jitter %g: %d of %d "
           "points with another owner than the nearest particle; %d "
           "particles without points; max stress error / |sigma| = %.3g\n",
           gauss_points, jitter, mismatched, points, empty, error);
    TEST_INT(mismatched, 0);
    /* the fallback is exercised where the lattice has corner particles */
    TEST_TRUE(gauss_points > 1 || empty > 0);
    /* 1e-14: two orders of summation of the same weighted sums. */
    TEST_TRUE(error <= 1e-14);
    free(owner);
    free(sum);
    free(particle);
    fixture_solver_destroy(&s);
}

/* Gauss 3x3x3 on the lattice cells of the column of test_column_waves
 * (3 x 3 x 41 particles, h = 0.25 m, base fixed, rollers, gravity
 * switched on at t = 0): the top rings about its static deflection at
 * f1 = c_p / (4 H); the energy stays constant. */
static void test_column(void)
{
    struct gsn_case c;
    struct fixture_solver s;
    const int count[3] = {3, 3, 41};
    const double lo[3] = {0, 0, 0}, hi[3] = {0.5, 0.5, 10.0};
    TEST_INT(fixture_solver_case("cases/column_longitudinal.yaml", 3, count, lo,
                                 hi, 0.0, 1e-3, &c, &s),
             GSN_OK);
    struct gsn_explicit *e = s.loop;
    const double M =
        c.material.bulk_modulus + 4.0 * c.material.shear_modulus / 3.0;
    const double H = 10.0, rho = c.material.density;
    const double f1 = sqrt(M / rho) / (4.0 * H);
    const double static_top = -rho * 9.81 * H * H / (2.0 * M);
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    e->dt = c.time_step_safety * stable;
    const int steps = (int)ceil(c.time_end / e->dt);
    double *time = malloc(sizeof(double) * (size_t)steps);
    double *top = malloc(sizeof(double) * (size_t)steps);
    double *u = malloc(sizeof(double) * 3 * (size_t)e->particle_count);
    TEST_TRUE(time && top && u);
    double balance0 = 0.0, drift = 0.0, work = 0.0;
    for (int k = 0; k < steps; ++k) {
        TEST_INT(gsn_explicit_step(e), GSN_OK);
        gsn_explicit_particle_field(e, e->displacement, u);
        int at_top = 0;
        top[k] = 0.0;
        for (int i = 0; i < e->particle_count; ++i)
            if (s.model.position[3 * i + 2] > H - 1e-9) {
                top[k] += u[3 * i + 2];
                at_top++;
            }
        top[k] /= at_top;
        time[k] = e->time;
        double balance =
            e->conserved_kinetic_energy + e->internal_energy - e->external_work;
        if (k == 0)
            balance0 = balance;
        drift = fmax(drift, fabs(balance - balance0));
        work = fmax(work, fabs(e->external_work));
    }
    int periods = 0;
    double f =
        fixture_crossing_frequency(time, top, steps, static_top, &periods);
    printf("column, Gauss 3x3x3, %d points, dt %.3g s: %d periods, f1 = "
           "%.5f Hz (exact %.5f, error %.3f%%), energy drift %.3g of the "
           "work done\n",
           e->main_point_count, e->dt, periods, f, f1, 100.0 * (f / f1 - 1.0),
           drift / work);
    /* 1%: the tolerance, as for SCNI in test_column_waves. */
    TEST_REL(f, f1, 0.01);
    TEST_TRUE(periods >= 9);
    /* The issue asked 1e-4; with the kinetic energy central differences
     * conserve (explicit.h) the balance of this linear column is constant
     * to round-off (3e-15 measured, 2026-12-07): 1e-12. */
    TEST_TRUE(drift <= 1e-12 * work);
    free(time);
    free(top);
    free(u);
    fixture_solver_destroy(&s);
}

int main(void)
{
    test_begin();
    test_mass_box();
    test_mass_tetrahedra(2);
    test_translation_and_momentum();
    test_linear_field();
    test_domains(3, JITTER);
    test_domains(1, 0.0);
    test_column();
    return test_end("test_gauss");
}
