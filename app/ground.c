/* geoscni ground (issue 22, point 3; docs/site.md): a gmsh geometry of
 * layered ground from survey data. The ground is a grid of elevations
 * (x y z lines); each layer lies under the one above it, a given thickness
 * thick or down to a grid of its own bottom's elevations, the last one down
 * to a level base. The .geo is written in gmsh's built-in kernel from plane
 * pieces alone: two triangles per grid cell on the ground and on every
 * layer's bottom (three points are always in one plane), and on the sides
 * vertical quadrilaterals between grid points. Its named surfaces (ground,
 * base, xmin, xmax, ymin, ymax) and volumes (the layers) are what a case
 * file's boundary: and materials: name. */
#include "app.h"

#include "geoscni/error.h"
#include "geoscni/files.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { GROUND_MAX_LAYERS = 16, GROUND_LINE_SIZE = 1024 };

/* A grid of elevations: z[j nx + i] at (x[i], y[j]). */
struct grid {
    int nx, ny;
    double *x, *y, *z;
};

static void grid_free(struct grid *g)
{
    free(g->x);
    free(g->y);
    free(g->z);
    memset(g, 0, sizeof *g);
}

static int compare_doubles(const void *a, const void *b)
{
    double u = *(const double *)a, v = *(const double *)b;
    return (u > v) - (u < v);
}

/* The distinct values of v (count of them), sorted, merged within tol. */
static int distinct(double *v, int count, double tol)
{
    qsort(v, (size_t)count, sizeof *v, compare_doubles);
    int n = 0;
    for (int k = 0; k < count; ++k)
        if (n == 0 || v[k] - v[n - 1] > tol)
            v[n++] = v[k];
    return n;
}

static int find_value(const double *v, int n, double value, double tol)
{
    int lo = 0, hi = n - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (fabs(v[mid] - value) <= tol)
            return mid;
        if (v[mid] < value)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

/* Reads "x y z" lines (spaces, tabs or commas; # comments) into a full
 * rectangular grid; every message names the file and the line. */
static int grid_read(const char *path, struct grid *g)
{
    memset(g, 0, sizeof *g);
    FILE *file = fopen(path, "r");
    GSN_CHECK(file, errno == ENOENT ? GSN_ERR_INPUT : GSN_ERR_IO,
              "%s: cannot open the elevation grid: %s", path, strerror(errno));
    double *points = NULL;
    int *lines = NULL, count = 0, capacity = 0, line = 0, rc = GSN_OK;
    char text[GROUND_LINE_SIZE];
    while (fgets(text, sizeof text, file)) {
        ++line;
        char *hash = strchr(text, '#');
        if (hash)
            *hash = '\0';
        for (char *c = text; *c; ++c)
            if (*c == ',' || *c == ';' || *c == '\t')
                *c = ' ';
        double v[3];
        char extra[2];
        int read = sscanf(text, "%lf %lf %lf %1s", &v[0], &v[1], &v[2], extra);
        if (read <= 0)
            continue; /* blank */
        GSN_CHECK_GOTO(read == 3 && isfinite(v[0]) && isfinite(v[1]) &&
                           isfinite(v[2]),
                       rc, GSN_ERR_INPUT, done,
                       "%s:%d: expected three numbers 'x y z' (m), got '%.60s'",
                       path, line, strtok(text, "\n"));
        if (count == capacity) {
            capacity = capacity ? 2 * capacity : 1024;
            double *p = realloc(points, sizeof(double) * 3 * (size_t)capacity);
            int *l = realloc(lines, sizeof(int) * (size_t)capacity);
            if (p)
                points = p;
            if (l)
                lines = l;
            GSN_CHECK_GOTO(p && l, rc, GSN_ERR_MEMORY, done, "out of memory");
        }
        memcpy(&points[3 * count], v, sizeof v);
        lines[count++] = line;
    }
    GSN_CHECK_GOTO(count >= 4, rc, GSN_ERR_INPUT, done,
                   "%s: %d points; a grid needs at least 2 x 2", path, count);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < count; ++k)
        for (int a = 0; a < 2; ++a) {
            lo[a] = fmin(lo[a], points[3 * k + a]);
            hi[a] = fmax(hi[a], points[3 * k + a]);
        }
    double tol = 1e-9 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    g->x = malloc(sizeof(double) * (size_t)count);
    g->y = malloc(sizeof(double) * (size_t)count);
    GSN_CHECK_GOTO(g->x && g->y, rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int k = 0; k < count; ++k) {
        g->x[k] = points[3 * k];
        g->y[k] = points[3 * k + 1];
    }
    g->nx = distinct(g->x, count, tol);
    g->ny = distinct(g->y, count, tol);
    GSN_CHECK_GOTO(g->nx >= 2 && g->ny >= 2, rc, GSN_ERR_INPUT, done,
                   "%s: the points lie on one line (%d x values, %d y "
                   "values); a grid spans both",
                   path, g->nx, g->ny);
    GSN_CHECK_GOTO((long)g->nx * g->ny == count, rc, GSN_ERR_INPUT, done,
                   "%s: %d points on %d x values and %d y values: not a full "
                   "grid (%d x %d = %ld points); give every x with every y",
                   path, count, g->nx, g->ny, g->nx, g->ny,
                   (long)g->nx * g->ny);
    g->z = malloc(sizeof(double) * (size_t)count);
    GSN_CHECK_GOTO(g->z, rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int k = 0; k < count; ++k)
        g->z[k] = NAN;
    for (int k = 0; k < count; ++k) {
        int i = find_value(g->x, g->nx, points[3 * k], tol);
        int j = find_value(g->y, g->ny, points[3 * k + 1], tol);
        double *z = &g->z[(size_t)j * g->nx + i];
        GSN_CHECK_GOTO(isnan(*z), rc, GSN_ERR_INPUT, done,
                       "%s:%d: the point (%g, %g) is there twice", path,
                       lines[k], points[3 * k], points[3 * k + 1]);
        *z = points[3 * k + 2];
    }
done:
    fclose(file);
    free(points);
    free(lines);
    if (rc != GSN_OK)
        grid_free(g);
    return rc;
}

