/* Where plain SCNI fails and MSCNI and NSNI hold (docs/failure.md):
 * checkerboard modes in a long free-vibration run on a regular lattice.
 *
 * An 8^3 lattice block (1 m, rollers on x = 0, y = 0, z = 0, the other
 * faces free, elastic paper soil) is kicked with a small checkerboard
 * velocity (a random combination of the 21 checkerboard patterns of the
 * lattice: wave vectors in {0, pi/h}^3 \ {0}, 3 polarisations) and runs
 * STEPS steps at 0.8 of its stable step, about 30 periods of its lowest
 * mode. On a regular lattice plain SCNI leaves the checkerboards nearly as
 * soft as the longest waves (REFERENCES.md, "Zero-energy and soft modes";
 * test_stability), so the kick stays in the body as a large, slowly
 * oscillating checkerboard displacement: nothing restores it. MSCNI gives
 * the checkerboards a stiffness (test_stability: 5 to 46 times more), so
 * the same kick leaves a checkerboard a fraction as large, and the
 * displacement goes into smooth modes. (A linear undamped run conserves
 * energy: what differs is where the displacement goes, not how much
 * energy there is; in a softening run the soft modes are where the
 * deformation localizes, see docs/solver.md, "Stabilization".)
 *
 * Measured over the second half of the run: the share of sum_J |u(X_J)|^2
 * lying in the span of the 21 checkerboard patterns (orthonormal on the
 * lattice), and the RMS of that checkerboard displacement.
 *
 * Part 2, where checkerboards grow: the same lattice with the paper's soil
 * (damage and Drucker-Prager), bottom fixed, pressed from the top at
 * 0.1 m/s for 1 s (0.1 m, 10% of its height), and the same with damage
 * and plasticity off. The local checkerboard content of the displacement
 * is measured with a filter that passes the 21 checkerboards unchanged and
 * removes every linear field: at each interior particle, along each axis a
 * checkerboard varies on, the second difference (-1, 2, -1)/4, along the
 * others the average (1, 2, 1)/4; its norm over the interior particles is
 * divided by the norm of u over all particles. Softening makes plain
 * SCNI's checkerboards grow (several times the elastic run's content);
 * with MSCNI the content stays near its elastic level. */
#include "geoscni/case.h"
#include "solver_fixtures.h"
#include "testing.h"

enum { SIDE = 8, STEPS = 2000 };
/* Part 2: pressed for 1 s (at 0.1 m/s, cases/block_pressed_soil.yaml). */
static const double PRESS_TIME = 1.0;
static const int COUNT[3] = {SIDE, SIDE, SIDE};
static const double LO[3] = {0, 0, 0}, HI[3] = {1, 1, 1};
static const double SPACING = 1.0 / (SIDE - 1);

struct result {
    double share;     /* checkerboard share of |u|^2, second half */
    double amplitude; /* RMS checkerboard displacement, second half, m */
    double drift;     /* energy balance drift / initial kinetic energy */
    double drift_early, drift_late; /* the same over each half of the run */
};

/* +-1: the sign of checkerboard w (bits: x, y, z) at lattice point ijk. */
static double pattern(int w, const int ijk[3])
{
    int parity =
        ((w & 1) * ijk[0] + ((w >> 1) & 1) * ijk[1] + ((w >> 2) & 1) * ijk[2]) &
        1;
    return parity ? -1.0 : 1.0;
}

static void lattice_index(const double *x, int ijk[3])
{
    for (int d = 0; d < 3; ++d)
        ijk[d] = (int)lround(x[d] / SPACING);
}

/* Squared norm of the projection of u on the 21 checkerboards, and of u. */
static void checkerboard_norms(const double *x, const double *u, int n,
                               double *board, double *total)
{
    double projection[8][3] = {{0}};
    *total = 0.0;
    for (int p = 0; p < n; ++p) {
        int ijk[3];
        lattice_index(&x[3 * p], ijk);
        for (int w = 1; w < 8; ++w)
            for (int c = 0; c < 3; ++c)
                projection[w][c] += pattern(w, ijk) * u[3 * p + c];
        for (int c = 0; c < 3; ++c)
            *total += u[3 * p + c] * u[3 * p + c];
    }
    *board = 0.0;
    for (int w = 1; w < 8; ++w)
        for (int c = 0; c < 3; ++c)
            *board += projection[w][c] * projection[w][c] / n;
}

