/* What bounds the pass's gather on this core (issue 17): nanoseconds an
 * entry of dH = sum_I u_I (x) g_I over rows of 46 entries (Slope I's mean
 * with the default window cut), each entry a 16-bit slot into 720 slots
 * of 4 doubles (a block's increments, in L1) and its gradient, for the
 * stream in L2 (240 kB, swept again and again) and from memory (62 MB),
 * in three layouts:
 *   double      3 doubles an entry, each broadcast (the solver's gather);
 *   float       3 floats, each converted and broadcast;
 *   float-rows  3 floats converted as one vector and multiplied by the
 *               broadcast components of u (dH^T by rows; a 4th lane of
 *               the next entry's value, ignored).
 * A layout bound by the memory's bandwidth runs much slower from memory
 * than from L2; one bound by the core runs alike from both. Medians of 7
 * passes of about 10^8 entries, on one thread.
 * Usage: gather_bench */
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

typedef double v4 __attribute__((vector_size(32), aligned(8), may_alias));

enum {
    ROW = 46,        /* entries a row */
    SLOTS = 720,     /* slots a block */
    PASSES = 7,      /* timed passes a case */
    WORK = 100000000 /* entries a pass, about */
};

enum layout { LAYOUT_DOUBLE, LAYOUT_FLOAT, LAYOUT_FLOAT_ROWS, LAYOUT_COUNT };
static const char *const layout_name[LAYOUT_COUNT] = {"double", "float",
                                                      "float-rows"};

struct stream {
    size_t entries;
    uint16_t *slot;
    double *g;
    float *gf; /* 3 entries + 1: float-rows reads 4 */
    double *u4;
    double *dH; /* 9 a row */
};

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* u (x) g of entry k added to c (layout a constant where inlined). */
__attribute__((always_inline)) static inline void
entry_add(const struct stream *s, enum layout layout, size_t k, v4 *c0, v4 *c1,
          v4 *c2)
{
    const double *u = &s->u4[4 * s->slot[k]];
    if (layout == LAYOUT_DOUBLE) {
        const v4 uv = *(const v4 *)u;
        *c0 += uv * s->g[3 * k];
        *c1 += uv * s->g[3 * k + 1];
        *c2 += uv * s->g[3 * k + 2];
    } else if (layout == LAYOUT_FLOAT) {
        const v4 uv = *(const v4 *)u;
        *c0 += uv * (double)s->gf[3 * k];
        *c1 += uv * (double)s->gf[3 * k + 1];
        *c2 += uv * (double)s->gf[3 * k + 2];
    } else {
#if defined(__AVX2__)
        const v4 g = (v4)_mm256_cvtps_pd(_mm_loadu_ps(&s->gf[3 * k]));
#else
        const v4 g = {s->gf[3 * k], s->gf[3 * k + 1], s->gf[3 * k + 2], 0.0};
#endif
        *c0 += u[0] * g;
        *c1 += u[1] * g;
        *c2 += u[2] * g;
    }
}

/* The sums of the row from entry k, even and odd entries apart as in the
 * solver (so that consecutive entries do not wait for each other). */
__attribute__((always_inline)) static inline void
row_sums(const struct stream *s, enum layout layout, size_t k, v4 c[3])
{
    const v4 zero = {0.0, 0.0, 0.0, 0.0};
    v4 c0 = zero, c1 = zero, c2 = zero, d0 = zero, d1 = zero, d2 = zero;
    for (const size_t end = k + ROW; k < end; k += 2) {
        if (layout == LAYOUT_DOUBLE)
            __builtin_prefetch(&s->g[3 * k + 384]);
        else
            __builtin_prefetch(&s->gf[3 * k + 768]);
        entry_add(s, layout, k, &c0, &c1, &c2);
        entry_add(s, layout, k + 1, &d0, &d1, &d2);
    }
    c[0] = c0 + d0;
    c[1] = c1 + d1;
    c[2] = c2 + d2;
}

