/* The case reader: every key of DESIGN.md lands in the struct, defaults are
 * the named constants, and the resolved YAML written into output files reads
 * back to the same parameters bit for bit. */
#include "case_testing.h"
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "testing.h"

#include <string.h>

/* The same soil in two cases: every field but the lines it was read from
 * (the resolved YAML puts the keys on other lines). */
static int same_soil(const struct gsn_material *a, const struct gsn_material *b)
{
    struct gsn_material x = *a, y = *b;
    memset(&x.line, 0, sizeof x.line);
    memset(&y.line, 0, sizeof y.line);
    return memcmp(&x, &y, sizeof x) == 0;
}

static void check_valid(const struct gsn_case *c)
{
    TEST_TRUE(strstr(c->geometry, "/tests/foundation/cases/cube.geo") != NULL);
    TEST_TRUE(c->geometry[0] == '/');
    TEST_NEAR(c->particle_spacing, 0.25, 0.0);
    TEST_NEAR(c->kernel_support, 1.5, 0.0);
    TEST_NEAR(c->kernel_window_cut, 1e-3, 0.0);
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

/* material.drucker_prager in engineers' terms (issue 18, point 1): the
 * fits against their closed forms, and a case file through the reader and
 * back through the resolved YAML. */
static void test_mohr_coulomb(void)
{
    const double degree = acos(-1.0) / 180.0;
    double alpha = 0, R = 0, beta = 0;
    /* The paper's cone (alpha 0.07, R 0.19 MPa) is Drucker and Prager's
     * plane-strain fit of phi = 8.571 degrees, c = 0.13637 MPa
     * (REFERENCES.md): inverted exactly, a = tan(phi) / sqrt(9 + 12 tan^2),
     * k = 3 c / sqrt(9 + 12 tan^2) (a, k = alpha, R over sqrt 2), the
     * associated fit gives them back to rounding. */
    double a = 0.07 / sqrt(2.0), k = 0.19e6 / sqrt(2.0);
    double t = 3.0 * a / sqrt(1.0 - 12.0 * a * a);
    double phi = atan(t) / degree, c = k * sqrt(9.0 + 12.0 * t * t) / 3.0;
    TEST_NEAR(phi, 8.571, 0.0005); /* the reference's printed digits */
    TEST_NEAR(c, 0.13637e6, 5.0);
    gsn_drucker_prager_fit(GSN_DP_FIT_PLANE_STRAIN, c, phi, phi, &alpha, &R,
                           &beta);
    TEST_REL(alpha, 0.07, 1e-14);
    TEST_REL(R, 0.19e6, 1e-14);
    TEST_REL(beta, 0.07, 1e-14);
    /* Plane strain without dilation: a = sin(phi) / 3, k = c cos(phi), the
     * known match for psi = 0 (Davis and Selvadurai 2002). */
    gsn_drucker_prager_fit(GSN_DP_FIT_PLANE_STRAIN, 10e3, 30.0, 0.0, &alpha, &R,
                           &beta);
    TEST_REL(alpha, sqrt(2.0) * sin(30.0 * degree) / 3.0, 1e-15);
    TEST_REL(R, sqrt(2.0) * 10e3 * cos(30.0 * degree), 1e-15);
    TEST_NEAR(beta, 0.0, 0.0);
    /* The compression cone of phi = 30 degrees: a = 2 sin / (sqrt 3 (3 -
     * sin)) = 1 / (2.5 sqrt 3), k = 6 c cos / (sqrt 3 (3 - sin)). */
    gsn_drucker_prager_fit(GSN_DP_FIT_COMPRESSION, 10e3, 30.0, 30.0, &alpha, &R,
                           &beta);
    TEST_REL(alpha, sqrt(2.0) / (2.5 * sqrt(3.0)), 1e-15);
    TEST_REL(R, sqrt(2.0) * 6.0 * 10e3 * cos(30.0 * degree) / (2.5 * sqrt(3.0)),
             1e-15);

    struct gsn_case from_file, again;
    TEST_INT(gsn_case_load("cases/mohr_coulomb.yaml", &from_file), GSN_OK);
    const struct gsn_material *m = &from_file.material;
    TEST_INT(m->has_plasticity, 1);
    TEST_INT(m->dp_from_mohr_coulomb, 1);
    TEST_INT(m->dp_fit, GSN_DP_FIT_PLANE_STRAIN);
    TEST_NEAR(m->cohesion, 10e3, 0.0);
    TEST_NEAR(m->friction_angle, 30.0, 0.0);
    TEST_NEAR(m->dilation_angle, 5.0, 0.0);
    gsn_drucker_prager_fit(GSN_DP_FIT_PLANE_STRAIN, 10e3, 30.0, 5.0, &alpha, &R,
                           &beta);
    TEST_NEAR(m->dp_alpha, alpha, 0.0);
    TEST_NEAR(m->dp_R, R, 0.0);
    TEST_NEAR(m->dp_dilatancy, beta, 0.0);
    round_trip(&from_file, &again);
    TEST_TRUE(same_soil(&from_file.material, &again.material));

    /* Strength reduction (geoscni fos): c and tan(phi) over F, psi kept
     * below the reduced phi, the cone refitted; F = 1 gives the case's
     * cone back exactly, damage dropped. */
    struct gsn_material reduced, damaged = *m;
    damaged.has_damage = 1;
    gsn_material_reduce_strength(&damaged, 1.0, &reduced);
    TEST_NEAR(reduced.dp_alpha, m->dp_alpha, 0.0);
    TEST_NEAR(reduced.dp_R, m->dp_R, 0.0);
    TEST_NEAR(reduced.dp_dilatancy, m->dp_dilatancy, 0.0);
    TEST_INT(reduced.has_damage, 0);
    gsn_material_reduce_strength(m, 2.0, &reduced);
    double phi_2 = atan(tan(30.0 * degree) / 2.0) / degree; /* 16.10 deg */
    TEST_REL(reduced.cohesion, 5e3, 1e-15);
    TEST_REL(reduced.friction_angle, phi_2, 1e-15);
    TEST_NEAR(reduced.dilation_angle, 5.0, 0.0); /* below phi_2: kept */
    gsn_drucker_prager_fit(GSN_DP_FIT_PLANE_STRAIN, 5e3, phi_2, 5.0, &alpha, &R,
                           &beta);
    TEST_NEAR(reduced.dp_alpha, alpha, 0.0);
    TEST_NEAR(reduced.dp_R, R, 0.0);
    TEST_NEAR(reduced.dp_dilatancy, beta, 0.0);
    gsn_material_reduce_strength(m, 8.0, &reduced); /* phi 4.13 < psi 5 */
    TEST_NEAR(reduced.dilation_angle, reduced.friction_angle, 0.0);
    TEST_REL(reduced.dp_dilatancy, reduced.dp_alpha, 1e-15); /* associated */
}

/* water.table (docs/site.md, "Water"): points spread over the site are
 * met linearly on their Delaunay triangles: a plane through three points
 * exactly inside them, a paraboloid's grid at its nodes and, between
 * them, within the grid's linear error; beyond the hull the height of its
 * nearest place; points on a line in plan are a section; the refusals. */
static void test_water_table(void)
{
    static struct gsn_case c;
    memset(&c, 0, sizeof c);
    c.gravity[2] = -9.81;
    c.water.present = 1;
    c.water.unit_weight = 9810.0;
    int bad = 0;
    const double plane[3][2] = {{0.0, 0.0}, {40.0, 5.0}, {10.0, 30.0}};
    c.water.point_count = 3;
    for (int i = 0; i < 3; ++i) {
        c.water.points[i][0] = plane[i][0];
        c.water.points[i][1] = plane[i][1];
        c.water.points[i][2] = 10.0 + 0.1 * plane[i][0] - 0.05 * plane[i][1];
    }
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_SURFACE);
    TEST_INT(c.water.triangle_count, 1);
    for (int k = 1; k < 10; ++k) { /* inside: s, t > 0, s + t < 1 */
        double s = 0.07 * k, t = 0.9 - 0.093 * k;
        double x[3] = {s * 40.0 + t * 10.0, s * 5.0 + t * 30.0, -3.0};
        double z = 10.0 + 0.1 * x[0] - 0.05 * x[1];
        TEST_NEAR(gsn_water_table_height(&c, x), z, 1e-12);
        TEST_NEAR(gsn_water_pressure(&c, x), 9810.0 * (z + 3.0), 1e-8);
    }
    double beyond[3] = {-10.0, -10.0, 0.0}; /* nearest the corner (0, 0) */
    TEST_NEAR(gsn_water_table_height(&c, beyond), 10.0, 1e-12);
    /* a grid of 5 x 4 points on z = (x^2 + y^2) / 100 */
    c.water.point_count = 20;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 5; ++i) {
            double *p = c.water.points[5 * j + i];
            p[0] = 10.0 * i, p[1] = 10.0 * j;
            p[2] = (p[0] * p[0] + p[1] * p[1]) / 100.0;
        }
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_SURFACE);
    TEST_INT(c.water.triangle_count, 2 * 4 * 3);
    for (int n = 0; n < 20; ++n)
        TEST_NEAR(gsn_water_table_height(&c, c.water.points[n]),
                  c.water.points[n][2], 1e-12);
    double middle[3] = {15.0, 15.0, 0.0}; /* a cell's centre: linear error */
    double h = gsn_water_table_height(&c, middle);
    TEST_TRUE(h >= 4.5 - 1e-12 && h <= 4.5 + 2.0 * 100.0 / 4.0 / 100.0);
    /* on one line in plan: a section; back along it; twice; stacked */
    c.water.point_count = 3;
    const double line[3][3] = {{0, 0, 1}, {5, 5, 2}, {10, 10, 4}};
    memcpy(c.water.points, line, sizeof line);
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_SECTION);
    double along[3] = {7.5, 7.5, 0.0};
    TEST_NEAR(gsn_water_table_height(&c, along), 3.0, 1e-12);
    c.water.points[2][0] = c.water.points[2][1] = 2.0;
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_BACKWARDS);
    TEST_INT(bad, 2);
    const double twice[4][3] = {{0, 0, 1}, {10, 0, 2}, {0, 10, 3}, {10, 0, 4}};
    c.water.point_count = 4;
    memcpy(c.water.points, twice, sizeof twice);
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_TWICE);
    TEST_INT(bad, 3);
    c.water.point_count = 2;
    c.water.points[1][0] = c.water.points[1][1] = 0.0;
    TEST_INT(gsn_water_table_prepare(&c, &bad), GSN_WATER_STACKED);
}

