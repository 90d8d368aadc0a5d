/* geoscni pre on gmsh geometries (issue 3, "Tests"): the checks of point 3
 * on the L-shaped body (re-entrant edge), both coarse slopes, a cylinder
 * (curved boundary) and a box, each against the exact volume and face areas
 * where the body is polyhedral; the physical-surface tags of particles and
 * facets checked against the geometry; the same particles and facets on a
 * second run with another thread count; the caller's OpenMP thread count
 * kept. */
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/model.h"
#include "geoscni/pre.h"
#include "testing.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The checks of issue 3 point 3 hold to rounding (a few 1e-13 at most on
 * these models, from the clipping tolerance of 1e-14 of the diagonal);
 * 1e-11 keeps a margin of 10 below the 1e-10 and of 10 above what
 * was measured. */
#define CHECK_TOLERANCE 1e-11
/* Exact volumes and face areas of flat-faced bodies: sums over ~1e5 facets,
 * rounding only. */
#define EXACT 1e-12
/* A coordinate on a flat face: the mesh nodes lie on it up to gmsh's
 * rounding of the geometry (1e-12 m on 10 m bodies). */
#define ON_FACE 1e-9

static char folder[64];
static int facet_points_override; /* 0: as the case file says */

static int run_pre_with(const char *case_path, int threads, int tetrahedra_only,
                        struct gsn_model *m, struct gsn_case *c)
{
    struct gsn_pre_options options = {.threads = threads,
                                      .quiet = 1,
                                      .reproducible = 1,
                                      .tetrahedra_only = tetrahedra_only};
    int rc = gsn_case_load(case_path, c);
    if (rc == GSN_OK && facet_points_override)
        c->facet_points = facet_points_override;
    if (rc == GSN_OK)
        rc = gsn_pre_run(c, folder, &options);
    char path[128];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    if (rc == GSN_OK)
        rc = gsn_model_read(path, m);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    return rc;
}

static int run_pre(const char *case_path, int threads, struct gsn_model *m,
                   struct gsn_case *c)
{
    return run_pre_with(case_path, threads, 0, m, c);
}

static void expect_model_checks(const struct gsn_model *m, double volume)
{
    struct gsn_cells_report r;
    memset(&r, 0, sizeof r);
    TEST_INT(gsn_cells_check(m, volume, &r), GSN_OK);
    TEST_TRUE(r.volume_error <= CHECK_TOLERANCE);
    TEST_TRUE(r.closure_error <= CHECK_TOLERANCE);
    TEST_TRUE(r.moment_error <= CHECK_TOLERANCE);
    TEST_TRUE(r.area_error <= CHECK_TOLERANCE);
    printf("  %d particles, %d facets: volume %.1e closure %.1e moment %.1e "
           "area %.1e\n",
           m->particle_count, m->facet_count, r.volume_error, r.closure_error,
           r.moment_error, r.area_error);
}

static double tetrahedra_volume(const struct gsn_model *m)
{
    double sum = 0.0;
    for (int t = 0; t < m->tetrahedron_count; ++t) {
        const int *v = &m->tetrahedra[4 * t];
        const double *a = &m->position[3 * v[0]];
        double e[3][3];
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                e[k][j] = m->position[3 * v[k + 1] + j] - a[j];
        sum += fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                    e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                    e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
               6.0;
    }
    return sum;
}

static int particle_on(const struct gsn_model *m, int p, int s)
{
    for (int e = m->particle_surface_offset[p];
         e < m->particle_surface_offset[p + 1]; ++e)
        if (m->particle_surface[e] == s)
            return 1;
    return 0;
}

/* A flat face: axis coordinate = value, inside [lo, hi] on the other two.
 * The particles tagged with it lie on it, and every particle on it is
 * tagged; its boundary facets' quadrature points lie on it; its area is
 * exact. */
struct face {
    const char *name;
    int axis;
    double value;
    double lo[3], hi[3]; /* extent of the face (and of any other faces in
                            the same group: checked per particle) */
    double area;         /* of the whole physical surface */
};