static struct result run(struct gsn_case *c, enum gsn_stabilization stab)
{
    struct result r = {0, 0, 0, 0, 0};
    c->stabilization = stab;
    struct fixture_solver f;
    TEST_INT(fixture_solver_create(c, COUNT, LO, HI, 0.0, 1e-3, &f), GSN_OK);
    struct gsn_explicit *e = f.loop;
    const double *x = f.model.position;
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    e->dt = 0.8 * stable;
    /* The kick: the same random weights of the 21 patterns for both. */
    double weight[8][3];
    unsigned state = 99u;
    for (int w = 0; w < 8; ++w)
        for (int k = 0; k < 3; ++k) {
            state = state * 1664525u + 1013904223u;
            weight[w][k] = 1e-3 * ((double)(state >> 8) / 16777216.0 - 0.5);
        }
    for (int p = 0; p < e->particle_count; ++p) {
        int ijk[3];
        lattice_index(&x[3 * p], ijk);
        for (int k = 0; k < 3; ++k) {
            e->velocity[3 * p + k] = 0.0;
            for (int w = 1; w < 8; ++w)
                e->velocity[3 * p + k] += weight[w][k] * pattern(w, ijk);
        }
    }
    double *u = malloc(3 * (size_t)e->particle_count * sizeof *u);
    double board_sum = 0.0, total_sum = 0.0, balance0 = 0.0, kinetic1 = 0.0;
    int samples = 0;
    for (int step = 0; step < STEPS; ++step) {
        TEST_INT(gsn_explicit_step(e), GSN_OK);
        double balance =
            e->kinetic_energy + e->internal_energy - e->external_work;
        if (step == 0) { /* after the first step's constraint correction */
            balance0 = balance;
            kinetic1 = e->kinetic_energy;
        }
        r.drift = fmax(r.drift, fabs(balance - balance0) / kinetic1);
        if (step < STEPS / 2)
            r.drift_early = r.drift;
        else
            r.drift_late =
                fmax(r.drift_late, fabs(balance - balance0) / kinetic1);
        if (step < STEPS / 2)
            continue;
        gsn_explicit_particle_field(e, e->displacement, u);
        double board, total;
        checkerboard_norms(x, u, e->particle_count, &board, &total);
        board_sum += board;
        total_sum += total;
        samples++;
    }
    r.share = board_sum / total_sum;
    r.amplitude = sqrt(board_sum / samples / e->particle_count);
    free(u);
    fixture_solver_destroy(&f);
    return r;
}

/* Norm of the checkerboard filter of u over the interior particles over
 * the norm of u (part 2). */
static double local_checkerboard(const double *x, const double *u, int n)
{
    int at[SIDE * SIDE * SIDE];
    for (int p = 0; p < n; ++p) {
        int ijk[3];
        lattice_index(&x[3 * p], ijk);
        at[(ijk[2] * SIDE + ijk[1]) * SIDE + ijk[0]] = p;
    }
    const double varies[3] = {-0.25, 0.5, -0.25}, even[3] = {0.25, 0.5, 0.25};
    double board = 0.0, total = 0.0;
    for (int p = 0; p < 3 * n; ++p)
        total += u[p] * u[p];
    for (int k = 1; k < SIDE - 1; ++k)
        for (int j = 1; j < SIDE - 1; ++j)
            for (int i = 1; i < SIDE - 1; ++i)
                for (int w = 1; w < 8; ++w)
                    for (int c = 0; c < 3; ++c) {
                        double v = 0.0;
                        for (int o = 0; o < 27; ++o) {
                            int d[3] = {o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1};
                            double weight = 1.0;
                            for (int a = 0; a < 3; ++a)
                                weight *= (w >> a) & 1 ? varies[d[a] + 1]
                                                       : even[d[a] + 1];
                            int q = at[((k + d[2]) * SIDE + j + d[1]) * SIDE +
                                       i + d[0]];
                            v += weight * u[3 * q + c];
                        }
                        board += v * v;
                    }
    return sqrt(board / total);
}

