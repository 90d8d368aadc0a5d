/* What pre checks of the geometry gmsh has read (issue 21, point 7), and
 * the coarse mesh the checks and the particle estimate use. Runs where gmsh
 * does: in pre's child process (child.h). */
#ifndef GEOSCNI_PRE_GEOMETRY_H
#define GEOSCNI_PRE_GEOMETRY_H

#include "geoscni/case.h"

#include <stddef.h>

/* Far from the origin (in particle spacings) coordinates lose the digits
 * the nodal domains need: rounding 1.1e-16 |x| against the checks'
 * 1e-10 of a spacing; the 2.5e5 of a slope at UTM coordinates failed them. */
#define GEOMETRY_FAR_SPACINGS 1e5
/* Points closer than this fraction of the model's diagonal are one place. */
#define GEOMETRY_SAME_POINT 1e-9

/* A coarse mesh of the body: nodes (m), tetrahedra, the triangles of the
 * surfaces that bound a volume (with each one's gmsh surface tag) and the
 * segments of the curves; indices into position. */
struct coarse_mesh {
    double size; /* m, the element size it was made with */
    int node_count;
    double *position;
    int tetrahedron_count;
    int *tetrahedra;
    int triangle_count;
    int *triangles;
    int *triangle_surface;
    int segment_count;
    int *segments;
};

void coarse_mesh_free(struct coarse_mesh *m);

/* gmsh's last error message, or "no message". */
void geometry_gmsh_last_error(char *out, size_t size);

/* Before meshing: the geometry lies near the origin (within
 * GEOMETRY_FAR_SPACINGS of the smallest spacing), no two points of its
 * curves are at one place (a zero-length curve), and particles.spacing is
 * no larger than the body. Errors name the file and say what to change. */
int geometry_check(const struct gsn_case *c);

/* Meshes the surfaces at the coarse size (the model's diagonal / 8) and
 * checks that each volume's surfaces close it and that volumes do not
 * touch without sharing faces; then meshes the volumes (Delaunay) and
 * reads the coarse mesh into m. Leaves the mesh in gmsh (clear it). */
int geometry_coarse_mesh(const struct gsn_case *c, struct coarse_mesh *m);

/* The line of the first statement of a .geo file that is `word;` (say
 * Exit or Abort), 0 if none: a file that stops gmsh's parser. */
int geometry_statement_line(const char *path, const char *word);

#endif
