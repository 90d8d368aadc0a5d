/* One number of a finished run, in SI units: what `geoscni converge`
 * follows from level to level (docs/converge.md). */
#ifndef GEOSCNI_QUANTITY_H
#define GEOSCNI_QUANTITY_H

#include "geoscni/case.h"

#ifdef __cplusplus
extern "C" {
#endif

enum gsn_quantity_kind {
    GSN_QUANTITY_PEAK_FORCE = 0,  /* the largest force on the body through a
                                     moving boundary entry, along its motion
                                     (the load-settlement plot's peak) */
    GSN_QUANTITY_FORCE_AT,        /* that force at a given settlement */
    GSN_QUANTITY_DISPLACEMENT_AT, /* |u| at a point of the reference body,
                                     at the last frame */
    GSN_QUANTITY_FACTOR_OF_SAFETY /* geoscni fos of the level (app/fos.c),
                                     not a run's number */
};

struct gsn_quantity {
    enum gsn_quantity_kind kind;
    int per_area; /* a force over the surface's reference area: a pressure
                     (peak_pressure, pressure_at), the number that stays
                     when a slab's thickness follows the spacing */
    char surface[GSN_NAME_SIZE]; /* the boundary entry; "": the one the case
                                    moves (gsn_quantity_resolve) */
    double at;                   /* FORCE_AT: the settlement, m */
    double point[3];             /* DISPLACEMENT_AT: m */
};

/* Parses "peak_force", "peak_force:SURFACE", "force_at:S" (S in m),
 * "force_at:S:SURFACE", the same with "pressure" for "force",
 * "displacement_at:X,Y,Z" (m), or "factor_of_safety". */
int gsn_quantity_parse(const char *text, struct gsn_quantity *q);

/* Names the boundary entry of a force where none was given (the case's one
 * entry with a prescribed velocity) and checks that it moves; writes what
 * the quantity is in words ("peak force on 'footing'") and its unit. */
int gsn_quantity_resolve(const struct gsn_case *c, struct gsn_quantity *q,
                         char *description, size_t size, const char **unit);

/* The quantity of the run in outdir (history.csv; for a displacement the
 * last frame of results.h5 interpolated in model.h5's tetrahedra). A force
 * is the whole body's: twice the half model's where the case mirrors it
 * (output.mirror), as the load-settlement plot shows it. */
int gsn_quantity_measure(const char *outdir, const struct gsn_case *c,
                         const struct gsn_quantity *q, double *value);

/* The reference area (m^2, as gmsh measured it) of physical surface name
 * in outdir/model.h5. */
int gsn_quantity_surface_area(const char *outdir, const char *name,
                              double *area);

#ifdef __cplusplus
}
#endif
#endif