static void expect_face(const struct gsn_model *m, const struct face *f)
{
    int s = gsn_model_find_surface(m, f->name);
    TEST_TRUE(s >= 0);
    if (s < 0)
        return;
    TEST_REL(m->surface_area[s], f->area, EXACT);
    int wrong_tag = 0, missing_tag = 0;
    for (int p = 0; p < m->particle_count; ++p) {
        const double *x = &m->position[3 * p];
        int inside = fabs(x[f->axis] - f->value) <= ON_FACE;
        for (int k = 0; k < 3; ++k)
            inside &= x[k] >= f->lo[k] - ON_FACE && x[k] <= f->hi[k] + ON_FACE;
        int tagged = particle_on(m, p, s);
        wrong_tag += tagged && !inside;
        missing_tag += inside && !tagged;
    }
    TEST_INT(wrong_tag, 0);
    TEST_INT(missing_tag, 0);
    int off_face = 0;
    for (int k = 0; k < m->facet_count; ++k) {
        if (m->facet_surface[k] != s)
            continue;
        off_face += m->facet_neighbour[k] != -1;
        off_face += fabs(fabs(m->facet_normal[3 * k + f->axis]) - 1.0) > 1e-12;
        for (int q = m->facet_point_offset[k]; q < m->facet_point_offset[k + 1];
             ++q)
            off_face +=
                fabs(m->facet_point[3 * q + f->axis] - f->value) > ON_FACE;
    }
    TEST_INT(off_face, 0);
}

/* Every boundary facet carries a surface: all faces of these bodies are
 * named. */
static void expect_all_tagged(const struct gsn_model *m)
{
    int untagged = 0;
    for (int k = 0; k < m->facet_count; ++k)
        untagged += m->facet_neighbour[k] < 0 && m->facet_surface[k] < 0;
    TEST_INT(untagged, 0);
}

static void test_box(void)
{
    struct gsn_model m;
    struct gsn_case c;
    /* gmsh sets OpenMP's thread count to its General.NumThreads; pre must
     * give the caller's back (geoscni run solves in the same process) */
    const int threads = omp_get_max_threads() + 1;
    omp_set_num_threads(threads);
    int rc = run_pre("../../geometries/box.yaml", 0, &m, &c);
    TEST_INT(omp_get_max_threads(), threads);
    if (rc != GSN_OK) {
        TEST_TRUE(0);
        return;
    }
    expect_model_checks(&m, 2.0);
    expect_all_tagged(&m);
    const struct face faces[] = {{"xmin", 0, 0.0, {0, 0, 0}, {0, 1, 1}, 1.0},
                                 {"xmax", 0, 2.0, {2, 0, 0}, {2, 1, 1}, 1.0},
                                 {"bottom", 2, 0.0, {0, 0, 0}, {2, 1, 0}, 2.0},
                                 {"top", 2, 1.0, {0, 0, 1}, {2, 1, 1}, 2.0}};
    for (size_t i = 0; i < sizeof faces / sizeof faces[0]; ++i)
        expect_face(&m, &faces[i]);
    /* a corner particle carries its three faces */
    int corner = -1;
    for (int p = 0; p < m.particle_count && corner < 0; ++p)
        if (m.position[3 * p] == 0.0 && m.position[3 * p + 1] == 0.0 &&
            m.position[3 * p + 2] == 0.0)
            corner = p;
    TEST_TRUE(corner >= 0);
    if (corner >= 0)
        TEST_INT(m.particle_surface_offset[corner + 1] -
                     m.particle_surface_offset[corner],
                 3);
    gsn_model_free(&m);
}

