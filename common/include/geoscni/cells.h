/* Nodal domains: Voronoi cells of the particles clipped to the body, as the
 * facets of a gsn_model (seed paper section 4, SCNI), with the checks every
 * set of cells passes. One library for pre, which builds them on the
 * reference configuration, and the solver, which builds them again on the
 * current positions when it updates the reference configuration (the
 * tetrahedra of the pre mesh, their nodes moved with the particles, are the
 * body's convex pieces). CGAL sits in one C++ file behind a C interface. */
#ifndef GEOSCNI_CELLS_H
#define GEOSCNI_CELLS_H

#include "geoscni/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Labels of the faces of the clipping polyhedra that are not particle
 * indices (>= 0) or physical surfaces (-1 - surface index). */
#define GSN_CELLS_LABEL_HULL (-1000000000)     /* bounding box: outside */
#define GSN_CELLS_LABEL_INTERNAL (-1000000001) /* between two pieces */
#define GSN_CELLS_LABEL_UNTAGGED (-1000000002) /* boundary, no surface */

/* The body as convex pieces (the mesh tetrahedra) for cells that cross its
 * boundary. Borrowed arrays. */
struct gsn_cells_body {
    int tetrahedron_count;
    const int *tetrahedra; /* tetrahedron_count x 4 particle indices */
    /* label of the face opposite vertex k of each tetrahedron: -1 - s on
     * physical surface s, GSN_CELLS_LABEL_UNTAGGED on an unnamed boundary,
     * GSN_CELLS_LABEL_INTERNAL between two tetrahedra */
    const int *face_label;
};

struct gsn_cells_input {
    int particle_count;
    const double *position;     /* particle_count x 3, borrowed */
    double lo[3], hi[3];        /* a box holding the body */
    int box_label[6];           /* labels of the box faces */
    struct gsn_cells_body body; /* tetrahedron_count 0: the box is the body */
    int facet_points;           /* 1 or 3 */
    int tetrahedra_only;        /* never cut a cell by its boundary planes */
    int threads;                /* 0: OpenMP's default */
};

/* Facets of the nodal domains, before the model is assembled. */
struct gsn_cells_result {
    int particle_count;
    double *volume;   /* particle_count */
    double *centroid; /* particle_count x 3 */
    int facet_count;
    int *facet_owner, *facet_neighbour, *facet_surface;
    double *facet_area, *facet_normal;
    int *facet_point_offset;
    double *facet_point, *facet_weight;
    double twin_error;    /* largest twin area mismatch / V^(2/3) */
    int crossing_count;   /* cells that meet the body's boundary */
    int pieced_count;     /* of those, cut by tetrahedra (not convex there) */
    double time_delaunay; /* s */
    double time_cells;    /* s */
};

/* Builds the clipped cells. Duplicate particles are GSN_ERR_INPUT naming
 * both by index and position. */
int gsn_cells_build(const struct gsn_cells_input *in,
                    struct gsn_cells_result *out);

void gsn_cells_result_free(struct gsn_cells_result *r);

/* Moves the facets, volumes and centroids into m, which must already have
 * particle_count set; allocates m's arrays with the given other sizes and
 * leaves them for the caller to fill. */
int gsn_cells_model_create(struct gsn_cells_result *r,
                           int particle_surface_entries, int surface_count,
                           int tetrahedron_count, struct gsn_model *m);

/* Tolerances of the model checks (issue 3, point 3). */
#define GSN_CELLS_TOLERANCE_VOLUME 1e-10  /* sum of volumes, relative */
#define GSN_CELLS_TOLERANCE_CLOSURE 1e-10 /* |sum A n| / V^(2/3) per cell */
#define GSN_CELLS_TOLERANCE_MOMENT 1e-10  /* first-moment identity / V */
#define GSN_CELLS_TOLERANCE_TWIN 1e-10    /* twin facet areas / V^(2/3) */
#define GSN_CELLS_TOLERANCE_AREA 1e-10    /* surface areas, relative */

/* What the checks measured: each error is the largest over the model, in
 * the units of its tolerance above. */