/* Part 2: the pressed block in `extra` more steps than 0.8 of the stable
 * step gives; returns the local checkerboard content at the end (0.1 m),
 * and in half that at half time (0.05 m). */
static double pressed(struct gsn_case *c, enum gsn_stabilization stab, int soil,
                      int extra, double *half)
{
    c->stabilization = stab;
    c->material.has_damage = c->material.has_plasticity = soil;
    struct fixture_solver f;
    TEST_INT(fixture_solver_create(c, COUNT, LO, HI, 0.0, 1e-3, &f), GSN_OK);
    struct gsn_explicit *e = f.loop;
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    long steps = (long)ceil(PRESS_TIME / (0.8 * stable)) + extra;
    e->dt = PRESS_TIME / (double)steps;
    double *u = malloc(3 * (size_t)e->particle_count * sizeof *u);
    for (long step = 0; step < steps; ++step) {
        int rc = gsn_explicit_step(e);
        if (rc != GSN_OK) {
            gsn_error_print(stderr);
            TEST_INT(rc, GSN_OK);
            break;
        }
        if (step + 1 == steps / 2) {
            gsn_explicit_particle_field(e, e->displacement, u);
            *half = local_checkerboard(f.model.position, u, e->particle_count);
        }
    }
    gsn_explicit_particle_field(e, e->displacement, u);
    double content = local_checkerboard(f.model.position, u, e->particle_count);
    free(u);
    fixture_solver_destroy(&f);
    return content;
}

/* The median over step counts (0.8 of the stable step, then one step more
 * each): three for the elastic runs; seven with the soil, where softening
 * makes the run chaotic and the content moves by 10 to 15% from one step
 * count to the next, so that a median of three hangs on the round-off:
 * MSCNI at 1208 to 1214 steps gave 0.0401, 0.0315, 0.0389, 0.0301,
 * 0.0301, 0.0355, 0.0313 with the boundary matrices ordered by nested
 * dissection (constraint.c) and 0.0363, 0.0333, 0.0335, 0.0322, 0.0309,
 * 0.0326, 0.0302 with AMD's order before (the same values to round-off):
 * SCNI / MSCNI 2.42 and 2.81 from three, 2.98 and 2.89 from seven. */
static double pressed_median(struct gsn_case *c, enum gsn_stabilization stab,
                             int soil, double *half)
{
    enum { MOST = 7 };
    const int counts = soil ? MOST : 3;
    double content[MOST], halves[MOST];
    for (int extra = 0; extra < counts; ++extra)
        content[extra] = pressed(c, stab, soil, extra, &halves[extra]);
    *half = test_median(halves, counts);
    return test_median(content, counts);
}