int main(void)
{
    test_begin();
    struct gsn_case c, again;
    TEST_INT(gsn_case_load("cases/valid.yaml", &c), GSN_OK);
    check_valid(&c);
    TEST_INT(c.boundaries[2].line, 19); /* the line of "top:" in the file */

    /* Round trip through the resolved YAML. */
    round_trip(&c, &again);
    check_valid(&again);
    TEST_TRUE(same_soil(&c.material, &again.material));
    /* the paper's whole window, 0, is written and read back as such, not
     * taken for the default cut */
    c.kernel_window_cut = 0.0;
    round_trip(&c, &again);
    TEST_NEAR(again.kernel_window_cut, 0.0, 0.0);
    /* a case text stored before the key was always written (0 left out)
     * reads as this version writes the same case */
    char *text = NULL;
    TEST_INT(gsn_case_to_yaml_string(&c, &text), GSN_OK);
    char *old = text ? malloc(strlen(text) + 1) : NULL;
    char *key = text ? strstr(text, ", window_cut: 0}") : NULL;
    TEST_TRUE(old && key);
    if (old && key) {
        size_t at = (size_t)(key - text);
        memcpy(old, text, at);
        strcpy(old + at, key + strlen(", window_cut: 0"));
        gsn_case_yaml_upgrade(&old);
        TEST_TRUE(!strcmp(old, text));
        gsn_case_yaml_upgrade(&old); /* once is enough */
        TEST_TRUE(!strcmp(old, text));
    }
    free(old);
    free(text);

    /* Defaults of the optional keys. */
    TEST_INT(gsn_case_load("cases/minimal.yaml", &c), GSN_OK);
    TEST_NEAR(c.kernel_support, GSN_DEFAULT_KERNEL_SUPPORT, 0.0);
    TEST_INT(c.kernel_basis_order, GSN_DEFAULT_KERNEL_BASIS_ORDER);
    TEST_NEAR(c.kernel_window_cut, GSN_DEFAULT_KERNEL_WINDOW_CUT, 0.0);
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
    /* reference updates: on by default with large kinematics and nodal
     * integration, off with MSCNI, damage, small kinematics or Gauss */
    TEST_INT(c.reference_update, 1);
    TEST_INT(c.reference_min_steps, GSN_DEFAULT_REFERENCE_MIN_STEPS);
    struct gsn_case variant = c;
    variant.stabilization = GSN_STABILIZATION_NSNI;
    TEST_INT(gsn_case_reference_update_default(&variant), 1);
    variant.stabilization = GSN_STABILIZATION_MSCNI;
    TEST_INT(gsn_case_reference_update_default(&variant), 0);
    variant = c;
    variant.small_strain = 1;
    TEST_INT(gsn_case_reference_update_default(&variant), 0);
    variant = c;
    variant.integration = GSN_INTEGRATION_GAUSS;
    TEST_INT(gsn_case_reference_update_default(&variant), 0);
    TEST_INT(gsn_case_load("cases/valid.yaml", &variant), GSN_OK);
    TEST_INT(variant.reference_update, 0); /* the paper's soil: damage */

    test_mohr_coulomb();
    test_water_table();

    /* A missing case file is an I/O error naming the file. */
    TEST_INT(gsn_case_load("cases/no_such_case.yaml", &c), GSN_ERR_IO);
    TEST_TRUE(strstr(gsn_error_message(), "cases/no_such_case.yaml") != NULL);
    gsn_error_clear();
    return test_end("test_case");
}
