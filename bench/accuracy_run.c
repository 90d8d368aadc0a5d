/* One run of the speed-and-accuracy chart (bench/accuracy_chart.sh): an
 * elastic problem with a closed-form answer, solved by the project's
 * explicit loop (gsn_explicit_step) at one particle spacing with one
 * integration method; prints one CSV row with the error and the times.
 *
 *   accuracy_run PROBLEM CASE METHOD SPACING [THREADS]
 *   accuracy_run --header
 *
 * PROBLEM: column (the only one so far; add a row to `problems` below).
 * METHOD:  scni | mscni | dni | gauss2 | gauss3.
 * CASE:    the problem's case file (material and boundaries; its
 *          integration and spacing are replaced by METHOD and SPACING).
 *
 * column: the standing-wave column of REFERENCES.md ("Elastic dynamics"),
 * H = 10 m, base fixed, top free, rollers on the lateral faces, first
 * longitudinal mode f1 = c_p / (4 H) = 3.6283 Hz. The fixed base is
 * replaced by its mirror image: a free-free bar of length 2H with rollers,
 * started in the exact first mode v_z = V cos(pi z / (2H)), whose mid-plane
 * z = H stays still by antisymmetry (the same closed form, the same f1).
 * (The mirror dates from when the loop refused Gauss points; every method
 * now runs through the same loop with the same essential boundaries and its own
 * lumped mass, eq. (28), and the mirror is kept so that the nodal methods'
 * numbers stay those of the first chart.)
 * Exact: u_z(z, t) = (V / w) cos(pi z / (2H)) sin(w t), u_x = u_y = 0,
 * w = 2 pi f1. Error: the L2 displacement error at the particles
 * (u(X_J) = sum_I Psi_I(X_J) d_I, lumped-mass weighted) over two periods,
 * relative to the exact solution's norm; also the frequency error from the
 * zero crossings of the top's mean displacement. Time step: `auto` (0.8 of
 * the free body's stable step, as geoscni solve).
 *
 * Times: wall clock and CPU time of the build (shape functions, integration,
 * constraints, loop, stable step) and of the steps alone (sampling the
 * error is not timed); pre (the lattice's nodal domains) apart. On a shared
 * machine the CPU time of a 1-thread run is what an idle core's wall time
 * would be; the chart plots it. V = 1e-4 m/s keeps the
 * strain at 7e-7, so large-deformation effects stay far below the
 * discretization error. */
#include "explicit.h"
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "geoscni/model.h"
#include "geoscni/pre.h"
#include "material.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double wall_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* What a run measures. */
struct measure {
    double error;     /* the chart's error, - */
    double value;     /* the measured quantity (column: f1, Hz) */
    double exact;     /* its closed form */
    double secondary; /* |value - exact| / exact */
};

/* A problem: its particle box at spacing h, its initial state, what it
 * samples after each step and what it reports at the end. */
struct problem {
    const char *name;
    double layer_jitter; /* inner z layers moved by up to this x spacing */
    void (*box)(double h, int count[3], double lo[3], double hi[3]);
    double (*end_time)(const struct gsn_case *c);
    void (*start)(struct gsn_explicit *e, const struct gsn_case *c);
    void (*sample)(const struct gsn_explicit *e, const struct gsn_case *c,
                   const double *u, void *work);
    void (*finish)(const struct gsn_explicit *e, const struct gsn_case *c,
                   void *work, struct measure *out);
};

/* ---- column ------------------------------------------------------------- */

static const double COLUMN_H = 10.0;       /* m, the column's height */
static const double COLUMN_SPEED = 1.0e-4; /* V, m/s */
static const double COLUMN_PERIODS = 2.0;  /* periods in the L2 error */

static double p_wave_speed(const struct gsn_case *c)
{
    const struct gsn_material *m = &c->material;
    return sqrt((m->bulk_modulus + 4.0 * m->shear_modulus / 3.0) / m->density);
}

static double column_omega(const struct gsn_case *c)
{
    return 2.0 * M_PI * p_wave_speed(c) / (4.0 * COLUMN_H);
}

static void column_box(double h, int count[3], double lo[3], double hi[3])
{
    count[0] = count[1] = 3;
    count[2] = (int)lround(2.0 * COLUMN_H / h) + 1;
    lo[0] = lo[1] = lo[2] = 0.0;
    hi[0] = hi[1] = 2.0 * h;
    hi[2] = 2.0 * COLUMN_H;
}

/* A quarter period past two periods: the crossing at 2 T is inside. */
static double column_end_time(const struct gsn_case *c)
{
    return (COLUMN_PERIODS + 0.25) * 2.0 * M_PI / column_omega(c);
}

