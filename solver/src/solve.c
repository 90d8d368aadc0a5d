/* solver: the driver. The time loop is built in issue 5. */
#include "geoscni/error.h"
#include "geoscni/solver.h"

int gsn_solve_run(const struct gsn_case *c, const char *outdir,
                  const struct gsn_solve_options *options)
{
    (void)options;
    GSN_CHECK(0, GSN_ERR_INTERNAL,
              "%s: geoscni solve is not implemented in this build yet "
              "(output folder %s)",
              c->path, outdir);
}
