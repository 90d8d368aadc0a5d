/* A tiny test harness: each check prints what failed with file:line and the
 * values, and the program's exit status counts failures. Floating-point
 * traps (invalid, divide by zero, overflow) are on in every test that calls
 * test_begin (STYLE.md rule 12). */
#ifndef GEOSCNI_TESTING_H
#define GEOSCNI_TESTING_H

#include <fenv.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int test_failures = 0;
static int test_checks = 0;

static inline void test_begin(void)
{
    feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
}

static inline int test_end(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, test_checks, test_failures);
    return test_failures ? 1 : 0;
}

#define TEST_TRUE(condition)                                                   \
    do {                                                                       \
        ++test_checks;                                                         \
        if (!(condition)) {                                                    \
            ++test_failures;                                                   \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__,   \
                    #condition);                                               \
        }                                                                      \
    } while (0)

/* |actual - expected| <= tolerance, printing both values on failure. */
#define TEST_NEAR(actual, expected, tolerance)                                 \
    do {                                                                       \
        ++test_checks;                                                         \
        double test_a_ = (actual), test_e_ = (expected);                       \
        double test_t_ = (tolerance);                                          \
        if (!(fabs(test_a_ - test_e_) <= test_t_)) {                           \
            ++test_failures;                                                   \
            fprintf(stderr,                                                    \
                    "%s:%d: %s = %.17g, expected %.17g within %.3g "           \
                    "(error %.3g)\n",                                          \
                    __FILE__, __LINE__, #actual, test_a_, test_e_, test_t_,    \
                    fabs(test_a_ - test_e_));                                  \
        }                                                                      \
    } while (0)

/* Relative: |actual - expected| <= tolerance |expected|. */
#define TEST_REL(actual, expected, tolerance)                                  \
    TEST_NEAR(actual, expected, (tolerance)*fabs((double)(expected)))

#define TEST_INT(actual, expected)                                             \
    do {                                                                       \
        ++test_checks;                                                         \
        long test_a_ = (long)(actual), test_e_ = (long)(expected);             \
        if (test_a_ != test_e_) {                                              \
            ++test_failures;                                                   \
            fprintf(stderr, "%s:%d: %s = %ld, expected %ld\n", __FILE__,       \
                    __LINE__, #actual, test_a_, test_e_);                      \
        }                                                                      \
    } while (0)

/* qsort's order of doubles, ascending. */
static inline int test_by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* x[n / 2] of x[0 .. n) sorted (sorts x): the median for odd n. */
static inline double test_median(double *x, int n)
{
    qsort(x, (size_t)n, sizeof *x, test_by_value);
    return x[n / 2];
}

/* The bytes of the file at path (malloc'd, *size set), or NULL. */
static inline unsigned char *test_file_bytes(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *bytes = NULL;
    long end = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (end = ftell(f)) >= 0 &&
        fseek(f, 0, SEEK_SET) == 0 &&
        (bytes = malloc((size_t)end + 1)) != NULL &&
        fread(bytes, 1, (size_t)end, f) != (size_t)end) {
        free(bytes);
        bytes = NULL;
    }
    fclose(f);
    *size = (size_t)end;
    return bytes;
}

#endif