static void test_lshape(void)
{
    struct gsn_model m;
    struct gsn_case c;
    if (run_pre("../../geometries/lshape.yaml", 0, &m, &c) != GSN_OK) {
        TEST_TRUE(0);
        return;
    }
    /* [0,2] x [0,1] x [0,1] plus [0,1] x [0,1] x [1,2] */
    expect_model_checks(&m, 3.0);
    expect_all_tagged(&m);
    const struct face faces[] = {{"bottom", 2, 0.0, {0, 0, 0}, {2, 1, 0}, 2.0},
                                 {"top", 2, 2.0, {0, 0, 2}, {1, 1, 2}, 1.0},
                                 {"front", 0, 2.0, {2, 0, 0}, {2, 1, 1}, 1.0},
                                 {"back", 0, 0.0, {0, 0, 0}, {0, 1, 2}, 2.0}};
    for (size_t i = 0; i < sizeof faces / sizeof faces[0]; ++i)
        expect_face(&m, &faces[i]);
    /* three points per fan triangle: the same checks, more points */
    struct gsn_model m3;
    facet_points_override = 3;
    if (run_pre("../../geometries/lshape.yaml", 0, &m3, &c) == GSN_OK) {
        expect_model_checks(&m3, 3.0);
        TEST_TRUE(m3.facet_point_offset[m3.facet_count] >= 3 * m3.facet_count);
        gsn_model_free(&m3);
    } else {
        TEST_TRUE(0);
    }
    facet_points_override = 0;
    int step = gsn_model_find_surface(&m, "step");
    TEST_TRUE(step >= 0);
    if (step >= 0)
        TEST_REL(m.surface_area[step], 2.0, EXACT);
    /* the cells at the re-entrant edge x = 1, z = 1 keep the notch out:
     * nothing of any cell lies in the notch x > 1, z > 1 */
    int in_notch = 0;
    for (int p = 0; p < m.particle_count; ++p) {
        const double *g = &m.centroid[3 * p];
        in_notch += g[0] > 1.0 + 1e-12 && g[2] > 1.0 + 1e-12;
    }
    for (int q = 0; q < m.facet_point_offset[m.facet_count]; ++q) {
        const double *x = &m.facet_point[3 * q];
        in_notch += x[0] > 1.0 + 1e-12 && x[2] > 1.0 + 1e-12;
    }
    TEST_INT(in_notch, 0);
    gsn_model_free(&m);
}

static void test_cylinder(void)
{
    struct gsn_model m;
    struct gsn_case c;
    if (run_pre("../../geometries/cylinder.yaml", 0, &m, &c) != GSN_OK) {
        TEST_TRUE(0);
        return;
    }
    /* the body is the mesh: its faceted volume, computed here again */
    double volume = tetrahedra_volume(&m);
    expect_model_checks(&m, volume);
    expect_all_tagged(&m);
    /* the faceted cylinder is inside the true one, within the chord error
     * 1 - cos(pi h / (2 pi r)) ~ 0.5 % at h = 0.2, r = 1 */
    TEST_TRUE(volume < 2.0 * M_PI && volume > 0.98 * 2.0 * M_PI);
    int mantle = gsn_model_find_surface(&m, "mantle");
    TEST_TRUE(mantle >= 0);
    if (mantle >= 0)
        TEST_TRUE(fabs(m.surface_area[mantle] - 4.0 * M_PI) <
                  0.02 * 4.0 * M_PI);
    gsn_model_free(&m);
}

/* Slope I or II: cross-section (0,0) (20,0) (10,10) (0,10), width w. */
static void test_slope(const char *case_path, double w, const double flo[3],
                       const double fhi[3])
{
    struct gsn_model m, again;
    struct gsn_case c;
    if (run_pre(case_path, 1, &m, &c) != GSN_OK) {
        TEST_TRUE(0);
        return;
    }
    expect_model_checks(&m, 150.0 * w);
    expect_all_tagged(&m);
    double footing = (fhi[0] - flo[0]) * (fhi[1] - flo[1]);
    const struct face faces[] = {
        {"bottom", 2, 0.0, {0, 0, 0}, {20, w, 0}, 20.0 * w},
        {"back", 0, 0.0, {0, 0, 0}, {0, w, 10}, 10.0 * w},
        {"footing",
         2,
         10.0,
         {flo[0], flo[1], 10},
         {fhi[0], fhi[1], 10},
         footing},
        {"top", 2, 10.0, {0, 0, 10}, {10, w, 10}, 10.0 * w - footing}};
    for (size_t i = 0; i < 3; ++i)
        expect_face(&m, &faces[i]);
    int top = gsn_model_find_surface(&m, "top");
    TEST_TRUE(top >= 0);
    if (top >= 0)
        TEST_REL(m.surface_area[top], faces[3].area, EXACT);
    int sides = gsn_model_find_surface(&m, "sides");
    int face = gsn_model_find_surface(&m, "face");
    TEST_TRUE(sides >= 0 && face >= 0);
    if (sides >= 0 && face >= 0) {
        TEST_REL(m.surface_area[sides], 300.0, EXACT);
        TEST_REL(m.surface_area[face], 10.0 * sqrt(2.0) * w, EXACT);
    }
    /* the same mesh and cells on a second run with two threads */
    if (run_pre(case_path, 2, &again, &c) == GSN_OK) {
        TEST_INT(again.particle_count, m.particle_count);
        TEST_INT(again.facet_count, m.facet_count);
        if (again.particle_count == m.particle_count &&
            again.facet_count == m.facet_count) {
            size_t n = (size_t)m.particle_count, nf = (size_t)m.facet_count;
            size_t points = (size_t)m.facet_point_offset[nf];
            TEST_TRUE(memcmp(again.position, m.position,
                             3 * n * sizeof(double)) == 0);
            TEST_TRUE(memcmp(again.volume, m.volume, n * sizeof(double)) == 0);
            TEST_TRUE(memcmp(again.facet_owner, m.facet_owner,
                             nf * sizeof(int)) == 0);
            TEST_TRUE(memcmp(again.facet_point, m.facet_point,
                             3 * points * sizeof(double)) == 0);
        }
        gsn_model_free(&again);
    } else {
        TEST_TRUE(0);
    }
    gsn_model_free(&m);
}

