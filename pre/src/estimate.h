/* The particle count of a mesh before it is made (issue 21, point 6): the
 * mesh-size function gmsh will use (particles.spacing capped by the
 * refinements' Box and Threshold fields, refine.c) integrated over a coarse
 * mesh of the body. No gmsh here: plain arrays in, a number out. */
#ifndef GEOSCNI_PRE_ESTIMATE_H
#define GEOSCNI_PRE_ESTIMATE_H

#include "geoscni/case.h"

/* A coarse mesh of the body: nodes (m), the volume's tetrahedra, the
 * triangles of its surfaces and the segments of its curves (indices into
 * position). */
struct estimate_body {
    int node_count;
    const double *position;
    int tetrahedron_count;
    const int *tetrahedra;
    int triangle_count;
    const int *triangles;
    int segment_count;
    const int *segments;
};

/* A refinement as gmsh's fields see it: a box (GSN_REFINE_BOX) or the
 * triangles of a surface (GSN_REFINE_SURFACE; indices into the body's
 * nodes), with the spacing there, the width where it holds (surfaces) and
 * the distance over which it grows to particles.spacing. */
struct estimate_refinement {
    enum gsn_refine_kind kind;
    double box[6];
    int triangle_count;
    const int *triangles;
    double spacing, width, distance;
};

/* Nodes per unit of size^-3 dV, size^-2 dA and size^-1 dl of a gmsh
 * tetrahedral mesh whose size is given: N = volume * int dV / size^3 +
 * surface * int dA / size^2 + edge * int dl / size. */
struct estimate_coefficients {
    double volume, surface, edge;
};

/* The coefficients of gmsh 4.8's 3D algorithms (estimate.c says how they
 * were measured): HXT (pre's default) and Delaunay (reproducible). */
void estimate_coefficients_for(int reproducible,
                               struct estimate_coefficients *k);

/* The particle count of the body meshed at spacing with the refinements.
 * The integrals are adaptive on the coarse elements (exact where the size
 * is linear on an element) to about 1 %; the work stops early once the
 * count passes cap: then *at_least is set and *count, at least cap, is a
 * lower bound. */
int estimate_particles(const struct estimate_body *body, double spacing,
                       const struct estimate_refinement *refinements,
                       int refinement_count,
                       const struct estimate_coefficients *k, double cap,
                       double *count, int *at_least);

/* Squared distance from p to the triangle abc. */
double estimate_triangle_distance2(const double p[3], const double a[3],
                                   const double b[3], const double c[3]);

/* The same integrals without coefficients: int dV/size^3, int dA/size^2 and
 * int dl/size over the body (for tests). */
int estimate_integrals(const struct estimate_body *body, double spacing,
                       const struct estimate_refinement *refinements,
                       int refinement_count, double integrals[3]);

#endif
