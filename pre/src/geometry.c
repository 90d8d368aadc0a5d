/* Checks of the geometry (geometry.h). Each names the file and the gmsh
 * entities, and says what to change: gmsh itself reports these mistakes,
 * if at all, as a failure deep in its mesher ("Unable to recover the
 * edge"), an abort, or a mesh with a crack. */
#include "geometry.h"
#include "estimate.h"
#include "geoscni/error.h"

#include <ctype.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    GMSH_LINE = 1,
    GMSH_TRIANGLE = 2,
    GMSH_TETRAHEDRON = 4,
    GMSH_ALGORITHM_DELAUNAY = 1,
    COARSE_DIVISIONS = 8, /* coarse mesh size: the diagonal / 8 */
    LIST_SIZE = 256
};

/* Coplanar triangles of two volumes lie on each other when a centroid of
 * one is this close (fraction of the diagonal) to the other... */
#define GEOMETRY_TOUCH 1e-9
/* ... and their normals are parallel to this. */
#define GEOMETRY_PARALLEL 1e-9

#define GMSH_OK(ierr, ...) GSN_CHECK((ierr) == 0, GSN_ERR_LIBRARY, __VA_ARGS__)

void geometry_gmsh_last_error(char *out, size_t size)
{
    int ierr = 0;
    char *message = NULL;
    gmshLoggerGetLastError(&message, &ierr);
    snprintf(out, size, "%s",
             ierr == 0 && message && message[0] ? message : "no message");
    gmshFree(message);
}

void coarse_mesh_free(struct coarse_mesh *m)
{
    free(m->position);
    free(m->tetrahedra);
    free(m->triangles);
    free(m->triangle_surface);
    free(m->segments);
    memset(m, 0, sizeof *m);
}

static int model_box(double box[6])
{
    int ierr = 0;
    gmshModelGetBoundingBox(-1, -1, &box[0], &box[1], &box[2], &box[3], &box[4],
                            &box[5], &ierr);
    GMSH_OK(ierr, "cannot get the bounding box of the geometry");
    return GSN_OK;
}

/* The union of the volumes' bounding boxes. */
static int volume_box(double box[6])
{
    int *volumes = NULL, ierr = 0;
    size_t count = 0;
    gmshModelGetEntities(&volumes, &count, 3, &ierr);
    GMSH_OK(ierr, "cannot list the volumes");
    for (int k = 0; k < 3; ++k) {
        box[k] = HUGE_VAL;
        box[k + 3] = -HUGE_VAL;
    }
    for (size_t v = 0; v + 1 < count && ierr == 0; v += 2) {
        double b[6];
        gmshModelGetBoundingBox(3, volumes[v + 1], &b[0], &b[1], &b[2], &b[3],
                                &b[4], &b[5], &ierr);
        for (int k = 0; k < 3; ++k) {
            box[k] = fmin(box[k], b[k]);
            box[k + 3] = fmax(box[k + 3], b[k + 3]);
        }
    }
    gmshFree(volumes);
    GMSH_OK(ierr, "cannot get the bounding boxes of the volumes");
    return GSN_OK;
}

static double box_diagonal(const double box[6])
{
    double sum = 0.0;
    for (int k = 0; k < 3; ++k)
        sum += (box[k + 3] - box[k]) * (box[k + 3] - box[k]);
    return sqrt(sum);
}

/* The smallest spacing the case asks for anywhere. */
static double smallest_spacing(const struct gsn_case *c)
{
    double h = c->particle_spacing;
    for (int i = 0; i < c->refinement_count; ++i)
        h = fmin(h, c->refinements[i].spacing);
    return h;
}

static int check_position(const struct gsn_case *c, const double box[6])
{
    double centre[3], offset = 0.0;
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5 * (box[k] + box[k + 3]);
        offset += centre[k] * centre[k];
    }
    offset = sqrt(offset);
    double h = smallest_spacing(c);
    GSN_CHECK(offset <= GEOMETRY_FAR_SPACINGS * h, GSN_ERR_INPUT,
              "%s: the geometry lies %.3g m from the origin, %.2g particle "
              "spacings of %g m (its bounding box: x %.10g to %.10g, y %.10g "
              "to %.10g, z %.10g to %.10g); at such coordinates the particles' "
              "nodal domains lose the digits they need: translate the geometry "
              "near the origin, e.g. subtract (%.0f, %.0f, %.0f) from its "
              "coordinates",
              c->geometry, offset, offset / h, h, box[0], box[3], box[1],
              box[4], box[2], box[5], floor(box[0]), floor(box[1]),
              floor(box[2]));
    return GSN_OK;
}

