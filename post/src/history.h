/* history.csv (DESIGN.md, "What a run leaves"): a header of column names,
 * then one row of numbers per output interval. */
#ifndef GEOSCNI_POST_HISTORY_H
#define GEOSCNI_POST_HISTORY_H

#include "geoscni/case.h"

enum { GSN_HISTORY_NAME_SIZE = 96 };

struct gsn_history {
    int column_count;
    char (*names)[GSN_HISTORY_NAME_SIZE];
    int row_count;
    double *values; /* row_count x column_count, row-major */
};

/* Reads path. A last line cut short (no newline, wrong column count: a run
 * still writing or stopped) is left out; any other malformed line is an
 * input error naming path:line. */
int gsn_history_read(const char *path, struct gsn_history *history);

/* Frees the arrays and zeroes the struct; accepts a zeroed struct. */
void gsn_history_free(struct gsn_history *history);

/* Index of a column by name, or -1: "time" finds "time_s", "a_fz" finds
 * "a_fz_N" (units after the names), and the bare names of older files. */
int gsn_history_column(const struct gsn_history *history, const char *name);

/* The load-settlement curve of boundary entry `name` moved along
 * direction (a unit vector): for every row, x the mean displacement of its
 * particles along it (m) and y factor times the force on the body through
 * it along it (kN), both signed: a force against the motion (the surface
 * holding the body back) is negative. GSN_ERR_INPUT when a column of the
 * entry is missing. */
int gsn_history_motion_curve(const struct gsn_history *history,
                             const char *name, const double direction[3],
                             double factor, double *x, double *y);

/* The unit vector of a boundary entry's prescribed velocity (its moving
 * components); 0 if it does not move. */
int gsn_boundary_motion(const struct gsn_boundary *b, double direction[3]);

/* Copies column into out (row_count values). */
void gsn_history_copy_column(const struct gsn_history *history, int column,
                             double *out);

#endif
