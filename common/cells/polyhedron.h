/* Convex polyhedra clipped by planes: the kernel of the nodal domains.
 *
 * A polyhedron is a list of faces, each a polygon of shared vertex indices
 * (counter-clockwise seen from outside) with a label (the neighbour particle
 * or boundary surface on its other side) and its plane n.y <= b. Vertices
 * are classified once per plane and every cut edge is split once, so the
 * two faces that share an edge always share the new vertex: the result is a
 * closed surface by construction, whatever the rounding (TOOLCHAIN.md,
 * "Clipped Voronoi cells"). Coordinates are local to the particle. */
#ifndef GEOSCNI_CELLS_POLYHEDRON_H
#define GEOSCNI_CELLS_POLYHEDRON_H

#include "geoscni/cells.h"

enum {
    POLY_MAX_VERTICES = 1024,
    POLY_MAX_FACES = 256,
    POLY_MAX_ENTRIES = 3072
};

/* Labels that are not particle indices (>= 0) or surfaces (-1 - index). */
#define POLY_LABEL_HULL GSN_CELLS_LABEL_HULL
#define POLY_LABEL_INTERNAL GSN_CELLS_LABEL_INTERNAL
#define POLY_LABEL_UNTAGGED GSN_CELLS_LABEL_UNTAGGED

enum gsn_poly_clip_result {
    POLY_CLIP_UNCHANGED = 0,
    POLY_CLIP_CUT,
    POLY_CLIP_EMPTY,
    POLY_CLIP_OVERFLOW,
    POLY_CLIP_TOPOLOGY
};

struct gsn_poly {
    int vertex_count;
    int face_count;
    double vertex[3 * POLY_MAX_VERTICES];
    int face_label[POLY_MAX_FACES];
    double face_plane[4 * POLY_MAX_FACES]; /* unit n, b: n.y <= b inside */
    int face_start[POLY_MAX_FACES + 1];
    int entry[POLY_MAX_ENTRIES];
};

/* Scratch space of one thread for gsn_poly_clip. */
struct gsn_poly_scratch {
    double distance[POLY_MAX_VERTICES];
    signed char side[POLY_MAX_VERTICES];
    int map[POLY_MAX_VERTICES];
    int next[POLY_MAX_VERTICES];
    struct gsn_poly out;
};

/* The box [lo, hi] (local coordinates) with face labels in the order
 * xmin, xmax, ymin, ymax, zmin, zmax. */
void gsn_poly_init_box(struct gsn_poly *p, const double lo[3],
                       const double hi[3], const int label[6]);

/* A tetrahedron (v: 4 x 3); label[k] is the face opposite vertex k. Returns 0
 * if the tetrahedron is degenerate (zero volume). */
int gsn_poly_init_tetrahedron(struct gsn_poly *p, const double *v,
                              const int label[4]);

/* Copies the used part of a polyhedron. */
void gsn_poly_copy(struct gsn_poly *restrict to,
                   const struct gsn_poly *restrict from);

/* Keeps the part n.y <= b (n a unit vector); the new face gets label.
 * Vertices within eps of the plane count as on it. A face lying in the
 * plane takes the new label. On OVERFLOW or TOPOLOGY p is unchanged. */
enum gsn_poly_clip_result gsn_poly_clip(struct gsn_poly *p,
                                        struct gsn_poly_scratch *s,
                                        const double n[3], double b, int label,
                                        double eps);

/* Largest squared distance of a vertex from the origin. */
double gsn_poly_radius2(const struct gsn_poly *p);

/* Volume and the first moment (volume times centroid), by tetrahedra from
 * the origin. */
void gsn_poly_volume(const struct gsn_poly *p, double *volume,
                     double moment[3]);

/* Area vector (area times outward unit normal) of face f, by a fan of
 * triangles from its first vertex. */
void gsn_poly_face_area(const struct gsn_poly *p, int f, double area[3]);

/* Quadrature points (local) and weights of face f: facet_points 1 gives the
 * centroid with the whole area; 3 gives three points per fan triangle
 * (degree 2, Strang-Fix). normal is the face's unit normal; weights are the
 * fan triangles' areas projected on it, so they add up to the area. Returns
 * the number of points written (at most 3 * (vertices - 2)). */
int gsn_poly_face_quadrature(const struct gsn_poly *p, int f,
                             const double normal[3], int facet_points,
                             double *restrict point, double *restrict weight);

/* Whether the triangle t (3 x 3, local coordinates) meets the polyhedron in a
 * set of positive area (more than area_eps). */
int gsn_poly_meets_triangle(const struct gsn_poly *p, const double *t,
                            double eps, double area_eps);

#endif