static int check_spacing(const struct gsn_case *c)
{
    double box[6];
    GSN_CALL(volume_box(box));
    int thin = 0;
    for (int k = 1; k < 3; ++k)
        if (box[k + 3] - box[k] < box[thin + 3] - box[thin])
            thin = k;
    double thickness = box[thin + 3] - box[thin];
    char where[GSN_PATH_SIZE + 32];
    if (c->particle_spacing_line > 0)
        snprintf(where, sizeof where, "%s:%d", c->path,
                 c->particle_spacing_line);
    else
        snprintf(where, sizeof where, "%s", c->path);
    GSN_CHECK(c->particle_spacing <= thickness, GSN_ERR_INPUT,
              "%s: 'particles.spacing' (%g m) is larger than the body of %s, "
              "which is %g m across in %c (its bounding box is %g x %g x %g "
              "m); use a spacing of at most %.2g m (4 particles across)",
              where, c->particle_spacing, c->geometry, thickness, "xyz"[thin],
              box[3] - box[0], box[4] - box[1], box[5] - box[2],
              0.25 * thickness);
    return GSN_OK;
}

struct point {
    int tag;
    double x[3];
};

static int compare_points(const void *a, const void *b)
{
    double x = ((const struct point *)a)->x[0];
    double y = ((const struct point *)b)->x[0];
    return (x > y) - (x < y);
}

/* A curve whose end points are p and q, or 0. */
static int curve_joining(int p, int q)
{
    int *up = NULL, *down = NULL, ierr = 0, found = 0;
    size_t up_count = 0, down_count = 0;
    gmshModelGetAdjacencies(0, p, &up, &up_count, &down, &down_count, &ierr);
    for (size_t i = 0; ierr == 0 && i < up_count && !found; ++i) {
        int *ends = NULL, curve[2] = {1, up[i]};
        size_t end_count = 0;
        gmshModelGetBoundary(curve, 2, &ends, &end_count, 0, 0, 0, &ierr);
        for (size_t e = 0; ierr == 0 && e + 1 < end_count; e += 2)
            if (ends[e + 1] == q)
                found = up[i];
        gmshFree(ends);
    }
    gmshFree(up);
    gmshFree(down);
    return found;
}

/* No two points that end curves at one place. */
static int check_points(const struct gsn_case *c, double diagonal)
{
    int *tags = NULL, ierr = 0, rc = GSN_OK;
    size_t count = 0, n = 0;
    gmshModelGetEntities(&tags, &count, 0, &ierr);
    GMSH_OK(ierr, "cannot list the points");
    struct point *points = malloc(sizeof *points * (count / 2 + 1));
    GSN_CHECK_GOTO(points != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu points", count / 2);
    for (size_t i = 0; i + 1 < count; i += 2) {
        int *up = NULL, *down = NULL;
        size_t up_count = 0, down_count = 0;
        double *x = NULL;
        size_t x_count = 0;
        gmshModelGetAdjacencies(0, tags[i + 1], &up, &up_count, &down,
                                &down_count, &ierr);
        if (ierr == 0 && up_count > 0)
            gmshModelGetValue(0, tags[i + 1], NULL, 0, &x, &x_count, &ierr);
        if (ierr == 0 && x_count == 3) {
            points[n].tag = tags[i + 1];
            memcpy(points[n++].x, x, sizeof(double[3]));
        }
        gmshFree(up);
        gmshFree(down);
        gmshFree(x);
        GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                       "cannot read point %d", tags[i + 1]);
    }
    qsort(points, n, sizeof *points, compare_points);
    double tolerance = GEOMETRY_SAME_POINT * diagonal;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1;
             j < n && points[j].x[0] - points[i].x[0] <= tolerance; ++j) {
            const double *a = points[i].x, *b = points[j].x;
            if (fabs(a[1] - b[1]) > tolerance || fabs(a[2] - b[2]) > tolerance)
                continue;
            int p =
                points[i].tag < points[j].tag ? points[i].tag : points[j].tag;
            int q = points[i].tag + points[j].tag - p;
            int curve = curve_joining(p, q);
            if (curve)
                GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                               "%s: curve %d has zero length: it joins points "
                               "%d and %d, which are both at (%.10g, %.10g, "
                               "%.10g); use one point there and drop the "
                               "curve",
                               c->geometry, curve, p, q, a[0], a[1], a[2]);
            GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                           "%s: points %d and %d are both at (%.10g, %.10g, "
                           "%.10g); use one point there (curves that meet "
                           "must share their end point)",
                           c->geometry, p, q, a[0], a[1], a[2]);
        }
