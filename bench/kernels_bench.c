/* Benchmark of the kernels (issue 4, point 6): time to build the RK shape
 * functions and the SCNI smoothed gradients for Slope I at paper resolution
 * (about 52,000 particles in 1500 m^3), and the bytes stored per particle.
 * With a case file, pre builds the model (gmsh + clipped Voronoi cells);
 * without, the particles are a lattice jittered by +-0.2h with the same
 * count in a 15 x 10 x 10 m box (the same volume), with nodal domains from
 * gsn_pre_domains_box. Times are wall clock and CPU (the machine is shared:
 * compare ratios, check the load).
 *
 *   build-kernels/bin/kernels_bench geometries/slope_I.yaml
 *   build-kernels/bin/kernels_bench [nx ny nz]   (default 49 33 33) */
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "geoscni/pre.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Runs pre on the case into a temporary folder and reads the model. */
static int model_from_case(const char *path, struct gsn_model *m,
                           double *support)
{
    static struct gsn_case c;
    GSN_CALL(gsn_case_load(path, &c));
    char dir[] = "/tmp/kernels_bench_XXXXXX";
    GSN_CHECK(mkdtemp(dir) != NULL, GSN_ERR_IO, "cannot create %s", dir);
    struct gsn_pre_options o;
    memset(&o, 0, sizeof o);
    o.quiet = 1;
    double t0 = omp_get_wtime();
    GSN_CALL(gsn_pre_run(&c, dir, &o));
    char file[4200];
    snprintf(file, sizeof file, "%s/model.h5", dir);
    GSN_CALL(gsn_model_read(file, m));
    printf("pre (gmsh mesh and nodal domains, for reference): %.2f s\n",
           omp_get_wtime() - t0);
    remove(file);
    rmdir(dir);
    *support = c.kernel_support;
    return GSN_OK;
}

static double uniform(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static int model_jittered(int argc, char **argv, struct gsn_model *m)
{
    int size[3] = {49, 33, 33};
    for (int d = 0; d < 3 && d + 1 < argc; ++d)
        size[d] = atoi(argv[d + 1]);
    const double length[3] = {15.0, 10.0, 10.0};
    int n = size[0] * size[1] * size[2];
    double *x = malloc(3 * (size_t)n * sizeof *x);
    GSN_CHECK(x, GSN_ERR_MEMORY, "cannot allocate %d particles", n);
    unsigned long long seed = 1;
    int p = 0;
    for (int k = 0; k < size[2]; ++k)
        for (int j = 0; j < size[1]; ++j)
            for (int i = 0; i < size[0]; ++i, ++p) {
                int ijk[3] = {i, j, k};
                for (int d = 0; d < 3; ++d) {
                    double h = length[d] / (size[d] - 1);
                    double v = ijk[d] * h;
                    if (ijk[d] > 0 && ijk[d] < size[d] - 1)
                        v += 0.2 * h * (2.0 * uniform(&seed) - 1.0);
                    x[3 * p + d] = v;
                }
            }
    const double lo[3] = {0, 0, 0};
    double t0 = omp_get_wtime();
    int rc = gsn_pre_domains_box(x, n, lo, length, 1, m);
    free(x);
    GSN_CALL(rc);
    printf("nodal domains (pre, for reference): %.2f s\n",
           omp_get_wtime() - t0);
    return GSN_OK;
}

int main(int argc, char **argv)
{
    struct gsn_model m;
    double support = 1.5;
    int threads = omp_get_max_threads(); /* pre may change it */
    int from_case = argc > 1 && strstr(argv[1], ".yaml") != NULL;
    if ((from_case ? model_from_case(argv[1], &m, &support)
                   : model_jittered(argc, argv, &m)) != GSN_OK) {
        gsn_error_print(stderr);
        return 1;
    }
    omp_set_num_threads(threads);
    int n = m.particle_count;
    printf("%d particles, %d facets, %d facet points, support %.2f, %d "
           "threads\n",
           n, m.facet_count, m.facet_point_offset[m.facet_count], support,
           omp_get_max_threads());
    enum { METHODS = 5 };
    const char *names[METHODS] = {"scni", "scni + mscni 6", "scni + mscni 2",
                                  "scni + nsni", "dni"};
    const enum gsn_integration method[METHODS] = {
        GSN_INTEGRATION_SCNI, GSN_INTEGRATION_SCNI, GSN_INTEGRATION_SCNI,
        GSN_INTEGRATION_SCNI, GSN_INTEGRATION_DNI};
    const enum gsn_stabilization stab[METHODS] = {
        GSN_STABILIZATION_NONE, GSN_STABILIZATION_MSCNI,
        GSN_STABILIZATION_MSCNI, GSN_STABILIZATION_NSNI,
        GSN_STABILIZATION_NONE};
    const int subcells[METHODS] = {6, 6, 2, 6, 6};
    for (int s = 0; s < METHODS; ++s) {
        struct gsn_kernel_options o = {1.5,     1,    method[s],   2,
                                       stab[s], 1.0,  subcells[s], 0,
                                       NULL,    NULL, 0.0};
        struct gsn_quadrature *q = NULL;
        double t0 = omp_get_wtime(), c0 = cpu_seconds();
        if (gsn_quadrature_create(&m, &o, NULL, 0, &q)) {
            gsn_error_print(stderr);
            return 1;
        }
        double t = omp_get_wtime() - t0, cpu = cpu_seconds() - c0;
        size_t bytes = gsn_quadrature_bytes(q);
        int nnz = q->gradient.offset[q->point_count];
        int main_nnz = q->gradient.offset[q->main_point_count];
        printf("%-14s: %.2f s (%.2f s CPU) to build shape functions and "
               "gradients; %d "
               "points, %.1f neighbours per nodal row, %.1f gradient entries "
               "per particle; %.0f bytes per particle (%.1f MB)\n",
               names[s], t, cpu, q->point_count, (double)main_nnz / n,
               (double)nnz / n, (double)bytes / n, bytes / 1e6);
        size_t pv = (size_t)q->particle_values.offset[n];
        size_t bv = (size_t)q->boundary_values.offset[q->boundary_point_count];
        printf("               per particle: gradient rows %.0f B (28 B per "
               "entry), points %.0f B, Psi at particles %.0f B (%.1f "
               "entries), boundary points %.0f B\n",
               (double)nnz * 28.0 / n + 4.0 * (q->point_count + 1) / n,
               36.0 * q->point_count / n, 12.0 * pv / n + 4.0, (double)pv / n,
               (12.0 * bv + 36.0 * q->boundary_point_count) / n);
        if (s == 0) {
            /* row-sum lumped mass eq. (28) per unit density */
            double *mass = calloc((size_t)n, sizeof *mass), low = INFINITY;
            const struct gsn_shape_rows *r = &q->particle_values;
            for (int L = 0; L < n; ++L)
                for (int e = r->offset[L]; e < r->offset[L + 1]; ++e)
                    mass[r->index[e]] += r->value[e] * m.volume[L];
            for (int i = 0; i < n; ++i)
                low = fmin(low, mass[i] / m.volume[i]);
            printf("               smallest lumped mass m_I / (rho V_I): "
                   "%.3f\n",
                   low);
            free(mass);
        }
        gsn_quadrature_destroy(&q);
    }
    gsn_model_free(&m);
    return 0;
}
