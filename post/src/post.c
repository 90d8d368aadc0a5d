/* post: the driver. Files, plots and pictures are built in issue 6. */
#include "geoscni/post.h"
#include "geoscni/error.h"

int gsn_post_run(const char *outdir, const struct gsn_post_options *options)
{
    (void)options;
    GSN_CHECK(0, GSN_ERR_INTERNAL,
              "geoscni post is not implemented in this build yet (output "
              "folder %s)",
              outdir);
}
