/* pre's part of the economy keys (docs/economy.md): graded particle spacing
 * from particles.refine as gmsh size fields, and the checks of symmetry
 * planes and refinement surfaces against the geometry. */
#ifndef GEOSCNI_PRE_REFINE_H
#define GEOSCNI_PRE_REFINE_H

#include "estimate.h"
#include "geometry.h"
#include "geoscni/case.h"
#include "geoscni/model.h"

/* After gmsh opened the geometry: every refinement surface is a physical
 * surface, every symmetry entry's surface a plane normal to x, y or z (by
 * the bounding boxes of its gmsh entities). Errors name the case's line. */
int pre_refine_check(const struct gsn_case *c);

/* Sets the size fields of particles.refine (Box; Distance + Threshold;
 * combined with Min) as gmsh's background mesh. Nothing to do without
 * refinements. Samples each refinement surface by meshing it at its
 * spacing: call it only once the estimate allows that spacing. */
int pre_refine_fields(const struct gsn_case *c);

/* The particle count of the case's mesh (estimate.h) from the coarse mesh:
 * particles.spacing and every refinement, before any of them is meshed.
 * Stops integrating past cap (*at_least: the count is a lower bound). */
int pre_refine_estimate(const struct gsn_case *c, const struct coarse_mesh *m,
                        const struct estimate_coefficients *k, double cap,
                        double *estimate, int *at_least);

/* Prints the particles of each refinement region and of the rest. */
int pre_refine_report(const struct gsn_case *c, const struct gsn_model *m);

#endif
