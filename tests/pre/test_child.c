/* gmsh's child process (pre/src/child.c, issue 21 point 1) with work
 * functions that end as gmsh can: arrays sent back, an error raised, exit()
 * (a .geo's Exit;), a signal (an abort, a crash). */
#include "child.h"
#include "geoscni/error.h"
#include "testing.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int work_arrays(struct pre_child *child, void *arg)
{
    const int *values = arg;
    pre_child_stage(child, "sending");
    GSN_CALL(pre_child_send(child, values, sizeof(int[3])));
    /* a large array: more than a pipe holds, read while it is written */
    size_t n = 1u << 22;
    double *big = malloc(sizeof(double) * n);
    GSN_CHECK(big != NULL, GSN_ERR_MEMORY, "out of memory");
    for (size_t i = 0; i < n; ++i)
        big[i] = (double)i;
    int rc = pre_child_send(child, big, sizeof(double) * n);
    free(big);
    return rc;
}

static int work_error(struct pre_child *child, void *arg)
{
    (void)child;
    (void)arg;
    GSN_CHECK(0, GSN_ERR_INPUT, "bad.geo: the child's own message");
    return GSN_OK;
}

static int work_exit(struct pre_child *child, void *arg)
{
    (void)arg;
    pre_child_stage(child, "reading it");
    fprintf(stderr, "Info    : not an error\n");
    exit(0); /* as gmsh's parser does on 'Exit;' */
}

static int work_abort(struct pre_child *child, void *arg)
{
    (void)arg;
    pre_child_stage(child, "meshing it");
    fprintf(stderr, "Error   : Unable to recover the edge 1\n");
    fprintf(stderr, "Error   : Unable to recover the edge 1\n");
    abort(); /* as std::terminate does */
}

static int work_crash(struct pre_child *child, void *arg)
{
    (void)arg;
    pre_child_stage(child, "crashing");
    raise(SIGSEGV);
    return GSN_OK;
}

int main(void)
{
    test_begin();
    struct pre_child_result r;
    int values[3] = {7, 8, 9};
    TEST_INT(pre_child_run(work_arrays, values, &r), GSN_OK);
    TEST_INT(r.died, 0);
    TEST_INT(r.array_count, 2);
    TEST_TRUE(r.size[0] == sizeof values &&
              memcmp(r.array[0], values, sizeof values) == 0);
    TEST_TRUE(r.size[1] == sizeof(double) << 22);
    if (r.array_count == 2)
        TEST_NEAR(((double *)r.array[1])[(1 << 22) - 1], (1 << 22) - 1, 0);
    pre_child_result_free(&r);
    TEST_TRUE(r.array[0] == NULL);

    TEST_INT(pre_child_run(work_error, NULL, &r), GSN_ERR_INPUT);
    TEST_TRUE(strcmp(gsn_error_message(), "bad.geo: the child's own message") ==
              0);
    gsn_error_clear();

    TEST_INT(pre_child_run(work_exit, NULL, &r), GSN_OK);
    TEST_INT(r.died, 1);
    TEST_INT(r.exited, 1);
    TEST_INT(r.exit_status, PRE_CHILD_EXIT_CALLED);
    TEST_TRUE(strcmp(r.stage, "reading it") == 0);
    TEST_TRUE(r.messages[0] == '\0');

    TEST_INT(pre_child_run(work_abort, NULL, &r), GSN_OK);
    TEST_INT(r.died, 1);
    TEST_INT(r.signal, SIGABRT);
    TEST_TRUE(strcmp(r.stage, "meshing it") == 0);
    /* gmsh's message, once */
    TEST_TRUE(strcmp(r.messages, "Unable to recover the edge 1") == 0);
    printf("abort: while %s: %s\n", r.stage, r.messages);

    TEST_INT(pre_child_run(work_crash, NULL, &r), GSN_OK);
    TEST_INT(r.died, 1);
    /* AddressSanitizer catches the signal and exits with status 1 */
    TEST_TRUE(r.signal == SIGSEGV ? strstr(r.messages, "signal 11") != NULL
                                  : r.exited && r.messages[0] != '\0');
    printf("crash: while %s: %s\n", r.stage, r.messages);
    return test_end("test_child");
}
