/* Versions come from the headers (gmsh, HDF5) and from CMake's find_package
 * results (CGAL, VTK), passed as compile definitions. */
#include "geoscni/version.h"

#include <gmshc.h>
#include <hdf5.h>

#ifndef GSN_CODE_VERSION
#error "GSN_CODE_VERSION must be defined by the build"
#endif
#ifndef GSN_CGAL_VERSION
#error "GSN_CGAL_VERSION must be defined by the build"
#endif
#ifndef GSN_VTK_VERSION
#error "GSN_VTK_VERSION must be defined by the build"
#endif

#define GSN_STRINGIFY_(x) #x
#define GSN_STRINGIFY(x) GSN_STRINGIFY_(x)

const char *gsn_code_version(void)
{
    return GSN_CODE_VERSION;
}

const char *gsn_library_versions(void)
{
    return "gmsh " GMSH_API_VERSION ", CGAL " GSN_CGAL_VERSION
           ", HDF5 " GSN_STRINGIFY(H5_VERS_MAJOR) "." GSN_STRINGIFY(
               H5_VERS_MINOR) "." GSN_STRINGIFY(H5_VERS_RELEASE) ", "
                                                                 "VTK"
                                                                 " " GSN_VTK_VERSION;
}
