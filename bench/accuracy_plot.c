/* The speed-and-accuracy chart (bench/accuracy_chart.sh, bearing_chart.sh):
 * error against time (the CPU time of a 1-thread run, column cpu_s: on a
 * shared machine the wall time of an idle core) on log-log axes, one curve
 * per method, from the CSV that accuracy_run (or bearing_capacity.sh)
 * writes; the legend gives each method's convergence rate, the
 * least-squares slope of log(error) against log(spacing). Drawn by post's
 * chart (vtk_output.h) on post's private Xvfb when there is no display
 * (display.h).
 *
 *   accuracy_plot CSV PROBLEM PNG [TITLE [ERROR_LABEL]]
 *
 * Prints the rates. Exit status 0, 1 (VTK or I/O failed), 2 (bad input). */
#include "csv.h"
#include "display.h"
#include "geoscni/error.h"
#include "vtk_output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The methods in the order of the legend, with their labels; a method's
 * colour is its place here, whether or not the others are in the CSV. */
static const char *const METHODS[][2] = {{"scni", "SCNI"},
                                         {"mscni", "SCNI + MSCNI"},
                                         {"nsni", "SCNI + NSNI"},
                                         {"dni", "DNI"},
                                         {"gauss2", "Gauss 2x2x2"},
                                         {"gauss3", "Gauss 3x3x3"},
                                         {"nsni0.1", "SCNI + NSNI 0.1"}};
enum { METHOD_COUNT = sizeof METHODS / sizeof METHODS[0] };
enum { LINE_SIZE = 4096, MAX_COLUMNS = 64, MAX_POINTS = 256 };

struct series {
    int count;
    double spacing[MAX_POINTS], time[MAX_POINTS], error[MAX_POINTS];
};

/* Reads the rows of one problem into the series of the known methods;
 * 2 on bad input (the message printed). */
static int read_csv(const char *path, const char *problem,
                    struct series *series)
{
    FILE *file = fopen(path, "r");
    if (!file) {
        fprintf(stderr, "accuracy_plot: cannot open %s\n", path);
        return 2;
    }
    char header[LINE_SIZE], line[LINE_SIZE];
    char *names[MAX_COLUMNS], *cells[MAX_COLUMNS];
    int columns = fgets(header, sizeof header, file)
                      ? csv_split(header, names, MAX_COLUMNS)
                      : 0;
    int c_problem = csv_column(names, columns, "problem"),
        c_method = csv_column(names, columns, "method"),
        c_spacing = csv_column(names, columns, "spacing"),
        c_time = csv_column(names, columns, "cpu_s"),
        c_error = csv_column(names, columns, "error");
    int rc = 0, rows = 0;
    if (c_problem < 0 || c_method < 0 || c_spacing < 0 || c_time < 0 ||
        c_error < 0) {
        fprintf(stderr,
                "accuracy_plot: %s: the header needs problem, method, "
                "spacing, cpu_s and error\n",
                path);
        rc = 2;
    }
    for (int number = 2; rc == 0 && fgets(line, sizeof line, file); ++number) {
        if (csv_split(line, cells, MAX_COLUMNS) < columns ||
            strcmp(cells[c_problem], problem) != 0)
            continue;
        int m = 0;
        while (m < METHOD_COUNT && strcmp(cells[c_method], METHODS[m][0]) != 0)
            ++m;
        if (m == METHOD_COUNT)
            continue;
        struct series *s = &series[m];
        char *end[3];
        double spacing = strtod(cells[c_spacing], &end[0]);
        double time = strtod(cells[c_time], &end[1]);
        double error = strtod(cells[c_error], &end[2]);
        if (end[0] == cells[c_spacing] || end[1] == cells[c_time] ||
            end[2] == cells[c_error] || s->count == MAX_POINTS) {
            fprintf(stderr,
                    "accuracy_plot: %s:%d: spacing, cpu_s and error must be "
                    "numbers (at most %d rows a method)\n",
                    path, number, MAX_POINTS);
            rc = 2;
            break;
        }
        s->spacing[s->count] = spacing;
        s->time[s->count] = time;
        s->error[s->count++] = error;
        ++rows;
    }
    fclose(file);
    if (rc == 0 && rows == 0) {
        fprintf(stderr, "accuracy_plot: no rows of %s in %s\n", problem, path);
        rc = 2;
    }
    return rc;
}

/* Least-squares slope of log(error) against log(spacing). */
static double rate(const struct series *s)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = s->count;
    for (int i = 0; i < s->count; ++i) {
        double x = log(s->spacing[i]), y = log(s->error[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return n > 1 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : 0.0;
}

int main(int argc, char **argv)
{
    if (argc < 4 || argc > 6) {
        fprintf(stderr, "usage: %s CSV PROBLEM PNG [TITLE [ERROR_LABEL]]\n",
                argv[0]);
        return 2;
    }
    static struct series series[METHOD_COUNT];
    int rc = read_csv(argv[1], argv[2], series);
    if (rc != 0)
        return rc;
    char labels[METHOD_COUNT][128];
    const char *names[METHOD_COUNT];
    const double *x[METHOD_COUNT], *y[METHOD_COUNT];
    int counts[METHOD_COUNT], colours[METHOD_COUNT], shown = 0;
    for (int m = 0; m < METHOD_COUNT; ++m) {
        if (series[m].count == 0)
            continue;
        snprintf(labels[m], sizeof labels[m], "%s: rate %.2f", METHODS[m][1],
                 rate(&series[m]));
        printf("%s\n", labels[m]);
        names[shown] = labels[m];
        x[shown] = series[m].time;
        y[shown] = series[m].error;
        counts[shown] = series[m].count;
        colours[shown++] = m;
    }
    struct gsn_display display = {0};
    if (gsn_display_open(&display) != 0 || !display.available) {
        fprintf(stderr, "accuracy_plot: no display: %s\n", display.reason);
        gsn_display_close(&display);
        return 1;
    }
    const struct gsn_chart_style style = {.log_axes = 1,
                                          .markers = 1,
                                          .always_legend = 1,
                                          .legend_right = 1,
                                          .colour = colours};
    rc = gsn_vtk_chart_write(argv[3], argc >= 5 ? argv[4] : argv[2],
                             "time: build + steps (s, CPU of 1 thread)",
                             argc >= 6 ? argv[5] : "error", shown, names,
                             counts, x, y, &style);
    gsn_display_close(&display);
    if (rc != GSN_OK) {
        fprintf(stderr, "accuracy_plot: %s\n", gsn_error_message());
        return 1;
    }
    return 0;
}
