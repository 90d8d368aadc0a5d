/* Voronoi cells clipped to a box (issue 3, points 2-3 and "Tests"): the
 * checks of point 3 on an exact regular lattice (every point cospherical
 * with its neighbours), the same lattice jittered by 1e-9, and random
 * points; exact cell volumes on the lattice; degree-2 facet quadrature;
 * independence of the thread count; negative controls. */
#include "geoscni/error.h"
#include "geoscni/pre.h"
#include "testing.h"

#include <stdint.h>
#include <string.h>

/* Checks within these: the clipping is exact up to rounding, and the sums
 * over ~20 facets of a cell lose a few ulps, far below the 1e-10 of issue 3
 * point 3; asking for 1e-12 leaves a margin of 100 and still catches any
 * geometric bug, which shows up at 1e-9 (jitter) or worse. */
#define TIGHT 1e-12

static const double lo[3] = {0.0, 0.0, 0.0};
static const double hi[3] = {1.0, 2.0, 1.5};
enum { NX = 5, NY = 9, NZ = 7 }; /* spacing 0.25 */

static uint64_t rng_state = 88172645463325252ull;
static double uniform(void) /* xorshift64*, in [0, 1) */
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}

static int lattice(double *x, double jitter)
{
    int n = 0;
    const int count[3] = {NX, NY, NZ};
    for (int k = 0; k < NZ; ++k)
        for (int j = 0; j < NY; ++j)
            for (int i = 0; i < NX; ++i) {
                const int index[3] = {i, j, k};
                for (int c = 0; c < 3; ++c) {
                    double h = (hi[c] - lo[c]) / (count[c] - 1);
                    double v = lo[c] + index[c] * h;
                    /* particles on a face stay on it */
                    if (index[c] > 0 && index[c] < count[c] - 1)
                        v += jitter * h * (2.0 * uniform() - 1.0);
                    x[3 * n + c] = v;
                }
                ++n;
            }
    return n;
}

static void expect_checks_pass(const struct gsn_cells_report *r)
{
    TEST_TRUE(r->volume_error <= TIGHT);
    TEST_TRUE(r->closure_error <= TIGHT);
    TEST_TRUE(r->moment_error <= TIGHT);
    TEST_TRUE(r->twin_error <= TIGHT);
    TEST_TRUE(r->area_error <= TIGHT);
    printf("  volume %.2e closure %.2e moment %.2e twin %.2e area %.2e\n",
           r->volume_error, r->closure_error, r->moment_error, r->twin_error,
           r->area_error);
}

static void test_lattice(int facet_points)
{
    double x[3 * NX * NY * NZ];
    int n = lattice(x, 0.0);
    struct gsn_model m;
    struct gsn_cells_report r;
    int rc = gsn_pre_domains_box_ex(x, n, lo, hi, facet_points, 0, &m, &r);
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return;
    }
    expect_checks_pass(&r);
    double h[3] = {0.25, 0.25, 0.25};
    /* exact cells: h^3 halved on each face the particle lies on; the
     * clipped vertices are sums of exact binary fractions, so rounding
     * stays at a few ulps */
    for (int p = 0; p < n; ++p) {
        double expected = h[0] * h[1] * h[2];
        for (int c = 0; c < 3; ++c)
            if (x[3 * p + c] == lo[c] || x[3 * p + c] == hi[c])
                expected *= 0.5;
        TEST_REL(m.volume[p], expected, 1e-14);
        int surfaces =
            m.particle_surface_offset[p + 1] - m.particle_surface_offset[p];
        int on = 0;
        for (int c = 0; c < 3; ++c)
            on += (x[3 * p + c] == lo[c]) + (x[3 * p + c] == hi[c]);
        TEST_INT(surfaces, on);
    }
    /* touching diagonal neighbours give no facet: only the axis ones */
    int interior = (NX - 1) * NY * NZ + NX * (NY - 1) * NZ + NX * NY * (NZ - 1);
    int boundary = 2 * (NY * NZ + NX * NZ + NX * NY);
    TEST_INT(m.facet_count, interior + boundary);
    /* the Delaunay tetrahedra of the lattice fill the box, and their hull
     * faces carry the box faces: each face's triangles add up to its area
     * (the body the solver follows through reference updates) */
    TEST_TRUE(m.tetrahedron_count > 0);
    double volume = 0.0, area[6] = {0, 0, 0, 0, 0, 0};
    for (int t = 0; t < m.tetrahedron_count; ++t) {
        volume += gsn_body_tetrahedron_volume(m.position, &m.tetrahedra[4 * t]);
        for (int k = 0; k < 4; ++k) {
            int face = m.tetrahedron_face[4 * t + k];
            TEST_TRUE(face >= GSN_MODEL_FACE_INTERNAL && face < 6);
            if (face < 0)
                continue;
            const int *o = gsn_cells_tetrahedron_face[k];
            const int *v = &m.tetrahedra[4 * t];
            area[face] += gsn_cells_triangle_area(&m.position[3 * v[o[0]]],
                                                  &m.position[3 * v[o[1]]],
                                                  &m.position[3 * v[o[2]]]);
        }
    }
    /* a sum of about 10^3 volumes, each rounded to 1e-16 */
    TEST_REL(volume, (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]),
             1e-13);
    for (int f = 0; f < 6; ++f)
        TEST_REL(area[f], m.surface_area[f], 1e-13);
    TEST_INT(m.surface_count, 6);
    TEST_TRUE(strcmp(m.surface_name[0], "xmin") == 0);
    TEST_TRUE(strcmp(m.surface_name[5], "zmax") == 0);
    gsn_model_free(&m);
}

