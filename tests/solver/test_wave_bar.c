/* Uniaxial-strain wave in a 10 m bar with rollers (REFERENCES.md, "Elastic
 * dynamics"): a step pressure p0 = 10 kPa at x = L sends a front at
 * c_p = sqrt((K + 4 mu / 3) / rho) = 145.13 m/s, behind which the particles
 * move at p0 / (rho c_p) = 0.036650 m/s. Runs geoscni solve on a lattice bar
 * and measures both from the frames at t = 0.02 s and 0.05 s. */
#include "geoscni/case.h"
#include "geoscni/results.h"
#include "geoscni/solver.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <string.h>

enum { NX = 81 };
static const double LENGTH = 10.0, P0 = 1.0e4;

/* Mean x velocity of the particles at each lattice station along x. */
static void velocity_profile(const struct gsn_model *m,
                             const struct gsn_frame *f, double profile[NX])
{
    int count[NX] = {0};
    memset(profile, 0, sizeof(double) * NX);
    for (int j = 0; j < m->particle_count; ++j) {
        int station = (int)lround(m->position[3 * j] / (LENGTH / (NX - 1)));
        profile[station] += f->field[GSN_FRAME_VELOCITY][3 * j];
        count[station]++;
    }
    for (int s = 0; s < NX; ++s)
        profile[s] /= count[s];
}

/* Where |v| first reaches half the plateau, walking from x = 0 to x = L. */
static double front_position(const double profile[NX], double plateau)
{
    double h = LENGTH / (NX - 1);
    for (int s = 1; s < NX; ++s) {
        double a = fabs(profile[s - 1]), b = fabs(profile[s]);
        if (a < 0.5 * plateau && b >= 0.5 * plateau)
            return h * (s - 1 + (0.5 * plateau - a) / (b - a));
    }
    return -1.0;
}

int main(void)
{
    test_begin();
    struct gsn_case c;
    TEST_INT(gsn_case_load("cases/bar_wave.yaml", &c), GSN_OK);
    char folder[] = "/tmp/geoscni-test-wave-XXXXXX";
    int count[3] = {NX, 5, 5};
    double lo[3] = {0, 0, 0}, hi[3] = {LENGTH, 0.5, 0.5};
    TEST_INT(fixture_solve_box(&c, folder, count, lo, hi, 0.0), GSN_OK);

    char path[4096];
    struct gsn_model m;
    snprintf(path, sizeof path, "%s/model.h5", folder);
    TEST_INT(gsn_model_read(path, &m), GSN_OK);
    snprintf(path, sizeof path, "%s/results.h5", folder);
    hid_t file = H5I_INVALID_HID;
    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file), GSN_OK);
    struct gsn_frame f;
    TEST_INT(gsn_frame_allocate(&f, m.particle_count), GSN_OK);

    double c_p = sqrt((27.4e6 + 4.0 * 9.15e6 / 3.0) / 1880.0);
    double v0 = P0 / (1880.0 * c_p);
    double profile[NX], front[2], times[2];
    int frames[2] = {2, 5};
    for (int k = 0; k < 2; ++k) {
        TEST_INT(gsn_results_frame_read(file, frames[k], &f), GSN_OK);
        times[k] = f.time;
        velocity_profile(&m, &f, profile);
        front[k] = front_position(profile, v0);
        printf("t = %.4f s: front at x = %.4f m (exact %.4f m)\n", f.time,
               front[k], LENGTH - c_p * f.time);
    }
    double speed = (front[0] - front[1]) / (times[1] - times[0]);
    printf("front speed %.3f m/s, exact %.3f m/s, error %.2f%%\n", speed, c_p,
           100.0 * (speed / c_p - 1.0));
    /* 2%: the tolerance; the lattice's dispersion (REFERENCES.md:
     * c_num/c = sin(kh)/kh) smears the front but moves its middle at c_p. */
    TEST_REL(speed, c_p, 0.02);

    /* Plateau behind the front at t = 0.05 s: from 1 m behind the front to
     * 0.5 m before the loaded end. */
    double sum = 0.0;
    int n = 0;
    for (int s = 0; s < NX; ++s) {
        double x = s * LENGTH / (NX - 1);
        if (x > front[1] + 1.0 && x < LENGTH - 0.5) {
            sum += profile[s];
            n++;
        }
    }
    double plateau = -sum / n;
    printf("particle velocity behind the front %.6f m/s, exact %.6f m/s, "
           "error %.2f%%\n",
           plateau, v0, 100.0 * (plateau / v0 - 1.0));
    TEST_REL(plateau, v0, 0.02); /* the tolerance */

    gsn_frame_free(&f);
    gsn_h5_close(&file);
    gsn_model_free(&m);
    char command[4200];
    snprintf(command, sizeof command, "rm -rf '%s'", folder);
    TEST_INT(system(command), 0);
    return test_end("test_wave_bar");
}
