/* The deep-penetration chart (bench/deep_penetration.sh): the footing's
 * pressure q / s_u against its settlement w / B, one curve per run, beside
 * the small-strain Prandtl limit (2 + pi) and Salgado et al.'s (2004) depth
 * factor (2 + pi)(1 + 0.27 sqrt(w / B)) (docs/deep_penetration.md). Drawn
 * by post's chart (vtk_output.h) on post's private Xvfb when there is no
 * display (display.h).
 *
 *   penetration_plot PNG HISTORY LABEL AREA [HISTORY LABEL AREA ...]
 *
 * HISTORY: a run's history.csv with footing_uz_m and footing_fz_N; AREA:
 * the footing's area in the model (m^2; B = 1 m, s_u = 1 kPa). Rows of a
 * burst (q below 0 or above twice Salgado's) are left out of the curve, so
 * that they do not set the scale, and printed. Prints for every run its
 * last settlement and the mean q / s_u over the settlement windows of
 * docs/deep_penetration.md's table (0.15-0.25, 0.4-0.6, 0.8-1 B; single
 * rows are chaotic beyond 0.3 B), the bursts left out. Exit status 0, 1
 * (VTK or I/O failed), 2 (bad input). */
#include "csv.h"
#include "display.h"
#include "vtk_output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { LINE_SIZE = 8192, MAX_COLUMNS = 128, MAX_POINTS = 4096, MAX_RUNS = 8 };
#define UNDRAINED_STRENGTH 1000.0 /* s_u of the case, Pa */
#define PRANDTL 5.141592653589793 /* 2 + pi */

/* Salgado et al.'s (2004) pressure at settlement w / B. */
static double salgado(double w)
{
    return PRANDTL * (1.0 + 0.27 * sqrt(w));
}

/* Reads w / B and q / s_u of one run; returns the point count, -1 on
 * error (printed). */
static int read_run(const char *path, double area, double *w, double *q)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "penetration_plot: cannot open %s\n", path);
        return -1;
    }
    char line[LINE_SIZE], *cells[MAX_COLUMNS];
    int columns =
        fgets(line, sizeof line, f) ? csv_split(line, cells, MAX_COLUMNS) : 0;
    int uz = csv_column(cells, columns, "footing_uz_m"),
        fz = csv_column(cells, columns, "footing_fz_N"), count = 0;
    if (uz < 0 || fz < 0) {
        fprintf(stderr,
                "penetration_plot: %s has no footing_uz_m and "
                "footing_fz_N columns\n",
                path);
        fclose(f);
        return -1;
    }
    while (count < MAX_POINTS && fgets(line, sizeof line, f)) {
        int n = csv_split(line, cells, MAX_COLUMNS);
        if (n <= uz || n <= fz)
            continue;
        w[count] = -atof(cells[uz]);
        q[count] = -atof(cells[fz]) / area / UNDRAINED_STRENGTH;
        if (q[count] < 0.0 || q[count] > 2.0 * salgado(w[count])) {
            printf("%s: a burst left out at w / B = %.3f (q / s_u = %.3g)\n",
                   path, w[count], q[count]);
            continue;
        }
        ++count;
    }
    fclose(f);
    return count;
}

int main(int argc, char **argv)
{
    if (argc < 5 || (argc - 2) % 3 != 0 || (argc - 2) / 3 > MAX_RUNS) {
        fprintf(stderr,
                "usage: penetration_plot PNG HISTORY LABEL AREA "
                "[HISTORY LABEL AREA ...] (at most %d runs)\n",
                MAX_RUNS);
        return 2;
    }
    int runs = (argc - 2) / 3, series = runs + 2;
    static double w[MAX_RUNS + 2][MAX_POINTS], q[MAX_RUNS + 2][MAX_POINTS];
    const char *names[MAX_RUNS + 2];
    int counts[MAX_RUNS + 2];
    double w_end = 0.1;
    for (int r = 0; r < runs; ++r) {
        double area = atof(argv[2 + 3 * r + 2]);
        if (!(area > 0.0)) {
            fprintf(stderr, "penetration_plot: area %s must be positive\n",
                    argv[2 + 3 * r + 2]);
            return 2;
        }
        counts[r] = read_run(argv[2 + 3 * r], area, w[r], q[r]);
        if (counts[r] < 0)
            return 2;
        names[r] = argv[2 + 3 * r + 1];
        for (int i = 0; i < counts[r]; ++i)
            w_end = fmax(w_end, w[r][i]);
    }
    static const double window[][2] = {{0.15, 0.25}, {0.4, 0.6}, {0.8, 1.0}};
    for (int r = 0; r < runs; ++r) {
        double last = counts[r] > 0 ? w[r][counts[r] - 1] : 0.0;
        printf("%s: to w / B = %.3f; mean q / s_u", names[r], last);
        for (int k = 0; k < 3; ++k) {
            double sum = 0.0;
            int n = 0;
            for (int i = 0; i < counts[r]; ++i)
                if (w[r][i] >= window[k][0] && w[r][i] <= window[k][1]) {
                    sum += q[r][i];
                    ++n;
                }
            if (n > 0)
                printf(" %.2f over %.2f-%.2f B (%d rows)%s", sum / n,
                       window[k][0], window[k][1], n, k < 2 ? "," : "");
            else
                printf(" - over %.2f-%.2f B%s", window[k][0], window[k][1],
                       k < 2 ? "," : "");
        }
        printf("\n");
    }
    /* the references over the runs' settlements */
    enum { REFERENCE_POINTS = 101 };
    names[runs] = "Salgado et al. 2004: (2 + pi)(1 + 0.27 sqrt(w/B))";
    names[runs + 1] = "Prandtl, small strain: 2 + pi";
    for (int i = 0; i < REFERENCE_POINTS; ++i) {
        double x = w_end * i / (REFERENCE_POINTS - 1);
        w[runs][i] = w[runs + 1][i] = x;
        q[runs][i] = salgado(x);
        q[runs + 1][i] = PRANDTL;
    }
    counts[runs] = counts[runs + 1] = REFERENCE_POINTS;
    const double *x[MAX_RUNS + 2], *y[MAX_RUNS + 2];
    for (int s = 0; s < series; ++s) {
        x[s] = w[s];
        y[s] = q[s];
    }
    struct gsn_display display = {0};
    if (gsn_display_open(&display) != 0 || !display.available) {
        fprintf(stderr, "penetration_plot: no display: %s\n", display.reason);
        gsn_display_close(&display);
        return 1;
    }
    const struct gsn_chart_style style = {.always_legend = 1};
    int rc = gsn_vtk_chart_write(
        argv[1], "Strip footing pushed into weightless Tresca clay",
        "settlement w / B", "pressure q / s_u", series, names, counts, x, y,
        &style);
    gsn_display_close(&display);
    if (rc != 0) {
        fprintf(stderr, "penetration_plot: could not write %s\n", argv[1]);
        return 1;
    }
    return 0;
}
