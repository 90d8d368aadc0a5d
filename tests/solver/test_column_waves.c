/* Standing waves in a 10 m column with the base fixed and the top free
 * (REFERENCES.md, "Elastic dynamics"): a body force switched on at t = 0
 * sets the column ringing about its static deflection, mostly in its first
 * mode, f1 = c / (4 H) with c = c_p (longitudinal) or c_s (shear). The
 * frequency is measured from the upward zero crossings of the top's motion
 * about the static deflection over ten periods; the total energy
 * KE + W_int - W_ext (history.csv's energy_balance_J, with the kinetic
 * energy central differences conserve) must stay constant. */
#include "geoscni/case.h"
#include "geoscni/solver.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <string.h>

enum { MAX_ROWS = 4096 };

struct record {
    int count;
    double time[MAX_ROWS], top[MAX_ROWS], balance[MAX_ROWS], work[MAX_ROWS];
};

/* Reads history.csv: the top's mean displacement along axis, the energy
 * balance and the external work. */
static void read_history(const char *folder, int axis, struct record *r)
{
    char path[4200], line[8192];
    snprintf(path, sizeof path, "%s/history.csv", folder);
    FILE *file = fopen(path, "r");
    TEST_TRUE(file != NULL);
    if (!file)
        return;
    int top_column = -1, work = -1, balance = -1, column = 0;
    TEST_TRUE(fgets(line, sizeof line, file) != NULL);
    const char *names[3] = {"zmax_ux_m", "zmax_uy_m", "zmax_uz_m"};
    for (char *token = strtok(line, ",\n"); token;
         token = strtok(NULL, ",\n"), ++column) {
        if (strcmp(token, names[axis]) == 0)
            top_column = column;
        if (strcmp(token, "external_work_J") == 0)
            work = column;
        if (strcmp(token, "energy_balance_J") == 0)
            balance = column;
    }
    TEST_TRUE(top_column >= 0 && work >= 0 && balance >= 0);
    r->count = 0;
    while (fgets(line, sizeof line, file) && r->count < MAX_ROWS) {
        double value[64];
        int n = 0;
        for (char *token = strtok(line, ",\n"); token && n < 64;
             token = strtok(NULL, ",\n"))
            value[n++] = strtod(token, NULL);
        r->time[r->count] = value[0];
        r->top[r->count] = value[top_column];
        r->balance[r->count] = value[balance];
        r->work[r->count] = value[work];
        r->count++;
    }
    fclose(file);
}

/* Runs a column case; returns the measured frequency (Hz). */
static double column_frequency(const char *case_path, int axis,
                               double static_top, double expected)
{
    struct gsn_case c;
    TEST_INT(gsn_case_load(case_path, &c), GSN_OK);
    char folder[] = "/tmp/geoscni-test-column-XXXXXX";
    const int count[3] = {3, 3, 41};
    const double lo[3] = {0, 0, 0}, hi[3] = {0.5, 0.5, 10.0};
    TEST_INT(fixture_solve_box(&c, folder, count, lo, hi, 0.0), GSN_OK);
    static struct record r;
    read_history(folder, axis, &r);
    /* Upward zero crossings of the motion about the static deflection. */
    int periods = 0;
    double frequency = fixture_crossing_frequency(r.time, r.top, r.count,
                                                  static_top, &periods);
    /* Energy: constant from the first row on, relative to the work done. */
    double drift = 0.0, scale = 0.0;
    for (int i = 0; i < r.count; ++i) {
        drift = fmax(drift, fabs(r.balance[i] - r.balance[0]));
        scale = fmax(scale, fabs(r.work[i]));
    }
    printf("%s: %d periods, f1 = %.5f Hz (exact %.5f, error %.3f%%), energy "
           "drift %.3g of the work done\n",
           case_path, periods, frequency, expected,
           100.0 * (frequency / expected - 1.0), drift / scale);
    /* 1%: the tolerance; the lattice's dispersion at this spacing
     * (kh = 0.04 for the first mode) costs 0.03%. */
    TEST_REL(frequency, expected, 0.01);
    TEST_TRUE(periods >= 9);
    /* The issue asked 1e-4; central differences conserve this balance
     * exactly on a linear body (explicit.h, conserved_kinetic_energy), so
     * what is left is the column's geometric nonlinearity and round-off
     * (1.8e-9 and 1.6e-10 measured, 2026-12-07). 1e-7: fifty times that.
     * (With 1/2 v M v the balance swings by (omega_1 dt / 2)^2 of the
     * mode's energy, 1.1e-4 at the auto step of 1.7 ms.) */
    TEST_TRUE(drift <= 1e-7 * scale);
    char command[4200];
    snprintf(command, sizeof command, "rm -rf '%s'", folder);
    TEST_INT(system(command), 0);
    return frequency;
}

int main(void)
{
    test_begin();
    const double rho = 1880.0, K = 27.4e6, mu = 9.15e6, g = 9.81, H = 10.0;
    const double M = K + 4.0 * mu / 3.0;
    /* Static top deflection of a fixed-free column under its weight:
     * rho g H^2 / (2 modulus). */
    column_frequency("cases/column_longitudinal.yaml", 2,
                     -rho * g * H * H / (2.0 * M), sqrt(M / rho) / (4.0 * H));
    column_frequency("cases/column_shear.yaml", 0, rho * g * H * H / (2.0 * mu),
                     sqrt(mu / rho) / (4.0 * H));
    return test_end("test_column_waves");
}
