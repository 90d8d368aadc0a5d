/* Folders, atomic writes, write errors, folder locks and file hashes. */
#include "geoscni/files.h"
#include "geoscni/error.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

/* The lock file of an output folder (gsn_folder_lock). */
#define FOLDER_LOCK_NAME ".geoscni.lock"
/* A file system with less free space than this after a failed write is
 * taken as full: the write that failed used up the rest. */
#define FULL_FREE_BYTES (1024.0 * 1024.0)

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
        if (mkdir(partial, 0777) == 0 || errno == EEXIST)
            continue;
        if (errno == ENOSPC || errno == EDQUOT)
            return GSN_WRITE_ERROR(partial, errno,
                                   "cannot create the output folder");
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

/* 1 if the file system holding path (or, if path does not exist, its
 * folder) has next to no space left for this process. */
static int file_system_full(const char *path)
{
    struct statvfs info;
    char folder[4096];
    int found = statvfs(path, &info) == 0;
    if (!found &&
        snprintf(folder, sizeof folder, "%s", path) < (int)sizeof folder) {
        char *slash = strrchr(folder, '/');
        if (slash)
            *slash = '\0';
        found = statvfs(slash ? folder : ".", &info) == 0;
    }
    if (!found)
        return 0;
    double blocks =
        geteuid() == 0 ? (double)info.f_bfree : (double)info.f_bavail;
    return blocks * (double)info.f_frsize < FULL_FREE_BYTES;
}

int gsn_write_error_raise(const char *file, int line, const char *func,
                          const char *path, int error_number, const char *what)
{
    if (error_number == ENOSPC || error_number == EDQUOT ||
        file_system_full(path))
        return gsn_error_raise(
            GSN_ERR_NO_SPACE, file, line, func,
            "%s: %s: no space left on device%s; free some space on it, or "
            "choose an output folder on another disk",
            path, what, error_number == EDQUOT ? " (disk quota exceeded)" : "");
    if (error_number != 0)
        return gsn_error_raise(GSN_ERR_IO, file, line, func, "%s: %s: %s", path,
                               what, strerror(error_number));
    return gsn_error_raise(GSN_ERR_IO, file, line, func, "%s: %s", path, what);
}

/* The pid the holder of a lock wrote into it, 0 if it has not yet. */
static long lock_owner(int fd)
{
    for (int attempt = 0; attempt < 50; ++attempt) {
        char text[32] = "";
        ssize_t n = pread(fd, text, sizeof text - 1, 0);
        long pid = n > 0 ? strtol(text, NULL, 10) : 0;
        if (pid > 0)
            return pid;
        nanosleep(&(struct timespec){0, 10000000}, NULL); /* 10 ms */
    }
    return 0;
}

int gsn_folder_lock(const char *folder, int *lock)
{
    char path[4096];
    *lock = -1;
    GSN_CALL(gsn_path_join(path, sizeof path, folder, FOLDER_LOCK_NAME));
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0 && (errno == ENOSPC || errno == EDQUOT))
        return GSN_WRITE_ERROR(path, errno, "cannot create the lock file");
    GSN_CHECK(fd >= 0, GSN_ERR_INPUT,
              "%s: cannot create the lock file of the output folder: %s; "
              "the output folder must be writable",
              path, strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        int error_number = errno;
        long owner = error_number == EWOULDBLOCK ? lock_owner(fd) : 0;
        close(fd);
        GSN_CHECK(error_number != EWOULDBLOCK, GSN_ERR_BUSY,
                  "%s is in use by another geoscni (pid %ld): wait until it "
                  "ends, or choose another output folder",
                  folder, owner);
        GSN_CHECK(0, GSN_ERR_IO, "%s: cannot lock: %s", path,
                  strerror(error_number));
    }
    char text[32];
    int n = snprintf(text, sizeof text, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) != 0 || pwrite(fd, text, (size_t)n, 0) != n) {
        int error_number = errno;
        close(fd);
        return GSN_WRITE_ERROR(path, error_number,
                               "cannot write the lock file");
    }
    *lock = fd;
    return GSN_OK;
}