struct gsn_cells_report {
    double volume_error;  /* |sum V - body volume| / body volume */
    double closure_error; /* max over cells |sum A n| / V^(2/3) */
    double moment_error;  /* max |sum A n_j (c_k - x_k) - V delta_jk| / V */
    double twin_error;    /* max |A_ij - A_ji| / V^(2/3), when known */
    double area_error;    /* max over surfaces |area - gmsh's| / gmsh's */
    double min_volume;    /* smallest cell volume, m^3 */
    /* gsn_cells_model_at only: */
    double body_volume;   /* of the tetrahedra, m^3 */
    int crossing_count;   /* cells that meet the body's boundary */
    int pieced_count;     /* of those, cut by tetrahedra */
    double time_delaunay; /* s */
    double time_cells;    /* s */
};

/* Checks a model (issue 3, point 3): the volumes add up to body_volume, every
 * cell closes, sum over facets of A n_j (c_k - x_k) = V delta_jk per cell
 * (with the facets' quadrature points), every cell has positive volume, each
 * (owner, neighbour) pair is consistent, and the boundary area of every
 * surface equals m->surface_area. Fills report (may be NULL) and returns
 * GSN_ERR_INPUT naming the worst cell or surface when a check fails. */
int gsn_cells_check(const struct gsn_model *m, double body_volume,
                    struct gsn_cells_report *report);

/* The body as tetrahedra whose nodes are the particles, each positively
 * oriented where it was made, with what each face lies on (the model's
 * convention: a surface index, GSN_MODEL_FACE_INTERNAL or
 * GSN_MODEL_FACE_UNTAGGED). Its union is the body; the cells are clipped
 * to it. */
struct gsn_body {
    int tetrahedron_count;
    int *tetrahedra; /* x 4 particle indices */
    int *face;       /* x 4: the face opposite vertex k */
};

/* The face opposite vertex k of a positively oriented tetrahedron, its
 * vertices ordered so that their normal points out of it. */
extern const int gsn_cells_tetrahedron_face[4][3];

/* Area of the triangle (a, b, c) (3 coordinates each), m^2. */
double gsn_cells_triangle_area(const double *a, const double *b,
                               const double *c);

void gsn_body_free(struct gsn_body *b);
int gsn_body_copy(const struct gsn_body *from, struct gsn_body *to);

/* Signed volume of tetrahedron v at positions x (m^3). */
double gsn_body_tetrahedron_volume(const double *x, const int v[4]);

/* The tetrahedron of smallest signed volume at positions x, and that
 * volume over the mean (ratio; <= 0 where one is turned inside out). */
int gsn_body_worst(const struct gsn_body *b, const double *x, double *ratio);

/* The Delaunay tetrahedra of the points as a body (their convex hull),
 * every hull face GSN_MODEL_FACE_UNTAGGED for the caller to name. */
int gsn_body_of_points(const double *x, int particle_count,
                       struct gsn_body *out);

/* A new body for particles at x that the old body no longer fits (some of
 * its tetrahedra turned inside out): the Delaunay tetrahedra of x whose
 * centroids the old body's boundary surface encloses (its winding number,
 * so a boundary folded over itself still encloses its inside), their
 * boundary faces named as the old boundary triangles nearest to them. */
int gsn_body_remesh(const struct gsn_body *old, const double *x,
                    int particle_count, struct gsn_body *out);

struct gsn_cells_options {
    int facet_points;    /* quadrature points per facet: 1 or 3 */
    int threads;         /* 0: OpenMP's default */
    int tetrahedra_only; /* tests: cut every boundary cell by tetrahedra */
};

/* The cells of model m's particles at the given positions (n x 3, m; NULL:
 * m's own), clipped to the body (NULL: m's tetrahedra and their faces)
 * with its nodes at those positions: into out (allocated here, freed with
 * gsn_model_free), a copy of m with the positions, volumes, centroids,
 * facets, surface areas (of the body's boundary triangles there) and the
 * body of the new cells, checked (gsn_cells_check against the
 * tetrahedra's volume). A tetrahedron that the positions turn inside out
 * or flat is GSN_ERR_NUMERICAL naming it. report may be NULL. */
int gsn_cells_model_at(const struct gsn_model *m, const double *position,
                       const struct gsn_body *body,
                       const struct gsn_cells_options *options,
                       struct gsn_model *out, struct gsn_cells_report *report);

/* The body label of a tetrahedron face as the clipping uses it, from the
 * model's (surface index, GSN_MODEL_FACE_INTERNAL or
 * GSN_MODEL_FACE_UNTAGGED), and back. */
int gsn_cells_label_from_face(int face);
int gsn_cells_face_from_label(int label);

#ifdef __cplusplus
}
#endif
#endif
