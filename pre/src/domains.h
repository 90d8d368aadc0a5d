/* Nodal domains: Voronoi cells of the particles clipped to the body, as the
 * facets of a gsn_model (seed paper section 4, SCNI). Internal to pre. */
#ifndef GEOSCNI_PRE_DOMAINS_H
#define GEOSCNI_PRE_DOMAINS_H

#include "geoscni/model.h"
#include "geoscni/pre.h"

/* The body as convex pieces (the mesh tetrahedra) for cells that cross its
 * boundary. Borrowed arrays. */
struct domain_body {
    int tetrahedron_count;
    const int *tetrahedra; /* tetrahedron_count x 4 particle indices */
    /* label of the face opposite vertex k of each tetrahedron: -1 - s on
     * physical surface s, POLY_LABEL_UNTAGGED on an unnamed boundary,
     * POLY_LABEL_INTERNAL between two tetrahedra */
    const int *face_label;
};

struct domain_input {
    int particle_count;
    const double *position;  /* particle_count x 3, borrowed */
    double lo[3], hi[3];     /* a box holding the body */
    int box_label[6];        /* labels of the box faces */
    struct domain_body body; /* tetrahedron_count 0: the box is the body */
    int facet_points;        /* 1 or 3 */
    int tetrahedra_only;     /* never cut a cell by its boundary planes */
    int threads;             /* 0: OpenMP's default */
};

/* Facets of the nodal domains, before the model is assembled. */
struct domain_result {
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
int domains_build(const struct domain_input *in, struct domain_result *out);

void domains_result_free(struct domain_result *r);

/* Moves the facets, volumes and centroids into m, which must already have
 * particle_count set; allocates m's arrays with the given other sizes and
 * leaves them for the caller to fill. */
int domains_model_create(struct domain_result *r, int particle_surface_entries,
                         int surface_count, int tetrahedron_count,
                         struct gsn_model *m);

#endif