/* Every step-th grid line (the last one kept). */
static int grid_thin(struct grid *g, int step)
{
    if (step <= 1)
        return GSN_OK;
    int mx = (g->nx - 1 + step - 1) / step + 1,
        my = (g->ny - 1 + step - 1) / step + 1;
    double *z = malloc(sizeof(double) * (size_t)mx * (size_t)my);
    GSN_CHECK(z, GSN_ERR_MEMORY, "out of memory");
    for (int j = 0; j < my; ++j)
        for (int i = 0; i < mx; ++i) {
            int si = i * step < g->nx ? i * step : g->nx - 1;
            int sj = j * step < g->ny ? j * step : g->ny - 1;
            z[j * mx + i] = g->z[(size_t)sj * g->nx + si];
        }
    for (int i = 0; i < mx; ++i)
        g->x[i] = g->x[i * step < g->nx ? i * step : g->nx - 1];
    for (int j = 0; j < my; ++j)
        g->y[j] = g->y[j * step < g->ny ? j * step : g->ny - 1];
    free(g->z);
    g->z = z;
    g->nx = mx;
    g->ny = my;
    return GSN_OK;
}

struct layer {
    char name[GSN_NAME_SIZE];
    double thickness;   /* m, when > 0 */
    struct grid bottom; /* its bottom's elevations, when given as a file */
};

/* "name:THICKNESS" or "name:FILE.xyz" or "name" (the last: to the base),
 * comma-separated. */
static int layers_parse(const char *text, int step, struct layer *layers,
                        int *count)
{
    *count = 0;
    char *copy = strdup(text);
    GSN_CHECK(copy, GSN_ERR_MEMORY, "out of memory");
    int rc = GSN_OK;
    char *save = NULL;
    for (char *item = strtok_r(copy, ",", &save); item;
         item = strtok_r(NULL, ",", &save)) {
        GSN_CHECK_GOTO(*count < GROUND_MAX_LAYERS, rc, GSN_ERR_INPUT, done,
                       "--layers: more than %d layers", GROUND_MAX_LAYERS);
        struct layer *l = &layers[(*count)++];
        memset(l, 0, sizeof *l);
        char *colon = strchr(item, ':');
        if (colon)
            *colon = '\0';
        GSN_CHECK_GOTO(item[0] && strlen(item) < GSN_NAME_SIZE &&
                           strspn(item, "abcdefghijklmnopqrstuvwxyz"
                                        "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789_") == strlen(item),
                       rc, GSN_ERR_INPUT, done,
                       "--layers: '%s' is not a name (letters, digits and _)",
                       item);
        snprintf(l->name, sizeof l->name, "%s", item);
        if (!colon) {
            GSN_CHECK_GOTO(!strtok_r(NULL, ",", &save), rc, GSN_ERR_INPUT, done,
                           "--layers: '%s' has no thickness, which only the "
                           "last layer may leave out (it reaches the base)",
                           item);
            break;
        }
        char *end = NULL;
        l->thickness = strtod(colon + 1, &end);
        if (end != colon + 1 && *end == '\0') {
            GSN_CHECK_GOTO(l->thickness > 0.0 && isfinite(l->thickness), rc,
                           GSN_ERR_INPUT, done,
                           "--layers: the thickness of '%s' must be positive, "
                           "got %s",
                           l->name, colon + 1);
            continue;
        }
        l->thickness = 0.0;
        GSN_CALL_GOTO(grid_read(colon + 1, &l->bottom), rc, done);
        GSN_CALL_GOTO(grid_thin(&l->bottom, step), rc, done);
    }
done:
    free(copy);
    return rc;
}