static void column_start(struct gsn_explicit *e, const struct gsn_case *c)
{
    (void)c;
    const double *x = e->model->position;
    for (int i = 0; i < e->particle_count; ++i)
        e->velocity[3 * i + 2] =
            COLUMN_SPEED * cos(M_PI * x[3 * i + 2] / (2.0 * COLUMN_H));
}

enum { MAX_CROSSINGS = 64 };

struct column_work {
    double error2, norm2; /* L2 sums over the samples up to 2 T */
    double previous_top;  /* top mean u_z at the previous step */
    double previous_time; /* s */
    int crossings;        /* zero crossings of the top after t = 0 */
    double crossing[MAX_CROSSINGS];
};

static void column_sample(const struct gsn_explicit *e,
                          const struct gsn_case *c, const double *u, void *work)
{
    struct column_work *w = work;
    const double *x = e->model->position;
    double omega = column_omega(c), t = e->time;
    double top = 0.0;
    int top_count = 0;
    if (t <= COLUMN_PERIODS * 2.0 * M_PI / omega + 0.5 * e->dt) {
        double s = sin(omega * t) * COLUMN_SPEED / omega;
        for (int i = 0; i < e->particle_count; ++i) {
            double exact = s * cos(M_PI * x[3 * i + 2] / (2.0 * COLUMN_H));
            double dz = u[3 * i + 2] - exact;
            w->error2 += e->mass[i] * (u[3 * i] * u[3 * i] +
                                       u[3 * i + 1] * u[3 * i + 1] + dz * dz);
            w->norm2 += e->mass[i] * exact * exact;
        }
    }
    for (int i = 0; i < e->particle_count; ++i)
        if (x[3 * i + 2] > 2.0 * COLUMN_H - 1e-9) {
            top += u[3 * i + 2];
            top_count++;
        }
    top /= top_count;
    /* Crossings after the start (the top starts at 0 and moves up). */
    if (e->step > 1 && w->previous_top * top < 0.0 &&
        w->crossings < MAX_CROSSINGS)
        w->crossing[w->crossings++] =
            w->previous_time +
            (t - w->previous_time) * w->previous_top / (w->previous_top - top);
    w->previous_top = top;
    w->previous_time = t;
}

static void column_finish(const struct gsn_explicit *e,
                          const struct gsn_case *c, void *work,
                          struct measure *out)
{
    (void)e;
    struct column_work *w = work;
    double f1 = column_omega(c) / (2.0 * M_PI);
    /* Crossing n (n = 1, 2, ...) at n / (2 f): least-squares slope. */
    double sn = 0, st = 0, snn = 0, snt = 0;
    int n = w->crossings;
    for (int k = 0; k < n; ++k) {
        sn += k + 1;
        st += w->crossing[k];
        snn += (double)(k + 1) * (k + 1);
        snt += (k + 1) * w->crossing[k];
    }
    double slope = n > 1 ? (n * snt - sn * st) / (n * snn - sn * sn) : 0.0;
    out->value = slope > 0.0 ? 1.0 / (2.0 * slope) : 0.0;
    out->exact = f1;
    out->secondary = fabs(out->value - f1) / f1;
    out->error = sqrt(w->error2 / w->norm2);
}

static const struct problem problems[] = {
    {"column", 0.0, column_box, column_end_time, column_start, column_sample,
     column_finish},
    {"column_jittered", 0.2, column_box, column_end_time, column_start,
     column_sample, column_finish},
};

/* ---- the run ------------------------------------------------------------ */

struct method {
    const char *name;
    enum gsn_integration integration;
    enum gsn_stabilization stabilization;
    int gauss_points;
};

static const struct method methods[] = {
    {"scni", GSN_INTEGRATION_SCNI, GSN_STABILIZATION_NONE, 0},
    {"mscni", GSN_INTEGRATION_SCNI, GSN_STABILIZATION_MSCNI, 0},
    {"nsni", GSN_INTEGRATION_SCNI, GSN_STABILIZATION_NSNI, 0},
    {"dni", GSN_INTEGRATION_DNI, GSN_STABILIZATION_NONE, 0},
    {"gauss2", GSN_INTEGRATION_GAUSS, GSN_STABILIZATION_NONE, 2},
    {"gauss3", GSN_INTEGRATION_GAUSS, GSN_STABILIZATION_NONE, 3},
};

/* The lattice's coordinates along each axis: count[d] values from lo[d] to
 * hi[d], evenly spaced; with jitter > 0 the inner layers along z move by up
 * to jitter x spacing, mirrored about the middle (layer k and layer
 * count - 1 - k move by opposite amounts), so the body stays symmetric. */
