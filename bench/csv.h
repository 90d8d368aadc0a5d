/* The plain CSVs the bench programs read (accuracy_plot, penetration_plot):
 * no quoting, a header of column names. */
#ifndef GEOSCNI_BENCH_CSV_H
#define GEOSCNI_BENCH_CSV_H

#include <string.h>

/* Splits line at commas in place, its line end removed, into at most
 * most cells; returns their number. */
static inline int csv_split(char *line, char **cells, int most)
{
    int count = 0;
    line[strcspn(line, "\r\n")] = '\0';
    for (char *c = line; count < most;) {
        cells[count++] = c;
        c = strchr(c, ',');
        if (!c)
            break;
        *c++ = '\0';
    }
    return count;
}

/* The index of the column called name among count names, or -1. */
static inline int csv_column(char **names, int count, const char *name)
{
    for (int i = 0; i < count; ++i)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

#endif
