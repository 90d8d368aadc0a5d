/* pre: the driver (issue 3). Loads the geometry with the gmsh C API, meshes
 * it with tetrahedra at particles.spacing (HXT on one gmsh thread; gmsh's
 * Delaunay where the same input must give the same particles), takes the
 * mesh nodes as particles, builds the
 * nodal domains (domains.c), tags boundary particles and facets with the
 * physical surfaces, checks the model and writes model.h5 atomically.
 * gmsh 4.8 pitfalls: TOOLCHAIN.md, "gmsh 4.8 C API". */
#include "geoscni/pre.h"
#include "geoscni/cells.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "refine.h"

#include <fenv.h>
#include <gmshc.h>
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    GMSH_TRIANGLE = 2,    /* 3-node triangle */
    GMSH_TETRAHEDRON = 4, /* 4-node tetrahedron */
    GMSH_ALGORITHM_DELAUNAY = 1,
    GMSH_ALGORITHM_HXT = 10,
    COARSE_DIVISIONS = 8 /* size of the volume-estimate mesh: diagonal / 8 */
};

/* The last message gmsh logged as an error, or a placeholder. */
static void gmsh_last_error(char *out, size_t size)
{
    int ierr = 0;
    char *message = NULL;
    gmshLoggerGetLastError(&message, &ierr);
    snprintf(out, size, "%s",
             ierr == 0 && message && message[0] ? message : "no message");
    gmshFree(message);
}

