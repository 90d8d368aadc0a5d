/* pre: gmsh geometry -> particles and clipped Voronoi nodal domains ->
 * model.h5 (DESIGN.md, "Pipeline"). */
#ifndef GEOSCNI_PRE_H
#define GEOSCNI_PRE_H

#include "geoscni/case.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct gsn_pre_options {
    int force;   /* allow more than GSN_DEFAULT_MAX_PARTICLES particles */
    int threads; /* 0: OpenMP's default */
    int quiet;   /* no progress output */
};

/* Builds OUTDIR/model.h5 from the case. */
int gsn_pre_run(const struct gsn_case *c, const char *outdir,
                const struct gsn_pre_options *options);

/* The version of the gmsh library loaded at run time, e.g. "4.8.4". */
int gsn_pre_gmsh_version(char *out, size_t size);

#ifdef __cplusplus
}
#endif
#endif
