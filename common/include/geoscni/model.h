/* The model that pre writes to model.h5 and the solver reads: particles,
 * their nodal domains (clipped Voronoi cells) as facets with quadrature
 * points, the physical surfaces, and the tetrahedra for visualization.
 * Arrays are n x columns row-major, as the datasets of schema.h. */
#ifndef GEOSCNI_MODEL_H
#define GEOSCNI_MODEL_H

#include "geoscni/case.h"
#include "geoscni/h5io.h"

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_model {
    int particle_count;
    double *position;             /* particle_count x 3, m */
    double *volume;               /* particle_count, m^3 */
    double *centroid;             /* particle_count x 3, m */
    int *particle_surface_offset; /* particle_count + 1 */
    int *particle_surface;        /* surface indices, CSR */

    int facet_count;
    int *facet_owner;        /* facet_count */
    int *facet_neighbour;    /* facet_count, -1 on the boundary */
    int *facet_surface;      /* facet_count, -1 if interior or untagged */
    double *facet_area;      /* facet_count, m^2 */
    double *facet_normal;    /* facet_count x 3, outward from the owner */
    int *facet_point_offset; /* facet_count + 1 */
    double *facet_point;     /* points x 3, m */
    double *facet_weight;    /* points, m^2 */

    int surface_count;
    char (*surface_name)[GSN_H5_STRING_SIZE];
    int *surface_tag;     /* gmsh physical tag */
    double *surface_area; /* m^2, as gmsh measures it */

    /* gmsh's physical volumes (materials: gives each its soil) */
    int volume_count;
    char (*volume_name)[GSN_H5_STRING_SIZE];
    int *volume_tag;         /* gmsh physical tag */
    int *particle_volume;    /* particle_count: index into the volumes, -1
                                in none; a particle on an interface takes
                                the volume with most of its tetrahedra */
    int *tetrahedron_volume; /* tetrahedron_count: index, -1 in none */

    int tetrahedron_count;
    int *tetrahedra; /* tetrahedron_count x 4 particle indices */
    /* tetrahedron_count x 4: what the face opposite vertex k of each
     * tetrahedron lies on: a surface index, or GSN_MODEL_FACE_INTERNAL
     * (shared by two tetrahedra), or GSN_MODEL_FACE_UNTAGGED (the body's
     * boundary outside every physical surface) */
    int *tetrahedron_face;
};

#define GSN_MODEL_FACE_INTERNAL (-1)
#define GSN_MODEL_FACE_UNTAGGED (-2)

/* Allocates every array for the given sizes (zeroed); offsets are left 0. */
int gsn_model_allocate(struct gsn_model *m, int particle_count,
                       int particle_surface_entries, int facet_count,
                       int facet_point_count, int surface_count,
                       int tetrahedron_count);

/* Allocates the names and tags of volume_count physical volumes (the
 * particles' and tetrahedra's indices come with gsn_model_allocate, -1). */
int gsn_model_allocate_volumes(struct gsn_model *m, int volume_count);

/* Copies the physical volumes (names, tags, the particles' and the
 * tetrahedra's indices) of from into to, which has the same particles and
 * tetrahedra. */
int gsn_model_copy_volumes(const struct gsn_model *from, struct gsn_model *to);

/* Frees every array and zeroes the struct; accepts a zeroed struct. */
void gsn_model_free(struct gsn_model *m);

/* Writes path atomically (a temporary name renamed when complete) with the
 * resolved case recorded. */
int gsn_model_write(const char *path, const struct gsn_model *m,
                    const struct gsn_case *c);

/* Reads and checks the shape and index ranges of a model file. */
int gsn_model_read(const char *path, struct gsn_model *m);

/* Renumbers the particles in Morton (Z) order of their positions and the
 * facets by owner, so that neighbours lie near each other in memory; every
 * index array (facets, surfaces, tetrahedra) follows. */
int gsn_model_sort_spatially(struct gsn_model *m);

/* 1 if the particle carries the surface's tag. */
int gsn_model_particle_on_surface(const struct gsn_model *m, int particle,
                                  int surface);

/* Index of a physical volume by name, or -1. */
int gsn_model_find_volume(const struct gsn_model *m, const char *name);

/* Index of a surface by name, or -1. */
int gsn_model_find_surface(const struct gsn_model *m, const char *name);

/* The plane of a surface that is one plane normal to a coordinate axis
 * (a symmetry plane): its particles' coordinates along axis (0, 1, 2) agree
 * to 1e-9 of the body's size, at offset (m). GSN_ERR_INPUT, naming the
 * surface, if the surface has no particles or is not such a plane. */
int gsn_model_surface_plane(const struct gsn_model *m, int surface, int *axis,
                            double *offset);

/* Marks, for every boundary entry of c with symmetry: true, the component
 * normal to its plane (gsn_model_surface_plane) as fixed; a surface that is
 * not an axis-aligned plane is refused with the case file's line. */
int gsn_case_resolve_symmetry(struct gsn_case *c, const struct gsn_model *m);

#ifdef __cplusplus
}
#endif
#endif
