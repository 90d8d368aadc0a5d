/* Output folders and atomic file writing (a temporary name renamed when the
 * file is complete), shared by the stages. */
#ifndef GEOSCNI_FILES_H
#define GEOSCNI_FILES_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Creates folder (and its parents) if needed and checks it is writable. */
int gsn_folder_prepare(const char *folder);

/* out = folder + "/" + name; fails if it does not fit. */
int gsn_path_join(char *out, size_t size, const char *folder, const char *name);

/* The temporary name under which path is written: path + ".part". */
int gsn_path_temporary(char *out, size_t size, const char *path);

/* Renames the temporary file of path onto path. */
int gsn_file_commit(const char *path);

/* Removes the temporary file of path, if any (after a failure). */
void gsn_file_discard(const char *path);

#ifdef __cplusplus
}
#endif
#endif
