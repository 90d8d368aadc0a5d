/* pre: the driver. Meshing and the nodal domains are built in issue 3. */
#include "geoscni/pre.h"
#include "geoscni/error.h"

#include <gmshc.h>
#include <stdio.h>

int gsn_pre_run(const struct gsn_case *c, const char *outdir,
                const struct gsn_pre_options *options)
{
    (void)options;
    GSN_CHECK(0, GSN_ERR_INTERNAL,
              "%s: geoscni pre is not implemented in this build yet (output "
              "folder %s)",
              c->path, outdir);
}

int gsn_pre_gmsh_version(char *out, size_t size)
{
    int ierr = 0;
    gmshInitialize(0, NULL, 0, &ierr);
    GSN_CHECK(ierr == 0, GSN_ERR_LIBRARY, "gmsh could not be initialized");
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    char *version = NULL;
    gmshOptionGetString("General.Version", &version, &ierr);
    int ok = ierr == 0 && version != NULL;
    if (ok)
        snprintf(out, size, "%s", version);
    gmshFree(version);
    gmshFinalize(&ierr);
    GSN_CHECK(ok, GSN_ERR_LIBRARY, "gmsh did not report its version");
    return GSN_OK;
}