/* Fast path against brute force: cells cut by the planes of a convex
 * boundary patch equal the same cells intersected tetrahedron by
 * tetrahedron, in volume, centroid and boundary area per surface. */
static void test_against_tetrahedra(const char *case_path)
{
    struct gsn_model fast, brute;
    struct gsn_case c;
    if (run_pre_with(case_path, 0, 0, &fast, &c) != GSN_OK ||
        run_pre_with(case_path, 0, 1, &brute, &c) != GSN_OK) {
        TEST_TRUE(0);
        return;
    }
    TEST_INT(fast.particle_count, brute.particle_count);
    if (fast.particle_count == brute.particle_count) {
        int n = fast.particle_count, ns = fast.surface_count;
        double volume = 0.0, centroid = 0.0, area = 0.0;
        double *a = calloc(2 * (size_t)n * (size_t)ns + 1, sizeof(double));
        for (int p = 0; p < n; ++p) {
            double h = cbrt(brute.volume[p]);
            volume = fmax(volume, fabs(fast.volume[p] - brute.volume[p]) /
                                      brute.volume[p]);
            for (int k = 0; k < 3; ++k)
                centroid = fmax(centroid, fabs(fast.centroid[3 * p + k] -
                                               brute.centroid[3 * p + k]) /
                                              h);
        }
        const struct gsn_model *models[2] = {&fast, &brute};
        for (int which = 0; which < 2; ++which)
            for (int f = 0; f < models[which]->facet_count; ++f) {
                int s = models[which]->facet_surface[f];
                if (s >= 0)
                    a[((size_t)which * (size_t)n +
                       (size_t)models[which]->facet_owner[f]) *
                          (size_t)ns +
                      (size_t)s] += models[which]->facet_area[f];
            }
        for (size_t e = 0; e < (size_t)n * (size_t)ns; ++e) {
            size_t p = e / (size_t)ns;
            double scale = cbrt(brute.volume[p]) * cbrt(brute.volume[p]);
            area =
                fmax(area, fabs(a[e] - a[(size_t)n * (size_t)ns + e]) / scale);
        }
        free(a);
        /* both are the same cell up to the clipping tolerance (1e-14 of
         * the diagonal) and rounding over different cuts */
        TEST_TRUE(volume <= 1e-11);
        TEST_TRUE(centroid <= 1e-11);
        TEST_TRUE(area <= 1e-11);
        printf("  against the tetrahedra: volume %.1e centroid %.1e boundary "
               "area %.1e; facets %d vs %d\n",
               volume, centroid, area, fast.facet_count, brute.facet_count);
    }
    gsn_model_free(&fast);
    gsn_model_free(&brute);
}

int main(void)
{
    test_begin();
    snprintf(folder, sizeof folder, "/tmp/geoscni_test_pre_XXXXXX");
    if (!mkdtemp(folder)) {
        perror("mkdtemp");
        return 1;
    }
    test_box();
    test_lshape();
    test_cylinder();
    test_slope("../../geometries/slope_I_coarse.yaml", 10.0,
               (const double[3]){6, 0, 10}, (const double[3]){9, 10, 10});
    test_slope("../../geometries/slope_II_coarse.yaml", 12.0,
               (const double[3]){6, 4.5, 10}, (const double[3]){9, 7.5, 10});
    test_against_tetrahedra("../../geometries/slope_II_coarse.yaml");
    test_against_tetrahedra("../../geometries/cylinder.yaml");
    char path[128];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    unlink(path);
    rmdir(folder);
    return test_end("test_pre_gmsh");
}