void gsn_folder_unlock(int *lock)
{
    if (*lock >= 0)
        close(*lock); /* releases the flock */
    *lock = -1;
}

/* 64-bit words: xor, multiply by the FNV prime, fold the high half down
 * (so every bit reaches the low ones); the size and a final mix (murmur3's
 * fmix64) at the end. */
static uint64_t hash_mix(uint64_t h, uint64_t word)
{
    h = (h ^ word) * 0x100000001b3ull;
    return h ^ (h >> 32);
}

int gsn_file_hash(const char *path, char out[GSN_FILE_HASH_SIZE])
{
    enum { CHUNK = 1 << 20 }; /* a multiple of 8 */
    FILE *file = fopen(path, "rb");
    GSN_CHECK(file != NULL, GSN_ERR_INPUT, "%s: cannot open: %s", path,
              strerror(errno));
    unsigned char *buffer = malloc(CHUNK);
    if (!buffer) {
        fclose(file);
        GSN_CHECK(0, GSN_ERR_MEMORY, "out of memory");
    }
    uint64_t h = 0xcbf29ce484222325ull, size = 0;
    size_t n;
    while ((n = fread(buffer, 1, CHUNK, file)) > 0) {
        size_t words = n / 8;
        for (size_t k = 0; k < words; ++k) {
            uint64_t word;
            memcpy(&word, buffer + 8 * k, 8);
            h = hash_mix(h, word);
        }
        if (n % 8) { /* only at the end of the file */
            uint64_t word = 0;
            memcpy(&word, buffer + 8 * words, n % 8);
            h = hash_mix(h, word);
        }
        size += n;
    }
    int failed = ferror(file);
    free(buffer);
    fclose(file);
    GSN_CHECK(!failed, GSN_ERR_IO, "%s: read error", path);
    h ^= size;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    snprintf(out, GSN_FILE_HASH_SIZE, "%016llx %llu bytes",
             (unsigned long long)h, (unsigned long long)size);
    return GSN_OK;
}

/* A number after a key in a /proc-style file ("MemAvailable:  123 kB"). */
static double read_key_number(const char *path, const char *key)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1.0;
    char line[256];
    double value = -1.0;
    size_t n = strlen(key);
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, n) == 0) {
            value = strtod(line + n, NULL);
            break;
        }
    fclose(f);
    return value;
}

static double read_number_file(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1.0;
    char text[64] = "";
    int ok = fgets(text, sizeof text, f) != NULL;
    fclose(f);
    return ok && text[0] >= '0' && text[0] <= '9' ? strtod(text, NULL) : -1.0;
}

double gsn_memory_available(const char **source)
{
    double best = -1.0;
    *source = "unknown";
    double kilobytes = read_key_number("/proc/meminfo", "MemAvailable:");
    if (kilobytes >= 0.0) {
        best = 1024.0 * kilobytes;
        *source = "MemAvailable of /proc/meminfo";
    }
    double limit = read_number_file("/sys/fs/cgroup/memory.max");
    double used = read_number_file("/sys/fs/cgroup/memory.current");
    if (limit >= 0.0 && used >= 0.0 && (best < 0.0 || limit - used < best)) {
        best = limit - used > 0.0 ? limit - used : 0.0;
        *source = "the cgroup's memory.max";
    }
    struct rlimit address;
    double virtual_kb = read_key_number("/proc/self/status", "VmSize:");
    if (getrlimit(RLIMIT_AS, &address) == 0 &&
        address.rlim_cur != RLIM_INFINITY && virtual_kb >= 0.0) {
        double room = (double)address.rlim_cur - 1024.0 * virtual_kb;
        if (best < 0.0 || room < best) {
            best = room > 0.0 ? room : 0.0;
            *source = "the address-space limit (ulimit -v)";
        }
    }
    return best > 0.0 ? best : 0.0;
}
