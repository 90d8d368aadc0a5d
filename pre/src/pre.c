/* pre: the driver (issue 3). In a child process (child.h, issue 21): loads
 * the geometry with the gmsh C API, checks it (geometry.c), estimates the
 * particle count (estimate.c), meshes it with tetrahedra at
 * particles.spacing (HXT on one gmsh thread; gmsh's Delaunay where the same
 * input must give the same particles) and sends the mesh back. Then takes
 * the mesh nodes as particles, builds the nodal domains (domains.c), tags
 * boundary particles and facets with the physical surfaces, checks the
 * model and writes model.h5 atomically.
 * gmsh 4.8 pitfalls: TOOLCHAIN.md, "gmsh 4.8 C API". */
#include "geoscni/pre.h"
#include "child.h"
#include "estimate.h"
#include "geometry.h"
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
    GMSH_ALGORITHM_HXT = 10
};

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
    geometry_gmsh_last_error(gmsh, sizeof gmsh);
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
    int volume_count; /* physical volumes */
    char (*volume_name)[GSN_H5_STRING_SIZE];
    int *volume_tag;
    int *tetrahedron_volume, *particle_volume; /* -1: in none */
};

static void mesh_free(struct mesh *m)
{
    free(m->volume_name);
    free(m->volume_tag);
    free(m->tetrahedron_volume);
    free(m->particle_volume);
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
    /* errors only, on stderr: in pre's child process (child.h) that is a
     * file the parent reads should gmsh die */
    gmshOptionSetNumber("General.Terminal", 1, &ierr);
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
    int abort_line = geometry_statement_line(c->geometry, "Abort");
    GSN_CHECK(count > 0 || abort_line == 0, GSN_ERR_INPUT,
              "%s:%d: gmsh stops reading the geometry at 'Abort;', before "
              "it defines a volume to fill with particles; delete it",
              c->geometry, abort_line);
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

/* Meshes the volume: Delaunay on one thread by default, the same mesh on
 * every run; HXT (particles.mesher: hxt) is faster but, in gmsh 4.8, not
 * reproducible even on one thread (the node count of the L-shape varies by
 * 1 % from run to run), and falls back to Delaunay where it fails. */
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

/* Node tags of the tetrahedra become particle indices 0.. in tag order. */
static int mesh_read_tetrahedra(const struct gsn_case *c, struct mesh *m,
                                int **index_of_tag, size_t *tag_limit,
                                size_t **element_tags)
{
    size_t *elements = NULL, element_count = 0, *nodes = NULL, node_count = 0;
    size_t *tags = NULL, tag_count = 0;
    double *coord = NULL, *parametric = NULL;
    size_t coord_n = 0, parametric_n = 0;
    int *index = NULL;
    int ierr = 0, rc = GSN_OK;
    gmshModelMeshGetElementsByType(GMSH_TETRAHEDRON, &elements, &element_count,
                                   &nodes, &node_count, -1, 0, 1, &ierr);
    *element_tags = elements; /* gmshFree'd by the caller */
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the tetrahedra");
    size_t nt = node_count / 4;
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
    index = malloc(sizeof(int) * (limit + 1));
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
    index = NULL;
done:
    free(index); /* kept only when all went well */
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

/* The name of physical group tag of dimension dim, or its tag as text
 * when it has none. */
static void physical_group_name(int dim, int tag, char out[GSN_H5_STRING_SIZE])
{
    char *name = NULL;
    int ierr = 0;
    gmshModelGetPhysicalName(dim, tag, &name, &ierr);
    if (ierr == 0 && name && name[0])
        snprintf(out, GSN_H5_STRING_SIZE, "%s", name);
    else
        snprintf(out, GSN_H5_STRING_SIZE, "%d", tag);
    gmshFree(name);
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
        physical_group_name(2, tag, m->surface_name[s]);
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

/* The physical volumes: names, tags and each tetrahedron's (element_tags:
 * the gmsh tag of tetrahedron t, in mesh order). */
static int mesh_read_volumes(struct mesh *m, const size_t *element_tags)
{
    int *groups = NULL, ierr = 0, rc = GSN_OK;
    size_t group_count = 0, limit = 0, nt = (size_t)m->tetrahedron_count;
    int *tetrahedron_of = NULL;
    gmshModelGetPhysicalGroups(&groups, &group_count, 3, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the physical volumes");
    int nv = (int)(group_count / 2);
    for (size_t t = 0; t < nt; ++t)
        limit = element_tags[t] + 1 > limit ? element_tags[t] + 1 : limit;
    m->volume_count = nv;
    m->volume_name = calloc((size_t)nv + 1, sizeof *m->volume_name);
    m->volume_tag = calloc((size_t)nv + 1, sizeof(int));
    m->tetrahedron_volume = malloc(sizeof(int) * (nt + 1));
    tetrahedron_of = malloc(sizeof(int) * (limit + 1));
    GSN_CHECK_GOTO(m->volume_name && m->volume_tag && m->tetrahedron_volume &&
                       tetrahedron_of,
                   rc, GSN_ERR_MEMORY, done, "cannot allocate the volumes");
    for (size_t i = 0; i <= limit; ++i)
        tetrahedron_of[i] = -1;
    for (size_t t = 0; t < nt; ++t) {
        tetrahedron_of[element_tags[t]] = (int)t;
        m->tetrahedron_volume[t] = -1;
    }
    for (int v = 0; v < nv; ++v) {
        int tag = groups[2 * v + 1];
        physical_group_name(3, tag, m->volume_name[v]);
        m->volume_tag[v] = tag;
        int *entities = NULL;
        size_t entity_count = 0;
        ierr = 0;
        gmshModelGetEntitiesForPhysicalGroup(3, tag, &entities, &entity_count,
                                             &ierr);
        for (size_t e = 0; ierr == 0 && e < entity_count; ++e) {
            size_t *elements = NULL, count = 0, *nodes = NULL, node_count = 0;
            gmshModelMeshGetElementsByType(GMSH_TETRAHEDRON, &elements, &count,
                                           &nodes, &node_count, entities[e], 0,
                                           1, &ierr);
            for (size_t k = 0; ierr == 0 && k < count; ++k)
                if (elements[k] < limit && tetrahedron_of[elements[k]] >= 0)
                    m->tetrahedron_volume[tetrahedron_of[elements[k]]] = v;
            gmshFree(elements);
            gmshFree(nodes);
        }
        gmshFree(entities);
        GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                       "cannot read physical volume %s", m->volume_name[v]);
    }
done:
    free(tetrahedron_of);
    gmshFree(groups);
    return rc;
}

/* Each particle's volume: the one whose tetrahedra around it have the
 * largest volume (a particle on an interface between layers belongs to
 * both; the lower index on a tie). */
static int mesh_particle_volumes(struct mesh *m)
{
    int n = m->node_count, nv = m->volume_count;
    m->particle_volume = malloc(sizeof(int) * ((size_t)n + 1));
    double *share =
        calloc((size_t)n * (size_t)(nv > 0 ? nv : 1), sizeof(double));
    if (!m->particle_volume || !share) {
        free(share);
        GSN_CHECK(0, GSN_ERR_MEMORY, "cannot allocate the particles' volumes");
    }
    for (int t = 0; t < m->tetrahedron_count; ++t) {
        int v = m->tetrahedron_volume[t];
        if (v < 0)
            continue;
        double size = fabs(
            gsn_body_tetrahedron_volume(m->position, &m->tetrahedra[4 * t]));
        for (int k = 0; k < 4; ++k)
            share[(size_t)m->tetrahedra[4 * t + k] * (size_t)nv + (size_t)v] +=
                size;
    }
    for (int i = 0; i < n; ++i) {
        int best = -1;
        for (int v = 0; v < nv; ++v)
            if (share[(size_t)i * (size_t)nv + (size_t)v] > 0.0 &&
                (best < 0 || share[(size_t)i * (size_t)nv + (size_t)v] >
                                 share[(size_t)i * (size_t)nv + (size_t)best]))
                best = v;
        m->particle_volume[i] = best;
    }
    free(share);
    return GSN_OK;
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
/* names as "a, b, c" (unnamed: "(unnamed)"; none: "none"). */
static void join_names(char *const *names, size_t count, char *out, size_t size)
{
    snprintf(out, size, "none");
    size_t used = 0;
    for (size_t g = 0; g < count && used + 1 < size; ++g) {
        int w = snprintf(out + used, size - used, "%s%s", g ? ", " : "",
                         names[g][0] ? names[g] : "(unnamed)");
        used += w > 0 ? (size_t)w : 0;
    }
}

/* The names of the physical groups of dimension dim, NULL-terminated;
 * free with names_free. */
static int physical_names(int dim, char ***out, size_t *count)
{
    int *groups = NULL, ierr = 0, rc = GSN_OK;
    size_t group_count = 0;
    gmshModelGetPhysicalGroups(&groups, &group_count, dim, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the physical groups");
    *count = group_count / 2;
    char **names = calloc(*count + 1, sizeof *names);
    GSN_CHECK_GOTO(names != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu names", *count);
    for (size_t g = 0; g < *count; ++g) {
        gmshModelGetPhysicalName(dim, groups[2 * g + 1], &names[g], &ierr);
        GSN_CHECK_GOTO(ierr == 0 && names[g], rc, GSN_ERR_LIBRARY, done,
                       "cannot read the name of physical group %d",
                       groups[2 * g + 1]);
    }
done:
    gmshFree(groups);
    *out = names;
    return rc;
}

static void names_free(char **names, size_t count)
{
    for (size_t g = 0; names && g < count; ++g)
        gmshFree(names[g]);
    free(names);
}

/* materials: against the geometry's physical volumes: every entry names
 * one, and every part of the body lies in exactly one that has a soil. */
static int pre_check_volumes(const struct gsn_case *c)
{
    char **names = NULL, list[1024];
    size_t count = 0;
    int *entities = NULL, ierr = 0, rc = GSN_OK;
    size_t entity_count = 0;
    GSN_CALL_GOTO(physical_names(3, &names, &count), rc, done);
    join_names(names, count, list, sizeof list);
    for (int k = 0; c->materials_by_volume && k < c->material_count; ++k) {
        const char *name = c->materials[k].volume;
        int found = 0;
        for (size_t g = 0; g < count && !found; ++g)
            found = strcmp(names[g], name) == 0;
        if (found)
            continue;
        const char *guess = gsn_closest_word(name, (const char *const *)names);
        GSN_CHECK_GOTO(
            0, rc, GSN_ERR_INPUT, done,
            "%s:%d: 'materials.%s' names no physical volume of %s%s%s"
            "%s (it has: %s)%s",
            c->path, c->materials[k].line.entry, name, c->geometry,
            guess ? "; did you mean '" : "", guess ? guess : "",
            guess ? "'?" : "", list,
            count ? ""
                  : "; name the volumes in the geometry: "
                    "Physical Volume(\"clay\") = {1};");
    }
    gmshModelGetEntities(&entities, &entity_count, 3, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the volumes");
    for (size_t e = 0; e < entity_count / 2; ++e) {
        int tag = entities[2 * e + 1], *groups = NULL;
        size_t group_count = 0;
        gmshModelGetPhysicalGroupsForEntity(3, tag, &groups, &group_count,
                                            &ierr);
        char *first = NULL, *second = NULL;
        if (group_count > 0)
            gmshModelGetPhysicalName(3, groups[0], &first, &ierr);
        if (group_count > 1)
            gmshModelGetPhysicalName(3, groups[1], &second, &ierr);
        gmshFree(groups);
        int material = first ? gsn_case_find_material(c, first) : -1;
        char text[3 * GSN_PATH_SIZE] = "";
        if (group_count > 1)
            snprintf(text, sizeof text,
                     "%s: volume %d lies in the physical volumes '%s' and "
                     "'%s'; a part of the body has one soil: keep it in one",
                     c->geometry, tag, first ? first : "",
                     second ? second : "");
        else if (c->materials_by_volume && group_count == 0)
            snprintf(text, sizeof text,
                     "%s: volume %d lies in no physical volume, so "
                     "'materials' (%s) gives it no soil; add it to one, "
                     "e.g. Physical Volume(\"clay\") = {%d}; (the "
                     "geometry's: %s)",
                     c->geometry, tag, c->path, tag, list);
        else if (c->materials_by_volume && material < 0)
            snprintf(text, sizeof text,
                     "%s: physical volume '%s' has no soil in %s: add "
                     "'%s: {density: ..., bulk_modulus: ..., shear_modulus: "
                     "...}' under 'materials'",
                     c->geometry, first, c->path, first);
        gmshFree(first);
        gmshFree(second);
        GSN_CHECK_GOTO(!text[0], rc, GSN_ERR_INPUT, done, "%s", text);
    }
done:
    gmshFree(entities);
    names_free(names, count);
    return rc;
}

static int pre_check_boundaries(const struct gsn_case *c)
{
    char **names = NULL, list[1024];
    size_t count = 0;
    int rc = GSN_OK;
    GSN_CALL_GOTO(physical_names(2, &names, &count), rc, done);
    for (int b = 0; b < c->boundary_count; ++b) {
        const char *name = c->boundaries[b].name;
        int found = 0;
        for (size_t g = 0; g < count && !found; ++g)
            found = strcmp(names[g], name) == 0;
        if (found)
            continue;
        char hint[GSN_H5_STRING_SIZE + 32] = "";
        join_names(names, count, list, sizeof list);
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
    names_free(names, count);
    return rc;
}

/* What pre checks in the geometry before meshing: the boundaries' and the
 * refinements' surfaces exist, symmetry planes are axis-aligned, the
 * materials' volumes exist and fill the body. */
static int pre_check_surfaces(const struct gsn_case *c)
{
    GSN_CALL(pre_check_boundaries(c));
    GSN_CALL(pre_check_volumes(c));
    GSN_CALL(pre_refine_check(c));
    return GSN_OK;
}

/* Delaunay unless the case asks for HXT (particles.mesher); tests may
 * force Delaunay on any case */
static int pre_reproducible(const struct gsn_case *c,
                            const struct gsn_pre_options *options)
{
    return c->mesher == GSN_MESHER_DELAUNAY ||
           (options && options->reproducible);
}

/* What the child learns before the real mesh: the geometry read and
 * checked, the particle estimate from a coarse mesh (issue 21, point 6:
 * before any meshing at the case's spacings). */
/* What pre_survey learns. */
struct survey {
    double estimate; /* particles */
    int at_least;    /* the estimate stopped early: a lower bound */
    double volume;   /* m^3, of the coarse mesh */
};

static int pre_survey(struct pre_child *child, const struct gsn_case *c,
                      int reproducible, struct survey *s)
{
    pre_child_stage(child, "reading it");
    GSN_CALL(gmsh_open_geometry(c));
    pre_child_stage(child, "checking it");
    GSN_CALL(geometry_check(c));
    GSN_CALL(pre_check_surfaces(c));
    pre_child_stage(child, "meshing it coarsely to estimate the particle "
                           "count");
    struct coarse_mesh coarse;
    GSN_CALL(geometry_coarse_mesh(c, &coarse));
    s->volume = 0.0;
    for (int t = 0; t < coarse.tetrahedron_count; ++t) {
        const int *v = &coarse.tetrahedra[4 * t];
        double e[3][3];
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                e[k][j] = coarse.position[3 * v[k + 1] + j] -
                          coarse.position[3 * v[0] + j];
        s->volume += fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                          e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                          e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                     6.0;
    }
    struct estimate_coefficients k;
    estimate_coefficients_for(reproducible, &k);
    int rc =
        pre_refine_estimate(c, &coarse, &k, 10.0 * GSN_DEFAULT_MAX_PARTICLES,
                            &s->estimate, &s->at_least);
    coarse_mesh_free(&coarse);
    GSN_CALL(rc);
    int ierr = 0;
    gmshModelMeshClear(NULL, 0, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot clear the coarse mesh");
    return GSN_OK;
}

/* The particle limit, before any meshing at the case's spacings. */
static int pre_check_count(const struct gsn_case *c, const struct survey *s,
                           int force)
{
    char where[GSN_PATH_SIZE + 16];
    snprintf(where, sizeof where, "%s", c->path);
    if (c->particle_spacing_line > 0)
        snprintf(where, sizeof where, "%s:%d", c->path,
                 c->particle_spacing_line);
    GSN_CHECK(force || s->estimate <= GSN_DEFAULT_MAX_PARTICLES, GSN_ERR_INPUT,
              "%s: particles.spacing (%g m)%s in a body of %.4g m^3 give%s "
              "%s %.3g particles, more than %d; use a larger spacing%s, or "
              "--force",
              where, c->particle_spacing,
              c->refinement_count ? " and particles.refine" : "", s->volume,
              c->refinement_count ? "" : "s",
              s->at_least ? "at least" : "about", s->estimate,
              GSN_DEFAULT_MAX_PARTICLES,
              c->refinement_count ? " or larger refine spacings" : "");
    return GSN_OK;
}

static int pre_mesh(struct pre_child *child, const struct gsn_case *c,
                    const struct gsn_pre_options *options, struct mesh *m,
                    double *estimate)
{
    int reproducible = pre_reproducible(c, options);
    double h = c->particle_spacing;
    struct survey survey;
    GSN_CALL(pre_survey(child, c, reproducible, &survey));
    *estimate = survey.estimate;
    GSN_CALL(pre_check_count(c, &survey, options->force));
    pre_child_stage(child, "sampling the refinement surfaces");
    GSN_CALL(pre_refine_fields(c));
    GSN_CALL(gmsh_set_size(0.0, h));
    pre_child_stage(child, "meshing it with tetrahedra at spacing %g m", h);
    GSN_CALL(gmsh_generate(c, reproducible));
    pre_child_stage(child, "reading its mesh");
    int *index = NULL;
    size_t limit = 0, *element_tags = NULL;
    int rc = GSN_OK;
    struct face_hash surface_of;
    memset(&surface_of, 0, sizeof surface_of);
    rc = mesh_read_tetrahedra(c, m, &index, &limit, &element_tags);
    if (rc == GSN_OK)
        rc = mesh_read_volumes(m, element_tags);
    gmshFree(element_tags);
    GSN_CALL_GOTO(rc, rc, done);
    GSN_CALL_GOTO(mesh_particle_volumes(m), rc, done);
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

struct pre_job {
    const struct gsn_case *c;
    const struct gsn_pre_options *options;
    int mesh_surfaces; /* check: mesh the surfaces at the spacing */
};

/* The counts of a mesh as sent: particles, tetrahedra, surfaces, surface
 * entries of the particles, volumes. */
enum { MESH_ARRAYS = 13 };

/* pre's child: the mesh, sent array by array (mesh_receive). */
static int pre_mesh_child(struct pre_child *child, void *arg)
{
    const struct pre_job *job = arg;
    const struct gsn_case *c = job->c;
    struct gmsh_session session; /* never ended: the child exits */
    GSN_CALL(gmsh_session_begin_case(&session, c));
    struct mesh m;
    memset(&m, 0, sizeof m);
    double numbers[1] = {0}; /* the estimate */
    int rc = pre_mesh(child, c, job->options, &m, &numbers[0]);
    int n = m.node_count, nt = m.tetrahedron_count, ns = m.surface_count;
    int nv = m.volume_count;
    int counts[5] = {n, nt, ns, rc == GSN_OK ? m.particle_surface_offset[n] : 0,
                     nv};
    const void *data[MESH_ARRAYS] = {counts,
                                     numbers,
                                     m.position,
                                     m.tetrahedra,
                                     m.face_label,
                                     m.surface_name,
                                     m.surface_tag,
                                     m.particle_surface_offset,
                                     m.particle_surface,
                                     m.volume_name,
                                     m.volume_tag,
                                     m.tetrahedron_volume,
                                     m.particle_volume};
    size_t size[MESH_ARRAYS] = {sizeof counts,
                                sizeof numbers,
                                sizeof(double) * 3 * (size_t)n,
                                sizeof(int) * 4 * (size_t)nt,
                                sizeof(int) * 4 * (size_t)nt,
                                sizeof *m.surface_name * (size_t)ns,
                                sizeof(int) * (size_t)ns,
                                sizeof(int) * ((size_t)n + 1),
                                sizeof(int) * (size_t)counts[3],
                                sizeof *m.volume_name * (size_t)nv,
                                sizeof(int) * (size_t)nv,
                                sizeof(int) * (size_t)nt,
                                sizeof(int) * (size_t)n};
    for (int i = 0; rc == GSN_OK && i < MESH_ARRAYS; ++i)
        rc = pre_child_send(child, data[i], size[i]);
    mesh_free(&m);
    return rc;
}

/* The mesh from the arrays pre_mesh_child sent; takes them. */
static int mesh_receive(struct pre_child_result *r, struct mesh *m,
                        double *estimate)
{
    GSN_CHECK(r->array_count == MESH_ARRAYS && r->size[0] == sizeof(int[5]) &&
                  r->size[1] == sizeof(double[1]),
              GSN_ERR_INTERNAL, "the meshing process sent %d arrays",
              r->array_count);
    const int *counts = r->array[0];
    const double *numbers = r->array[1];
    size_t n = (size_t)counts[0], nt = (size_t)counts[1],
           ns = (size_t)counts[2], entries = (size_t)counts[3],
           nv = (size_t)counts[4];
    size_t expected[MESH_ARRAYS] = {r->size[0],
                                    r->size[1],
                                    sizeof(double) * 3 * n,
                                    sizeof(int) * 4 * nt,
                                    sizeof(int) * 4 * nt,
                                    sizeof *m->surface_name * ns,
                                    sizeof(int) * ns,
                                    sizeof(int) * (n + 1),
                                    sizeof(int) * entries,
                                    sizeof *m->volume_name * nv,
                                    sizeof(int) * nv,
                                    sizeof(int) * nt,
                                    sizeof(int) * n};
    for (int i = 0; i < MESH_ARRAYS; ++i)
        GSN_CHECK(r->size[i] == expected[i], GSN_ERR_INTERNAL,
                  "array %d from the meshing process has %zu bytes, not %zu", i,
                  r->size[i], expected[i]);
    m->node_count = counts[0];
    m->tetrahedron_count = counts[1];
    m->surface_count = counts[2];
    m->volume_count = counts[4];
    *estimate = numbers[0];
    void **take[MESH_ARRAYS] = {NULL,
                                NULL,
                                (void **)&m->position,
                                (void **)&m->tetrahedra,
                                (void **)&m->face_label,
                                (void **)&m->surface_name,
                                (void **)&m->surface_tag,
                                (void **)&m->particle_surface_offset,
                                (void **)&m->particle_surface,
                                (void **)&m->volume_name,
                                (void **)&m->volume_tag,
                                (void **)&m->tetrahedron_volume,
                                (void **)&m->particle_volume};
    for (int i = 2; i < MESH_ARRAYS; ++i) {
        *take[i] = r->array[i];
        r->array[i] = NULL;
    }
    return GSN_OK;
}

/* The error of a gmsh child that died: gmsh's own message and the file. */
static int pre_child_died(const struct gsn_case *c,
                          const struct pre_child_result *r)
{
    if (r->exited && r->exit_status == PRE_CHILD_EXIT_CALLED) {
        int line = geometry_statement_line(c->geometry, "Exit");
        GSN_CHECK(line == 0, GSN_ERR_INPUT,
                  "%s:%d: 'Exit;' ends gmsh, and the program with it, while "
                  "it reads the geometry; delete it (geoscni meshes the "
                  "geometry itself)",
                  c->geometry, line);
        GSN_CHECK(0, GSN_ERR_INPUT,
                  "%s: gmsh ended the program while %s%s%s (does the "
                  "geometry, or a file it includes, end with 'Exit;'?)",
                  c->geometry, r->stage[0] ? r->stage : "reading it",
                  r->messages[0] ? ": " : "", r->messages);
    }
    GSN_CHECK(0, GSN_ERR_INPUT, "%s: gmsh failed while %s: %s", c->geometry,
              r->stage[0] ? r->stage : "reading it",
              r->messages[0] ? r->messages : "no message");
    return GSN_OK;
}

/* Meshes the case in a child process (child.h). */
static int pre_mesh_isolated(const struct gsn_case *c,
                             const struct gsn_pre_options *options,
                             struct mesh *m, double *estimate)
{
    struct pre_job job = {c, options, 0};
    struct pre_child_result r;
    GSN_CALL(pre_child_run(pre_mesh_child, &job, &r));
    int rc = r.died ? pre_child_died(c, &r) : mesh_receive(&r, m, estimate);
    pre_child_result_free(&r);
    GSN_CALL(rc);
    return GSN_OK;
}
/* The particles of each physical volume, on one line. */
static void pre_volume_report(const struct gsn_model *m)
{
    if (m->volume_count == 0)
        return;
    printf("pre: volumes");
    for (int v = 0; v < m->volume_count; ++v) {
        int count = 0;
        for (int i = 0; i < m->particle_count; ++i)
            count += m->particle_volume[i] == v;
        printf("%s %s %d particles", v ? "," : "", m->volume_name[v], count);
    }
    printf("\n");
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
    struct mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    struct gsn_model bare, m;
    memset(&bare, 0, sizeof bare);
    memset(&m, 0, sizeof m);
    double estimate = 0.0;
    GSN_CALL_GOTO(pre_mesh_isolated(c, options, &mesh, &estimate), rc, done);
    double t_mesh = omp_get_wtime() - t0;
    if (!c->materials_by_volume && mesh.volume_count > 1)
        fprintf(stderr,
                "warning: %s: %s has %d physical volumes, and 'material' "
                "gives them all one soil; give each its own under "
                "'materials' (docs/material.md, \"Layers\")\n",
                c->path, c->geometry, mesh.volume_count);

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
    GSN_CALL_GOTO(gsn_model_allocate_volumes(&bare, mesh.volume_count), rc,
                  done);
    memcpy(bare.volume_name, mesh.volume_name,
           sizeof *bare.volume_name * (size_t)mesh.volume_count);
    memcpy(bare.volume_tag, mesh.volume_tag,
           sizeof(int) * (size_t)mesh.volume_count);
    memcpy(bare.particle_volume, mesh.particle_volume, sizeof(int) * (size_t)n);
    memcpy(bare.tetrahedron_volume, mesh.tetrahedron_volume,
           sizeof(int) * (size_t)mesh.tetrahedron_count);
    for (int f = 0; f < 4 * mesh.tetrahedron_count; ++f)
        bare.tetrahedron_face[f] =
            gsn_cells_face_from_label(mesh.face_label[f]);
    /* every tetrahedron positively oriented (the body's convention) */
    for (int t = 0; t < mesh.tetrahedron_count; ++t) {
        int *v = &bare.tetrahedra[4 * t], *f = &bare.tetrahedron_face[4 * t];
        if (gsn_body_tetrahedron_volume(bare.position, v) < 0.0) {
            int swap = v[2];
            v[2] = v[3];
            v[3] = swap;
            swap = f[2];
            f[2] = f[3];
            f[3] = swap;
        }
    }
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
        int reproducible = pre_reproducible(c, options);
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
        printf("pre: time %.2f s: meshing %.2f (gmsh's %s%s), Delaunay %.2f, "
               "cells %.2f, writing %.2f -> %s\n",
               omp_get_wtime() - t0, t_mesh,
               gsn_mesher_name(reproducible ? GSN_MESHER_DELAUNAY
                                            : GSN_MESHER_HXT),
               reproducible ? ": the same particles on every run"
                            : ", not reproducible: particles.mesher",
               check.time_delaunay, check.time_cells, t_write, path);
        pre_volume_report(&m);
        GSN_CALL_GOTO(pre_refine_report(c, &m), rc, done);
    }
done:
    gsn_model_free(&m);
    gsn_model_free(&bare);
    mesh_free(&mesh);
    return rc;
}

/* The surfaces on the body's boundary (of one volume) in no physical
 * group: free, and out of reach of boundary: (check says so). */
static int pre_unnamed_surfaces(double *count)
{
    int *surfaces = NULL, ierr = 0;
    size_t n = 0;
    *count = 0;
    gmshModelGetEntities(&surfaces, &n, 2, &ierr);
    for (size_t e = 0; ierr == 0 && e + 1 < n; e += 2) {
        int *up = NULL, *down = NULL, *groups = NULL;
        size_t up_n = 0, down_n = 0, group_n = 0;
        gmshModelGetAdjacencies(2, surfaces[e + 1], &up, &up_n, &down, &down_n,
                                &ierr);
        if (ierr == 0)
            gmshModelGetPhysicalGroupsForEntity(2, surfaces[e + 1], &groups,
                                                &group_n, &ierr);
        *count += up_n == 1 && group_n == 0;
        gmshFree(up);
        gmshFree(down);
        gmshFree(groups);
    }
    gmshFree(surfaces);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the unnamed surfaces");
    return GSN_OK;
}

/* check's child: the survey, the physical surfaces' names, and the
 * surfaces meshed at the spacing. */
static int pre_check_child(struct pre_child *child, void *arg)
{
    const struct pre_job *job = arg;
    const struct gsn_case *c = job->c;
    struct gmsh_session session; /* never ended: the child exits */
    GSN_CALL(gmsh_session_begin_case(&session, c));
    struct survey s;
    GSN_CALL(pre_survey(child, c, pre_reproducible(c, job->options), &s));
    /* estimate, at least, volume, surfaces meshed, unnamed surfaces */
    double numbers[5] = {s.estimate, s.at_least, s.volume, 0, 0};
    GSN_CALL(pre_unnamed_surfaces(&numbers[4]));
    /* the surfaces at the spacing cost as little as the estimate says */
    if (job->mesh_surfaces && s.estimate <= GSN_DEFAULT_MAX_PARTICLES) {
        int ierr = 0;
        pre_child_stage(child, "meshing its surfaces at spacing %g m",
                        c->particle_spacing);
        GSN_CALL(gmsh_set_size(0.0, c->particle_spacing));
        gmshModelMeshGenerate(2, &ierr);
        GMSH_CHECK(ierr, GSN_ERR_INPUT,
                   "%s: gmsh cannot mesh the surfaces of the geometry at "
                   "spacing %g m",
                   c->geometry, c->particle_spacing);
        numbers[3] = 1;
    }
    GSN_CALL(pre_child_send(child, numbers, sizeof numbers));
    int *groups = NULL, ierr = 0;
    size_t group_count = 0;
    gmshModelGetPhysicalGroups(&groups, &group_count, 2, &ierr);
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot list the physical surfaces");
    char(*names)[GSN_NAME_SIZE] = calloc(group_count / 2 + 1, sizeof *names);
    for (size_t g = 0; names && ierr == 0 && g + 1 < group_count; g += 2) {
        char *name = NULL;
        gmshModelGetPhysicalName(2, groups[g + 1], &name, &ierr);
        if (name && name[0])
            snprintf(names[g / 2], sizeof names[g / 2], "%s", name);
        else
            snprintf(names[g / 2], sizeof names[g / 2], "%d", groups[g + 1]);
        gmshFree(name);
    }
    gmshFree(groups);
    int rc = names ? GSN_OK : GSN_ERR_MEMORY;
    if (rc == GSN_OK)
        rc = pre_child_send(child, names, sizeof *names * (group_count / 2));
    free(names);
    GSN_CHECK(rc == GSN_OK, rc, "cannot send the physical surfaces' names");
    GMSH_CHECK(ierr, GSN_ERR_LIBRARY, "cannot read the physical names");
    return GSN_OK;
}

int gsn_pre_check_geometry(const struct gsn_case *c, int mesh_surfaces,
                           struct gsn_pre_survey *survey)
{
    struct gsn_pre_options options = {.quiet = 1};
    struct pre_job job = {c, &options, mesh_surfaces};
    struct pre_child_result r;
    GSN_CALL(pre_child_run(pre_check_child, &job, &r));
    int rc = GSN_OK;
    if (r.died)
        GSN_CALL_GOTO(pre_child_died(c, &r), rc, done);
    GSN_CHECK_GOTO(r.array_count == 2 && r.size[0] == sizeof(double[5]) &&
                       r.size[1] % GSN_NAME_SIZE == 0,
                   rc, GSN_ERR_INTERNAL, done,
                   "the checking process sent %d arrays", r.array_count);
    if (survey) {
        const double *numbers = r.array[0];
        const char(*names)[GSN_NAME_SIZE] = r.array[1];
        memset(survey, 0, sizeof *survey);
        survey->particle_estimate = numbers[0];
        survey->estimate_at_least = numbers[1] != 0;
        survey->volume = numbers[2];
        survey->surfaces_meshed = numbers[3] != 0;
        survey->unnamed_surface_count = (int)numbers[4];
        int count = (int)(r.size[1] / GSN_NAME_SIZE);
        for (int g = 0; g < count; ++g) {
            if (gsn_case_find_boundary(c, names[g]) >= 0)
                continue;
            size_t used = strlen(survey->free_surfaces);
            snprintf(survey->free_surfaces + used,
                     sizeof survey->free_surfaces - used, "%s%s",
                     survey->free_surface_count ? ", " : "", names[g]);
            survey->free_surface_count++;
        }
    }
done:
    pre_child_result_free(&r);
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