/* Raises code with the message and gmsh's last error appended. */
static int gmsh_raise(int code, const char *file, int line, const char *func,
                      const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static int gmsh_raise(int code, const char *file, int line, const char *func,
                      const char *format, ...)
{
    char what[1024], gmsh[512];
    va_list args;
    va_start(args, format);
    vsnprintf(what, sizeof what, format, args);
    va_end(args);
    gmsh_last_error(gmsh, sizeof gmsh);
    return gsn_error_raise(code, file, line, func, "%s (gmsh: %s)", what, gmsh);
}

/* Checks gmsh's ierr; code says whose fault a failure is. */
#define GMSH_CHECK(ierr, code, ...)                                            \
    do {                                                                       \
        if ((ierr) != 0)                                                       \
            return gmsh_raise((code), __FILE__, __LINE__, __func__,            \
                              __VA_ARGS__);                                    \
    } while (0)

struct mesh {
    int node_count; /* particles */
    double *position;
    int tetrahedron_count;
    int *tetrahedra;
    int *face_label; /* 4 per tetrahedron, see gsn_cells_body */
    int surface_count;
    char (*surface_name)[GSN_H5_STRING_SIZE];
    int *surface_tag;
    int *particle_surface_offset, *particle_surface;
};

static void mesh_free(struct mesh *m)
{
    free(m->position);
    free(m->tetrahedra);
    free(m->face_label);
    free(m->surface_name);
    free(m->surface_tag);
    free(m->particle_surface_offset);
    free(m->particle_surface);
    memset(m, 0, sizeof *m);
}

/* ---- faces of the tetrahedra: a hash of sorted node triples ------------- */

struct face_hash {
    size_t size; /* power of two */
    int *key;    /* 3 per slot, key[3 i] = -1: empty */
    int *value;
};

static void face_sort(const int v[3], int key[3])
{
    int a = v[0], b = v[1], c = v[2], t;
    if (a > b) {
        t = a;
        a = b;
        b = t;
    }
    if (b > c) {
        t = b;
        b = c;
        c = t;
    }
    if (a > b) {
        t = a;
        a = b;
        b = t;
    }
    key[0] = a;
    key[1] = b;
    key[2] = c;
}

/* The slot of key: where it is, or the empty slot where it would go. */
static size_t face_slot(const struct face_hash *h, const int key[3])
{
    uint64_t x = ((uint64_t)(unsigned)key[0] * 0x9E3779B97F4A7C15ull) ^
                 ((uint64_t)(unsigned)key[1] * 0xC2B2AE3D27D4EB4Full) ^
                 ((uint64_t)(unsigned)key[2] * 0x165667B19E3779F9ull);
    size_t i = (size_t)(x ^ (x >> 29)) & (h->size - 1);
    while (h->key[3 * i] != -1 &&
           (h->key[3 * i] != key[0] || h->key[3 * i + 1] != key[1] ||
            h->key[3 * i + 2] != key[2]))
        i = (i + 1) & (h->size - 1);
    return i;
}

static int face_found(const struct face_hash *h, size_t slot)
{
    return h->key[3 * slot] != -1;
}

static void face_insert(struct face_hash *h, size_t slot, const int key[3],
                        int value)
{
    memcpy(&h->key[3 * slot], key, sizeof(int[3]));
    h->value[slot] = value;
}

static int face_hash_create(struct face_hash *h, size_t entries)
{
    h->size = 1024;
    while (h->size < 2 * entries)
        h->size *= 2;
    h->key = malloc(sizeof(int) * 3 * h->size);
    h->value = malloc(sizeof(int) * h->size);
    GSN_CHECK(h->key && h->value, GSN_ERR_MEMORY,
              "cannot allocate a hash of %zu faces", entries);
    for (size_t i = 0; i < h->size; ++i)
        h->key[3 * i] = -1;
    return GSN_OK;
}

static void face_hash_free(struct face_hash *h)
{
    free(h->key);
    free(h->value);
    memset(h, 0, sizeof *h);
}

/* ---- gmsh -------------------------------------------------------------- */

/* What gmsh changes in the caller's process while it runs: it computes with
 * floating-point exceptions (HXT divides by zero), so the caller's traps
 * are held, and it sets OpenMP's thread count to its General.NumThreads,
 * so the caller's count (geoscni run solves next) is given back. */
struct gmsh_session {
    fenv_t environment;
    int threads;
};

static int gmsh_session_begin(struct gmsh_session *s, int argc, char **argv)
{
    int ierr = 0;
    s->threads = omp_get_max_threads();
    feholdexcept(&s->environment);
    gmshInitialize(argc, argv, 0, &ierr);
    if (ierr != 0) {
        fesetenv(&s->environment);
        omp_set_num_threads(s->threads);
    }
    GSN_CHECK(ierr == 0, GSN_ERR_LIBRARY, "gmsh could not be initialized");
    return GSN_OK;
}

/* A session for the case: a .geo file's DefineConstant[h = ...] takes the
 * spacing; in gmsh 4.8 only "-setnumber" does this (gmshOnelabSetNumber
 * before gmshOpen does not reach the parser). */
static int gmsh_session_begin_case(struct gmsh_session *s,
                                   const struct gsn_case *c)
{
    char spacing[64];
    snprintf(spacing, sizeof spacing, "%.17g", c->particle_spacing);
    char *argv[] = {"geoscni", "-setnumber", "h", spacing, NULL};
    GSN_CALL(gmsh_session_begin(s, 4, argv));
    return GSN_OK;
}

static void gmsh_session_end(struct gmsh_session *s)
{
    int ierr = 0;
    gmshFinalize(&ierr);
    fesetenv(&s->environment);
    omp_set_num_threads(s->threads);
}

static int gmsh_open_geometry(const struct gsn_case *c)
{
    int ierr = 0;
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    gmshOptionSetNumber("General.Verbosity", 1, &ierr);
    /* gmsh asks on stdin before meshing a geometry whose point sizes (h,
     * the spacing) are tiny against its size; without a popup it takes the
     * default, continue: the estimate's mesh is coarse whatever h is, and
     * the particle count limit refuses a huge real one */
    gmshOptionSetNumber("General.NoPopup", 1, &ierr);
    /* one thread: the same input gives the same mesh (TOOLCHAIN.md) */
    gmshOptionSetNumber("General.NumThreads", 1, &ierr);
    gmshOptionSetNumber("Mesh.MaxNumThreads1D", 1, &ierr);
    gmshOptionSetNumber("Mesh.MaxNumThreads2D", 1, &ierr);
    gmshOptionSetNumber("Mesh.MaxNumThreads3D", 1, &ierr);
    /* the generator's state survives gmshFinalize: reset it every run */
    gmshOptionSetNumber("Mesh.RandomSeed", 1, &ierr);
    srand(1);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot set the gmsh options");
    gmshOpen(c->geometry, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_INPUT, "%s:%d: gmsh cannot read the geometry %s",
               c->path, c->geometry_line, c->geometry);
    int *dim_tags = NULL;
    size_t count = 0;
    gmshModelGetEntities(&dim_tags, &count, 3, &ierr);
    gmshFree(dim_tags);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the volumes");
    GSN_CHECK(count > 0, GSN_ERR_INPUT,
              "%s:%d: the geometry %s has no volume to fill with particles",
              c->path, c->geometry_line, c->geometry);
    return GSN_OK;
}

static int gmsh_set_size(double min, double max)
{
    int ierr = 0;
    gmshOptionSetNumber("Mesh.MeshSizeMin", min, &ierr);
    gmshOptionSetNumber("Mesh.MeshSizeMax", max, &ierr);
    /* linear tetrahedra only, whatever the geometry file asks for */
    gmshOptionSetNumber("Mesh.ElementOrder", 1, &ierr);
    gmshOptionSetNumber("Mesh.RecombineAll", 0, &ierr);
    gmshOptionSetNumber("Mesh.Recombine3DAll", 0, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot set the mesh size");
    return GSN_OK;
}

/* Sum of |volume| of the tetrahedra of the current mesh. */
static int gmsh_mesh_volume(double *volume)
{
    int ierr = 0;
    size_t *elements = NULL, element_count = 0, *nodes = NULL, node_count = 0;
    size_t *tags = NULL, tag_count = 0;
    double *coord = NULL, *parametric = NULL;
    size_t coord_n = 0, parametric_n = 0;
    gmshModelMeshGetElementsByType(GMSH_TETRAHEDRON, &elements, &element_count,
                                   &nodes, &node_count, -1, 0, 1, &ierr);
    if (ierr == 0)
        gmshModelMeshGetNodes(&tags, &tag_count, &coord, &coord_n, &parametric,
                              &parametric_n, -1, -1, 0, 0, &ierr);
    double sum = 0.0;
    size_t limit = 0;
    for (size_t i = 0; ierr == 0 && i < tag_count; ++i)
        limit = tags[i] + 1 > limit ? tags[i] + 1 : limit;
    size_t *row = ierr == 0 ? malloc(sizeof(size_t) * (limit + 1)) : NULL;
    if (row) {
        for (size_t i = 0; i < tag_count; ++i)
            row[tags[i]] = i;
        for (size_t t = 0; t + 3 < node_count; t += 4) {
            const double *x0 = &coord[3 * row[nodes[t]]];
            double e[3][3];
            for (int k = 0; k < 3; ++k)
                for (int j = 0; j < 3; ++j)
                    e[k][j] = coord[3 * row[nodes[t + k + 1]] + j] - x0[j];
            sum += fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                        e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                        e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                   6.0;
        }
    }
    free(row);
    gmshFree(elements);
    gmshFree(nodes);
    gmshFree(tags);
    gmshFree(coord);
    gmshFree(parametric);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot read the mesh");
    GSN_CHECK(row != NULL, GSN_ERR_MEMORY, "cannot allocate %zu node tags",
              limit);
    *volume = sum;
    return GSN_OK;
}

/* Meshes the volume. HXT is fast but, in gmsh 4.8, not reproducible even
 * on one thread (the node count of the L-shape varies by 1 % from run to
 * run); Delaunay on one thread is, and about 5 times slower. HXT falls back
 * to Delaunay where it fails. */
static int gmsh_generate(const struct gsn_case *c, int reproducible)
{
    int ierr = 0;
    gmshOptionSetNumber(
        "Mesh.Algorithm3D",
        reproducible ? GMSH_ALGORITHM_DELAUNAY : GMSH_ALGORITHM_HXT, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot set Mesh.Algorithm3D");
    gmshModelMeshGenerate(3, &ierr);
    if (ierr != 0 && !reproducible) {
        ierr = 0;
        gmshModelMeshClear(NULL, 0, &ierr);
        gmshOptionSetNumber("Mesh.Algorithm3D", GMSH_ALGORITHM_DELAUNAY, &ierr);
        gmshModelMeshGenerate(3, &ierr);
    }
    GMSH_CHECK(ierr, GSN_ERR_INPUT,
               "%s:%d: gmsh cannot mesh the volume of %s with tetrahedra "
               "(spacing %g m)",
               c->path, c->geometry_line, c->geometry, c->particle_spacing);
    return GSN_OK;
}

/* The body's volume from a coarse mesh (size diagonal / 8), so that the
 * particle count can be estimated before the real mesh is made. */
static int estimate_volume(const struct gsn_case *c, double *volume)
{
    int ierr = 0;
    double box[6];
    gmshModelGetBoundingBox(-1, -1, &box[0], &box[1], &box[2], &box[3], &box[4],
                            &box[5], &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot get the bounding box");
    double diagonal = sqrt((box[3] - box[0]) * (box[3] - box[0]) +
                           (box[4] - box[1]) * (box[4] - box[1]) +
                           (box[5] - box[2]) * (box[5] - box[2]));
    /* the minimum overrides the sizes of the geometry's points */
    GSN_CALL(gmsh_set_size(diagonal / COARSE_DIVISIONS,
                           diagonal / COARSE_DIVISIONS));
    GSN_CALL(gmsh_generate(c, 1));
    GSN_CALL(gmsh_mesh_volume(volume));
    gmshModelMeshClear(NULL, 0, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot clear the mesh");
    return GSN_OK;
}

/* Node tags of the tetrahedra become particle indices 0.. in tag order. */
static int mesh_read_tetrahedra(const struct gsn_case *c, struct mesh *m,
                                int **index_of_tag, size_t *tag_limit)
{
    size_t *elements = NULL, element_count = 0, *nodes = NULL, node_count = 0;
    int ierr = 0, rc = GSN_OK;
    gmshModelMeshGetElementsByType(GMSH_TETRAHEDRON, &elements, &element_count,
                                   &nodes, &node_count, -1, 0, 1, &ierr);
    gmshFree(elements);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the tetrahedra");
    size_t nt = node_count / 4;
    size_t *tags = NULL, tag_count = 0;
    double *coord = NULL, *parametric = NULL;
    size_t coord_n = 0, parametric_n = 0;
    GSN_CHECK_GOTO(nt > 0, rc, GSN_ERR_INPUT, done,
                   "%s:%d: gmsh made no tetrahedra in %s", c->path,
                   c->geometry_line, c->geometry);
    GSN_CHECK_GOTO(nt < (1u << 29), rc, GSN_ERR_INPUT, done,
                   "%zu tetrahedra: too many for 32-bit indices", nt);
    gmshModelMeshGetNodes(&tags, &tag_count, &coord, &coord_n, &parametric,
                          &parametric_n, -1, -1, 0, 0, &ierr);
    GSN_CHECK_GOTO(ierr == 0 && coord_n == 3 * tag_count, rc, GSN_ERR_LIBRARY,
                   done, "cannot read the mesh nodes");
    size_t limit = 0;
    for (size_t i = 0; i < tag_count; ++i)
        limit = tags[i] + 1 > limit ? tags[i] + 1 : limit;
    int *index = malloc(sizeof(int) * (limit + 1));
    GSN_CHECK_GOTO(index != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu node tags", limit);
    for (size_t i = 0; i <= limit; ++i)
        index[i] = -1;
    /* only nodes of tetrahedra are particles, numbered in tag order */
    for (size_t e = 0; e < node_count; ++e)
        index[nodes[e] < limit ? nodes[e] : limit] = -2;
    GSN_CHECK_GOTO(index[limit] == -1, rc, GSN_ERR_LIBRARY, done,
                   "a tetrahedron has an unknown node");
    int n = 0;
    for (size_t t = 0; t < limit; ++t)
        if (index[t] == -2)
            index[t] = n++;
    m->node_count = n;
    m->position = malloc(sizeof(double) * 3 * (size_t)n);
    m->tetrahedron_count = (int)nt;
    m->tetrahedra = malloc(sizeof(int) * 4 * nt);
    GSN_CHECK_GOTO(m->position && m->tetrahedra, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %d particles", n);
    for (size_t i = 0; i < tag_count; ++i)
        if (index[tags[i]] >= 0)
            memcpy(&m->position[3 * index[tags[i]]], &coord[3 * i],
                   sizeof(double[3]));
    for (size_t t = 0; t < 4 * nt; ++t)
        m->tetrahedra[t] = index[nodes[t]];
    *index_of_tag = index;
    *tag_limit = limit;
done:
    gmshFree(nodes);
    gmshFree(tags);
    gmshFree(coord);
    gmshFree(parametric);
    return rc;
}

static int compare_pairs(const void *pa, const void *pb)
{
    const int *a = pa, *b = pb;
    return a[0] != b[0] ? (a[0] > b[0]) - (a[0] < b[0])
                        : (a[1] > b[1]) - (a[1] < b[1]);
}

/* Adds the triangles of surface entity `entity` to physical surface s. */
static int mesh_read_surface_entity(const int *index, size_t limit,
                                    struct face_hash *surface_of, int entity,
                                    int s, int **pairs, size_t *pair_count,
                                    size_t *capacity)
{
    size_t *elements = NULL, element_count = 0, *nodes = NULL, node_count = 0;
    int ierr = 0, rc = GSN_OK;
    gmshModelMeshGetElementsByType(GMSH_TRIANGLE, &elements, &element_count,
                                   &nodes, &node_count, entity, 0, 1, &ierr);
    gmshFree(elements);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the triangles of surface %d", entity);
    for (size_t t = 0; t + 2 < node_count; t += 3) {
        int v[3], key[3];
        for (int k = 0; k < 3; ++k)
            v[k] = nodes[t + k] < limit ? index[nodes[t + k]] : -1;
        if (v[0] < 0 || v[1] < 0 || v[2] < 0)
            continue; /* a surface that bounds no volume */
        face_sort(v, key);
        size_t slot = face_slot(surface_of, key);
        if (!face_found(surface_of, slot))
            face_insert(surface_of, slot, key, s);
        if (*pair_count + 6 > *capacity) {
            size_t c = *capacity ? 2 * *capacity : 4096;
            int *grown = realloc(*pairs, sizeof(int) * c);
            GSN_CHECK_GOTO(grown != NULL, rc, GSN_ERR_MEMORY, done,
                           "cannot allocate the particle surfaces");
            *pairs = grown;
            *capacity = c;
        }
        for (int k = 0; k < 3; ++k) {
            (*pairs)[(*pair_count)++] = v[k];
            (*pairs)[(*pair_count)++] = s;
        }
    }
done:
    gmshFree(nodes);
    return rc;
}

/* The physical surfaces: names, their triangles (hashed into surface_of)
 * and the particles on them. */
static int mesh_read_surfaces(struct mesh *m, const int *index, size_t limit,
                              struct face_hash *surface_of)
{
    int *groups = NULL, ierr = 0, rc = GSN_OK;
    size_t group_count = 0;
    gmshModelGetPhysicalGroups(&groups, &group_count, 2, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the physical surfaces");
    int ns = (int)(group_count / 2);
    int *pairs = NULL; /* (particle, surface) */
    size_t pair_count = 0, capacity = 0;
    m->surface_count = ns;
    m->surface_name = calloc((size_t)ns + 1, sizeof *m->surface_name);
    m->surface_tag = calloc((size_t)ns + 1, sizeof(int));
    m->particle_surface_offset = calloc((size_t)m->node_count + 1, sizeof(int));
    GSN_CHECK_GOTO(m->surface_name && m->surface_tag &&
                       m->particle_surface_offset,
                   rc, GSN_ERR_MEMORY, done, "cannot allocate the surfaces");
    for (int s = 0; s < ns; ++s) {
        int tag = groups[2 * s + 1];
        char *name = NULL;
        gmshModelGetPhysicalName(2, tag, &name, &ierr);
        if (ierr == 0 && name && name[0])
            snprintf(m->surface_name[s], sizeof m->surface_name[s], "%s", name);
        else
            snprintf(m->surface_name[s], sizeof m->surface_name[s], "%d", tag);
        gmshFree(name);
        m->surface_tag[s] = tag;
        int *entities = NULL;
        size_t entity_count = 0;
        ierr = 0;
        gmshModelGetEntitiesForPhysicalGroup(2, tag, &entities, &entity_count,
                                             &ierr);
        for (size_t e = 0; ierr == 0 && rc == GSN_OK && e < entity_count; ++e)
            rc = mesh_read_surface_entity(index, limit, surface_of, entities[e],
                                          s, &pairs, &pair_count, &capacity);
        gmshFree(entities);
        GSN_CHECK_GOTO(rc == GSN_OK && ierr == 0, rc,
                       rc != GSN_OK ? rc : GSN_ERR_LIBRARY, done,
                       "cannot read physical surface %s", m->surface_name[s]);
    }
    /* particle -> surfaces, each once, in surface order */
    size_t count = pair_count / 2, unique = 0;
    if (count > 0)
        qsort(pairs, count, 2 * sizeof(int), compare_pairs);
    for (size_t e = 0; e < count; ++e)
        if (e == 0 || compare_pairs(&pairs[2 * e], &pairs[2 * e - 2]) != 0) {
            pairs[2 * unique] = pairs[2 * e];
            pairs[2 * unique + 1] = pairs[2 * e + 1];
            ++unique;
        }
    m->particle_surface = malloc(sizeof(int) * (unique + 1));
    GSN_CHECK_GOTO(m->particle_surface != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate the particle surfaces");
    for (size_t e = 0; e < unique; ++e) {
        ++m->particle_surface_offset[pairs[2 * e] + 1];
        m->particle_surface[e] = pairs[2 * e + 1];
    }
    for (int p = 0; p < m->node_count; ++p)
        m->particle_surface_offset[p + 1] += m->particle_surface_offset[p];
done:
    gmshFree(groups);
    free(pairs);
    return rc;
}

/* Label of every face of every tetrahedron: internal (shared by two),
 * a physical surface, or an untagged boundary. */
static int mesh_label_faces(struct mesh *m, const struct face_hash *surface_of)
{
    size_t nt = (size_t)m->tetrahedron_count;
    struct face_hash faces;
    memset(&faces, 0, sizeof faces);
    int rc = GSN_OK;
    GSN_CALL_GOTO(face_hash_create(&faces, 4 * nt), rc, done);
    m->face_label = malloc(sizeof(int) * 4 * nt);
    GSN_CHECK_GOTO(m->face_label != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate the face labels");
    static const int opposite[4][3] = {
        {1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 4; ++k) {
            const int *v = &m->tetrahedra[4 * t];
            int face[3] = {v[opposite[k][0]], v[opposite[k][1]],
                           v[opposite[k][2]]};
            int key[3];
            face_sort(face, key);
            size_t slot = face_slot(&faces, key);
            int f = (int)(4 * t) + k;
            if (!face_found(&faces, slot)) {
                face_insert(&faces, slot, key, f);
                size_t s = face_slot(surface_of, key);
                m->face_label[f] = face_found(surface_of, s)
                                       ? -1 - surface_of->value[s]
                                       : GSN_CELLS_LABEL_UNTAGGED;
            } else {
                GSN_CHECK_GOTO(m->face_label[faces.value[slot]] !=
                                   GSN_CELLS_LABEL_INTERNAL,
                               rc, GSN_ERR_INPUT, done,
                               "the mesh has a face shared by more than two "
                               "tetrahedra (nodes %d %d %d)",
                               key[0], key[1], key[2]);
                m->face_label[faces.value[slot]] = GSN_CELLS_LABEL_INTERNAL;
                m->face_label[f] = GSN_CELLS_LABEL_INTERNAL;
            }
        }
done:
    face_hash_free(&faces);
    return rc;
}

/* Every boundary of the case names a physical surface of the geometry:
 * checked right after gmsh reads it, before any meshing (pre and check). */
static int pre_check_boundaries(const struct gsn_case *c)
{
    int *groups = NULL, ierr = 0, rc = GSN_OK;
    size_t group_count = 0;
    gmshModelGetPhysicalGroups(&groups, &group_count, 2, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the physical surfaces");
    size_t count = group_count / 2;
    char **names = calloc(count + 1, sizeof *names); /* NULL-terminated */
    GSN_CHECK_GOTO(names != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu surface names", count);
    for (size_t g = 0; g < count; ++g) {
        gmshModelGetPhysicalName(2, groups[2 * g + 1], &names[g], &ierr);
        GSN_CHECK_GOTO(ierr == 0 && names[g], rc, GSN_ERR_LIBRARY, done,
                       "cannot read the name of physical surface %d",
                       groups[2 * g + 1]);
    }
    for (int b = 0; b < c->boundary_count; ++b) {
        const char *name = c->boundaries[b].name;
        int found = 0;
        for (size_t g = 0; g < count && !found; ++g)
            found = strcmp(names[g], name) == 0;
        if (found)
            continue;
        char list[1024] = "none", hint[GSN_H5_STRING_SIZE + 32] = "";
        size_t used = 0;
        for (size_t g = 0; g < count && used + 1 < sizeof list; ++g) {
            int w =
                snprintf(list + used, sizeof list - used, "%s%s", g ? ", " : "",
                         names[g][0] ? names[g] : "(unnamed)");
            used += w > 0 ? (size_t)w : 0;
        }
        const char *guess = gsn_closest_word(name, (const char *const *)names);
        if (guess)
            snprintf(hint, sizeof hint, "; did you mean '%s'?", guess);
        GSN_CHECK_GOTO(0, rc, GSN_ERR_INPUT, done,
                       "%s:%d: boundary '%s' names no physical surface of "
                       "%s%s (it has: %s)",
                       c->path, c->boundaries[b].line, name, c->geometry, hint,
                       list);
    }
done:
    for (size_t g = 0; names && g < count; ++g)
        gmshFree(names[g]);
    free(names);
    gmshFree(groups);
    return rc;
}

/* What pre checks in the geometry before meshing: the boundaries' and the
 * refinements' surfaces exist, symmetry planes are axis-aligned. */
static int pre_check_surfaces(const struct gsn_case *c)
{
    GSN_CALL(pre_check_boundaries(c));
    GSN_CALL(pre_refine_check(c));
    return GSN_OK;
}

static int pre_mesh(const struct gsn_case *c,
                    const struct gsn_pre_options *options, struct mesh *m,
                    double *estimate)
{
    GSN_CALL(gmsh_open_geometry(c));
    GSN_CALL(pre_check_surfaces(c));
    double volume = 0.0;
    GSN_CALL(estimate_volume(c, &volume));
    double h = c->particle_spacing;
    *estimate = volume / (h * h * h);
    GSN_CALL(pre_refine_fields(c, estimate));
    GSN_CHECK(options->force || *estimate <= GSN_DEFAULT_MAX_PARTICLES,
              GSN_ERR_INPUT,
              "%s: spacing %g m in a body of %.4g m^3 gives about %.3g "
              "particles, more than %d; use a larger particles.spacing or "
              "--force",
              c->path, h, volume, *estimate, GSN_DEFAULT_MAX_PARTICLES);
    GSN_CALL(gmsh_set_size(0.0, h));
    const char *variable = getenv("GEOSCNI_REPRODUCIBLE");
    int reproducible = options->reproducible ||
                       (variable && variable[0] && strcmp(variable, "0") != 0);
    GSN_CALL(gmsh_generate(c, reproducible));
    int *index = NULL;
    size_t limit = 0;
    int rc = GSN_OK;
    struct face_hash surface_of;
    memset(&surface_of, 0, sizeof surface_of);
    GSN_CALL(mesh_read_tetrahedra(c, m, &index, &limit));
    GSN_CALL_GOTO(
        face_hash_create(&surface_of, (size_t)m->tetrahedron_count + 1024), rc,
        done);
    GSN_CALL_GOTO(mesh_read_surfaces(m, index, limit, &surface_of), rc, done);
    GSN_CALL_GOTO(mesh_label_faces(m, &surface_of), rc, done);
done:
    free(index);
    face_hash_free(&surface_of);
    return rc;
}

int gsn_pre_run(const struct gsn_case *c, const char *outdir,
                const struct gsn_pre_options *options)
{
    static const struct gsn_pre_options defaults = {0, 0, 0, 0, 0};
    if (!options)
        options = &defaults;
    char path[GSN_PATH_SIZE];
    GSN_CALL(gsn_folder_prepare(outdir));
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "model.h5"));
    GSN_CHECK(c->particle_spacing > 0.0, GSN_ERR_INPUT,
              "%s: particles.spacing must be positive", c->path);

    double t0 = omp_get_wtime();
    int rc = GSN_OK;
    struct gmsh_session session;
    GSN_CALL(gmsh_session_begin_case(&session, c));
    struct mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    struct gsn_model bare, m;
    memset(&bare, 0, sizeof bare);
    memset(&m, 0, sizeof m);
    double estimate = 0.0;
    /* HXT takes OpenMP's thread count, whatever gmsh's options say */
    omp_set_num_threads(1);
    rc = pre_mesh(c, options, &mesh, &estimate);
    gmsh_session_end(&session);
    if (rc != GSN_OK)
        goto done;
    double t_mesh = omp_get_wtime() - t0;

    /* The particles, their surfaces and the body's tetrahedra, in Morton
     * order (the solver's passes then find neighbours in cache), then
     * their cells, checked (gsn_cells_model_at). */
    int n = mesh.node_count, ns = mesh.surface_count;
    int entries = mesh.particle_surface_offset[n];
    GSN_CALL_GOTO(
        gsn_model_allocate(&bare, n, entries, 0, 0, ns, mesh.tetrahedron_count),
        rc, done);
    memcpy(bare.position, mesh.position, sizeof(double) * 3 * (size_t)n);
    memcpy(bare.particle_surface_offset, mesh.particle_surface_offset,
           sizeof(int) * (size_t)(n + 1));
    memcpy(bare.particle_surface, mesh.particle_surface,
           sizeof(int) * (size_t)entries);
    memcpy(bare.surface_name, mesh.surface_name,
           sizeof *bare.surface_name * (size_t)ns);
    memcpy(bare.surface_tag, mesh.surface_tag, sizeof(int) * (size_t)ns);
    memcpy(bare.tetrahedra, mesh.tetrahedra,
           sizeof(int) * 4 * (size_t)mesh.tetrahedron_count);
    for (int f = 0; f < 4 * mesh.tetrahedron_count; ++f)
        bare.tetrahedron_face[f] =
            gsn_cells_face_from_label(mesh.face_label[f]);
    GSN_CALL_GOTO(gsn_model_sort_spatially(&bare), rc, done);
    struct gsn_cells_options cells = {c->facet_points, options->threads,
                                      options->tetrahedra_only};
    struct gsn_cells_report check;
    memset(&check, 0, sizeof check);
    GSN_CALL_GOTO(gsn_cells_model_at(&bare, NULL, NULL, &cells, &m, &check), rc,
                  done);
    double t1 = omp_get_wtime();
    GSN_CALL_GOTO(gsn_model_write(path, &m, c), rc, done);
    double t_write = omp_get_wtime() - t1;
    if (!options->quiet) {
        printf("pre: %d particles (estimate %.0f), %d tetrahedra, %d facets "
               "(%d quadrature points), %d cells cut by the boundary (%d by "
               "tetrahedra)\n",
               n, estimate, m.tetrahedron_count, m.facet_count,
               m.facet_point_offset[m.facet_count], check.crossing_count,
               check.pieced_count);
        printf("pre: volume %.10g m^3 (error %.1e), closure %.1e, moment "
               "%.1e, twins %.1e, surface areas %.1e (tolerance 1e-10)\n",
               check.body_volume, check.volume_error, check.closure_error,
               check.moment_error, check.twin_error, check.area_error);
        printf("pre: time %.2f s: meshing %.2f, Delaunay %.2f, cells %.2f, "
               "writing %.2f -> %s\n",
               omp_get_wtime() - t0, t_mesh, check.time_delaunay,
               check.time_cells, t_write, path);
        GSN_CALL_GOTO(pre_refine_report(c, &m), rc, done);
    }
done:
    gsn_model_free(&m);
    gsn_model_free(&bare);
    mesh_free(&mesh);
    return rc;
}

int gsn_pre_check_geometry(const struct gsn_case *c)
{
    struct gmsh_session session;
    GSN_CALL(gmsh_session_begin_case(&session, c));
    int rc = GSN_OK;
    GSN_CALL_GOTO(gmsh_open_geometry(c), rc, done);
    GSN_CALL_GOTO(pre_check_surfaces(c), rc, done);
done:
    gmsh_session_end(&session);
    return rc;
}

int gsn_pre_gmsh_version(char *out, size_t size)
{
    int ierr = 0;
    struct gmsh_session session;
    GSN_CALL(gmsh_session_begin(&session, 0, NULL));
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    char *version = NULL;
    gmshOptionGetString("General.Version", &version, &ierr);
    int ok = ierr == 0 && version != NULL;
    if (ok)
        snprintf(out, size, "%s", version);
    gmshFree(version);
    gmsh_session_end(&session);
    GSN_CHECK(ok, GSN_ERR_LIBRARY, "gmsh did not report its version");
    return GSN_OK;
}
