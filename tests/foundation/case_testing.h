/* Shared by the case-file tests: a case through the resolved YAML that
 * every output file stores, and back. */
#ifndef GEOSCNI_CASE_TESTING_H
#define GEOSCNI_CASE_TESTING_H

#include "geoscni/case.h"
#include "geoscni/error.h"
#include "testing.h"

#include <stdlib.h>

/* Writes c as resolved YAML and loads it back into again (checked). */
static inline void round_trip(const struct gsn_case *c, struct gsn_case *again)
{
    char path[] = "/tmp/geoscni-test-case-XXXXXX";
    int fd = mkstemp(path);
    TEST_TRUE(fd >= 0);
    FILE *out = fdopen(fd, "w");
    TEST_INT(gsn_case_write_yaml(c, out), GSN_OK);
    fclose(out);
    int rc = gsn_case_load(path, again);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    TEST_INT(rc, GSN_OK);
    remove(path);
}

#endif
