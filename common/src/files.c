/* Folders and atomic writes. */
#include "geoscni/files.h"
#include "geoscni/error.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int gsn_folder_prepare(const char *folder)
{
    char partial[4096];
    size_t n = strlen(folder);
    GSN_CHECK(n > 0 && n < sizeof partial, GSN_ERR_INPUT,
              "output folder name is empty or too long");
    for (size_t i = 1; i <= n; ++i) {
        if (folder[i] != '/' && folder[i] != '\0')
            continue;
        memcpy(partial, folder, i);
        partial[i] = '\0';
        if (mkdir(partial, 0777) != 0 && errno != EEXIST)
            return gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                                   "%s: cannot create the output folder: %s",
                                   partial, strerror(errno));
    }
    struct stat info;
    GSN_CHECK(stat(folder, &info) == 0 && S_ISDIR(info.st_mode), GSN_ERR_INPUT,
              "%s: the output path exists and is not a folder", folder);
    GSN_CHECK(access(folder, W_OK | X_OK) == 0, GSN_ERR_INPUT,
              "%s: the output folder is not writable; choose another with -o",
              folder);
    return GSN_OK;
}

int gsn_path_join(char *out, size_t size, const char *folder, const char *name)
{
    int n = snprintf(out, size, "%s/%s", folder, name);
    GSN_CHECK(n > 0 && (size_t)n < size, GSN_ERR_INPUT, "path too long: %s/%s",
              folder, name);
    return GSN_OK;
}

int gsn_path_temporary(char *out, size_t size, const char *path)
{
    int n = snprintf(out, size, "%s.part", path);
    GSN_CHECK(n > 0 && (size_t)n < size, GSN_ERR_INPUT, "path too long: %s",
              path);
    return GSN_OK;
}

int gsn_file_commit(const char *path)
{
    char temporary[4096];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    GSN_CHECK(rename(temporary, path) == 0, GSN_ERR_IO,
              "cannot rename %s to %s: %s", temporary, path, strerror(errno));
    return GSN_OK;
}

void gsn_file_discard(const char *path)
{
    char temporary[4096];
    if (snprintf(temporary, sizeof temporary, "%s.part", path) <
        (int)sizeof temporary)
        unlink(temporary);
}
