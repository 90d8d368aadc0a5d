/* Reproducibility of the explicit loop (issue 5, point 4): a run stopped
 * half way and continued with --restart ends with the same bits as an
 * uninterrupted run, and a run on 1 or 3 threads ends with the same bits as
 * on 2 (the passes gather in a fixed order, whichever thread runs a block). The
 * block is large enough that the loops do run in parallel. With output.times
 * and output.every (issue 8, point 4) the restarted run writes the
 * uninterrupted run's frames, at the same steps with the same bits, plus the
 * frame where the first part ended; a frame that the first part wrote after its
 * checkpoint (as a run killed between checkpoints leaves) is dropped and
 * written again. Likewise with gravity ramped (time.ramp) across the cut. */
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

/* Opens a results file and reads its frame count and particle count. */
static hid_t results_open(const char *folder, int writable, int *count, int *n)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/results.h5", folder);
    hid_t file = H5I_INVALID_HID;
    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, writable, &file), GSN_OK);
    TEST_INT(gsn_results_frame_count(file, count), GSN_OK);
    struct gsn_dataset_info info = gsn_frame_fields[GSN_FRAME_DISPLACEMENT];
    char dataset[64];
    snprintf(dataset, sizeof dataset, GSN_FRAME_GROUP_FORMAT "/%s", 0,
             info.path);
    info.path = dataset;
    size_t rows = 0;
    TEST_INT(gsn_h5_rows(file, &info, &rows), GSN_OK);
    *n = (int)rows;
    return file;
}

/* Every frame of the uninterrupted run (whole) is in the restarted one
 * (parts), at the same step with the same time and bits; parts has one
 * frame more, at the step where its first part ended (cut_step), and its
 * steps increase. */
static void check_restart_frames(const char *whole, const char *parts,
                                 int cut_step)
{
    int count[2], n = 0;
    hid_t file[2] = {results_open(whole, 0, &count[0], &n),
                     results_open(parts, 0, &count[1], &n)};
    struct gsn_frame a, b;
    TEST_INT(gsn_frame_allocate(&a, n), GSN_OK);
    TEST_INT(gsn_frame_allocate(&b, n), GSN_OK);
    int matched = 0, extra = 0, previous = -1, k = 0;
    for (int j = 0; j < count[1]; ++j) {
        TEST_INT(gsn_results_frame_read(file[1], j, &b), GSN_OK);
        TEST_TRUE(b.step > previous);
        previous = b.step;
        if (k < count[0])
            TEST_INT(gsn_results_frame_read(file[0], k, &a), GSN_OK);
        if (k < count[0] && a.step == b.step) {
            int same = a.time == b.time;
            for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
                same &= memcmp(a.field[f], b.field[f],
                               sizeof(double) * (size_t)n *
                                   gsn_frame_fields[f].columns) == 0;
            TEST_TRUE(same);
            matched++;
            k++;
        } else {
            TEST_INT(b.step, cut_step);
            extra++;
        }
    }
    printf("%s vs %s: %d of %d frames at the same steps with the same bits, "
           "%d more at the cut (step %d)\n",
           whole, parts, matched, count[0], extra, cut_step);
    TEST_INT(matched, count[0]);
    TEST_TRUE(extra <= 1);
    gsn_frame_free(&a);
    gsn_frame_free(&b);
    gsn_h5_close(&file[0]);
    gsn_h5_close(&file[1]);
}

/* A run's results opened (writable or not) with its last frame read into
 * frame (allocated here; the caller frees it and closes the file); count
 * gets the frame count. */
static hid_t last_frame_read(const char *folder, int writable,
                             struct gsn_frame *frame, int *count)
{
    int n = 0;
    hid_t file = results_open(folder, writable, count, &n);
    TEST_INT(gsn_frame_allocate(frame, n), GSN_OK);
    TEST_INT(gsn_results_frame_read(file, *count - 1, frame), GSN_OK);
    return file;
}

/* The step of a run's last frame. */
static int last_frame_step(const char *folder)
{
    int count = 0;
    struct gsn_frame frame;
    hid_t file = last_frame_read(folder, 0, &frame, &count);
    int step = frame.step;
    gsn_frame_free(&frame);
    gsn_h5_close(&file);
    return step;
}

/* Appends to a run's results a copy of its last frame at a later step, as a
 * run killed after a frame but before its checkpoint leaves; returns the
 * step of the last frame before it. */
