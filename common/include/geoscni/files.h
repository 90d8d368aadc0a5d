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

/* Raises the error of a failed write of path, `what` saying what failed
 * ("cannot write dataset 'x'"): GSN_ERR_NO_SPACE, with "no space left on
 * device" and what to do, when error_number is ENOSPC or EDQUOT or the file
 * system of path is full; else GSN_ERR_IO with strerror(error_number) (0:
 * none known). Returns the code. */
int gsn_write_error_raise(const char *file, int line, const char *func,
                          const char *path, int error_number, const char *what);
#define GSN_WRITE_ERROR(path, error_number, what)                              \
    gsn_write_error_raise(__FILE__, __LINE__, __func__, (path),                \
                          (error_number), (what))

/* Takes the lock of an output folder (an flock'd FOLDER/.geoscni.lock that
 * holds the owner's pid), so that two geoscni processes never write one
 * folder: held until gsn_folder_unlock or the process ends. Another holder
 * is GSN_ERR_BUSY naming its pid. The folder must exist. */
int gsn_folder_lock(const char *folder, int *lock);

/* Releases a lock of gsn_folder_lock; accepts -1 and sets *lock to -1. */
void gsn_folder_unlock(int *lock);

/* Size of the text of gsn_file_hash. */
enum { GSN_FILE_HASH_SIZE = 48 };

/* A 64-bit hash of the contents of path and its size, as text ("%016llx
 * %llu bytes"), to tell whether an input changed (not cryptographic). */
int gsn_file_hash(const char *path, char out[GSN_FILE_HASH_SIZE]);

/* The memory this process may still take, in bytes: the least of the
 * system's MemAvailable, the room left under its cgroup's memory.max, and
 * the room left under its address-space limit (ulimit -v); source names
 * which one it is. 0 with source "unknown" if none can be read. */
double gsn_memory_available(const char **source);

#ifdef __cplusplus
}
#endif
#endif
