/* The error chain: codes map to texts and exit statuses defined once; CHECK
 * records where an error was raised, CALL each frame it passed through. */
#include "geoscni/error.h"
#include "testing.h"

#include <string.h>

static int raise_input(int value)
{
    GSN_CHECK(value > 0, GSN_ERR_INPUT, "value must be > 0, got %d", value);
    return GSN_OK;
}

static int pass_through(int value)
{
    GSN_CALL(raise_input(value));
    return GSN_OK;
}

static int cleanup_path(int value, int *cleaned)
{
    int rc = GSN_OK;
    GSN_CALL_GOTO(pass_through(value), rc, done);
done:
    *cleaned = 1;
    return rc;
}

int main(void)
{
    test_begin();
    TEST_INT(gsn_error_exit_status(GSN_OK), 0);
    TEST_INT(gsn_error_exit_status(GSN_ERR_INPUT), 2);
    TEST_INT(gsn_error_exit_status(GSN_ERR_NUMERICAL), 3);
    TEST_INT(gsn_error_exit_status(GSN_ERR_IO), 2);
    TEST_INT(gsn_error_exit_status(GSN_ERR_INTERNAL), 1);
    TEST_INT(gsn_error_exit_status(-5), 1);
    TEST_TRUE(strcmp(gsn_error_text(GSN_ERR_NUMERICAL), "numerical failure") ==
              0);
    TEST_TRUE(strcmp(gsn_error_text(99), "unknown error code") == 0);

    TEST_INT(pass_through(3), GSN_OK);
    TEST_INT(pass_through(-1), GSN_ERR_INPUT);
    TEST_TRUE(strcmp(gsn_error_message(), "value must be > 0, got -1") == 0);

    /* The printed chain names the raising function and each caller. */
    char *text = NULL;
    size_t size = 0;
    FILE *stream = open_memstream(&text, &size);
    gsn_error_print(stream);
    fclose(stream);
    TEST_TRUE(strstr(text, "error: value must be > 0, got -1\n") == text);
    TEST_TRUE(strstr(text, "raised in raise_input (tests/foundation/"
                           "test_error.c:") != NULL);
    TEST_TRUE(strstr(text, "from pass_through") != NULL);
    TEST_TRUE(strstr(text, "[bad input]") != NULL);
    free(text);

    /* What a user sees: the message alone, the chain with --verbose. */
    stream = open_memstream(&text, &size);
    gsn_error_print_user(stream, 0);
    fclose(stream);
    TEST_TRUE(strcmp(text, "error: value must be > 0, got -1\n") == 0);
    free(text);
    stream = open_memstream(&text, &size);
    gsn_error_print_user(stream, 1);
    fclose(stream);
    TEST_TRUE(strstr(text, "raised in raise_input") != NULL);
    free(text);
    TEST_INT(gsn_error_exit_status(GSN_ERR_NO_SPACE), 1);
    TEST_INT(gsn_error_exit_status(GSN_ERR_BUSY), 2);

    int cleaned = 0;
    gsn_error_clear();
    TEST_INT(cleanup_path(0, &cleaned), GSN_ERR_INPUT);
    TEST_INT(cleaned, 1);

    /* A code passed up without a raise is still reported, never lost. */
    gsn_error_clear();
    TEST_INT(gsn_error_pass(GSN_ERR_IO, "x.c", 1, "f", "g()"), GSN_ERR_IO);
    TEST_TRUE(strstr(gsn_error_message(), "no message recorded") != NULL);
    /* Raising GSN_OK is a bug and is recorded as an internal error. */
    TEST_INT(gsn_error_raise(GSN_OK, "x.c", 1, "f", "oops"), GSN_ERR_INTERNAL);
    gsn_error_clear();
    TEST_TRUE(gsn_error_message()[0] == '\0');
    return test_end("test_error");
}
