/* Boxes of particles for the solver tests: a lattice (optionally jittered)
 * with its clipped Voronoi cells (gsn_pre_domains_box, surfaces xmin, xmax,
 * ymin, ymax, zmin, zmax), either written as OUTDIR/model.h5 for geoscni
 * solve or set up in memory with the solver's own pieces. */
#ifndef GEOSCNI_SOLVER_FIXTURES_H
#define GEOSCNI_SOLVER_FIXTURES_H

#include "constraint.h"
#include "explicit.h"
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"
#include "geoscni/pre.h"
#include "geoscni/solver.h"
#include "geoscni/tensor.h"
#include "material.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* count[k] particles along axis k on [lo, hi], interior particles moved by
 * up to jitter x spacing along each axis (deterministic). */
static inline int fixture_box(const int count[3], const double lo[3],
                              const double hi[3], double jitter,
                              int facet_points, struct gsn_model *m)
{
    int n = count[0] * count[1] * count[2];
    double *points = malloc(sizeof(double) * 3 * (size_t)n);
    if (!points)
        return GSN_ERR_MEMORY;
    unsigned state = 2024u;
    int at = 0;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                int index[3] = {i, j, k};
                for (int a = 0; a < 3; ++a) {
                    double h = (hi[a] - lo[a]) / (count[a] - 1);
                    double x = lo[a] + index[a] * h;
                    state = state * 1664525u + 1013904223u;
                    double r = (double)(state >> 8) / 16777216.0 - 0.5;
                    if (index[a] > 0 && index[a] < count[a] - 1)
                        x += 2.0 * r * jitter * h;
                    points[at++] = x;
                }
            }
    int rc = gsn_pre_domains_box(points, n, lo, hi, facet_points, m);
    free(points);
    return rc;
}

/* The same box written as folder/model.h5. */
static inline int fixture_box_model(const char *folder, const int count[3],
                                    const double lo[3], const double hi[3],
                                    double jitter, const struct gsn_case *c)
{
    struct gsn_model m;
    int rc = fixture_box(count, lo, hi, jitter, c->facet_points, &m);
    if (rc != GSN_OK)
        return rc;
    char path[4096];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    rc = gsn_model_write(path, &m, c);
    gsn_model_free(&m);
    return rc;
}

/* Makes the folder (a mkdtemp template), writes the box model into it and
 * runs geoscni solve on it quietly; prints the error chain on failure. */
static inline int fixture_solve_box(const struct gsn_case *c, char *folder,
                                    const int count[3], const double lo[3],
                                    const double hi[3], double jitter)
{
    if (!mkdtemp(folder))
        return GSN_ERR_IO;
    int rc = fixture_box_model(folder, count, lo, hi, jitter, c);
    struct gsn_solve_options options = {.quiet = 1};
    if (rc == GSN_OK)
        rc = gsn_solve_run(c, folder, &options);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    return rc;
}

/* The solver's pieces for a case on a box, in memory. */
struct fixture_solver {
    struct gsn_model model;
    struct gsn_quadrature *quadrature;
    struct gsn_material_set *materials;
    struct gsn_material_model *material; /* the first of materials */
    struct gsn_constraints *constraints;
    struct gsn_explicit *loop;
};

static inline void fixture_solver_destroy(struct fixture_solver *s)
{
    gsn_explicit_destroy(&s->loop);
    gsn_constraints_destroy(&s->constraints);
    gsn_material_set_destroy(&s->materials);
    s->material = NULL;
    gsn_quadrature_destroy(&s->quadrature);
    gsn_model_free(&s->model);
}

/* The cells of a box lattice of count[k] particles along axis k (in the
 * order of fixture_box: x fastest) as hexahedra of 8 vertices (vertex
 * (i,j,k) at i + 2j + 4k, gsn_quadrature_create's background cells), from
 * the particles' positions, jittered or not: they tile the box. Returns
 * the array (cell_count x 24, caller frees) or NULL. */
static inline double *fixture_lattice_cells(const int count[3],
                                            const double *position,
                                            int *cell_count)
{
    int cells = (count[0] - 1) * (count[1] - 1) * (count[2] - 1), at = 0;
    double *v = malloc(sizeof(double) * 24 * (size_t)(cells > 0 ? cells : 1));
    *cell_count = cells;
    for (int k = 0; v && k < count[2] - 1; ++k)
        for (int j = 0; j < count[1] - 1; ++j)
            for (int i = 0; i < count[0] - 1; ++i, ++at)
                for (int a = 0; a < 8; ++a) {
                    int p = (i + (a & 1)) +
                            count[0] * ((j + ((a >> 1) & 1)) +
                                        count[1] * (k + ((a >> 2) & 1)));
                    memcpy(&v[24 * at + 3 * a], &position[3 * p],
                           3 * sizeof(double));
                }
    return v;
}