int main(void)
{
    test_begin();
    struct gsn_case c;
    TEST_INT(gsn_case_load("cases/block_rollers.yaml", &c), GSN_OK);
    struct result scni = run(&c, GSN_STABILIZATION_NONE);
    struct result mscni = run(&c, GSN_STABILIZATION_MSCNI);
    struct result nsni = run(&c, GSN_STABILIZATION_NSNI);
    const char *names[3] = {"SCNI", "SCNI + MSCNI", "SCNI + NSNI"};
    const struct result *r[3] = {&scni, &mscni, &nsni};
    for (int m = 0; m < 3; ++m)
        printf("%-12s: second half of %d steps: checkerboard share of |u|^2 "
               "%.3f, RMS checkerboard displacement %.3g m; energy drift "
               "%.1e of the kinetic energy of the kick (%.1e in the first "
               "half, %.1e in the second)\n",
               names[m], STEPS, r[m]->share, r[m]->amplitude, r[m]->drift,
               r[m]->drift_early, r[m]->drift_late);
    printf("checkerboard displacement, SCNI / MSCNI: %.2f, SCNI / NSNI: "
           "%.2f\n",
           scni.amplitude / mscni.amplitude, scni.amplitude / nsni.amplitude);
    /* Thresholds about halfway (in ratio) between the two methods'
     * measured values (docs/failure.md): the test fails if MSCNI stops
     * lifting the checkerboards or if plain SCNI stops showing them. */
    TEST_TRUE(scni.share > 0.15);
    TEST_TRUE(mscni.share < 0.10);
    TEST_TRUE(scni.amplitude > 2.5 * mscni.amplitude);
    /* Both runs stay stable: the energy balance wanders by 2e-2 (SCNI) and
     * 7e-2 (MSCNI) of the kick's kinetic energy, because the kick puts its
     * energy into the stiffest modes, where the energy of central
     * differences is off by O((w dt)^2) with w dt up to 1.6; an unstable
     * run grows without bound. */
    TEST_TRUE(scni.drift < 0.2 && mscni.drift < 0.2);
    /* NSNI lifts them as MSCNI does (the same thresholds), and further:
     * to the top of the spectrum (test_stability), where at 0.8 of the
     * stable step w dt = 1.6 and the energy of central differences
     * (1/2 v^T M v + U) differs from the conserved one by up to
     * (w dt)^2/4 / (1 - (w dt)^2/4) = 1.8 of it: the kick's energy swings
     * by that much without any growth. Stability is that the swing of the
     * second half stays that of the first. */
    TEST_TRUE(nsni.share < 0.10);
    TEST_TRUE(scni.amplitude > 2.5 * nsni.amplitude);
    TEST_TRUE(nsni.drift < 1.8);
    TEST_TRUE(nsni.drift_late <= 1.2 * nsni.drift_early);

    /* Part 2. */
    TEST_INT(gsn_case_load("cases/block_pressed_soil.yaml", &c), GSN_OK);
    double half[6], content[6];
    const char *labels[6] = {"SCNI, elastic",         "SCNI, soil",
                             "SCNI + MSCNI, elastic", "SCNI + MSCNI, soil",
                             "SCNI + NSNI, elastic",  "SCNI + NSNI, soil"};
    const enum gsn_stabilization kind[3] = {GSN_STABILIZATION_NONE,
                                            GSN_STABILIZATION_MSCNI,
                                            GSN_STABILIZATION_NSNI};
    for (int k = 0; k < 6; ++k) {
        content[k] = pressed_median(&c, kind[k / 2], k % 2, &half[k]);
        printf("pressed block, %-21s: local checkerboard content of u "
               "%.4f at 0.05 m, %.4f at 0.1 m\n",
               labels[k], half[k], content[k]);
    }
    printf("softening multiplies it by %.2f (SCNI), %.2f (MSCNI), %.2f "
           "(NSNI); with the soil SCNI / MSCNI %.2f, SCNI / NSNI %.2f\n",
           content[1] / content[0], content[3] / content[2],
           content[5] / content[4], content[1] / content[3],
           content[1] / content[5]);
    /* Thresholds about halfway (in ratio) between measured values
     * (docs/failure.md): softening grows SCNI's checkerboards well beyond
     * the elastic run's (5.3x); MSCNI's sub-cells yield with the soil
     * (docs/solver.md, "Stabilization"), so its checkerboards grow too, but
     * about half as much (2.9x; 1.5x when the sub-cells stayed
     * elastic, at the price of a strip-footing limit load 20% too high),
     * and SCNI ends with several times MSCNI's (3.0x; medians of seven
     * step counts, pressed_median). */
    TEST_TRUE(content[1] > 2.5 * content[0]);
    TEST_TRUE(content[3] / content[2] < 0.7 * (content[1] / content[0]));
    TEST_TRUE(content[1] > 2.5 * content[3]);
    /* NSNI (its shear part yields, its bulk part stays elastic) holds them
     * as well (2.2x, SCNI / NSNI 4.9); with the whole rate yielding its
     * face particles collapsed (det F 0.03) before 0.1 m */
    TEST_TRUE(content[5] / content[4] < 0.7 * (content[1] / content[0]));
    TEST_TRUE(content[1] > 2.5 * content[5]);
    return test_end("test_checkerboard");
}
