/* The error chain: one per process, guarded by a mutex so that threads of an
 * OpenMP loop may raise errors. The most recent raise starts a new chain. */
#include "geoscni/error.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

enum {
    ERROR_MESSAGE_SIZE = 1024,
    ERROR_FRAME_TEXT_SIZE = 160,
    ERROR_FRAMES = 32
};

struct error_frame {
    const char *file;
    const char *func;
    int line;
    char text[ERROR_FRAME_TEXT_SIZE];
};

static struct {
    pthread_mutex_t lock;
    int code;
    char message[ERROR_MESSAGE_SIZE];
    int frame_count;
    struct error_frame frames[ERROR_FRAMES];
} error_chain = {PTHREAD_MUTEX_INITIALIZER, GSN_OK, "", 0, {{0}}};

static const char *const error_texts[] = {
#define GSN_ERROR_TEXT(name, status, text) text,
    GSN_ERROR_LIST(GSN_ERROR_TEXT)
#undef GSN_ERROR_TEXT
};

static const int error_statuses[] = {
#define GSN_ERROR_STATUS(name, status, text) status,
    GSN_ERROR_LIST(GSN_ERROR_STATUS)
#undef GSN_ERROR_STATUS
};

static void frame_push(const char *file, int line, const char *func,
                       const char *text)
{
    if (error_chain.frame_count >= ERROR_FRAMES)
        return;
    struct error_frame *frame = &error_chain.frames[error_chain.frame_count++];
    frame->file = file;
    frame->line = line;
    frame->func = func;
    snprintf(frame->text, sizeof frame->text, "%s", text ? text : "");
}

int gsn_error_raise(int code, const char *file, int line, const char *func,
                    const char *format, ...)
{
    if (code <= GSN_OK || code >= GSN_ERROR_COUNT)
        code = GSN_ERR_INTERNAL;
    pthread_mutex_lock(&error_chain.lock);
    error_chain.code = code;
    va_list args;
    va_start(args, format);
    vsnprintf(error_chain.message, sizeof error_chain.message, format, args);
    va_end(args);
    error_chain.frame_count = 0;
    frame_push(file, line, func, NULL);
    pthread_mutex_unlock(&error_chain.lock);
    return code;
}

int gsn_error_pass(int code, const char *file, int line, const char *func,
                   const char *expression)
{
    if (code <= GSN_OK || code >= GSN_ERROR_COUNT)
        code = GSN_ERR_INTERNAL;
    pthread_mutex_lock(&error_chain.lock);
    if (error_chain.code == GSN_OK) {
        /* A code returned without a raise: record it so the chain says so. */
        error_chain.code = code;
        snprintf(error_chain.message, sizeof error_chain.message,
                 "%s (no message recorded)", error_texts[code]);
    }
    frame_push(file, line, func, expression);
    pthread_mutex_unlock(&error_chain.lock);
    return code;
}

const char *gsn_error_text(int code)
{
    if (code < GSN_OK || code >= GSN_ERROR_COUNT)
        return "unknown error code";
    return error_texts[code];
}

int gsn_error_exit_status(int code)
{
    if (code < GSN_OK || code >= GSN_ERROR_COUNT)
        return 1;
    return error_statuses[code];
}

const char *gsn_error_message(void)
{
    return error_chain.message;
}

void gsn_error_print(void *stream)
{
    FILE *out = stream ? (FILE *)stream : stderr;
    pthread_mutex_lock(&error_chain.lock);
    fprintf(out, "error: %s\n", error_chain.message);
    for (int i = 0; i < error_chain.frame_count; ++i) {
        const struct error_frame *frame = &error_chain.frames[i];
        fprintf(out, "  %s %s (%s:%d)%s%s\n", i == 0 ? "raised in" : "from",
                frame->func, frame->file, frame->line,
                frame->text[0] ? ": " : "", frame->text);
    }
    fprintf(out, "  [%s]\n", gsn_error_text(error_chain.code));
    pthread_mutex_unlock(&error_chain.lock);
}

void gsn_error_print_user(void *stream, int verbose)
{
    if (verbose) {
        gsn_error_print(stream);
        return;
    }
    FILE *out = stream ? (FILE *)stream : stderr;
    pthread_mutex_lock(&error_chain.lock);
    fprintf(out, "error: %s\n", error_chain.message);
    if (error_chain.code == GSN_ERR_INTERNAL ||
        error_chain.code == GSN_ERR_LIBRARY)
        fprintf(out,
                "  (%s: run again with --verbose and report what it "
                "prints)\n",
                error_texts[error_chain.code]);
    pthread_mutex_unlock(&error_chain.lock);
}

void gsn_error_clear(void)
{
    pthread_mutex_lock(&error_chain.lock);
    error_chain.code = GSN_OK;
    error_chain.message[0] = '\0';
    error_chain.frame_count = 0;
    pthread_mutex_unlock(&error_chain.lock);
}