/* Degree 2: the three-point rule integrates y^2 z over the face x = 0
 * exactly, cell by cell, summed: (2^3 / 3) (1.5^2 / 2). */
static void test_quadrature_degree(const double *x, int n)
{
    struct gsn_model m;
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 3, &m), GSN_OK);
    double sum = 0.0;
    for (int f = 0; f < m.facet_count; ++f) {
        if (m.facet_surface[f] != 0)
            continue;
        for (int q = m.facet_point_offset[f]; q < m.facet_point_offset[f + 1];
             ++q) {
            const double *p = &m.facet_point[3 * q];
            sum += m.facet_weight[q] * p[1] * p[1] * p[2];
        }
    }
    /* exact up to rounding of the sums over all the face's facets */
    TEST_REL(sum, 8.0 / 3.0 * 1.125, 1e-13);
    gsn_model_free(&m);
}

static void test_jittered(int facet_points)
{
    double x[3 * NX * NY * NZ];
    int n = lattice(x, 1e-9);
    struct gsn_model m;
    struct gsn_cells_report r;
    int rc = gsn_pre_domains_box_ex(x, n, lo, hi, facet_points, 0, &m, &r);
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK) {
        gsn_error_print(stderr);
        return;
    }
    expect_checks_pass(&r);
    /* a cell moves by 1e-9 h at most: its volume by about 1e-9 h^3 */
    double h3 = 0.25 * 0.25 * 0.25;
    for (int p = 0; p < n; ++p) {
        double expected = h3;
        for (int c = 0; c < 3; ++c)
            if (x[3 * p + c] == lo[c] || x[3 * p + c] == hi[c])
                expected *= 0.5;
        TEST_NEAR(m.volume[p], expected, 1e-8 * h3);
    }
    gsn_model_free(&m);
    test_quadrature_degree(x, n);
}

static void test_random_and_threads(void)
{
    enum { N = 2000 };
    static double x[3 * N];
    for (int p = 0; p < N; ++p)
        for (int c = 0; c < 3; ++c)
            x[3 * p + c] = lo[c] + (hi[c] - lo[c]) * uniform();
    struct gsn_model a, b;
    struct gsn_cells_report r;
    TEST_INT(gsn_pre_domains_box_ex(x, N, lo, hi, 3, 1, &a, &r), GSN_OK);
    expect_checks_pass(&r);
    TEST_INT(gsn_pre_domains_box_ex(x, N, lo, hi, 3, 2, &b, NULL), GSN_OK);
    /* the same bits whatever the thread count */
    TEST_INT(a.facet_count, b.facet_count);
    if (a.facet_count == b.facet_count) {
        int points = a.facet_point_offset[a.facet_count];
        TEST_TRUE(memcmp(a.volume, b.volume, sizeof(double) * N) == 0);
        TEST_TRUE(memcmp(a.facet_owner, b.facet_owner,
                         sizeof(int) * (size_t)a.facet_count) == 0);
        TEST_TRUE(memcmp(a.facet_point, b.facet_point,
                         sizeof(double) * 3 * (size_t)points) == 0);
    }
    gsn_model_free(&b);

    /* negative control: a facet's normal flipped is caught by the checks */
    int f = 0;
    while (a.facet_neighbour[f] < 0)
        ++f;
    for (int c = 0; c < 3; ++c)
        a.facet_normal[3 * f + c] = -a.facet_normal[3 * f + c];
    TEST_INT(gsn_cells_check(&a, 3.0, NULL), GSN_ERR_INPUT);
    for (int c = 0; c < 3; ++c)
        a.facet_normal[3 * f + c] = -a.facet_normal[3 * f + c];
    TEST_INT(gsn_cells_check(&a, 3.0, NULL), GSN_OK);
    /* a quadrature point moved along the facet breaks the moment check */
    a.facet_point[3 * a.facet_point_offset[f]] += 1e-6;
    TEST_INT(gsn_cells_check(&a, 3.0, NULL), GSN_ERR_INPUT);
    gsn_model_free(&a);
}

