/* Reproducibility of the explicit loop (issue 5, point 4): a run stopped
 * half way and continued with --restart ends with the same bits as an
 * uninterrupted run, and a run on 1 thread ends with the same bits as on 2
 * (the passes gather in a fixed order). The block is large enough that the
 * loops do run in parallel. */
#include "geoscni/case.h"
#include "geoscni/results.h"
#include "geoscni/solver.h"
#include "solver_fixtures.h"
#include "testing.h"

#include <omp.h>
#include <string.h>

static const int COUNT[3] = {14, 14, 14};
static const double LO[3] = {0, 0, 0}, HI[3] = {1.3, 1.3, 1.3};

/* Runs the case into a new folder; returns the folder (static storage). */
static const char *run(struct gsn_case *c, double end, int restart_of_folder,
                       char *folder, int threads)
{
    struct gsn_solve_options options = {.quiet = 1, .threads = threads};
    if (!restart_of_folder) {
        TEST_TRUE(mkdtemp(folder) != NULL);
        TEST_INT(fixture_box_model(folder, COUNT, LO, HI, 0.2, c), GSN_OK);
    }
    options.restart = restart_of_folder;
    double saved = c->time_end;
    c->time_end = end;
    int rc = gsn_solve_run(c, folder, &options);
    c->time_end = saved;
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    TEST_INT(rc, GSN_OK);
    return folder;
}

/* 1 if the last frames of two results files are equal bit for bit. */
static int same_last_frame(const char *a, const char *b)
{
    char path[2][4200];
    hid_t file[2];
    struct gsn_frame frame[2];
    int count[2], n = 0;
    for (int k = 0; k < 2; ++k) {
        snprintf(path[k], sizeof path[k], "%s/results.h5", k ? b : a);
        TEST_INT(gsn_h5_open(path[k], GSN_FILE_KIND_RESULTS, 0, &file[k]),
                 GSN_OK);
        TEST_INT(gsn_results_frame_count(file[k], &count[k]), GSN_OK);
        size_t rows = 0;
        struct gsn_dataset_info info = gsn_frame_fields[0];
        char dataset[64];
        snprintf(dataset, sizeof dataset, GSN_FRAME_GROUP_FORMAT "/%s",
                 count[k] - 1, gsn_frame_fields[0].path);
        info.path = dataset;
        TEST_INT(gsn_h5_rows(file[k], &info, &rows), GSN_OK);
        n = (int)rows;
        TEST_INT(gsn_frame_allocate(&frame[k], n), GSN_OK);
        TEST_INT(gsn_results_frame_read(file[k], count[k] - 1, &frame[k]),
                 GSN_OK);
    }
    /* The frame counts may differ by one: a run that stops half way ends
     * with a frame of its own. The last frames are compared. */
    int same = frame[0].step == frame[1].step && frame[0].time == frame[1].time;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        same &= memcmp(frame[0].field[f], frame[1].field[f],
                       sizeof(double) * (size_t)n *
                           gsn_frame_fields[f].columns) == 0;
    printf("%s vs %s: %d frames, last at step %d: %s\n", a, b, count[0],
           frame[0].step, same ? "identical" : "DIFFERENT");
    for (int k = 0; k < 2; ++k) {
        gsn_frame_free(&frame[k]);
        gsn_h5_close(&file[k]);
    }
    return same;
}

int main(void)
{
    test_begin();
    struct gsn_case c;
    TEST_INT(gsn_case_load("cases/restart_block.yaml", &c), GSN_OK);
    static char whole[] = "/tmp/geoscni-test-whole-XXXXXX";
    static char parts[] = "/tmp/geoscni-test-parts-XXXXXX";
    static char single[] = "/tmp/geoscni-test-single-XXXXXX";
    run(&c, c.time_end, 0, whole, 2);
    run(&c, 0.5 * c.time_end, 0, parts, 2);
    run(&c, c.time_end, 1, parts, 2);
    run(&c, c.time_end, 0, single, 1);
    /* Bit for bit: the restart restores every array of the loop's state. */
    TEST_TRUE(same_last_frame(whole, parts));
    /* Bit for bit: sums are gathered in point order on any thread count. */
    TEST_TRUE(same_last_frame(whole, single));
    char command[200];
    snprintf(command, sizeof command, "rm -rf %s %s %s", whole, parts, single);
    TEST_INT(system(command), 0);
    return test_end("test_restart");
}
