/* history.csv reader. */
#include "history.h"

#include "geoscni/error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *trim(char *text)
{
    while (*text == ' ' || *text == '\t')
        ++text;
    size_t n = strlen(text);
    while (n > 0 && strchr(" \t\r\n", text[n - 1]))
        text[--n] = '\0';
    return text;
}

static int history_header(const char *path, char *line,
                          struct gsn_history *history)
{
    int count = 1;
    for (const char *c = line; *c; ++c)
        count += *c == ',';
    history->names = calloc((size_t)count, sizeof *history->names);
    GSN_CHECK(history->names != NULL, GSN_ERR_MEMORY,
              "cannot allocate %d column names", count);
    history->column_count = count;
    char *rest = line;
    for (int k = 0; k < count; ++k) {
        char *name = trim(strsep(&rest, ","));
        GSN_CHECK(*name != '\0' && strlen(name) < GSN_HISTORY_NAME_SIZE,
                  GSN_ERR_INPUT,
                  "%s:1: column %d of the header is empty or too long", path,
                  k + 1);
        strcpy(history->names[k], name);
    }
    return GSN_OK;
}

/* Parses a row into values; 0 if it is malformed. */
static int history_row(char *line, int count, double *values)
{
    char *rest = line;
    for (int k = 0; k < count; ++k) {
        char *field = strsep(&rest, ",");
        if (!field)
            return 0;
        field = trim(field);
        char *end = NULL;
        errno = 0;
        values[k] = strtod(field, &end);
        if (*field == '\0' || *end != '\0' || errno == ERANGE ||
            !isfinite(values[k]))
            return 0;
    }
    return rest == NULL;
}

static int history_parse(FILE *file, const char *path,
                         struct gsn_history *history)
{
    char *line = NULL;
    size_t size = 0;
    int rc = GSN_OK;
    ssize_t length = getline(&line, &size, file);
    GSN_CHECK_GOTO(length > 0, rc, GSN_ERR_INPUT, done,
                   "%s: empty file, a header line was expected", path);
    GSN_CALL_GOTO(history_header(path, line, history), rc, done);
    size_t capacity = 0;
    for (int number = 2; (length = getline(&line, &size, file)) > 0; ++number) {
        int complete = line[length - 1] == '\n';
        if (*trim(line) == '\0')
            continue;
        if ((size_t)history->row_count == capacity) {
            capacity = capacity ? 2 * capacity : 256;
            double *grown =
                realloc(history->values,
                        capacity * history->column_count * sizeof(double));
            GSN_CHECK_GOTO(grown != NULL, rc, GSN_ERR_MEMORY, done,
                           "cannot allocate %zu history rows", capacity);
            history->values = grown;
        }
        double *row = history->values +
                      (size_t)history->row_count * history->column_count;
        if (history_row(line, history->column_count, row)) {
            ++history->row_count;
            continue;
        }
        if (!complete)
            break; /* the last line, cut short */
        GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                       "%s:%d: expected %d numbers separated by commas", path,
                       number, history->column_count);
    }
    GSN_CHECK_GOTO(!ferror(file), rc, GSN_ERR_IO, done, "%s: read error", path);
done:
    free(line);
    return rc;
}

int gsn_history_read(const char *path, struct gsn_history *history)
{
    memset(history, 0, sizeof *history);
    FILE *file = fopen(path, "r");
    GSN_CHECK(file != NULL, GSN_ERR_INPUT, "%s: cannot open: %s", path,
              strerror(errno));
    int rc = history_parse(file, path, history);
    fclose(file);
    if (rc != GSN_OK) {
        gsn_history_free(history);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "history_parse(file, path, history)");
    }
    return GSN_OK;
}

void gsn_history_free(struct gsn_history *history)
{
    free(history->names);
    free(history->values);
    memset(history, 0, sizeof *history);
}

/* 1 if column is name itself or name with its unit after it (time_s,
 * footing_fz_N: solve's header since 2026-12-02; before, bare names). */
static int column_is(const char *column, const char *name)
{
    static const char *const units[] = {"_s", "_m", "_N", "_J"};
    size_t n = strlen(name);
    if (strncmp(column, name, n) != 0)
        return 0;
    if (column[n] == '\0')
        return 1;
    for (size_t k = 0; k < sizeof units / sizeof units[0]; ++k)
        if (strcmp(column + n, units[k]) == 0)
            return 1;
    return 0;
}

int gsn_history_column(const struct gsn_history *history, const char *name)
{
    for (int k = 0; k < history->column_count; ++k)
        if (column_is(history->names[k], name))
            return k;
    return -1;
}

void gsn_history_copy_column(const struct gsn_history *history, int column,
                             double *out)
{
    for (int r = 0; r < history->row_count; ++r)
        out[r] = history->values[(size_t)r * history->column_count + column];
}

int gsn_history_motion_curve(const struct gsn_history *history,
                             const char *name, const double direction[3],
                             double factor, double *x, double *y)
{
    static const char *const suffix[6] = {"ux", "uy", "uz", "fx", "fy", "fz"};
    int column[6];
    for (int k = 0; k < 6; ++k) {
        char wanted[GSN_HISTORY_NAME_SIZE + 8];
        snprintf(wanted, sizeof wanted, "%s_%s", name, suffix[k]);
        column[k] = gsn_history_column(history, wanted);
        GSN_CHECK(column[k] >= 0, GSN_ERR_INPUT,
                  "history.csv lacks the column %s of the boundary entry "
                  "'%s'",
                  wanted, name);
    }
    for (int r = 0; r < history->row_count; ++r) {
        const double *row = history->values + (size_t)r * history->column_count;
        double u = 0.0, f = 0.0;
        for (int j = 0; j < 3; ++j) {
            u += row[column[j]] * direction[j];
            f += row[column[3 + j]] * direction[j];
        }
        x[r] = u;
        y[r] = 1e-3 * factor * f; /* N -> kN */
    }
    return GSN_OK;
}

int gsn_boundary_motion(const struct gsn_boundary *b, double direction[3])
{
    double norm = 0.0;
    for (int j = 0; j < 3; ++j) {
        direction[j] = b->has_velocity[j] ? b->velocity[j] : 0.0;
        norm += direction[j] * direction[j];
    }
    if (!(norm > 0.0))
        return 0;
    for (int j = 0; j < 3; ++j)
        direction[j] /= sqrt(norm);
    return 1;
}