/* The .geo's entity numbers: points of level l (0 the ground, L the base)
 * at grid node n, lines and surfaces numbered as written. */
struct writer {
    FILE *out;
    int nx, ny, levels;
    int next_line, next_surface;
    int *horizontal, *diagonal; /* per level: grid lines */
    int *post;                  /* per layer, boundary node: the
                                   vertical line down */
};

static int point_id(const struct writer *w, int level, int i, int j)
{
    return 1 + (level * w->ny + j) * w->nx + i;
}

static int line(struct writer *w, int a, int b)
{
    fprintf(w->out, "Line(%d) = {%d, %d};\n", w->next_line, a, b);
    return w->next_line++;
}

static int plane(struct writer *w, const int *curves, int count)
{
    int id = w->next_surface++;
    fprintf(w->out, "Curve Loop(%d) = {", id);
    for (int k = 0; k < count; ++k)
        fprintf(w->out, "%s%d", k ? ", " : "", curves[k]);
    fprintf(w->out, "};\nPlane Surface(%d) = {%d};\n", id, id);
    return id;
}

/* The boundary nodes in order around the grid: (i, j) pairs, 2 (nx + ny -
 * 2) of them, with the side of the edge that leaves each. */
static int perimeter(int nx, int ny, int *nodes, int *side)
{
    int k = 0;
    for (int i = 0; i < nx - 1; ++i, ++k) { /* y = ymin, x rising */
        nodes[2 * k] = i, nodes[2 * k + 1] = 0, side[k] = 2;
    }
    for (int j = 0; j < ny - 1; ++j, ++k) { /* x = xmax */
        nodes[2 * k] = nx - 1, nodes[2 * k + 1] = j, side[k] = 1;
    }
    for (int i = nx - 1; i > 0; --i, ++k) { /* y = ymax */
        nodes[2 * k] = i, nodes[2 * k + 1] = ny - 1, side[k] = 3;
    }
    for (int j = ny - 1; j > 0; --j, ++k) { /* x = xmin */
        nodes[2 * k] = 0, nodes[2 * k + 1] = j, side[k] = 0;
    }
    return k;
}

static void write_list(FILE *out, const char *what, const char *name,
                       const int *ids, int count)
{
    fprintf(out, "Physical %s(\"%s\") = {", what, name);
    for (int k = 0; k < count; ++k)
        fprintf(out, "%s%d", k ? ", " : "", ids[k]);
    fprintf(out, "};\n");
}

/* Writes the geometry of the levels (z: levels x nx ny; the last the base,
 * flat) to out. */
