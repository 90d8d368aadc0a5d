/* Code and library versions, recorded in every output file. */
#ifndef GEOSCNI_VERSION_H
#define GEOSCNI_VERSION_H

#ifdef __cplusplus
extern "C" {
#endif

/* "0.1.0 (git abc1234)" */
const char *gsn_code_version(void);

/* "gmsh 4.8.0, CGAL 5.5.1, HDF5 1.10.8, VTK 9.1.0": the versions geoscni was
 * built with (gmsh: the API version of its header). */
const char *gsn_library_versions(void);

#ifdef __cplusplus
}
#endif
#endif
