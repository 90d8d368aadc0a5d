/* One number of a finished run: see quantity.h. */
#include "geoscni/quantity.h"

#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/model.h"
#include "geoscni/results.h"
#include "history.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char quantity_forms[] =
    "peak_force, peak_force:SURFACE, force_at:SETTLEMENT, "
    "force_at:SETTLEMENT:SURFACE, the same with pressure for force, "
    "displacement_at:X,Y,Z (m), or factor_of_safety";

/* Reads count numbers separated by `separator` from text; the end of the
 * last number in *end. 1 on success. */
static int read_numbers(const char *text, int count, char separator,
                        double *out, const char **end)
{
    const char *p = text;
    for (int k = 0; k < count; ++k) {
        char *stop = NULL;
        errno = 0;
        out[k] = strtod(p, &stop);
        if (stop == p || errno == ERANGE || !isfinite(out[k]))
            return 0;
        p = stop;
        if (k + 1 < count) {
            if (*p != separator)
                return 0;
            ++p;
        }
    }
    *end = p;
    return 1;
}

int gsn_quantity_parse(const char *text, struct gsn_quantity *q)
{
    *q = (struct gsn_quantity){0};
    const char *rest = NULL;
    int ok = 0;
    for (int per_area = 0; per_area < 2 && !ok; ++per_area) {
        const char *word = per_area ? "pressure" : "force";
        size_t n = strlen(word);
        if (!strncmp(text, "peak_", 5) && !strncmp(text + 5, word, n) &&
            (text[5 + n] == '\0' || text[5 + n] == ':')) {
            q->kind = GSN_QUANTITY_PEAK_FORCE;
            rest = text + 5 + n;
            ok = 1;
        } else if (!strncmp(text, word, n) && !strncmp(text + n, "_at:", 4)) {
            q->kind = GSN_QUANTITY_FORCE_AT;
            ok = read_numbers(text + n + 4, 1, ',', &q->at, &rest) &&
                 q->at > 0.0;
        }
        q->per_area = per_area;
    }
    if (!ok && !strcmp(text, "factor_of_safety")) {
        q->kind = GSN_QUANTITY_FACTOR_OF_SAFETY;
        q->per_area = 0;
        rest = text + strlen(text);
        ok = 1;
    }
    if (!ok && !strncmp(text, "displacement_at:", 16)) {
        q->kind = GSN_QUANTITY_DISPLACEMENT_AT;
        q->per_area = 0;
        ok = read_numbers(text + 16, 3, ',', q->point, &rest) && *rest == '\0';
    }
    if (ok && *rest == ':') {
        ok = rest[1] != '\0' && strlen(rest + 1) < sizeof q->surface;
        if (ok)
            snprintf(q->surface, sizeof q->surface, "%s", rest + 1);
    } else if (ok) {
        ok = *rest == '\0';
    }
    GSN_CHECK(ok, GSN_ERR_INPUT,
              "--quantity '%s': give %s (a settlement above 0)", text,
              quantity_forms);
    return GSN_OK;
}

