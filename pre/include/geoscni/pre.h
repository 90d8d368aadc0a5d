/* pre: gmsh geometry -> particles and clipped Voronoi nodal domains ->
 * model.h5 (DESIGN.md, "Pipeline"). */
#ifndef GEOSCNI_PRE_H
#define GEOSCNI_PRE_H

#include "geoscni/case.h"
#include "geoscni/cells.h"
#include "geoscni/model.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_pre_options {
    int force;   /* allow more than GSN_DEFAULT_MAX_PARTICLES particles */
    int threads; /* 0: OpenMP's default */
    int quiet;   /* no progress output */
    /* for tests: gmsh's Delaunay mesher even where the case asks for HXT
     * (particles.mesher; Delaunay is the default) */
    int reproducible;
    /* for tests: every cell that meets the boundary is intersected with the
     * mesh tetrahedra, also where its boundary planes would do (the brute
     * force the faster path is checked against) */
    int tetrahedra_only;
};

/* Builds OUTDIR/model.h5 from the case: meshes the geometry with gmsh,
 * takes the mesh nodes as particles, clips their Voronoi cells to the body,
 * checks the model (gsn_cells_check) and writes it. */
int gsn_pre_run(const struct gsn_case *c, const char *outdir,
                const struct gsn_pre_options *options);

/* What check learns of a case's geometry (gsn_pre_check_geometry). */
struct gsn_pre_survey {
    double particle_estimate;  /* the particles pre would make (about) */
    int estimate_at_least;     /* far over the limit: a lower bound */
    double volume;             /* m^3, of a coarse mesh */
    int surfaces_meshed;       /* the surfaces were meshed at the spacing */
    int free_surface_count;    /* physical surfaces without a boundary entry */
    char free_surfaces[1024];  /* their names, ", "-separated */
    int unnamed_surface_count; /* boundary surfaces in no physical group */
};

/* What pre checks of the case against its geometry, without the volume
 * mesh, all in a child process (a gmsh abort or exit is an error here):
 * gmsh reads the geometry, which has a volume; it lies near the origin,
 * has no zero-length curve, and is no thinner than the spacing; every
 * boundary and surface refinement names a physical surface of it (with a
 * did-you-mean); symmetry surfaces are axis-aligned planes; a coarse mesh
 * shows that every volume is closed and that volumes do not touch without
 * sharing faces, and gives the particle estimate. With mesh_surfaces, the
 * surfaces are then meshed at particles.spacing (unless the estimate is
 * over the particle limit), which catches most of what would stop gmsh in
 * pre. survey may be NULL. */
int gsn_pre_check_geometry(const struct gsn_case *c, int mesh_surfaces,
                           struct gsn_pre_survey *survey);

/* The version of the gmsh library loaded at run time, e.g. "4.8.4". */
int gsn_pre_gmsh_version(char *out, size_t size);

/* Voronoi cells of n arbitrary points (n x 3, row-major, m) clipped to the
 * axis-aligned box [lo, hi] that holds them, as a complete model (allocated
 * here, freed with gsn_model_free): volumes, centroids, facets stored once
 * with owner and neighbour, quadrature points (facet_points 1: centroid;
 * 3: three points per triangle of a fan, degree 2). The boundary facets and
 * the particles lying on a face (within 1e-12 of the box diagonal) are tagged
 * with the surfaces xmin, xmax, ymin, ymax, zmin, zmax (indices 0..5); a
 * particle on an edge or corner carries every face it touches. No
 * tetrahedra. The model is checked (gsn_cells_check); report may be
 * NULL. threads 0 uses OpenMP's default. */
int gsn_pre_domains_box(const double *points, int n, const double lo[3],
                        const double hi[3], int facet_points,
                        struct gsn_model *m);

/* The same with the checks' report and a thread count. */
int gsn_pre_domains_box_ex(const double *points, int n, const double lo[3],
                           const double hi[3], int facet_points, int threads,
                           struct gsn_model *m,
                           struct gsn_cells_report *report);

/* Particles of a refinement region of the case (particles.refine[region];
 * region -1: the body outside every region and its transition) in a model:
 * count, and the median cell size V_I^(1/3) (m) of the interior particles
 * (no surface tag: boundary cells are cut) in its core, 0 if none. A box
 * region holds the particles inside the box grown by its distance, its
 * core those inside the box; a surface region holds the particles within
 * its width + distance of the surface's particles, its core those within
 * its width + a quarter of its distance. */
int gsn_pre_refinement_stats(const struct gsn_case *c,
                             const struct gsn_model *m, int region, int *count,
                             double *cell_size);

#ifdef __cplusplus
}
#endif
#endif