static int write_geo(FILE *out, const struct grid *g, const double *z,
                     int levels, const struct layer *layers, double spacing,
                     const char *source)
{
    int nx = g->nx, ny = g->ny, cells = (nx - 1) * (ny - 1), rc = GSN_OK;
    int nodes = nx * ny, layer_count = levels - 1;
    int around = 2 * (nx + ny - 2);
    struct writer w = {out, nx, ny, levels, 1, 1, NULL, NULL, NULL};
    int *ring = malloc(sizeof(int) * 2 * (size_t)around);
    int *side = malloc(sizeof(int) * (size_t)around);
    int *top = malloc(sizeof(int) * 2 * (size_t)cells * (size_t)levels);
    int *quad = malloc(sizeof(int) * (size_t)around * (size_t)layer_count);
    w.horizontal = malloc(sizeof(int) * (size_t)nodes * 2 * (size_t)levels);
    w.diagonal = malloc(sizeof(int) * (size_t)cells * (size_t)levels);
    w.post = malloc(sizeof(int) * (size_t)around * (size_t)layer_count);
    GSN_CHECK_GOTO(ring && side && top && quad && w.horizontal && w.diagonal &&
                       w.post,
                   rc, GSN_ERR_MEMORY, done, "out of memory");
    perimeter(nx, ny, ring, side);
    fprintf(out,
            "// Layered ground from %s, written by geoscni ground: %d x %d "
            "grid points, %d layers, built-in kernel (plane pieces only).\n"
            "// Surfaces: ground, base, xmin, xmax, ymin, ymax; volumes: the "
            "layers, top down:",
            source, nx, ny, layer_count);
    for (int l = 0; l < layer_count; ++l)
        fprintf(out, " %s", layers[l].name);
    fprintf(out,
            ".\nDefineConstant[h = %g]; // mesh size, m: geoscni sets it "
            "to particles.spacing\n",
            spacing);
    /* the points: every grid node on every level but the base, whose own
     * are on the perimeter only (it is flat) */
    for (int l = 0; l < levels; ++l)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                int inside = i > 0 && j > 0 && i < nx - 1 && j < ny - 1;
                if (l == levels - 1 && inside)
                    continue;
                fprintf(out, "Point(%d) = {%.17g, %.17g, %.17g, h};\n",
                        point_id(&w, l, i, j), g->x[i], g->y[j],
                        z[(size_t)l * nodes + (size_t)j * nx + i]);
            }
    /* the grid lines of each level: along x, along y, the cells' diagonals
     * (the base: its perimeter only) */
    for (int l = 0; l < levels; ++l) {
        int *h = &w.horizontal[(size_t)l * nodes * 2];
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                int base = l == levels - 1;
                h[2 * (j * nx + i)] =
                    i < nx - 1 && (!base || j == 0 || j == ny - 1)
                        ? line(&w, point_id(&w, l, i, j),
                               point_id(&w, l, i + 1, j))
                        : 0;
                h[2 * (j * nx + i) + 1] =
                    j < ny - 1 && (!base || i == 0 || i == nx - 1)
                        ? line(&w, point_id(&w, l, i, j),
                               point_id(&w, l, i, j + 1))
                        : 0;
            }
        for (int j = 0; j < ny - 1 && l < levels - 1; ++j)
            for (int i = 0; i < nx - 1; ++i)
                w.diagonal[(size_t)l * cells + j * (nx - 1) + i] = line(
                    &w, point_id(&w, l, i, j), point_id(&w, l, i + 1, j + 1));
    }
    /* the triangles of each level but the base, two per cell */
    for (int l = 0; l < levels - 1; ++l) {
        const int *h = &w.horizontal[(size_t)l * nodes * 2];
        for (int j = 0; j < ny - 1; ++j)
            for (int i = 0; i < nx - 1; ++i) {
                int d = w.diagonal[(size_t)l * cells + j * (nx - 1) + i];
                int lower[3] = {h[2 * (j * nx + i)],
                                h[2 * (j * nx + i + 1) + 1], -d};
                int upper[3] = {d, -h[2 * ((j + 1) * nx + i)],
                                -h[2 * (j * nx + i) + 1]};
                int *t = &top[2 * ((size_t)l * cells + j * (nx - 1) + i)];
                t[0] = plane(&w, lower, 3);
                t[1] = plane(&w, upper, 3);
            }
    }
    /* the base: one plane */
    {
        const int *h = &w.horizontal[(size_t)(levels - 1) * nodes * 2];
        int *loop = malloc(sizeof(int) * (size_t)around);
        GSN_CHECK_GOTO(loop, rc, GSN_ERR_MEMORY, done, "out of memory");
        for (int k = 0; k < around; ++k) {
            int i = ring[2 * k], j = ring[2 * k + 1];
            loop[k] = side[k] == 2   ? h[2 * (j * nx + i)]
                      : side[k] == 1 ? h[2 * (j * nx + i) + 1]
                      : side[k] == 3 ? -h[2 * (j * nx + i - 1)]
                                     : -h[2 * ((j - 1) * nx + i) + 1];
        }
        fprintf(out, "// the base\n");
        top[2 * (size_t)(levels - 1) * cells] = plane(&w, loop, around);
        free(loop);
    }
    /* the sides: a vertical line down from every boundary node of each
     * level, and a quadrilateral per boundary edge and layer */
    for (int l = 0; l < layer_count; ++l)
        for (int k = 0; k < around; ++k) {
            int i = ring[2 * k], j = ring[2 * k + 1];
            w.post[(size_t)l * around + k] =
                line(&w, point_id(&w, l, i, j), point_id(&w, l + 1, i, j));
        }
    for (int l = 0; l < layer_count; ++l)
        for (int k = 0; k < around; ++k) {
            int next = (k + 1) % around;
            int i = ring[2 * k], j = ring[2 * k + 1];
            const int *hu = &w.horizontal[(size_t)l * nodes * 2];
            const int *hd = &w.horizontal[(size_t)(l + 1) * nodes * 2];
            int e_up, e_down; /* the edge k -> next on levels l and l + 1 */
            if (side[k] == 2)
                e_up = hu[2 * (j * nx + i)], e_down = hd[2 * (j * nx + i)];
            else if (side[k] == 1)
                e_up = hu[2 * (j * nx + i) + 1],
                e_down = hd[2 * (j * nx + i) + 1];
            else if (side[k] == 3)
                e_up = -hu[2 * (j * nx + i - 1)],
                e_down = -hd[2 * (j * nx + i - 1)];
            else
                e_up = -hu[2 * ((j - 1) * nx + i) + 1],
                e_down = -hd[2 * ((j - 1) * nx + i) + 1];
            int curves[4] = {e_up, w.post[(size_t)l * around + next], -e_down,
                             -w.post[(size_t)l * around + k]};
            quad[(size_t)l * around + k] = plane(&w, curves, 4);
        }
    /* the layers' volumes */
    for (int l = 0; l < layer_count; ++l) {
        fprintf(out, "Surface Loop(%d) = {", l + 1);
        int bottom_count = l + 1 == levels - 1 ? 1 : 2 * cells;
        for (int k = 0; k < 2 * cells; ++k)
            fprintf(out, "%s%d", k ? ", " : "", top[2 * (size_t)l * cells + k]);
        for (int k = 0; k < bottom_count; ++k)
            fprintf(out, ", %d", top[2 * (size_t)(l + 1) * cells + k]);
        for (int k = 0; k < around; ++k)
            fprintf(out, ", %d", quad[(size_t)l * around + k]);
        fprintf(out, "};\nVolume(%d) = {%d};\n", l + 1, l + 1);
    }
    write_list(out, "Surface", "ground", top, 2 * cells);
    write_list(out, "Surface", "base", &top[2 * (size_t)(levels - 1) * cells],
               1);
    static const char *const side_name[4] = {"xmin", "xmax", "ymin", "ymax"};
    int *ids = malloc(sizeof(int) * (size_t)around * (size_t)layer_count);
    GSN_CHECK_GOTO(ids, rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int s = 0; s < 4; ++s) {
        int n = 0;
        for (int l = 0; l < layer_count; ++l)
            for (int k = 0; k < around; ++k)
                if (side[k] == s)
                    ids[n++] = quad[(size_t)l * around + k];
        write_list(out, "Surface", side_name[s], ids, n);
    }
    free(ids);
    for (int l = 0; l < layer_count; ++l) {
        int id = l + 1;
        write_list(out, "Volume", layers[l].name, &id, 1);
    }