int gsn_quantity_resolve(const struct gsn_case *c, struct gsn_quantity *q,
                         char *description, size_t size, const char **unit)
{
    if (q->kind == GSN_QUANTITY_DISPLACEMENT_AT) {
        snprintf(description, size, "displacement at (%g, %g, %g) m",
                 q->point[0], q->point[1], q->point[2]);
        *unit = "m";
        return GSN_OK;
    }
    if (q->kind == GSN_QUANTITY_FACTOR_OF_SAFETY) {
        snprintf(description, size, "factor of safety");
        *unit = "";
        return GSN_OK;
    }
    int found = -1;
    double direction[3];
    for (int b = 0; b < c->boundary_count; ++b) {
        int moves = gsn_boundary_motion(&c->boundaries[b], direction);
        if (q->surface[0]) {
            if (!strcmp(c->boundaries[b].name, q->surface)) {
                GSN_CHECK(moves, GSN_ERR_INPUT,
                          "%s:%d: boundary entry '%s' has no prescribed "
                          "velocity: a force is measured on an entry that "
                          "moves",
                          c->path, c->boundaries[b].line, q->surface);
                found = b;
            }
        } else if (moves) {
            GSN_CHECK(found < 0, GSN_ERR_INPUT,
                      "%s: boundary entries '%s' and '%s' both move: name "
                      "one in --quantity (peak_force:%s)",
                      c->path, c->boundaries[found].name, c->boundaries[b].name,
                      c->boundaries[b].name);
            found = b;
        }
    }
    GSN_CHECK(found >= 0, GSN_ERR_INPUT,
              q->surface[0] ? "%s: no boundary entry '%s'"
                            : "%s: no boundary entry moves (a prescribed "
                              "velocity): choose --quantity "
                              "displacement_at:X,Y,Z%s",
              c->path, q->surface);
    snprintf(q->surface, sizeof q->surface, "%s", c->boundaries[found].name);
    const char *what = q->per_area ? "pressure" : "force";
    if (q->kind == GSN_QUANTITY_PEAK_FORCE)
        snprintf(description, size, "peak %s on '%s'", what, q->surface);
    else
        snprintf(description, size, "%s on '%s' at a settlement of %g m", what,
                 q->surface, q->at);
    *unit = q->per_area ? "Pa" : "N";
    return GSN_OK;
}

int gsn_quantity_surface_area(const char *outdir, const char *name,
                              double *area)
{
    char path[GSN_PATH_SIZE];
    struct gsn_model m = {0};
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "model.h5"));
    GSN_CALL(gsn_model_read(path, &m));
    int surface = gsn_model_find_surface(&m, name);
    *area = surface >= 0 ? m.surface_area[surface] : 0.0;
    gsn_model_free(&m);
    GSN_CHECK(*area > 0.0, GSN_ERR_INPUT,
              "%s/model.h5: surface '%s' has no area to divide its force by",
              outdir, name);
    return GSN_OK;
}

/* The force of boundary entry q->surface along its motion against its
 * settlement, from history.csv: the peak, or the value at q->at. */
static int force_measure(const char *outdir, const struct gsn_case *c,
                         const struct gsn_quantity *q, double *value)
{
    const struct gsn_boundary *b = NULL;
    for (int k = 0; k < c->boundary_count; ++k)
        if (!strcmp(c->boundaries[k].name, q->surface))
            b = &c->boundaries[k];
    double direction[3];
    GSN_CHECK(b && gsn_boundary_motion(b, direction), GSN_ERR_INPUT,
              "%s: boundary entry '%s' does not move", c->path, q->surface);
    char path[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "history.csv"));
    struct gsn_history history;
    GSN_CALL(gsn_history_read(path, &history));
    int n = history.row_count, rc = GSN_OK;
    double *x = malloc(2 * sizeof(double) * (size_t)(n + 1)), *y = x + n + 1;
    GSN_CHECK_GOTO(x, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CHECK_GOTO(n > 0, rc, GSN_ERR_INPUT, done, "%s has no rows", path);
    /* N: 1000 times the plot's kN; a pressure is the model's force over the
     * model's area, mirrored or not */
    double factor = 1e3 * (c->output_mirror[0] ? 2 : 1), area = 0.0;
    if (q->per_area) {
        GSN_CALL_GOTO(gsn_quantity_surface_area(outdir, q->surface, &area), rc,
                      done);
        factor = 1e3 / area;
    }
    GSN_CALL_GOTO(
        gsn_history_motion_curve(&history, b->name, direction, factor, x, y),
        rc, done);
    if (q->kind == GSN_QUANTITY_PEAK_FORCE) {
        *value = y[0];
        for (int r = 1; r < n; ++r)
            *value = fmax(*value, y[r]);
        goto done;
    }
    for (int r = 0; r + 1 < n; ++r)
        if (x[r] <= q->at && q->at <= x[r + 1] && x[r + 1] > x[r]) {
            double w = (q->at - x[r]) / (x[r + 1] - x[r]);
            *value = (1.0 - w) * y[r] + w * y[r + 1];
            goto done;
        }
    double reached = x[0];
    for (int r = 1; r < n; ++r)
        reached = fmax(reached, x[r]);
    GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                   "%s: '%s' moved %g m at most, not the %g m of --quantity",
                   path, b->name, reached, q->at);