/* Builds the quadrature of the case on s->model (already filled; Gauss on
 * the given background cells, NULL for the model's tetrahedra), its
 * material, the constraints of its boundary entries (none if it has none)
 * and the loop with time step dt. Prints the error chain on failure. */
/* 1: the held facets keep Psi_I (no interpolant through the held
 * particles; the negative control of the patch test). */
static int fixture_plain_facets;

static inline int fixture_solver_from_cells(const struct gsn_case *c, double dt,
                                            const double *cells, int cell_count,
                                            struct fixture_solver *s)
{
    struct gsn_kernel_options kernel;
    gsn_kernel_options_from_case(c, &kernel);
    int rc = GSN_OK;
    if (c->boundary_count > 0 && !fixture_plain_facets)
        rc = gsn_constraints_discretize(&s->model, c, &kernel, cells,
                                        cell_count, NULL, &s->quadrature,
                                        &s->constraints, NULL);
    else
        rc = gsn_quadrature_create(&s->model, &kernel, cells, cell_count,
                                   &s->quadrature);
    if (rc == GSN_OK)
        rc = gsn_material_set_create(c, &s->model, &s->materials);
    if (rc == GSN_OK)
        s->material = s->materials->model[0];
    if (rc == GSN_OK && c->boundary_count > 0 && !s->constraints)
        rc = gsn_constraints_create(&s->model, c,
                                    &s->quadrature->particle_values, NULL,
                                    &s->constraints);
    if (rc == GSN_OK)
        rc = gsn_explicit_create(&s->model, s->quadrature, s->materials,
                                 s->constraints, c, dt, &s->loop);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        fixture_solver_destroy(s);
    }
    return rc;
}

/* The same with Gauss on the model's tetrahedra. */
static inline int fixture_solver_from_model(const struct gsn_case *c, double dt,
                                            struct fixture_solver *s)
{
    return fixture_solver_from_cells(c, dt, NULL, 0, s);
}

/* The same on a box of particles (fixture_box); Gauss on its lattice
 * cells (fixture_lattice_cells). */
static inline int fixture_solver_create(const struct gsn_case *c,
                                        const int count[3], const double lo[3],
                                        const double hi[3], double jitter,
                                        double dt, struct fixture_solver *s)
{
    memset(s, 0, sizeof *s);
    int rc = fixture_box(count, lo, hi, jitter, c->facet_points, &s->model);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return rc;
    }
    if (c->integration != GSN_INTEGRATION_GAUSS)
        return fixture_solver_from_model(c, dt, s);
    int cell_count = 0;
    double *cells =
        fixture_lattice_cells(count, s->model.position, &cell_count);
    rc = cells ? fixture_solver_from_cells(c, dt, cells, cell_count, s)
               : GSN_ERR_MEMORY;
    free(cells);
    return rc;
}

/* R - I for a rotation by theta about the unit axis a, without the
 * cancellation of forming R and subtracting I: sin t K + 2 sin^2(t/2) K^2. */
static inline void fixture_rotation_minus_identity(const double a[3],
                                                   double theta, double out[9])
{
    double K[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0}, K2[9];
    gsn_matrix_multiply(K, K, K2);
    double s = sin(theta), h = 2.0 * sin(0.5 * theta) * sin(0.5 * theta);
    for (int i = 0; i < 9; ++i)
        out[i] = s * K[i] + h * K2[i];
}

/* The step's increment is a linear field: previous_displacement = d, then
 * d_I = A X_I at every particle (A the displacement gradient, row-major;
 * X the reference positions). */
static inline void fixture_set_linear_field(struct gsn_explicit *e,
                                            const double A[9])
{
    const double *X = e->quadrature->rk->position;
    memcpy(e->previous_displacement, e->displacement,
           sizeof(double) * 3 * (size_t)e->particle_count);
    for (int i = 0; i < e->particle_count; ++i)
        for (int r = 0; r < 3; ++r)
            e->displacement[3 * i + r] = A[3 * r] * X[3 * i] +
                                         A[3 * r + 1] * X[3 * i + 1] +
                                         A[3 * r + 2] * X[3 * i + 2];
}

/* Loads the case at path; gauss_points > 0 replaces its integration by
 * Gauss points, gauss_points a direction (on the lattice cells of a box,
 * or the tetrahedra of a gmsh model). Prints the error chain on failure. */
static inline int fixture_case_load(const char *path, int gauss_points,
                                    struct gsn_case *c)
{
    int rc = gsn_case_load(path, c);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return rc;
    }
    if (gauss_points > 0) {
        c->integration = GSN_INTEGRATION_GAUSS;
        c->gauss_points = gauss_points;
    }
    return GSN_OK;
}

