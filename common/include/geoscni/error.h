/* Error codes and the error chain shared by every stage.
 *
 * Every function that can fail returns an int code (GSN_OK on success).
 * GSN_CHECK raises an error where it is detected; GSN_CALL passes one up,
 * adding the caller's file and line to the chain. The CLI prints the chain
 * and exits with the status the code maps to (DESIGN.md: 2 bad input,
 * 3 numerical failure). Codes, exit statuses and texts are defined once,
 * in GSN_ERROR_LIST. */
#ifndef GEOSCNI_ERROR_H
#define GEOSCNI_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

/* X(name, exit status, text) */
#define GSN_ERROR_LIST(X)                                                      \
    X(GSN_OK, 0, "success")                                                    \
    X(GSN_ERR_INPUT, 2, "bad input")                                           \
    X(GSN_ERR_NUMERICAL, 3, "numerical failure")                               \
    X(GSN_ERR_IO, 2, "file could not be read or written")                      \
    X(GSN_ERR_MEMORY, 1, "out of memory")                                      \
    X(GSN_ERR_LIBRARY, 1, "an external library failed")                        \
    X(GSN_ERR_INTERNAL, 1, "internal error (a bug in geoscni)")                \
    X(GSN_ERR_INTERRUPTED, 130, "interrupted")                                 \
    X(GSN_ERR_NO_SPACE, 1, "no space left on device")                          \
    X(GSN_ERR_BUSY, 2, "the output folder is in use")

enum gsn_error_code {
#define GSN_ERROR_ENUM(name, status, text) name,
    GSN_ERROR_LIST(GSN_ERROR_ENUM)
#undef GSN_ERROR_ENUM
        GSN_ERROR_COUNT
};

/* Records an error with its origin and returns code (never GSN_OK: a GSN_OK
 * code is recorded as GSN_ERR_INTERNAL). Thread-safe. */
int gsn_error_raise(int code, const char *file, int line, const char *func,
                    const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Adds a "called from" frame to the chain and returns code. */
int gsn_error_pass(int code, const char *file, int line, const char *func,
                   const char *expression);

/* Text of a code, and the process exit status it maps to. */
const char *gsn_error_text(int code);
int gsn_error_exit_status(int code);

/* The message of the first (deepest) error, "" if none. */
const char *gsn_error_message(void);

/* Prints the chain: the deepest message first, then where it was raised
 * and the frames it passed through. */
void gsn_error_print(void *stream);

/* What a user sees: "error: MESSAGE" alone, or with verbose the whole
 * chain (gsn_error_print); an internal error also asks for a report. */
void gsn_error_print_user(void *stream, int verbose);

/* Forgets the recorded chain. */
void gsn_error_clear(void);

#define GSN_CHECK(condition, code, ...)                                        \
    do {                                                                       \
        if (!(condition))                                                      \
            return gsn_error_raise((code), __FILE__, __LINE__, __func__,       \
                                   __VA_ARGS__);                               \
    } while (0)

#define GSN_CALL(expression)                                                   \
    do {                                                                       \
        int gsn_call_code_ = (expression);                                     \
        if (gsn_call_code_ != GSN_OK)                                          \
            return gsn_error_pass(gsn_call_code_, __FILE__, __LINE__,          \
                                  __func__, #expression);                      \
    } while (0)

/* Variants for functions with something to release: they set rc and jump to
 * the label instead of returning. */
#define GSN_CHECK_GOTO(condition, rc, code, label, ...)                        \
    do {                                                                       \
        if (!(condition)) {                                                    \
            (rc) = gsn_error_raise((code), __FILE__, __LINE__, __func__,       \
                                   __VA_ARGS__);                               \
            goto label;                                                        \
        }                                                                      \
    } while (0)

#define GSN_CALL_GOTO(expression, rc, label)                                   \
    do {                                                                       \
        int gsn_call_code_ = (expression);                                     \
        if (gsn_call_code_ != GSN_OK) {                                        \
            (rc) = gsn_error_pass(gsn_call_code_, __FILE__, __LINE__,          \
                                  __func__, #expression);                      \
            goto label;                                                        \
        }                                                                      \
    } while (0)

#ifdef __cplusplus
}
#endif
#endif
