/* gmsh in a child process (issue 21, point 1). gmsh can end the process (a
 * .geo's `Exit;`), abort it (an exception thrown inside one of its OpenMP
 * regions calls std::terminate, whatever the thread count) or crash. pre
 * runs every gmsh call in a forked child that sends its results back
 * through a pipe: such a failure then becomes an error of the parent, with
 * gmsh's own message and what the child was doing. */
#ifndef GEOSCNI_PRE_CHILD_H
#define GEOSCNI_PRE_CHILD_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { PRE_CHILD_MAX_ARRAYS = 16, PRE_CHILD_TEXT_SIZE = 1024 };

/* The child's end of the channel. */
struct pre_child;

/* What came back. When the work ran to its end (died == 0), the arrays it
 * sent, in order, malloc'ed (the caller owns them: pre_child_result_free or
 * take them and set the pointer to NULL). When the child died (died == 1):
 * what it was doing, gmsh's error messages (or the exception it threw, or
 * the signal), and whether it ended itself with exit() (exited, with
 * exit_status) rather than by a signal. */
struct pre_child_result {
    int died;
    int array_count;
    void *array[PRE_CHILD_MAX_ARRAYS];
    size_t size[PRE_CHILD_MAX_ARRAYS]; /* bytes */
    char stage[PRE_CHILD_TEXT_SIZE];
    char messages[PRE_CHILD_TEXT_SIZE];
    int exited, exit_status, signal;
};

typedef int (*pre_child_work)(struct pre_child *child, void *arg);

/* Runs work(child, arg) in a forked child on one OpenMP thread (libgomp's
 * thread pool does not survive fork). An error the work returns is raised
 * again in the parent with its code and message. The child's death is not
 * an error here: the caller, who knows the input, explains it from
 * result->stage and result->messages. */
int pre_child_run(pre_child_work work, void *arg,
                  struct pre_child_result *result);

/* Frees the arrays still held by result. */
void pre_child_result_free(struct pre_child_result *result);

/* Sends size bytes (copied) as the next array of the result. */
int pre_child_send(struct pre_child *child, const void *data, size_t size);

/* Says what the child does now ("meshing the surfaces of slope.geo"), for
 * the message should it die doing it. */
void pre_child_stage(struct pre_child *child, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Installs, in the child, a std::terminate handler that prints the
 * exception's text ("Exception : ...") and ends the child with
 * PRE_CHILD_TERMINATED (child_terminate.cpp). */
void pre_child_terminate_install(void);

/* Exit statuses of a child that died: std::terminate, or exit() called
 * (child.c). */
enum { PRE_CHILD_TERMINATED = 71, PRE_CHILD_EXIT_CALLED = 72 };

#ifdef __cplusplus
}
#endif
#endif
