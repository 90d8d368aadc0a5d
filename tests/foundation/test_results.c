/* results.h5 frames: written in order and read back bit for bit; a frame
 * whose count was not yet written (a crash mid-frame) is not counted; a
 * frame past the end is refused with a message; a frame without some
 * fields (output.fields) reads with them marked absent. */
#include "geoscni/error.h"
#include "geoscni/results.h"
#include "testing.h"

#include <string.h>
#include <unistd.h>

enum { PARTICLES = 5, FRAMES = 3 };

static void fill(struct gsn_frame *frame, int index)
{
    frame->time = 0.5 * index;
    frame->step = 500 * index;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        for (int i = 0; i < PARTICLES * gsn_frame_fields[f].columns; ++i)
            frame->field[f][i] = index + 0.1 * f + 1e-3 * i + 1.0 / 3.0;
}

int main(void)
{
    test_begin();
    char path[] = "/tmp/geoscni-test-results-XXXXXX";
    int fd = mkstemp(path);
    TEST_TRUE(fd >= 0);
    close(fd);
    hid_t file = H5I_INVALID_HID;
    TEST_INT(gsn_h5_create(path, GSN_FILE_KIND_RESULTS, "", &file), GSN_OK);
    struct gsn_frame written, read;
    TEST_INT(gsn_frame_allocate(&written, PARTICLES), GSN_OK);
    for (int k = 0; k < FRAMES; ++k) {
        fill(&written, k);
        TEST_INT(gsn_results_frame_write(file, k, &written), GSN_OK);
    }
    /* Frames are appended in order. */
    TEST_INT(gsn_results_frame_write(file, FRAMES + 1, &written),
             GSN_ERR_INTERNAL);
    gsn_error_clear();
    /* A group without the count update: as if the run died mid-frame. */
    hid_t partial = H5I_INVALID_HID;
    TEST_INT(gsn_h5_group(file, "frames/000003", &partial), GSN_OK);
    gsn_h5_close(&partial);
    gsn_h5_close(&file);

    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file), GSN_OK);
    int count = 0;
    TEST_INT(gsn_results_frame_count(file, &count), GSN_OK);
    TEST_INT(count, FRAMES);
    TEST_INT(gsn_frame_allocate(&read, PARTICLES), GSN_OK);
    for (int k = 0; k < FRAMES; ++k) {
        fill(&written, k);
        TEST_INT(gsn_results_frame_read(file, k, &read), GSN_OK);
        TEST_NEAR(read.time, written.time, 0.0);
        TEST_INT(read.step, written.step);
        for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
            TEST_TRUE(memcmp(read.field[f], written.field[f],
                             sizeof(double) * PARTICLES *
                                 gsn_frame_fields[f].columns) == 0);
    }
    TEST_INT(gsn_results_frame_read(file, FRAMES, &read), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "holds 3 frames") != NULL);
    gsn_error_clear();
    gsn_h5_close(&file);

    /* A model file is not a results file. */
    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_MODEL, 0, &file), GSN_ERR_INPUT);
    gsn_error_clear();

    /* A frame without a field (output.fields, docs/economy.md) reads with
     * that field absent and zeroed, the others intact. */
    file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    TEST_TRUE(H5Ldelete(file, "frames/000001/damage", H5P_DEFAULT) >= 0);
    H5Fclose(file);
    TEST_INT(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &file), GSN_OK);
    TEST_INT(gsn_results_frame_read(file, 1, &read), GSN_OK);
    TEST_INT(read.present,
             ((1u << GSN_FRAME_FIELD_COUNT) - 1) & ~(1u << GSN_FRAME_DAMAGE));
    TEST_NEAR(read.field[GSN_FRAME_DAMAGE][PARTICLES - 1], 0.0, 0.0);
    TEST_INT(gsn_results_frame_read(file, 0, &read), GSN_OK);
    TEST_INT(read.present, (1u << GSN_FRAME_FIELD_COUNT) - 1);
    gsn_h5_close(&file);

    /* Only the present fields are written. */
    TEST_INT(gsn_h5_create(path, GSN_FILE_KIND_RESULTS, "", &file), GSN_OK);
    written.present = (1u << GSN_FRAME_DISPLACEMENT) | (1u << GSN_FRAME_STRESS);
    TEST_INT(gsn_results_frame_write(file, 0, &written), GSN_OK);
    TEST_TRUE(gsn_h5_exists(file, "frames/000000/displacement"));
    TEST_TRUE(gsn_h5_exists(file, "frames/000000/stress"));
    TEST_TRUE(!gsn_h5_exists(file, "frames/000000/velocity"));
    TEST_TRUE(!gsn_h5_exists(file, "frames/000000/damage"));
    TEST_INT(gsn_results_frame_read(file, 0, &read), GSN_OK);
    TEST_INT(read.present, written.present);
    TEST_TRUE(memcmp(read.field[GSN_FRAME_STRESS],
                     written.field[GSN_FRAME_STRESS],
                     sizeof(double) * PARTICLES * 6) == 0);
    gsn_h5_close(&file);

    gsn_frame_free(&written);
    gsn_frame_free(&read);
    TEST_TRUE(read.field[0] == NULL);
    remove(path);
    return test_end("test_results");
}