/* fixture_case_load, then fixture_solver_create. */
static inline int fixture_solver_case(const char *path, int gauss_points,
                                      const int count[3], const double lo[3],
                                      const double hi[3], double jitter,
                                      double dt, struct gsn_case *c,
                                      struct fixture_solver *s)
{
    memset(s, 0, sizeof *s);
    int rc = fixture_case_load(path, gauss_points, c);
    return rc == GSN_OK ? fixture_solver_create(c, count, lo, hi, jitter, dt, s)
                        : rc;
}

/* The same on the particles gmsh makes for the case's geometry (pre, with
 * the reproducible mesher), through a model.h5 in a temporary folder. */
static inline int fixture_solver_from_gmsh(const struct gsn_case *c, double dt,
                                           struct fixture_solver *s)
{
    memset(s, 0, sizeof *s);
    char folder[] = "/tmp/geoscni-test-gmsh-XXXXXX", path[64], command[96];
    if (!mkdtemp(folder))
        return GSN_ERR_IO;
    struct gsn_pre_options options = {.quiet = 1, .reproducible = 1};
    int rc = gsn_pre_run(c, folder, &options);
    snprintf(path, sizeof path, "%s/model.h5", folder);
    if (rc == GSN_OK)
        rc = gsn_model_read(path, &s->model);
    snprintf(command, sizeof command, "rm -rf '%s'", folder);
    if (system(command) != 0 && rc == GSN_OK)
        rc = GSN_ERR_IO;
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return rc;
    }
    return fixture_solver_from_model(c, dt, s);
}

/* GSN_OK if `steps` steps of e from small random velocities (every mode
 * excited; a fixed sequence) keep the kinetic energy below 1e6 times its
 * initial value, GSN_ERR_NUMERICAL otherwise: the stable-step tests' run
 * (test_critical_step, test_mass_scaling). Clears the error of a blow-up. */
static inline int fixture_stays_bounded(struct gsn_explicit *e, int steps)
{
    unsigned state = 7u;
    for (int i = 0; i < 3 * e->particle_count; ++i) {
        state = state * 1664525u + 1013904223u;
        e->velocity[i] = 1e-3 * ((double)(state >> 8) / 16777216.0 - 0.5);
    }
    double initial = 0.0;
    for (int i = 0; i < 3 * e->particle_count; ++i)
        initial += 0.5 * e->mass[i / 3] * e->velocity[i] * e->velocity[i];
    int rc = GSN_OK;
    for (int k = 0; k < steps && rc == GSN_OK; ++k) {
        rc = gsn_explicit_step(e);
        if (rc == GSN_OK && !(e->kinetic_energy < 1e6 * initial))
            rc = GSN_ERR_NUMERICAL;
    }
    gsn_error_clear();
    return rc;
}

/* The frequency (Hz) of a signal value(time), count samples, from its
 * upward crossings of level (linear between samples): (crossings - 1)
 * over the time from the first to the last; *periods gets crossings - 1.
 * 0 with fewer than two crossings. */
static inline double fixture_crossing_frequency(const double *time,
                                                const double *value, int count,
                                                double level, int *periods)
{
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (int i = 1; i < count; ++i) {
        double a = value[i - 1] - level, b = value[i] - level;
        if (a < 0.0 && b >= 0.0) {
            double t = time[i - 1] + (time[i] - time[i - 1]) * (-a) / (b - a);
            if (crossings == 0)
                first = t;
            last = t;
            crossings++;
        }
    }
    *periods = crossings > 0 ? crossings - 1 : 0;
    return crossings > 1 ? (crossings - 1) / (last - first) : 0.0;
}

/* Reads the columns `names` (count of them) of folder/history.csv into
 * values[row * count + k], at most max_rows rows; returns the row count, or
 * -1 when the file or a column is missing. */
static inline int fixture_history(const char *folder, const char *const *names,
                                  int count, double *values, int max_rows)
{
    char path[4200], line[8192];
    snprintf(path, sizeof path, "%s/history.csv", folder);
    FILE *file = fopen(path, "r");
    if (!file)
        return -1;
    int column_of[16], rows = -1;
    for (int k = 0; k < count && k < 16; ++k)
        column_of[k] = -1;
    if (count <= 16 && fgets(line, sizeof line, file)) {
        int column = 0;
        for (char *token = strtok(line, ",\n"); token;
             token = strtok(NULL, ",\n"), ++column)
            for (int k = 0; k < count; ++k)
                if (strcmp(token, names[k]) == 0)
                    column_of[k] = column;
        rows = 0;
        for (int k = 0; k < count; ++k)
            if (column_of[k] < 0)
                rows = -1;
    }
    while (rows >= 0 && rows < max_rows && fgets(line, sizeof line, file)) {
        double value[256] = {0};
        int n = 0;
        for (char *token = strtok(line, ",\n"); token && n < 256;
             token = strtok(NULL, ",\n"))
            value[n++] = strtod(token, NULL);
        for (int k = 0; k < count; ++k)
            values[rows * count + k] = value[column_of[k]];
        rows++;
    }
    fclose(file);
    return rows;
}

#endif