done:
    free(x);
    gsn_history_free(&history);
    return rc;
}

/* Barycentric coordinates of x in tetrahedron t of m; 0 if it is flat. */
static int barycentric(const struct gsn_model *m, int t, const double x[3],
                       double w[4])
{
    const int *v = m->tetrahedra + 4 * (size_t)t;
    const double *p0 = m->position + 3 * (size_t)v[0];
    double a[3][3], r[3];
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j)
            a[j][k] = m->position[3 * (size_t)v[k + 1] + j] - p0[j];
        r[k] = x[k] - p0[k];
    }
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (det == 0.0)
        return 0;
    /* Cramer's rule for a w_123 = r */
    for (int k = 0; k < 3; ++k) {
        double b[3][3];
        memcpy(b, a, sizeof b);
        for (int j = 0; j < 3; ++j)
            b[j][k] = r[j];
        w[k + 1] = (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                    b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                    b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0])) /
                   det;
    }
    w[0] = 1.0 - w[1] - w[2] - w[3];
    return 1;
}

/* |u| at q->point in the last frame, linear in the tetrahedron of pre's
 * mesh that holds the point (the particles are its vertices). */
static int displacement_measure(const char *outdir, const struct gsn_case *c,
                                const struct gsn_quantity *q, double *value)
{
    char path[GSN_PATH_SIZE];
    struct gsn_model m = {0};
    struct gsn_frame frame = {0};
    hid_t file = H5I_INVALID_HID;
    int count = 0, rc = GSN_OK;
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "model.h5"));
    GSN_CALL(gsn_model_read(path, &m));
    int best = -1;
    double best_w[4] = {0}, best_low = -INFINITY;
    for (int t = 0; t < m.tetrahedron_count; ++t) {
        double w[4];
        if (!barycentric(&m, t, q->point, w))
            continue;
        double low = fmin(fmin(w[0], w[1]), fmin(w[2], w[3]));
        if (low > best_low) {
            best_low = low;
            best = t;
            memcpy(best_w, w, sizeof w);
        }
    }
    /* inside up to rounding: 1e-9 of the tetrahedron's coordinates */
    GSN_CHECK_GOTO(best >= 0 && best_low >= -1e-9, rc, GSN_ERR_INPUT, done,
                   "%s: the point (%g, %g, %g) m of --quantity is outside the "
                   "body",
                   c->path, q->point[0], q->point[1], q->point[2]);
    GSN_CALL_GOTO(gsn_path_join(path, sizeof path, outdir, "results.h5"), rc,
                  done);
    GSN_CALL_GOTO(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file), rc, done);
    GSN_CALL_GOTO(gsn_results_frame_count(file, &count), rc, done);
    GSN_CHECK_GOTO(count > 0, rc, GSN_ERR_INPUT, done, "%s has no frames",
                   path);
    GSN_CALL_GOTO(gsn_frame_allocate(&frame, m.particle_count), rc, done);
    GSN_CALL_GOTO(gsn_results_frame_read(file, count - 1, &frame), rc, done);
    double u[3] = {0.0, 0.0, 0.0};
    const int *v = m.tetrahedra + 4 * (size_t)best;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j)
            u[j] += best_w[k] *
                    frame.field[GSN_FRAME_DISPLACEMENT][3 * (size_t)v[k] + j];
    *value = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
done:
    gsn_h5_close(&file);
    gsn_frame_free(&frame);
    gsn_model_free(&m);
    return rc;
}

int gsn_quantity_measure(const char *outdir, const struct gsn_case *c,
                         const struct gsn_quantity *q, double *value)
{
    GSN_CHECK(q->kind != GSN_QUANTITY_FACTOR_OF_SAFETY, GSN_ERR_INTERNAL,
              "the factor of safety is a study's, not a run's");
    if (q->kind == GSN_QUANTITY_DISPLACEMENT_AT)
        GSN_CALL(displacement_measure(outdir, c, q, value));
    else
        GSN_CALL(force_measure(outdir, c, q, value));
    return GSN_OK;
}