done:
    free(ring);
    free(side);
    free(top);
    free(quad);
    free(w.horizontal);
    free(w.diagonal);
    free(w.post);
    return rc;
}

int command_ground(const struct arguments *a)
{
    const char *source = a->cases[0];
    GSN_CHECK(a->layers, GSN_ERR_INPUT,
              "ground needs --layers, e.g. --layers fill:2,clay:6,rock (each "
              "layer's thickness in m, or a grid file of its bottom's "
              "elevations; the last one reaches --base)");
    GSN_CHECK(a->has_base, GSN_ERR_INPUT,
              "ground needs --base Z: the elevation of the model's level "
              "bottom, m");
    int step = a->every > 0 ? a->every : 1;
    struct grid g;
    struct layer layers[GROUND_MAX_LAYERS];
    int count = 0, rc = GSN_OK;
    double *z = NULL;
    memset(layers, 0, sizeof layers);
    GSN_CALL(grid_read(source, &g));
    GSN_CALL_GOTO(grid_thin(&g, step), rc, done);
    GSN_CALL_GOTO(layers_parse(a->layers, step, layers, &count), rc, done);
    GSN_CHECK_GOTO(count >= 1 && layers[count - 1].thickness == 0.0 &&
                       layers[count - 1].bottom.z == NULL,
                   rc, GSN_ERR_INPUT, done,
                   "--layers: give the last layer without a thickness (it "
                   "reaches the base at %g m), e.g. --layers %s,rock",
                   a->base, a->layers);
    int nodes = g.nx * g.ny, levels = count + 1;
    z = malloc(sizeof(double) * (size_t)nodes * (size_t)levels);
    GSN_CHECK_GOTO(z, rc, GSN_ERR_MEMORY, done, "out of memory");
    memcpy(z, g.z, sizeof(double) * (size_t)nodes);
    for (int l = 0; l < count; ++l) {
        const struct layer *layer = &layers[l];
        GSN_CHECK_GOTO(!layer->bottom.z || (layer->bottom.nx == g.nx &&
                                            layer->bottom.ny == g.ny),
                       rc, GSN_ERR_INPUT, done,
                       "--layers: the bottom of '%s' is a %d x %d grid, the "
                       "ground %d x %d: give it on the ground's grid",
                       layer->name, layer->bottom.nx, layer->bottom.ny, g.nx,
                       g.ny);
        for (int n = 0; n < nodes; ++n) {
            double above = z[(size_t)l * nodes + n];
            double below = layer->bottom.z    ? layer->bottom.z[n]
                           : layer->thickness ? above - layer->thickness
                                              : a->base;
            GSN_CHECK_GOTO(
                below < above - 1e-6 * fabs(above - a->base) &&
                    below >= a->base,
                rc, GSN_ERR_INPUT, done,
                "%s: at (%g, %g) the layer '%s' would run from "
                "%g m down to %g m: %s",
                source, g.x[n % g.nx], g.y[n / g.nx], layer->name, above, below,
                below < a->base ? "below --base; give a lower base or thinner "
                                  "layers"
                                : "no thickness (layers that pinch out are not "
                                  "supported: give it some thickness there)");
            z[(size_t)(l + 1) * nodes + n] = below;
        }
    }
    double spacing = INFINITY;
    for (int i = 0; i + 1 < g.nx; ++i)
        spacing = fmin(spacing, g.x[i + 1] - g.x[i]);
    for (int j = 0; j + 1 < g.ny; ++j)
        spacing = fmin(spacing, g.y[j + 1] - g.y[j]);
    char path[GSN_PATH_SIZE], temporary[GSN_PATH_SIZE];
    if (a->outdir)
        snprintf(path, sizeof path, "%s", a->outdir);
    else {
        snprintf(path, sizeof path, "%s", source);
        char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
        if (dot && (!slash || dot > slash))
            *dot = '\0';
        strncat(path, ".geo", sizeof path - strlen(path) - 1);
    }
    GSN_CALL_GOTO(gsn_path_temporary(temporary, sizeof temporary, path), rc,
                  done);
    FILE *out = fopen(temporary, "w");
    GSN_CHECK_GOTO(out, rc, GSN_ERR_IO, done, "%s: cannot create: %s",
                   temporary, strerror(errno));
    rc = write_geo(out, &g, z, levels, layers, spacing, source);
    if (fclose(out) != 0 && rc == GSN_OK)
        rc =
            gsn_error_raise(GSN_ERR_IO, __FILE__, __LINE__, __func__,
                            "%s: cannot write: %s", temporary, strerror(errno));
    if (rc == GSN_OK)
        rc = gsn_file_commit(path);
    else
        gsn_file_discard(path);
    GSN_CALL_GOTO(rc, rc, done);
    if (!a->quiet) {
        printf("ground: %s: %d x %d points (x %g to %g m, y %g to %g m)",
               source, g.nx, g.ny, g.x[0], g.x[g.nx - 1], g.y[0],
               g.y[g.ny - 1]);
        if (step > 1)
            printf(", every %d-th grid line", step);
        printf("\n");
        printf("ground: layers");
        for (int l = 0; l < count; ++l) {
            if (layers[l].bottom.z)
                printf(" %s (to the grid of its bottom)", layers[l].name);
            else if (layers[l].thickness > 0.0)
                printf(" %s %g m", layers[l].name, layers[l].thickness);
            else
                printf(" %s (to the base at %g m)", layers[l].name, a->base);
            printf("%s", l + 1 < count ? "," : "\n");
        }
        printf("ground: -> %s: surfaces ground, base, xmin, xmax, ymin, ymax; "
               "volumes",
               path);
        for (int l = 0; l < count; ++l)
            printf(" %s", layers[l].name);
        printf(" (the grid's spacing %g m is the finest particles.spacing "
               "that follows it)\n",
               spacing);
    }
done:
    free(z);
    grid_free(&g);
    for (int l = 0; l < count; ++l)
        grid_free(&layers[l].bottom);
    return rc;
}