static double *lattice_axes(const int count[3], const double lo[3],
                            const double hi[3], double jitter)
{
    double *axis =
        malloc((size_t)(count[0] + count[1] + count[2]) * sizeof *axis);
    if (!axis)
        return NULL;
    double *at = axis;
    for (int d = 0; d < 3; ++d) {
        double h = (hi[d] - lo[d]) / (count[d] - 1);
        for (int i = 0; i < count[d]; ++i)
            at[i] = lo[d] + i * h;
        unsigned state = 2024u;
        for (int i = 1; d == 2 && jitter > 0.0 && i < count[d] - 1 - i; ++i) {
            state = state * 1664525u + 1013904223u;
            double r = 2.0 * ((double)(state >> 8) / 16777216.0) - 1.0;
            at[i] += r * jitter * h;
            at[count[d] - 1 - i] -= r * jitter * h;
        }
        at += count[d];
    }
    return axis;
}

/* The lattice cells between the particles, as hexahedra (the Gauss
 * background cells). */
static double *lattice_cells(const int count[3], const double *axis, int *cells)
{
    int c3[3] = {count[0] - 1, count[1] - 1, count[2] - 1};
    const double *coordinate[3] = {axis, axis + count[0],
                                   axis + count[0] + count[1]};
    *cells = c3[0] * c3[1] * c3[2];
    double *v = malloc(24 * (size_t)*cells * sizeof *v);
    if (!v)
        return NULL;
    int at = 0;
    for (int k = 0; k < c3[2]; ++k)
        for (int j = 0; j < c3[1]; ++j)
            for (int i = 0; i < c3[0]; ++i, ++at) {
                int ijk[3] = {i, j, k};
                for (int a = 0; a < 8; ++a)
                    for (int d = 0; d < 3; ++d)
                        v[24 * at + 3 * a + d] =
                            coordinate[d][ijk[d] + ((a >> d) & 1)];
            }
    return v;
}

static double *lattice_points(const int count[3], const double *axis)
{
    int n = count[0] * count[1] * count[2], at = 0;
    const double *coordinate[3] = {axis, axis + count[0],
                                   axis + count[0] + count[1]};
    double *x = malloc(3 * (size_t)n * sizeof *x);
    if (!x)
        return NULL;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                int ijk[3] = {i, j, k};
                for (int d = 0; d < 3; ++d)
                    x[at++] = coordinate[d][ijk[d]];
            }
    return x;
}

struct row {
    int particles, points;
    long steps;
    double dt, pre_s, build_s, solve_s; /* wall clock */
    double build_cpu_s, solve_cpu_s;    /* CPU (all threads) */
    struct measure m;
};

