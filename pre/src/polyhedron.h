/* Convex polyhedra clipped by planes: the kernel of the nodal domains.
 *
 * A polyhedron is a list of faces, each a polygon of shared vertex indices
 * (counter-clockwise seen from outside) with a label (the neighbour particle
 * or boundary surface on its other side) and its plane n.y <= b. Vertices
 * are classified once per plane and every cut edge is split once, so the
 * two faces that share an edge always share the new vertex: the result is a
 * closed surface by construction, whatever the rounding (TOOLCHAIN.md,
 * "Clipped Voronoi cells"). Coordinates are local to the particle. */
#ifndef GEOSCNI_PRE_POLYHEDRON_H
#define GEOSCNI_PRE_POLYHEDRON_H

enum {
    POLY_MAX_VERTICES = 1024,
    POLY_MAX_FACES = 256,
    POLY_MAX_ENTRIES = 3072
};

/* Labels that are not particle indices (>= 0) or surfaces (-1 - index). */
#define POLY_LABEL_HULL (-1000000000)     /* bounding box: outside the body */
#define POLY_LABEL_INTERNAL (-1000000001) /* between two convex pieces */
#define POLY_LABEL_UNTAGGED (-1000000002) /* boundary, no physical surface */

enum poly_clip_result {
    POLY_CLIP_UNCHANGED = 0,
    POLY_CLIP_CUT,
    POLY_CLIP_EMPTY,
    POLY_CLIP_OVERFLOW,
    POLY_CLIP_TOPOLOGY
};

struct poly {
    int vertex_count;
    int face_count;
    double vertex[3 * POLY_MAX_VERTICES];
    int face_label[POLY_MAX_FACES];
    double face_plane[4 * POLY_MAX_FACES]; /* unit n, b: n.y <= b inside */
    int face_start[POLY_MAX_FACES + 1];
    int entry[POLY_MAX_ENTRIES];
};

/* Scratch space of one thread for poly_clip. */
struct poly_scratch {
    double distance[POLY_MAX_VERTICES];
    signed char side[POLY_MAX_VERTICES];
    int map[POLY_MAX_VERTICES];
    int next[POLY_MAX_VERTICES];
    struct poly out;
};

/* The box [lo, hi] (local coordinates) with face labels in the order
 * xmin, xmax, ymin, ymax, zmin, zmax. */
void poly_init_box(struct poly *p, const double lo[3], const double hi[3],
                   const int label[6]);

/* A tetrahedron (v: 4 x 3); label[k] is the face opposite vertex k. Returns 0
 * if the tetrahedron is degenerate (zero volume). */
int poly_init_tetrahedron(struct poly *p, const double *v, const int label[4]);

/* Copies the used part of a polyhedron. */
void poly_copy(struct poly *restrict to, const struct poly *restrict from);

/* Keeps the part n.y <= b (n a unit vector); the new face gets label.
 * Vertices within eps of the plane count as on it. A face lying in the
 * plane takes the new label. On OVERFLOW or TOPOLOGY p is unchanged. */
enum poly_clip_result poly_clip(struct poly *p, struct poly_scratch *s,
                                const double n[3], double b, int label,
                                double eps);

/* Largest squared distance of a vertex from the origin. */
double poly_radius2(const struct poly *p);

/* Volume and the first moment (volume times centroid), by tetrahedra from
 * the origin. */
void poly_volume(const struct poly *p, double *volume, double moment[3]);

/* Area vector (area times outward unit normal) of face f, by a fan of
 * triangles from its first vertex. */
void poly_face_area(const struct poly *p, int f, double area[3]);

/* Quadrature points (local) and weights of face f: facet_points 1 gives the
 * centroid with the whole area; 3 gives three points per fan triangle
 * (degree 2, Strang-Fix). normal is the face's unit normal; weights are the
 * fan triangles' areas projected on it, so they add up to the area. Returns
 * the number of points written (at most 3 * (vertices - 2)). */
int poly_face_quadrature(const struct poly *p, int f, const double normal[3],
                         int facet_points, double *restrict point,
                         double *restrict weight);

/* Whether the triangle t (3 x 3, local coordinates) meets the polyhedron in a
 * set of positive area (more than area_eps). */
int poly_meets_triangle(const struct poly *p, const double *t, double eps,
                        double area_eps);

#endif