done:
    free(points);
    gmshFree(tags);
    return rc;
}

int geometry_check(const struct gsn_case *c)
{
    double box[6];
    GSN_CALL(model_box(box));
    GSN_CALL(check_position(c, box));
    GSN_CALL(check_points(c, box_diagonal(box)));
    GSN_CALL(check_spacing(c));
    return GSN_OK;
}

/* ---- the coarse mesh --------------------------------------------------- */

/* Node tag -> index into m->position, -1: none. */
struct node_index {
    size_t limit;
    int *index;
};

static int read_nodes(struct coarse_mesh *m, struct node_index *map)
{
    int ierr = 0, rc = GSN_OK;
    size_t *tags = NULL, count = 0, coord_n = 0, parametric_n = 0;
    double *coord = NULL, *parametric = NULL;
    gmshModelMeshGetNodes(&tags, &count, &coord, &coord_n, &parametric,
                          &parametric_n, -1, -1, 0, 0, &ierr);
    GSN_CHECK_GOTO(ierr == 0 && coord_n == 3 * count, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the coarse mesh's nodes");
    map->limit = 1;
    for (size_t i = 0; i < count; ++i)
        map->limit = tags[i] + 1 > map->limit ? tags[i] + 1 : map->limit;
    map->index = malloc(sizeof(int) * map->limit);
    m->position = malloc(sizeof(double) * (coord_n + 1));
    GSN_CHECK_GOTO(map->index && m->position, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu coarse nodes", count);
    for (size_t t = 0; t < map->limit; ++t)
        map->index[t] = -1;
    for (size_t i = 0; i < count; ++i)
        map->index[tags[i]] = (int)i;
    memcpy(m->position, coord, sizeof(double) * coord_n);
    m->node_count = (int)count;
done:
    gmshFree(tags);
    gmshFree(coord);
    gmshFree(parametric);
    return rc;
}

/* Appends the elements of a type (n nodes each) of entity tag (-1: all) to
 * *list (*count elements); *owner (if not NULL) gets owner_tag. */
static int read_elements(const struct node_index *map, int type, int n, int tag,
                         int **list, int *count, int **owner, int owner_tag)
{
    size_t *elements = NULL, element_count = 0, *nodes = NULL, node_count = 0;
    int ierr = 0, rc = GSN_OK;
    gmshModelMeshGetElementsByType(type, &elements, &element_count, &nodes,
                                   &node_count, tag, 0, 1, &ierr);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the coarse mesh's elements of type %d", type);
    size_t add = node_count / (size_t)n, total = (size_t)*count + add;
    int *grown = realloc(*list, sizeof(int) * (size_t)n * (total + 1));
    GSN_CHECK_GOTO(grown != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu coarse elements", total);
    *list = grown;
    if (owner) {
        int *owners = realloc(*owner, sizeof(int) * (total + 1));
        GSN_CHECK_GOTO(owners != NULL, rc, GSN_ERR_MEMORY, done,
                       "cannot allocate %zu coarse elements", total);
        *owner = owners;
    }
    for (size_t e = 0; e < add; ++e) {
        for (int k = 0; k < n; ++k) {
            size_t t = nodes[(size_t)n * e + k];
            int index = t < map->limit ? map->index[t] : -1;
            GSN_CHECK_GOTO(index >= 0, rc, GSN_ERR_LIBRARY, done,
                           "a coarse element has an unknown node %zu", t);
            (*list)[(size_t)n * ((size_t)*count + e) + k] = index;
        }
        if (owner)
            (*owner)[(size_t)*count + e] = owner_tag;
    }
    *count = (int)total;
done:
    gmshFree(elements);
    gmshFree(nodes);
    return rc;
}

/* The gmsh volumes a surface bounds: count and the first two. */
static int surface_volumes(int surface, int volumes[2], int *count)
{
    int *up = NULL, *down = NULL, ierr = 0;
    size_t up_count = 0, down_count = 0;
    gmshModelGetAdjacencies(2, surface, &up, &up_count, &down, &down_count,
                            &ierr);
    *count = (int)up_count;
    for (size_t i = 0; i < 2; ++i)
        volumes[i] = i < up_count ? up[i] : -1;
    gmshFree(up);
    gmshFree(down);
    GMSH_OK(ierr, "cannot get the volumes of surface %d", surface);
    return GSN_OK;
}

/* Everything of the current mesh: nodes, tetrahedra, the triangles of the
 * surfaces that bound a volume, the segments of the curves. */
static int read_mesh(struct coarse_mesh *m)
{
    struct node_index map = {0, NULL};
    int *surfaces = NULL, ierr = 0, rc = GSN_OK;
    size_t surface_count = 0;
    GSN_CALL_GOTO(read_nodes(m, &map), rc, done);
    GSN_CALL_GOTO(read_elements(&map, GMSH_TETRAHEDRON, 4, -1, &m->tetrahedra,
                                &m->tetrahedron_count, NULL, 0),
                  rc, done);
    GSN_CALL_GOTO(read_elements(&map, GMSH_LINE, 2, -1, &m->segments,
                                &m->segment_count, NULL, 0),
                  rc, done);
    gmshModelGetEntities(&surfaces, &surface_count, 2, &ierr);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot list the surfaces");
    for (size_t s = 0; s + 1 < surface_count; s += 2) {
        int volumes[2], count = 0;
        GSN_CALL_GOTO(surface_volumes(surfaces[s + 1], volumes, &count), rc,
                      done);
        if (count > 0)
            GSN_CALL_GOTO(read_elements(&map, GMSH_TRIANGLE, 3, surfaces[s + 1],
                                        &m->triangles, &m->triangle_count,
                                        &m->triangle_surface, surfaces[s + 1]),
                          rc, done);
    }
done:
    free(map.index);
    gmshFree(surfaces);
    return rc;
}

/* Appends " %d" to a list of tags unless it holds it. */
static void list_add(char *list, size_t size, int tag)
{
    char item[24];
    snprintf(item, sizeof item, " %d,", tag);
    char padded[LIST_SIZE + 2];
    snprintf(padded, sizeof padded, " %s,", list);
    if (strstr(padded, item))
        return;
    size_t used = strlen(list);
    snprintf(list + used, size - used, "%s%d", used ? ", " : "", tag);
}

static int compare_ints(const void *pa, const void *pb)
{
    int a = *(const int *)pa, b = *(const int *)pb;
    return (a > b) - (a < b);
}

struct edge {
    int a, b, surface;
};

static int compare_edges(const void *pa, const void *pb)
{
    const struct edge *x = pa, *y = pb;
    if (x->a != y->a)
        return (x->a > y->a) - (x->a < y->a);
    return (x->b > y->b) - (x->b < y->b);
}

/* Every edge of the triangles of volume's boundary surfaces is shared by an
 * even number of them (two, or a seam's pair). */
static int check_closed(const struct gsn_case *c, const struct coarse_mesh *m,
                        int volume)
{
    int dim_tag[2] = {3, volume}, *surfaces = NULL, ierr = 0, rc = GSN_OK;
    size_t count = 0, edge_count = 0;
    gmshModelGetBoundary(dim_tag, 2, &surfaces, &count, 0, 0, 0, &ierr);
    GMSH_OK(ierr, "cannot get the surfaces of volume %d", volume);
    struct edge *edges =
        malloc(sizeof *edges * 3 * ((size_t)m->triangle_count + 1));
    GSN_CHECK_GOTO(edges != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate the edges of volume %d", volume);
    /* the volume's surface tags, sorted, in place of its (dim, tag) pairs */
    size_t n = count / 2;
    for (size_t s = 0; s < n; ++s)
        surfaces[s] = abs(surfaces[2 * s + 1]);
    qsort(surfaces, n, sizeof(int), compare_ints);
    for (int t = 0; t < m->triangle_count; ++t) {
        int bounds = bsearch(&m->triangle_surface[t], surfaces, n, sizeof(int),
                             compare_ints) != NULL;
        for (int k = 0; bounds && k < 3; ++k) {
            int a = m->triangles[3 * t + k],
                b = m->triangles[3 * t + (k + 1) % 3];
            edges[edge_count].a = a < b ? a : b;
            edges[edge_count].b = a < b ? b : a;
            edges[edge_count++].surface = m->triangle_surface[t];
        }
    }
    qsort(edges, edge_count, sizeof *edges, compare_edges);
    char open[LIST_SIZE] = "";
    int open_count = 0, first = -1;
    for (size_t i = 0; i < edge_count;) {
        size_t j = i;
        while (j < edge_count && compare_edges(&edges[i], &edges[j]) == 0)
            ++j;
        if ((j - i) % 2 == 1) {
            if (first < 0)
                first = edges[i].a;
            ++open_count;
            for (size_t k = i; k < j; ++k)
                list_add(open, sizeof open, edges[k].surface);
        }
        i = j;
    }
    if (open_count > 0) {
        const double *x = &m->position[3 * first];
        GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                       "%s: the surfaces do not close a volume: volume %d is "
                       "bounded by surfaces that leave a gap along %d edges of "
                       "their mesh, at the border of surface%s %s (near "
                       "(%.4g, %.4g, %.4g)); add the missing surface to its "
                       "Surface Loop, or make neighbouring surfaces share "
                       "their curves",
                       c->geometry, volume, open_count,
                       strchr(open, ',') ? "s" : "", open, x[0], x[1], x[2]);
    }
done:
    free(edges);
    gmshFree(surfaces);
    return rc;
}

static void triangle_normal(const struct coarse_mesh *m, int t, double n[3],
                            double centroid[3])
{
    const double *a = &m->position[3 * m->triangles[3 * t]];
    const double *b = &m->position[3 * m->triangles[3 * t + 1]];
    const double *p = &m->position[3 * m->triangles[3 * t + 2]];
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = b[k] - a[k];
        v[k] = p[k] - a[k];
        centroid[k] = (a[k] + b[k] + p[k]) / 3.0;
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
        n[k] = length > 0 ? n[k] / length : 0.0;
}

/* No two volumes touch along surfaces of their own: a triangle of a surface
 * that bounds one volume lying on a triangle of a surface that bounds
 * another. */
static int check_touching(const struct gsn_case *c, const struct coarse_mesh *m,
                          double diagonal)
{
    int n = m->triangle_count, rc = GSN_OK;
    int *owner = malloc(sizeof(int) * ((size_t)n + 1));
    double *box = malloc(sizeof(double) * 6 * ((size_t)n + 1));
    GSN_CHECK_GOTO(owner && box, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %d triangles", n);
    for (int t = 0; t < n; ++t) {
        int volumes[2], count = 0;
        /* surfaces come in runs: ask gmsh once per run */
        if (t > 0 && m->triangle_surface[t] == m->triangle_surface[t - 1]) {
            owner[t] = owner[t - 1];
        } else {
            GSN_CALL_GOTO(
                surface_volumes(m->triangle_surface[t], volumes, &count), rc,
                done);
            owner[t] = count == 1 ? volumes[0] : -1;
        }
        for (int k = 0; k < 3; ++k) {
            box[6 * t + k] = HUGE_VAL;
            box[6 * t + k + 3] = -HUGE_VAL;
        }
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) {
                double x = m->position[3 * m->triangles[3 * t + v] + k];
                box[6 * t + k] = fmin(box[6 * t + k], x);
                box[6 * t + k + 3] = fmax(box[6 * t + k + 3], x);
            }
    }
    double tolerance = GEOMETRY_TOUCH * diagonal;
    for (int s = 0; s < n; ++s) {
        if (owner[s] < 0)
            continue;
        double ns[3], cs[3];
        triangle_normal(m, s, ns, cs);
        for (int t = 0; t < n; ++t) {
            if (owner[t] < 0 || owner[t] == owner[s])
                continue;
            int apart = 0;
            for (int k = 0; k < 3 && !apart; ++k)
                apart = cs[k] < box[6 * t + k] - tolerance ||
                        cs[k] > box[6 * t + k + 3] + tolerance;
            if (apart)
                continue;
            double nt[3], ct[3];
            triangle_normal(m, t, nt, ct);
            double parallel =
                fabs(ns[0] * nt[0] + ns[1] * nt[1] + ns[2] * nt[2]);
            if (parallel < 1.0 - GEOMETRY_PARALLEL)
                continue;
            const int *v = &m->triangles[3 * t];
            double d2 = estimate_triangle_distance2(cs, &m->position[3 * v[0]],
                                                    &m->position[3 * v[1]],
                                                    &m->position[3 * v[2]]);
            if (d2 > tolerance * tolerance)
                continue;
            int a = owner[s] < owner[t] ? s : t, b = s + t - a;
            GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                           "%s: volumes %d and %d touch without sharing a "
                           "face (surfaces %d and %d lie on each other near "
                           "(%.4g, %.4g, %.4g)): their particles would not "
                           "hold together; make them share the face, with "
                           "BooleanFragments{ Volume{...}; Delete; }{ } "
                           "(OpenCASCADE kernel) or Coherence; (built-in "
                           "kernel)",
                           c->geometry, owner[a], owner[b],
                           m->triangle_surface[a], m->triangle_surface[b],
                           cs[0], cs[1], cs[2]);
        }
    }
done:
    free(owner);
    free(box);
    return rc;
}

static int generate(int dim, int algorithm)
{
    int ierr = 0;
    gmshOptionSetNumber("Mesh.Algorithm3D", algorithm, &ierr);
    if (ierr == 0)
        gmshModelMeshGenerate(dim, &ierr);
    return ierr;
}

int geometry_coarse_mesh(const struct gsn_case *c, struct coarse_mesh *m)
{
    double box[6];
    int ierr = 0, rc = GSN_OK;
    memset(m, 0, sizeof *m);
    GSN_CALL(model_box(box));
    double diagonal = box_diagonal(box);
    m->size = diagonal / COARSE_DIVISIONS;
    /* the minimum overrides the sizes of the geometry's points */
    gmshOptionSetNumber("Mesh.MeshSizeMin", m->size, &ierr);
    gmshOptionSetNumber("Mesh.MeshSizeMax", m->size, &ierr);
    gmshOptionSetNumber("Mesh.ElementOrder", 1, &ierr);
    gmshOptionSetNumber("Mesh.RecombineAll", 0, &ierr);
    gmshOptionSetNumber("Mesh.Recombine3DAll", 0, &ierr);
    GMSH_OK(ierr, "cannot set the coarse mesh size");
    char gmsh[512];
    int surfaces_failed = generate(2, GMSH_ALGORITHM_DELAUNAY);
    if (surfaces_failed)
        geometry_gmsh_last_error(gmsh, sizeof gmsh);
    GSN_CHECK(!surfaces_failed, GSN_ERR_INPUT,
              "%s: gmsh cannot mesh the surfaces of the geometry at size %g "
              "m: %s",
              c->geometry, m->size, gmsh);
    GSN_CALL_GOTO(read_mesh(m), rc, done);
    int *volumes = NULL;
    size_t count = 0;
    gmshModelGetEntities(&volumes, &count, 3, &ierr);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot list the volumes");
    for (size_t v = 0; v + 1 < count && rc == GSN_OK; v += 2)
        rc = check_closed(c, m, volumes[v + 1]);
    gmshFree(volumes);
    GSN_CALL_GOTO(rc, rc, done);
    if (count > 2)
        GSN_CALL_GOTO(check_touching(c, m, diagonal), rc, done);
    double size = m->size;
    coarse_mesh_free(m);
    m->size = size;
    int volumes_failed = generate(3, GMSH_ALGORITHM_DELAUNAY);
    if (volumes_failed)
        geometry_gmsh_last_error(gmsh, sizeof gmsh);
    GSN_CHECK(!volumes_failed, GSN_ERR_INPUT,
              "%s: gmsh cannot fill the volumes of the geometry with "
              "tetrahedra at size %g m: %s",
              c->geometry, m->size, gmsh);
    GSN_CALL_GOTO(read_mesh(m), rc, done);
    GSN_CHECK_GOTO(m->tetrahedron_count > 0, rc, GSN_ERR_INPUT, done,
                   "%s: gmsh made no tetrahedra in the geometry's volumes",
                   c->geometry);
done:
    if (rc != GSN_OK)
        coarse_mesh_free(m);
    return rc;
}

int geometry_statement_line(const char *path, const char *word)
{
    FILE *file = fopen(path, "r");
    if (!file)
        return 0;
    char line[4096];
    int number = 0, found = 0;
    size_t length = strlen(word);
    while (!found && fgets(line, sizeof line, file)) {
        ++number;
        const char *p = line;
        while (isspace((unsigned char)*p))
            ++p;
        if (strncmp(p, word, length) != 0)
            continue;
        p += length;
        while (isspace((unsigned char)*p))
            ++p;
        if (*p == ';')
            found = number;
    }
    fclose(file);
    return found;
}
