/* The weight of the soil above a point (issue 22): the total vertical
 * stress of level ground, layered ground and slopes alike, for the
 * geostatic stage's K0 procedure (docs/solver.md, "The soil's own
 * weight"). */
#ifndef GEOSCNI_OVERBURDEN_H
#define GEOSCNI_OVERBURDEN_H

#include "geoscni/case.h"
#include "geoscni/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* sigma_v at each of count points (n x 3, m): -|g| times the integral of the
 * density along the vertical above the point through model m's tetrahedra,
 * each with its volume's material (c->materials), saturated below the
 * water table (Pa, compression negative). A point on the body's boundary
 * takes the largest of four columns a hair beside it (the vertical through
 * a mesh node runs along the tetrahedra's edges and faces). */
int gsn_overburden(const struct gsn_model *m, const struct gsn_case *c,
                   int count, const double *points, double *sigma_v);

#ifdef __cplusplus
}
#endif
#endif
