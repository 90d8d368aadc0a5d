/* STREAM triad a = b + s c (McCalpin's benchmark, own code): the memory
 * bandwidth the solver's figures are quoted against (issue 17). Arrays of
 * 2^24 doubles (128 MiB each, far past every cache), the best of 20 passes
 * on the OpenMP threads given; bytes counted as STREAM does (3 arrays a
 * pass, no write-allocate).
 * Usage: stream [THREADS...]   (default: 1, then the runtime's count) */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

enum { STREAM_LENGTH = 1 << 24, STREAM_PASSES = 20 };

static double triad_gbs(double *a, const double *b, const double *c,
                        int threads)
{
    double best = 1e30;
    for (int pass = 0; pass < STREAM_PASSES; ++pass) {
        double t0 = omp_get_wtime();
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long i = 0; i < STREAM_LENGTH; ++i)
            a[i] = b[i] + 3.0 * c[i];
        double t = omp_get_wtime() - t0;
        if (t < best)
            best = t;
    }
    return 3.0 * sizeof(double) * STREAM_LENGTH / best / 1e9;
}

int main(int argc, char **argv)
{
    double *a = malloc(sizeof(double) * STREAM_LENGTH);
    double *b = malloc(sizeof(double) * STREAM_LENGTH);
    double *c = malloc(sizeof(double) * STREAM_LENGTH);
    if (!a || !b || !c) {
        fprintf(stderr, "stream: out of memory\n");
        return 1;
    }
    int max_threads = omp_get_max_threads();
    /* first touch on every thread count's static schedule */
#pragma omp parallel for schedule(static)
    for (long i = 0; i < STREAM_LENGTH; ++i) {
        a[i] = 0.0;
        b[i] = 1.0;
        c[i] = 2.0;
    }
    int counts[16], n = 0;
    for (int i = 1; i < argc && n < 16; ++i)
        counts[n++] = atoi(argv[i]);
    if (n == 0) {
        counts[n++] = 1;
        if (max_threads > 1)
            counts[n++] = max_threads;
    }
    for (int i = 0; i < n; ++i) {
        if (counts[i] < 1) {
            fprintf(stderr, "stream: a thread count is a positive integer\n");
            return 2;
        }
        printf("STREAM triad, %d thread(s): %.1f GB/s\n", counts[i],
               triad_gbs(a, b, c, counts[i]));
    }
    free(a);
    free(b);
    free(c);
    return 0;
}
