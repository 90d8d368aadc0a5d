/* The case reader: every key of DESIGN.md lands in the struct, defaults are
 * the named constants, and the resolved YAML written into output files reads
 * back to the same parameters bit for bit. */
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "testing.h"

#include <string.h>

static void check_valid(const struct gsn_case *c)
{
    TEST_TRUE(strstr(c->geometry, "/tests/foundation/cases/cube.geo") != NULL);
    TEST_TRUE(c->geometry[0] == '/');
    TEST_NEAR(c->particle_spacing, 0.25, 0.0);
    TEST_NEAR(c->kernel_support, 1.5, 0.0);
    TEST_INT(c->integration, GSN_INTEGRATION_SCNI);
    TEST_NEAR(c->material.density, 1880.0, 0.0);
    TEST_NEAR(c->material.bulk_modulus, 27.4e6, 0.0);
    TEST_NEAR(c->material.shear_modulus, 9.15e6, 0.0);
    TEST_INT(c->material.has_damage, 1);
    TEST_NEAR(c->material.damage_e0, 0.02, 0.0);
    TEST_NEAR(c->material.damage_ef, 5.0, 0.0);
    TEST_INT(c->material.has_plasticity, 1);
    TEST_NEAR(c->material.dp_alpha, 0.07, 0.0);
    TEST_NEAR(c->material.dp_R, 0.19e6, 0.0);
    /* Associated flow unless a dilatancy is given. */
    TEST_NEAR(c->material.dp_dilatancy, 0.07, 0.0);
    TEST_NEAR(c->gravity[2], -9.81, 0.0);
    TEST_INT(c->boundary_count, 3);
    int top = gsn_case_find_boundary(c, "top");
    int sides = gsn_case_find_boundary(c, "sides");
    TEST_INT(gsn_case_find_boundary(c, "bottom"), 0);
    TEST_INT(gsn_case_find_boundary(c, "nowhere"), -1);
    TEST_TRUE(top == 2 && sides == 1);
    if (top == 2 && sides == 1) {
        TEST_INT(c->boundaries[sides].fixed[0] + c->boundaries[sides].fixed[1] +
                     c->boundaries[sides].fixed[2],
                 2);
        TEST_INT(c->boundaries[top].has_velocity[2], 1);
        TEST_INT(c->boundaries[top].has_velocity[0], 0);
        TEST_NEAR(c->boundaries[top].velocity[2], -0.01, 0.0);
    }
    TEST_NEAR(c->time_end, 2.0, 0.0);
    TEST_INT(c->time_step_auto, 0);
    TEST_NEAR(c->time_step, 1e-3, 0.0);
    TEST_NEAR(c->output_every, 0.5, 0.0);
}

int main(void)
{
    test_begin();
    struct gsn_case c, again;
    TEST_INT(gsn_case_load("cases/valid.yaml", &c), GSN_OK);
    check_valid(&c);
    TEST_INT(c.boundaries[2].line, 18); /* the line of "top:" in the file */

    /* Round trip through the resolved YAML. */
    char path[] = "/tmp/geoscni-test-case-XXXXXX";
    int fd = mkstemp(path);
    TEST_TRUE(fd >= 0);
    FILE *out = fdopen(fd, "w");
    TEST_INT(gsn_case_write_yaml(&c, out), GSN_OK);
    fclose(out);
    int rc = gsn_case_load(path, &again);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    TEST_INT(rc, GSN_OK);
    check_valid(&again);
    TEST_TRUE(memcmp(&c.material, &again.material, sizeof c.material) == 0);
    remove(path);

    /* Defaults of the optional keys. */
    TEST_INT(gsn_case_load("cases/minimal.yaml", &c), GSN_OK);
    TEST_NEAR(c.kernel_support, GSN_DEFAULT_KERNEL_SUPPORT, 0.0);
    TEST_INT(c.kernel_basis_order, GSN_DEFAULT_KERNEL_BASIS_ORDER);
    TEST_INT(c.facet_points, GSN_DEFAULT_FACET_POINTS);
    TEST_INT(c.integration, GSN_INTEGRATION_SCNI);
    TEST_INT(c.stabilization, GSN_STABILIZATION_NONE);
    TEST_INT(c.time_step_auto, 1);
    TEST_NEAR(c.time_step_safety, GSN_DEFAULT_TIME_STEP_SAFETY, 0.0);
    TEST_NEAR(c.output_every, 1.0 / GSN_DEFAULT_FRAMES, 0.0);
    TEST_INT(c.material.has_damage, 0);
    TEST_INT(c.material.has_plasticity, 0);
    TEST_INT(c.boundary_count, 0);
    TEST_NEAR(c.gravity[0] + c.gravity[1] + c.gravity[2], 0.0, 0.0);

    /* A missing case file is an I/O error naming the file. */
    TEST_INT(gsn_case_load("cases/no_such_case.yaml", &c), GSN_ERR_IO);
    TEST_TRUE(strstr(gsn_error_message(), "cases/no_such_case.yaml") != NULL);
    gsn_error_clear();
    return test_end("test_case");
}
