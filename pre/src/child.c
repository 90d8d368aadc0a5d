/* gmsh in a child process (child.h). The child sends records through a
 * pipe: what it is doing (stage), the arrays of its result, an error, and
 * "done" last; its stdout and stderr (gmsh's "Error   : ..." lines) go to a
 * temporary file the parent reads when the child died before "done". */
#include "child.h"
#include "geoscni/error.h"

#include <errno.h>
#include <omp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

enum record_kind { RECORD_STAGE = 1, RECORD_ARRAY, RECORD_ERROR, RECORD_DONE };

struct record_header {
    uint32_t kind;
    int32_t code;  /* RECORD_ERROR */
    uint64_t size; /* bytes that follow */
};

struct pre_child {
    int fd;
};

/* gmsh's messages kept for the parent's error message. */
enum { MESSAGES_KEPT = 3 };

static int write_all(int fd, const void *data, size_t size)
{
    const char *p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        p += n;
        size -= (size_t)n;
    }
    return 0;
}

/* Bytes read: size, fewer at the end of the pipe, -1 on an error. */
static ssize_t read_all(int fd, void *data, size_t size)
{
    char *p = data;
    size_t done = 0;
    while (done < size) {
        ssize_t n = read(fd, p + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return -1;
        if (n == 0)
            break;
        done += (size_t)n;
    }
    return (ssize_t)done;
}

static int record_write(int fd, int kind, int code, const void *data,
                        size_t size)
{
    struct record_header header = {(uint32_t)kind, code, size};
    if (write_all(fd, &header, sizeof header) != 0)
        return -1;
    return size > 0 ? write_all(fd, data, size) : 0;
}

int pre_child_send(struct pre_child *child, const void *data, size_t size)
{
    GSN_CHECK(record_write(child->fd, RECORD_ARRAY, 0, data, size) == 0,
              GSN_ERR_IO, "cannot send %zu bytes to the parent process: %s",
              size, strerror(errno));
    return GSN_OK;
}

void pre_child_stage(struct pre_child *child, const char *format, ...)
{
    char text[PRE_CHILD_TEXT_SIZE];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    (void)record_write(child->fd, RECORD_STAGE, 0, text, strlen(text) + 1);
}

/* exit() in the child (gmsh's `Exit;`, or its fatal errors) ends it here,
 * before the parent's atexit handlers (HDF5's, say) could run in it. */
static void child_exit_trap(void)
{
    _exit(PRE_CHILD_EXIT_CALLED);
}

static void child_main(int fd, pre_child_work work, void *arg)
{
    struct pre_child child = {fd};
    /* Ctrl-C ends the child whatever the parent's handler (the solver's
     * sets a flag): the parent reports the interrupt */
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    atexit(child_exit_trap);
    pre_child_terminate_install();
    omp_set_num_threads(1);
    int rc = work(&child, arg);
    if (rc != GSN_OK) {
        const char *message = gsn_error_message();
        (void)record_write(fd, RECORD_ERROR, rc, message, strlen(message) + 1);
    }
    (void)record_write(fd, RECORD_DONE, 0, NULL, 0);
    _exit(0);
}

/* Appends text to out (", "-separated) unless it is there already. */
static void append_distinct(char *out, size_t size, const char *text)
{
    if (!text[0] || strstr(out, text))
        return;
    size_t used = strlen(out);
    snprintf(out + used, size - used, "%s%s", used ? "; " : "", text);
}

/* gmsh's errors from the child's captured output, else the exception it
 * threw, else how it ended. */
static void messages_collect(FILE *capture, struct pre_child_result *r)
{
    char line[2048], exception[PRE_CHILD_TEXT_SIZE] = "";
    int kept = 0;
    rewind(capture);
    while (fgets(line, sizeof line, capture)) {
        line[strcspn(line, "\r\n")] = '\0';
        if ((!strncmp(line, "Error   : ", 10) ||
             !strncmp(line, "Fatal   : ", 10)) &&
            kept < MESSAGES_KEPT) {
            append_distinct(r->messages, sizeof r->messages, line + 10);
            ++kept;
        } else if (!strncmp(line, "Exception : ", 12)) {
            size_t length = strlen(line + 12);
            if (length >= sizeof exception)
                length = sizeof exception - 1;
            memcpy(exception, line + 12, length);
            exception[length] = '\0';
        }
    }
    if (!r->messages[0] && exception[0])
        snprintf(r->messages, sizeof r->messages, "%s", exception);
    if (!r->messages[0] && r->signal)
        snprintf(r->messages, sizeof r->messages, "signal %d, %s", r->signal,
                 strsignal(r->signal));
    else if (!r->messages[0] && r->exit_status != PRE_CHILD_EXIT_CALLED)
        snprintf(r->messages, sizeof r->messages, "it ended with status %d",
                 r->exit_status);
}

void pre_child_result_free(struct pre_child_result *result)
{
    for (int i = 0; i < result->array_count; ++i) {
        free(result->array[i]);
        result->array[i] = NULL;
    }
    result->array_count = 0;
}

/* Reads the child's records until the pipe closes. Sets *done when the
 * child said it was done; *code and message: the error it sent. */
static int records_read(int fd, struct pre_child_result *r, int *done,
                        int *code, char *message, size_t message_size)
{
    struct record_header h;
    ssize_t n;
    while ((n = read_all(fd, &h, sizeof h)) == (ssize_t)sizeof h) {
        if (h.kind == RECORD_DONE) {
            *done = 1;
            continue;
        }
        char *data = malloc(h.size + 1);
        GSN_CHECK(data != NULL, GSN_ERR_MEMORY,
                  "cannot allocate %llu bytes for the mesh",
                  (unsigned long long)h.size);
        if (read_all(fd, data, h.size) != (ssize_t)h.size) {
            free(data);
            return GSN_OK; /* the child died while writing */
        }
        data[h.size] = '\0';
        if (h.kind == RECORD_ARRAY && r->array_count < PRE_CHILD_MAX_ARRAYS) {
            r->array[r->array_count] = data;
            r->size[r->array_count++] = h.size;
            continue;
        }
        if (h.kind == RECORD_STAGE)
            snprintf(r->stage, sizeof r->stage, "%s", data);
        else if (h.kind == RECORD_ERROR) {
            *code = h.code;
            snprintf(message, message_size, "%s", data);
        }
        int unexpected = h.kind == RECORD_ARRAY;
        free(data);
        GSN_CHECK(!unexpected, GSN_ERR_INTERNAL,
                  "the child process sent more than %d arrays",
                  PRE_CHILD_MAX_ARRAYS);
    }
    GSN_CHECK(n >= 0, GSN_ERR_IO, "cannot read from the child process: %s",
              strerror(errno));
    return GSN_OK;
}

int pre_child_run(pre_child_work work, void *arg,
                  struct pre_child_result *result)
{
    memset(result, 0, sizeof *result);
    int fds[2];
    GSN_CHECK(pipe(fds) == 0, GSN_ERR_IO, "cannot create a pipe: %s",
              strerror(errno));
    /* gmsh's messages; without a temporary file they are lost, no more */
    FILE *capture = tmpfile();
    fflush(NULL); /* the child must not write the parent's buffers again */
    pid_t pid = fork();
    if (pid < 0) {
        int error = errno;
        close(fds[0]);
        close(fds[1]);
        if (capture)
            fclose(capture);
        GSN_CHECK(0, GSN_ERR_MEMORY,
                  "cannot start a process to run gmsh in: %s", strerror(error));
    }
    if (pid == 0) {
        close(fds[0]);
        int sink = capture ? fileno(capture) : -1;
        if (sink >= 0) {
            dup2(sink, STDOUT_FILENO);
            dup2(sink, STDERR_FILENO);
        }
        child_main(fds[1], work, arg);
    }
    close(fds[1]);
    int done = 0, code = GSN_OK;
    char message[PRE_CHILD_TEXT_SIZE] = "";
    int rc =
        records_read(fds[0], result, &done, &code, message, sizeof message);
    close(fds[0]);
    if (rc != GSN_OK)
        kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        continue;
    if (rc == GSN_OK && !done) {
        result->died = 1;
        result->exited = WIFEXITED(status);
        result->exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 0;
        result->signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
        if (capture)
            messages_collect(capture, result);
    }
    if (capture)
        fclose(capture);
    if (rc != GSN_OK) {
        pre_child_result_free(result);
        return rc;
    }
    if (result->died &&
        (result->signal == SIGINT || result->signal == SIGTERM)) {
        pre_child_result_free(result);
        GSN_CHECK(0, GSN_ERR_INTERRUPTED, "interrupted while %s",
                  result->stage[0] ? result->stage : "running gmsh");
    }
    if (done && code != GSN_OK) {
        pre_child_result_free(result);
        return gsn_error_raise(code, __FILE__, __LINE__, __func__, "%s",
                               message);
    }
    return GSN_OK;
}
