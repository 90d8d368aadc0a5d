/* results.h5 frames. The frame count attribute is written after the frame's
 * datasets, so a frame cut short by a crash is not counted. */
#include "geoscni/results.h"
#include "geoscni/error.h"

#include <stdlib.h>
#include <string.h>

int gsn_frame_allocate(struct gsn_frame *frame, int particle_count)
{
    memset(frame, 0, sizeof *frame);
    GSN_CHECK(particle_count >= 0, GSN_ERR_INTERNAL, "negative particle count");
    frame->particle_count = particle_count;
    frame->present = (1u << GSN_FRAME_FIELD_COUNT) - 1;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f) {
        size_t count = (size_t)particle_count * gsn_frame_fields[f].columns;
        frame->field[f] = calloc(count ? count : 1, sizeof(double));
        if (!frame->field[f]) {
            gsn_frame_free(frame);
            GSN_CHECK(0, GSN_ERR_MEMORY,
                      "cannot allocate a frame of %d "
                      "particles",
                      particle_count);
        }
    }
    return GSN_OK;
}

void gsn_frame_free(struct gsn_frame *frame)
{
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        free(frame->field[f]);
    memset(frame, 0, sizeof *frame);
}

static int frame_group_name(int index, char *name, size_t size)
{
    int n = snprintf(name, size, GSN_FRAME_GROUP_FORMAT, index);
    GSN_CHECK(n > 0 && (size_t)n < size && index >= 0, GSN_ERR_INTERNAL,
              "bad frame index %d", index);
    return GSN_OK;
}

int gsn_results_frame_write(hid_t file, int index,
                            const struct gsn_frame *frame)
{
    int count = 0;
    GSN_CALL(gsn_results_frame_count(file, &count));
    GSN_CHECK(index == count, GSN_ERR_INTERNAL,
              "frame %d written after %d frames: frames are appended in order",
              index, count);
    char name[64];
    GSN_CALL(frame_group_name(index, name, sizeof name));
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_group(file, name, &group));
    int rc = GSN_OK;
    GSN_CALL_GOTO(
        gsn_h5_attr_write_double(group, GSN_FRAME_ATTR_TIME, frame->time), rc,
        done);
    GSN_CALL_GOTO(
        gsn_h5_attr_write_int(group, GSN_FRAME_ATTR_STEP, frame->step), rc,
        done);
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        if (frame->present & (1u << f))
            GSN_CALL_GOTO(gsn_h5_write(group, &gsn_frame_fields[f],
                                       (size_t)frame->particle_count,
                                       frame->field[f]),
                          rc, done);
    GSN_CALL_GOTO(
        gsn_h5_attr_write_int(file, GSN_RESULTS_ATTR_FRAME_COUNT, index + 1),
        rc, done);
    GSN_CALL_GOTO(gsn_h5_flush(file), rc, done);
done:
    gsn_h5_close(&group);
    return rc;
}

int gsn_results_frame_count(hid_t file, int *count)
{
    *count = 0;
    if (H5Aexists(file, GSN_RESULTS_ATTR_FRAME_COUNT) <= 0)
        return GSN_OK;
    GSN_CALL(gsn_h5_attr_read_int(file, GSN_RESULTS_ATTR_FRAME_COUNT, count));
    return GSN_OK;
}

int gsn_results_frames_drop_after(hid_t file, int step, int *count,
                                  int *last_step)
{
    GSN_CALL(gsn_results_frame_count(file, count));
    int kept = *count;
    if (last_step)
        *last_step = -1;
    for (; kept > 0; --kept) {
        char name[64];
        GSN_CALL(frame_group_name(kept - 1, name, sizeof name));
        /* the last frame may have been cut short by a write that failed
         * (a full disk): it is after every checkpoint, dropped with the
         * rest */
        hid_t group = H5Gopen2(file, name, H5P_DEFAULT);
        if (group < 0 && kept == *count) {
            char path[256];
            if (H5Fget_name(file, path, sizeof path) < 0)
                snprintf(path, sizeof path, "the results file");
            GSN_CHECK(H5Ldelete(file, name, H5P_DEFAULT) >= 0, GSN_ERR_IO,
                      "%s: its last frame group '%s' was cut short where a "
                      "restart cannot mend it (a write that failed, the "
                      "disk full?): start over with 'geoscni run CASE.yaml "
                      "-o OUTDIR --rerun'",
                      path, name);
            continue;
        }
        if (group < 0) /* the error, with its message */
            GSN_CALL(gsn_h5_group_open(file, name, "frame group", &group));
        int frame_step = 0;
        int rc = gsn_h5_attr_read_int(group, GSN_FRAME_ATTR_STEP, &frame_step);
        H5Gclose(group);
        GSN_CALL(rc);
        if (frame_step <= step) {
            if (last_step)
                *last_step = frame_step;
            break;
        }
        GSN_CHECK(H5Ldelete(file, name, H5P_DEFAULT) >= 0, GSN_ERR_IO,
                  "cannot delete frame group '%s'", name);
    }
    if (kept < *count)
        GSN_CALL(
            gsn_h5_attr_write_int(file, GSN_RESULTS_ATTR_FRAME_COUNT, kept));
    *count = kept;
    return GSN_OK;
}

int gsn_results_frame_read(hid_t file, int index, struct gsn_frame *frame)
{
    int count = 0;
    GSN_CALL(gsn_results_frame_count(file, &count));
    GSN_CHECK(index >= 0 && index < count, GSN_ERR_INPUT,
              "frame %d asked for, but the results file holds %d frames", index,
              count);
    char name[64];
    GSN_CALL(frame_group_name(index, name, sizeof name));
    hid_t group = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_group_open(file, name, "frame group", &group));
    int rc = GSN_OK;
    GSN_CALL_GOTO(
        gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, &frame->time), rc,
        done);
    GSN_CALL_GOTO(
        gsn_h5_attr_read_int(group, GSN_FRAME_ATTR_STEP, &frame->step), rc,
        done);
    frame->present = 0;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f) {
        size_t columns = (size_t)gsn_frame_fields[f].columns;
        if (!gsn_h5_exists(group, gsn_frame_fields[f].path)) {
            memset(frame->field[f], 0,
                   sizeof(double) * columns * (size_t)frame->particle_count);
            continue;
        }
        GSN_CALL_GOTO(gsn_h5_read(group, &gsn_frame_fields[f],
                                  (size_t)frame->particle_count,
                                  frame->field[f]),
                      rc, done);
        frame->present |= 1u << f;
    }
done:
    gsn_h5_close(&group);
    return rc;
}