/* The rows of the stream, swept `repeats` times. */
__attribute__((always_inline)) static inline void
sweep(const struct stream *s, enum layout layout, size_t repeats)
{
    for (size_t r = 0; r < repeats; ++r)
        for (size_t row = 0; row < s->entries / ROW; ++row) {
            v4 c[3];
            row_sums(s, layout, row * ROW, c);
            for (int i = 0; i < 3; ++i)
                memcpy(&s->dH[9 * row + 3 * i], &c[i], 3 * sizeof(double));
        }
}

/* One timed sweep to about WORK entries: ns an entry. */
static double pass_ns(const struct stream *s, enum layout layout)
{
    size_t repeats = WORK / s->entries + 1;
    double t0 = omp_get_wtime();
    if (layout == LAYOUT_DOUBLE)
        sweep(s, LAYOUT_DOUBLE, repeats);
    else if (layout == LAYOUT_FLOAT)
        sweep(s, LAYOUT_FLOAT, repeats);
    else
        sweep(s, LAYOUT_FLOAT_ROWS, repeats);
    return (omp_get_wtime() - t0) / (double)(s->entries / ROW * ROW * repeats) *
           1e9;
}

static int stream_create(size_t entries, struct stream *s)
{
    s->entries = entries;
    s->slot = malloc(sizeof(uint16_t) * entries);
    s->g = malloc(sizeof(double) * (3 * entries + 384));
    s->gf = malloc(sizeof(float) * (3 * entries + 768));
    s->u4 = malloc(sizeof(double) * 4 * SLOTS);
    s->dH = malloc(sizeof(double) * 9 * (entries / ROW + 1));
    if (!s->slot || !s->g || !s->gf || !s->u4 || !s->dH)
        return 1;
    srand(1);
    for (size_t k = 0; k < entries; ++k)
        s->slot[k] = (uint16_t)(rand() % SLOTS);
    for (size_t k = 0; k < 3 * entries + 384; ++k)
        s->g[k] = rand() / (double)RAND_MAX - 0.5;
    for (size_t k = 0; k < 3 * entries + 768; ++k)
        s->gf[k] = (float)(k < 3 * entries ? s->g[k] : 0.0);
    for (int k = 0; k < 4 * SLOTS; ++k)
        s->u4[k] = k % 4 == 3 ? 0.0 : 1e-3 * k;
    return 0;
}

static void stream_free(struct stream *s)
{
    free(s->slot);
    free(s->g);
    free(s->gf);
    free(s->u4);
    free(s->dH);
}

int main(void)
{
    const size_t sizes[2] = {200 * ROW, 52000 * ROW};
    const char *where[2] = {"in L2", "from memory"};
    printf("gather: ns an entry, medians of %d passes, 1 thread\n", PASSES);
    printf("%-12s %10s %12s %8s\n", "layout", where[0], where[1], "ratio");
    double ns[LAYOUT_COUNT][2];
    for (int z = 0; z < 2; ++z) {
        struct stream s;
        if (stream_create(sizes[z], &s)) {
            fprintf(stderr, "gather_bench: out of memory\n");
            return 1;
        }
        for (int layout = 0; layout < LAYOUT_COUNT; ++layout) {
            double t[PASSES];
            pass_ns(&s, layout); /* warm */
            for (int p = 0; p < PASSES; ++p)
                t[p] = pass_ns(&s, layout);
            qsort(t, PASSES, sizeof t[0], by_value);
            ns[layout][z] = t[PASSES / 2];
        }
        stream_free(&s);
    }
    for (int layout = 0; layout < LAYOUT_COUNT; ++layout)
        printf("%-12s %10.2f %12.2f %8.2f\n", layout_name[layout],
               ns[layout][0], ns[layout][1], ns[layout][1] / ns[layout][0]);
    return 0;
}
