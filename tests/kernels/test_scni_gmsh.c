/* SCNI on irregular gmsh particles (issue 4, point 4): the models pre makes
 * from the coarse Slope I and from an L-shaped body (a re-entrant edge,
 * where clipped cells are not convex). eq. (23) at every particle, eq. (24)
 * at the particles whose kernel covers no boundary point, the linear patch
 * test for SCNI and SCNI+MSCNI (<= 1e-10) and DNI (> 1e-3, the negative
 * control). */
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/kernels.h"
#include "geoscni/pre.h"
#include "kernel_fixtures.h"

#include <stdlib.h>
#include <unistd.h>

/* Row-sum lumped mass of eq. (28) per unit density, m_I = sum_L Psi_I(X_L)
 * V_L: the total is the volume (partition of unity), and the explicit loop
 * needs every m_I > 0. Returns the relative error of the total and the
 * smallest m_I / V_I. */
static void lumped_mass(const struct gsn_model *m,
                        const struct gsn_quadrature *q, double *error,
                        double *smallest)
{
    int n = m->particle_count;
    double *mass = calloc((size_t)n, sizeof *mass), total = 0.0, body = 0.0;
    const struct gsn_shape_rows *r = &q->particle_values;
    for (int L = 0; L < n; ++L) {
        body += m->volume[L];
        for (int e = r->offset[L]; e < r->offset[L + 1]; ++e)
            mass[r->index[e]] += r->value[e] * m->volume[L];
    }
    *smallest = INFINITY;
    for (int i = 0; i < n; ++i) {
        total += mass[i];
        *smallest = fmin(*smallest, mass[i] / m->volume[i]);
    }
    *error = fabs(total / body - 1.0);
    free(mass);
}

static void check_case(const char *path)
{
    static struct gsn_case c;
    struct gsn_model m;
    memset(&m, 0, sizeof m);
    char folder[] = "/tmp/geoscni_kernels_XXXXXX", file[64];
    TEST_TRUE(mkdtemp(folder) != NULL);
    snprintf(file, sizeof file, "%s/model.h5", folder);
    struct gsn_pre_options options;
    memset(&options, 0, sizeof options);
    options.threads = 1;
    options.reproducible = 1; /* the same mesh on every run */
    options.quiet = 1;
    int rc = gsn_case_load(path, &c);
    if (rc == GSN_OK)
        rc = gsn_pre_run(&c, folder, &options);
    if (rc == GSN_OK)
        rc = gsn_model_read(file, &m);
    remove(file);
    rmdir(folder);
    if (rc)
        gsn_error_print(stderr);
    TEST_INT(rc, GSN_OK);
    if (rc)
        return;
    double h = c.particle_spacing, body = 0.0;
    /* the geometric part of eq. (23): pre's own check of the cells */
    for (int p = 0; p < m.particle_count; ++p)
        body += m.volume[p];
    struct gsn_cells_report check;
    memset(&check, 0, sizeof check);
    TEST_INT(gsn_cells_check(&m, body, &check), GSN_OK);
    const enum gsn_integration method[4] = {
        GSN_INTEGRATION_SCNI, GSN_INTEGRATION_SCNI, GSN_INTEGRATION_DNI,
        GSN_INTEGRATION_SCNI};
    const enum gsn_stabilization stab[4] = {
        GSN_STABILIZATION_NONE, GSN_STABILIZATION_MSCNI, GSN_STABILIZATION_NONE,
        GSN_STABILIZATION_NSNI};
    double residual[4] = {1.0, 1.0, 0.0, 1.0}, e23 = 1.0, e24 = 1.0;
    double mass_error = 1.0, mass_min = 0.0;
    int interior = 0;
    for (int s = 0; s < 4; ++s) {
        struct gsn_kernel_options o;
        gsn_kernel_options_from_case(&c, &o);
        o.integration = method[s];
        o.stabilization = stab[s];
        struct gsn_quadrature *q = NULL;
        rc = gsn_quadrature_create(&m, &o, NULL, 0, &q);
        if (rc)
            gsn_error_print(stderr);
        TEST_INT(rc, GSN_OK);
        if (rc)
            continue;
        residual[s] = fixture_patch_test(&m, q);
        if (s == 0) {
            fixture_completeness(&m, q, h, &e23, &e24, &interior);
            lumped_mass(&m, q, &mass_error, &mass_min);
        }
        gsn_quadrature_destroy(&q);
    }
    printf("%s: lumped mass: total volume within %.1e, smallest m_I / "
           "(rho V_I) %.3f\n",
           path, mass_error, mass_min);
    /* partition of unity summed over n particles: round-off */
    TEST_TRUE(mass_error <= 1e-12);
    TEST_TRUE(mass_min > 0.0);
    printf("%s: %d particles, %d facets: eq. (23) %.2e (the cells' own "
           "moment error %.2e), eq. (24) %.2e at %d interior particles; "
           "patch residual SCNI %.2e, MSCNI %.2e, NSNI %.2e, DNI %.2e\n",
           path, m.particle_count, m.facet_count, e23, check.moment_error, e24,
           interior, residual[0], residual[1], residual[3], residual[2]);
    /* identities: round-off of sums of ~100 terms of O(1) */
    TEST_TRUE(e23 <= 1e-12);
    TEST_TRUE(e24 <= 1e-12);
    TEST_TRUE(interior > 0);
    /* issue 4: SCNI exact to 1e-10; DNI fails by more than 1e-3 */
    TEST_TRUE(residual[0] <= 1e-10);
    TEST_TRUE(residual[1] <= 1e-10);
    TEST_TRUE(residual[3] <= 1e-10);
    TEST_TRUE(residual[2] > 1e-3);
    gsn_model_free(&m);
}

int main(void)
{
    test_begin();
    check_case("../../geometries/lshape.yaml");
    check_case("../../geometries/slope_I_coarse.yaml");
    return test_end("test_scni_gmsh");
}
