// The VTK library version at run time, behind an extern "C" interface.
#include "geoscni/post.h"

#include <vtkVersion.h>

extern "C" const char *gsn_post_vtk_version(void)
{
    return vtkVersion::GetVTKVersion();
}