static int append_frame_after_checkpoint(const char *folder)
{
    int count = 0;
    struct gsn_frame frame;
    hid_t file = last_frame_read(folder, 1, &frame, &count);
    int step = frame.step;
    frame.time *= (double)(step + 3) / step;
    frame.step = step + 3;
    frame.field[GSN_FRAME_DISPLACEMENT][0] += 1.0;
    TEST_INT(gsn_results_frame_write(file, count, &frame), GSN_OK);
    gsn_frame_free(&frame);
    gsn_h5_close(&file);
    return step;
}

/* The reference updates a run made: the last row of its history. */
static int updates_done(const char *folder)
{
    const char *names[] = {"reference_updates"};
    double values[4096];
    int rows = fixture_history(folder, names, 1, values, 4096);
    TEST_TRUE(rows > 0);
    printf("%s: %g reference updates\n", folder,
           rows > 0 ? values[rows - 1] : -1);
    return rows > 0 ? (int)values[rows - 1] : 0;
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
    /* three threads on this machine's two cores: one of them is often held
     * back, so the others take blocks from its range (explicit.c,
     * next_block) */
    static char three[] = "/tmp/geoscni-test-three-XXXXXX";
    run(&c, c.time_end, 0, three, 3);
    /* Bit for bit: the restart restores every array of the loop's state. */
    TEST_TRUE(same_last_frame(whole, parts));
    /* Bit for bit: sums are gathered in point order on any thread count. */
    TEST_TRUE(same_last_frame(whole, single));
    TEST_TRUE(same_last_frame(whole, three));

    /* Gravity ramped with time.ramp past the cut (issue 21, point 5): the
     * restart sets the loads of its checkpoint's time, the same bits. */
    static char whole_ramp[] = "/tmp/geoscni-test-whole-ramp-XXXXXX";
    static char parts_ramp[] = "/tmp/geoscni-test-parts-ramp-XXXXXX";
    c.time_ramp = 0.75 * c.time_end;
    run(&c, c.time_end, 0, whole_ramp, 2);
    run(&c, 0.5 * c.time_end, 0, parts_ramp, 2);
    run(&c, c.time_end, 1, parts_ramp, 2);
    TEST_TRUE(same_last_frame(whole_ramp, parts_ramp));
    c.time_ramp = 0.0;

    /* Frames every 0.01 s and at listed times (two on nearby steps, one on
     * a multiple of every), across a restart. */
    const double times[] = {0.0033, 0.0151, 0.0163, 0.02, 0.0271};
    c.output_time_count = (int)(sizeof times / sizeof times[0]);
    memcpy(c.output_times, times, sizeof times);
    static char whole_times[] = "/tmp/geoscni-test-whole-times-XXXXXX";
    static char parts_times[] = "/tmp/geoscni-test-parts-times-XXXXXX";
    run(&c, c.time_end, 0, whole_times, 2);
    run(&c, 0.55 * c.time_end, 0, parts_times, 2);
    int cut_step = append_frame_after_checkpoint(parts_times);
    run(&c, c.time_end, 1, parts_times, 2);
    check_restart_frames(whole_times, parts_times, cut_step);

    /* With reference updates every 0.005 s, at any step (issue 15, point 7): a
     * run stopped after some and continued builds the checkpoint's reference
     * again and ends with the uninterrupted run's bits; so does a run on
     * one thread. */
    c.output_time_count = 0;
    c.reference_update = 1;
    c.reference_every = 0.005;
    c.reference_min_steps = 1;
    static char whole_updates[] = "/tmp/geoscni-test-whole-updates-XXXXXX";
    static char parts_updates[] = "/tmp/geoscni-test-parts-updates-XXXXXX";
    static char single_updates[] = "/tmp/geoscni-test-single-updates-XXXXXX";
    run(&c, c.time_end, 0, whole_updates, 2);
    run(&c, 0.45 * c.time_end, 0, parts_updates, 2);
    int cut_updates = last_frame_step(parts_updates);
    run(&c, c.time_end, 1, parts_updates, 2);
    run(&c, c.time_end, 0, single_updates, 1);
    TEST_TRUE(updates_done(whole_updates) >= 6);
    TEST_TRUE(same_last_frame(whole_updates, parts_updates));
    /* and every frame of before the checkpoint (a restart after updates
     * once read the checkpoint's step from the replaced loop and dropped
     * them) */
    check_restart_frames(whole_updates, parts_updates, cut_updates);
    TEST_TRUE(same_last_frame(whole_updates, single_updates));

    char command[1000];
    snprintf(command, sizeof command, "rm -rf %s %s %s %s %s %s %s %s %s %s %s",
             whole, parts, single, three, whole_times, parts_times, whole_ramp,
             parts_ramp, whole_updates, parts_updates, single_updates);
    TEST_INT(system(command), 0);
    return test_end("test_restart");
}
