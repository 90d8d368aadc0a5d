/* Issue 16, point 2: long undamped runs keep their energy. An elastic
 * column (0.75 x 0.75 x 2 m, jittered particles) under its own weight, base
 * fixed, no damping: after gravity has risen it rings about its static
 * state, and K + W_int - W_ext (the supports are fixed: W_ext is the work
 * of gravity) must stay bounded, within 1e-3 of the work, with no trend,
 * for 2 x 10^5 steps (plain SCNI, large kinematics) and 10^5 (MSCNI, small
 * kinematics; 3 x 10^4 NSNI, large: its step is 0.6 of SCNI's here; 10^5
 * measured, 7.2e-6 J of 8.6 J). The symmetric operator of the held facets
 * and the mass-orthogonal projection (constraint.h) keep it so; under a
 * sudden load too (6 x 10^4 steps, no trend), within the minute CI
 * allows. Negative
 * control: Psi_I itself on the held facets, the non-symmetric boundary term and
 * the correction of B_c alone, the scheme of before (explicit.h,
 * legacy_boundary_term; gsn_constraints_set_boundary_only), which stopped the
 * CLI box of docs/solver.md after 35,000 steps. */
#include "geoscni/case.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <math.h>

struct energy_run {
    double largest_work; /* J */
    double early, late;  /* largest |balance| in the first and last
                            quarters of the rows, J */
    long steps;
    int finished;
};

/* sudden: gravity at full value from t = 0 (no ramp): every mode of the
 * box rings, the highest ones too. */
static struct energy_run run(enum gsn_stabilization stabilization,
                             int small_strain, int sudden, long steps,
                             int legacy, int whole_window)
{
    struct energy_run out = {0};
    struct gsn_case c;
    if (gsn_case_load("cases/long_box.yaml", &c) != GSN_OK) {
        gsn_error_print(stderr);
        TEST_TRUE(0);
        return out;
    }
    c.stabilization = stabilization;
    c.small_strain = small_strain;
    if (whole_window)
        c.kernel_window_cut = 0.0;
    if (sudden)
        c.time_ramp = 0.0;
    struct fixture_solver s;
    fixture_plain_facets = legacy;
    int rc = fixture_solver_from_gmsh(&c, 1e-4, &s);
    fixture_plain_facets = 0;
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK)
        return out;
    struct gsn_explicit *e = s.loop;
    e->legacy_boundary_term = legacy;
    if (legacy) /* and the correction of B_c alone */
        gsn_constraints_set_boundary_only(s.constraints);
    double stable = 0.0;
    TEST_INT(gsn_explicit_stable_step(e, &stable), GSN_OK);
    e->dt = 0.8 * stable;
    enum { ROWS = 400 };
    double balance[ROWS];
    long every = steps / ROWS;
    int rows = 0;
    for (long k = 1; k <= steps; ++k) {
        gsn_explicit_set_load_factor(
            e, gsn_ramp_factor(c.time_ramp, GSN_FIELD_VELOCITY,
                               gsn_explicit_time_of(e, e->step + 1)));
        if (gsn_explicit_step(e) != GSN_OK) {
            gsn_error_clear();
            break;
        }
        out.steps = k;
        double b = e->kinetic_energy + e->internal_energy - e->external_work;
        if (!isfinite(b))
            break;
        out.largest_work = fmax(out.largest_work, fabs(e->external_work));
        if (k % every == 0 && rows < ROWS)
            balance[rows++] = b;
    }
    out.finished = out.steps == steps && rows == ROWS;
    for (int r = 0; r < rows; ++r) {
        if (r < ROWS / 4)
            out.early = fmax(out.early, fabs(balance[r]));
        if (r >= 3 * ROWS / 4)
            out.late = fmax(out.late, fabs(balance[r]));
    }
    printf("%s, %s kinematics%s%s%s: %ld steps of %.3g s (t = %.4g s), work up "
           "to %.4g J, largest |K + W_int - W_ext| %.3g J in the first "
           "quarter, %.3g J in the last\n",
           stabilization == GSN_STABILIZATION_MSCNI  ? "MSCNI"
           : stabilization == GSN_STABILIZATION_NSNI ? "NSNI"
                                                     : "SCNI",
           small_strain ? "small" : "large", sudden ? ", sudden gravity" : "",
           legacy ? ", Psi_I and the old boundary term on the held facets" : "",
           whole_window ? ", the whole window" : "", out.steps, e->dt, e->time,
           out.largest_work, out.early, out.late);
    fixture_solver_destroy(&s);
    return out;
}

int main(void)
{
    test_begin();
    enum { RUNS = 4 };
    struct energy_run runs[RUNS] = {
        run(GSN_STABILIZATION_NONE, 0, 0, 200000, 0, 0),
        run(GSN_STABILIZATION_MSCNI, 1, 0, 100000, 0, 0),
        run(GSN_STABILIZATION_NSNI, 0, 0, 30000, 0, 0),
        run(GSN_STABILIZATION_NONE, 0, 1, 60000, 0, 0)};
    for (int k = 0; k < RUNS; ++k) {
        TEST_TRUE(runs[k].finished);
        /* no trend: the last quarter within twice the first (a drift that
         * doubled over 3/4 of the run would show) */
        TEST_TRUE(runs[k].late <= 2.0 * runs[k].early + 1e-9);
    }
    for (int k = 0; k < 3; ++k) { /* 1e-3 of the work: the bound
                                     (a sudden load leaves the highest modes
                                     ringing near the stability limit, where
                                     K of v_n misses the step's shadow
                                     energy by a bounded 0.5%) */
        TEST_TRUE(runs[k].early <= 1e-3 * runs[k].largest_work);
        TEST_TRUE(runs[k].late <= 1e-3 * runs[k].largest_work);
    }
    /* Negative control: the scheme of before (Psi_I and the non-symmetric
     * boundary term on the held facets, B_c alone corrected) under the
     * same sudden load: an error 4 times larger on this mesh (0.66 against
     * 0.16 J over 10^5 steps), though not growing within 10^5 steps here (on
     * the CLI's
     * mesh of docs/solver.md it grew after 35,000 steps). Both on the
     * paper's whole window, on which it was measured: with the default
     * window cut the old term's error is 2.8 times today's (0.508 against
     * 0.184 J; docs/kernels.md, "Window cut"). */
    struct energy_run whole = run(GSN_STABILIZATION_NONE, 0, 1, 60000, 0, 1);
    struct energy_run legacy = run(GSN_STABILIZATION_NONE, 0, 1, 60000, 1, 1);
    TEST_TRUE(whole.finished);
    TEST_TRUE(!legacy.finished || legacy.late > 3.0 * whole.late);
    return test_end("test_long_energy");
}
