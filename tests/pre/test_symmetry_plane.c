/* Symmetry planes on a model (docs/economy.md, "Symmetry"): on a box of
 * jittered lattice particles (gsn_pre_domains_box tags the faces xmin ..
 * zmax), every face is found to be the plane normal to its axis at its
 * coordinate, a symmetry entry on it fixes exactly that component, and a
 * surface whose particles leave the plane is refused with the case's line. */
#include "geoscni/error.h"
#include "geoscni/model.h"
#include "geoscni/pre.h"
#include "testing.h"

#include <string.h>

static const double lo[3] = {0.0, -1.0, 0.5};
static const double hi[3] = {1.0, 2.0, 1.5};
enum { N = 5 }; /* per direction */

int main(void)
{
    test_begin();
    double x[3 * N * N * N];
    int n = 0;
    unsigned state = 12345u;
    for (int k = 0; k < N; ++k)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const int index[3] = {i, j, k};
                for (int c = 0; c < 3; ++c) {
                    double t = (double)index[c] / (N - 1);
                    state = state * 1664525u + 1013904223u;
                    /* jitter interior coordinates only: faces stay flat */
                    if (index[c] > 0 && index[c] < N - 1)
                        t += 0.05 * ((double)(state >> 8) / 16777216.0 - 0.5);
                    x[3 * n + c] = lo[c] + t * (hi[c] - lo[c]);
                }
                ++n;
            }
    struct gsn_model m;
    memset(&m, 0, sizeof m);
    TEST_INT(gsn_pre_domains_box(x, n, lo, hi, 1, &m), GSN_OK);
    for (int s = 0; s < 6; ++s) {
        int axis = -1;
        double offset = 0.0;
        TEST_INT(gsn_model_surface_plane(&m, s, &axis, &offset), GSN_OK);
        TEST_INT(axis, s / 2);
        /* the faces' particles are placed at lo and hi exactly */
        TEST_NEAR(offset, s % 2 ? hi[s / 2] : lo[s / 2], 0.0);
    }

    static struct gsn_case c;
    memset(&c, 0, sizeof c);
    snprintf(c.path, sizeof c.path, "symmetry.yaml");
    c.boundary_count = 2;
    snprintf(c.boundaries[0].name, GSN_NAME_SIZE, "%s", m.surface_name[3]);
    c.boundaries[0].symmetry = 1;
    c.boundaries[0].line = 7;
    snprintf(c.boundaries[1].name, GSN_NAME_SIZE, "%s", m.surface_name[4]);
    c.boundaries[1].fixed[0] = 1;
    TEST_INT(gsn_case_resolve_symmetry(&c, &m), GSN_OK);
    TEST_INT(c.boundaries[0].fixed[0], 0);
    TEST_INT(c.boundaries[0].fixed[1], 1); /* ymax: normal y */
    TEST_INT(c.boundaries[0].fixed[2], 0);
    TEST_INT(c.boundaries[1].fixed[0] + c.boundaries[1].fixed[1] +
                 c.boundaries[1].fixed[2],
             1); /* not a symmetry entry: untouched */

    /* an interior particle tagged ymax: the surface leaves its plane */
    int interior = -1;
    for (int p = 0; p < m.particle_count && interior < 0; ++p)
        if (m.particle_surface_offset[p + 1] == m.particle_surface_offset[p])
            interior = p;
    TEST_TRUE(interior >= 0);
    int ymax_particle = -1;
    for (int p = 0; p < m.particle_count && ymax_particle < 0; ++p)
        if (gsn_model_particle_on_surface(&m, p, 3))
            ymax_particle = p;
    /* the tagged particle moved to an interior position */
    double saved[3];
    memcpy(saved, &m.position[3 * ymax_particle], sizeof saved);
    memcpy(&m.position[3 * ymax_particle], &m.position[3 * interior],
           sizeof saved);
    int axis = -1;
    double offset = 0.0;
    TEST_INT(gsn_model_surface_plane(&m, 3, &axis, &offset), GSN_ERR_INPUT);
    gsn_error_clear();
    c.boundaries[0].fixed[1] = 0;
    TEST_INT(gsn_case_resolve_symmetry(&c, &m), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "symmetry.yaml:7:") != NULL);
    gsn_error_clear();
    memcpy(&m.position[3 * ymax_particle], saved, sizeof saved);
    gsn_model_free(&m);
    return test_end("test_symmetry_plane");
}