static void test_bad_input(void)
{
    double x[3 * NX * NY * NZ];
    int n = lattice(x, 0.0);
    struct gsn_model m;
    /* a duplicate particle is named by index and position */
    memcpy(&x[3 * 7], &x[3 * 30], sizeof(double[3]));
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 1, &m), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "duplicate") != NULL);
    TEST_TRUE(m.facet_count == 0 && m.volume == NULL);
    /* nearly duplicate */
    n = lattice(x, 0.0);
    x[3 * 31] = x[3 * 32] + 1e-15;
    x[3 * 31 + 1] = x[3 * 32 + 1];
    x[3 * 31 + 2] = x[3 * 32 + 2];
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 1, &m), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "duplicate") != NULL);
    /* outside the box */
    n = lattice(x, 0.0);
    x[3 * 10] = 1.5;
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 1, &m), GSN_ERR_INPUT);
    n = lattice(x, 0.0);
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 2, &m), GSN_ERR_INPUT);
    gsn_error_clear();
}

/* Point sets of dimension 0, 1 and 2 (CGAL's triangulation has lower
 * dimension): one point fills the box; points on a line along x cut it into
 * slabs; a planar grid into columns. */
static void test_low_dimension(void)
{
    const double unit_lo[3] = {0, 0, 0}, unit_hi[3] = {1, 1, 1};
    struct gsn_model m;
    double one[3] = {0.3, 0.4, 0.5};
    TEST_INT(gsn_pre_domains_box(one, 1, unit_lo, unit_hi, 1, &m), GSN_OK);
    TEST_INT(m.facet_count, 6);
    TEST_REL(m.volume[0], 1.0, 1e-15);
    gsn_model_free(&m);
    double line[15];
    for (int i = 0; i < 5; ++i) {
        line[3 * i] = 0.1 + 0.2 * i;
        line[3 * i + 1] = line[3 * i + 2] = 0.5;
    }
    TEST_INT(gsn_pre_domains_box(line, 5, unit_lo, unit_hi, 3, &m), GSN_OK);
    for (int i = 0; i < 5; ++i)
        TEST_REL(m.volume[i], 0.2, 1e-14); /* rounding of 0.1 + 0.2 i */
    gsn_model_free(&m);
    double plane[75];
    for (int i = 0; i < 25; ++i) {
        plane[3 * i] = 0.1 + 0.2 * (i % 5);
        plane[3 * i + 1] = 0.1 + 0.2 * (i / 5);
        plane[3 * i + 2] = 0.5;
    }
    TEST_INT(gsn_pre_domains_box(plane, 25, unit_lo, unit_hi, 1, &m), GSN_OK);
    for (int i = 0; i < 25; ++i)
        TEST_REL(m.volume[i], 0.04, 1e-14);
    /* columns only: 40 interior faces and 4 x 5 on the sides, 50 on the
     * top and bottom */
    TEST_INT(m.facet_count, 40 + 20 + 50);
    gsn_model_free(&m);
}

int main(void)
{
    test_begin();
    test_lattice(1);
    test_lattice(3);
    test_jittered(1);
    test_jittered(3);
    test_random_and_threads();
    test_bad_input();
    test_low_dimension();
    return test_end("test_domains_box");
}