static int run(const struct problem *p, struct gsn_case *c,
               const struct method *method, double h, struct row *r)
{
    int count[3], cells = 0, rc = GSN_OK;
    double lo[3], hi[3];
    p->box(h, count, lo, hi);
    c->integration = method->integration;
    c->stabilization = method->stabilization;
    if (method->gauss_points)
        c->gauss_points = method->gauss_points;
    c->particle_spacing = h;

    struct gsn_model model;
    memset(&model, 0, sizeof model);
    struct gsn_quadrature *q = NULL;
    struct gsn_material_set *materials = NULL;
    struct gsn_constraints *constraints = NULL;
    struct gsn_explicit *e = NULL;
    double *background = NULL, *u = NULL;
    void *work = NULL;

    double t0 = wall_seconds();
    double *axis = lattice_axes(count, lo, hi, p->layer_jitter);
    double *x = axis ? lattice_points(count, axis) : NULL;
    if (x)
        rc = gsn_pre_domains_box(x, count[0] * count[1] * count[2], lo, hi,
                                 c->facet_points, &model);
    if (x && rc == GSN_OK && method->integration == GSN_INTEGRATION_GAUSS)
        background = lattice_cells(count, axis, &cells);
    int allocated = x != NULL;
    free(x);
    free(axis);
    GSN_CHECK(allocated, GSN_ERR_MEMORY, "out of memory");
    GSN_CALL_GOTO(rc, rc, done);
    if (method->integration == GSN_INTEGRATION_GAUSS) {
        GSN_CHECK_GOTO(background, rc, GSN_ERR_MEMORY, done, "out of memory");
    }
    double t1 = wall_seconds(), cpu1 = cpu_seconds();
    r->pre_s = t1 - t0;

    struct gsn_kernel_options kernel;
    gsn_kernel_options_from_case(c, &kernel);
    GSN_CALL_GOTO(gsn_constraints_discretize(&model, c, &kernel, background,
                                             cells, NULL, &q, &constraints,
                                             NULL),
                  rc, done);
    GSN_CALL_GOTO(gsn_material_set_create(c, &model, &materials), rc, done);
    GSN_CALL_GOTO(
        gsn_explicit_create(&model, q, materials, constraints, c, 1.0, &e), rc,
        done);
    double stable = 0.0;
    GSN_CALL_GOTO(gsn_explicit_stable_step(e, &stable), rc, done);
    double end = p->end_time(c);
    r->steps = (long)ceil(end / (c->time_step_safety * stable));
    e->dt = r->dt = end / (double)r->steps;
    r->build_s = wall_seconds() - t1;
    r->build_cpu_s = cpu_seconds() - cpu1;

    p->start(e, c);
    u = malloc(3 * (size_t)e->particle_count * sizeof *u);
    work = calloc(1, 1 << 16);
    GSN_CHECK_GOTO(u && work, rc, GSN_ERR_MEMORY, done, "out of memory");
    double solve = 0.0, solve_cpu = 0.0;
    for (long k = 0; k < r->steps; ++k) {
        double s0 = wall_seconds(), c0 = cpu_seconds();
        GSN_CALL_GOTO(gsn_explicit_step(e), rc, done);
        solve += wall_seconds() - s0;
        solve_cpu += cpu_seconds() - c0;
        gsn_explicit_particle_field(e, e->displacement, u);
        p->sample(e, c, u, work);
    }
    r->solve_s = solve;
    r->solve_cpu_s = solve_cpu;
    r->particles = e->particle_count;
    r->points = e->point_count;
    p->finish(e, c, work, &r->m);
done:
    free(u);
    free(work);
    free(background);
    gsn_explicit_destroy(&e);
    gsn_constraints_destroy(&constraints);
    gsn_material_set_destroy(&materials);
    gsn_quadrature_destroy(&q);
    gsn_model_free(&model);
    return rc;
}

static const char HEADER[] =
    "problem,method,spacing,particles,points,steps,dt,threads,pre_s,build_s,"
    "solve_s,wall_s,build_cpu_s,solve_cpu_s,cpu_s,load,error,value,exact,"
    "value_error";

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--header") == 0) {
        puts(HEADER);
        return 0;
    }
    if (argc < 5 || argc > 6) {
        fprintf(stderr,
                "usage: %s PROBLEM CASE METHOD SPACING [THREADS]\n"
                "       %s --header\n"
                "PROBLEM: column; METHOD: scni, mscni, dni, gauss2, gauss3\n",
                argv[0], argv[0]);
        return 2;
    }
    const struct problem *p = NULL;
    for (size_t i = 0; i < sizeof problems / sizeof *problems; ++i)
        if (strcmp(argv[1], problems[i].name) == 0)
            p = &problems[i];
    const struct method *method = NULL;
    for (size_t i = 0; i < sizeof methods / sizeof *methods; ++i)
        if (strcmp(argv[3], methods[i].name) == 0)
            method = &methods[i];
    double h = strtod(argv[4], NULL);
    int threads = argc == 6 ? atoi(argv[5]) : 1;
    if (!p || !method || !(h > 0.0) || threads < 1) {
        fprintf(stderr,
                "%s: unknown problem or method, or a bad spacing or "
                "thread count\n",
                argv[0]);
        return 2;
    }
    omp_set_num_threads(threads);
    static struct gsn_case c;
    struct row r;
    memset(&r, 0, sizeof r);
    int rc = gsn_case_load(argv[2], &c);
    if (rc == GSN_OK)
        rc = run(p, &c, method, h, &r);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return gsn_error_exit_status(rc);
    }
    double load = -1.0;
    FILE *loadavg = fopen("/proc/loadavg", "r");
    if (loadavg) {
        if (fscanf(loadavg, "%lf", &load) != 1)
            load = -1.0;
        fclose(loadavg);
    }
    printf("%s,%s,%.6g,%d,%d,%ld,%.6g,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,"
           "%.2f,%.6e,%.8g,%.8g,%.6e\n",
           p->name, method->name, h, r.particles, r.points, r.steps, r.dt,
           threads, r.pre_s, r.build_s, r.solve_s, r.build_s + r.solve_s,
           r.build_cpu_s, r.solve_cpu_s, r.build_cpu_s + r.solve_cpu_s, load,
           r.m.error, r.m.value, r.m.exact, r.m.secondary);
    return 0;
}
