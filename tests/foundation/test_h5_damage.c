/* Issue 19, point 1: no damaged file is read unnoticed. A model.h5 (a
 * synthetic one of 300 particles, small enough to flip every byte) is
 * written, then one bit of it is flipped at every STRIDE-th byte (argument:
 * 13 by default, in CI; 1, every byte, in bench/fuzz.sh) and the copy read
 * in a child process with gsn_model_read and the root attributes. Each copy
 * must give either the same model and attributes bit for bit (the bit was
 * in unused space) or an error whose message names the file; never a
 * different model read without a word, a crash or a hang; a bit in a
 * dataset's data must be reported as a checksum mismatch naming the
 * dataset. Prints the counts. (With HDF5's Fletcher32 filter on chunked
 * data in the 1.8 format instead of the CRC-32 attribute, 30 of 14,360
 * flips were read changed: the chunk index, a version 1 B-tree, has no
 * checksum, and a flipped bit of a chunk's filter mask skipped the
 * check.) */
#include "geoscni/error.h"
#include "geoscni/h5io.h"
#include "geoscni/model.h"
#include "testing.h"

#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define PARTICLES 300

/* A model with every table filled with distinct values (the reader checks
 * indices, so they stay in range). */
static void build_model(struct gsn_model *m)
{
    TEST_INT(gsn_model_allocate(m, PARTICLES, PARTICLES, PARTICLES, PARTICLES,
                                2, PARTICLES / 4),
             GSN_OK);
    for (int p = 0; p < PARTICLES; ++p) {
        for (int k = 0; k < 3; ++k) {
            m->position[3 * p + k] = 0.001 * p + 0.37 * k;
            m->centroid[3 * p + k] = m->position[3 * p + k] + 1e-4;
        }
        m->volume[p] = 1.0 + 1e-3 * p;
        m->particle_surface_offset[p + 1] = p + 1;
        m->particle_surface[p] = p % 2;
        m->facet_owner[p] = p;
        m->facet_neighbour[p] = p + 1 < PARTICLES ? p + 1 : -1;
        m->facet_surface[p] = p % 3 - 1;
        m->facet_area[p] = 0.5 + 1e-3 * p;
        m->facet_normal[3 * p + p % 3] = 1.0;
        m->facet_point_offset[p + 1] = p + 1;
        m->facet_weight[p] = m->facet_area[p];
        m->facet_point[3 * p] = 0.125 * p;
    }
    strcpy(m->surface_name[0], "bottom");
    strcpy(m->surface_name[1], "footing");
    m->surface_tag[0] = 7;
    m->surface_tag[1] = 8;
    m->surface_area[0] = m->surface_area[1] = 1.0;
    for (int t = 0; t < m->tetrahedron_count; ++t)
        for (int k = 0; k < 4; ++k) {
            m->tetrahedra[4 * t + k] = (4 * t + k) % PARTICLES;
            m->tetrahedron_face[4 * t + k] = GSN_MODEL_FACE_INTERNAL;
        }
}

#define SAME(field, count)                                                     \
    (memcmp(a->field, b->field, sizeof(*a->field) * (size_t)(count)) == 0)

static int same_model(const struct gsn_model *a, const struct gsn_model *b)
{
    int n = a->particle_count, f = a->facet_count, t = a->tetrahedron_count;
    if (n != b->particle_count || f != b->facet_count ||
        t != b->tetrahedron_count || a->surface_count != b->surface_count)
        return 0;
    int points = a->facet_point_offset[f];
    return SAME(position, 3 * n) && SAME(volume, n) && SAME(centroid, 3 * n) &&
           SAME(particle_surface_offset, n + 1) &&
           SAME(particle_surface, a->particle_surface_offset[n]) &&
           SAME(facet_owner, f) && SAME(facet_neighbour, f) &&
           SAME(facet_surface, f) && SAME(facet_area, f) &&
           SAME(facet_normal, 3 * f) && SAME(facet_point_offset, f + 1) &&
           SAME(facet_point, 3 * points) && SAME(facet_weight, points) &&
           SAME(surface_name, a->surface_count) &&
           SAME(surface_tag, a->surface_count) &&
           SAME(surface_area, a->surface_count) && SAME(tetrahedra, 4 * t) &&
           SAME(tetrahedron_face, 4 * t);
}

/* The root attributes a stage reads, joined. */
static int read_attributes(const char *path, char *out, size_t size)
{
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(path, GSN_FILE_KIND_MODEL, 0, &file));
    static const char *const names[] = {GSN_ATTR_CASE, GSN_ATTR_CODE_VERSION,
                                        GSN_ATTR_LIBRARY_VERSIONS};
    out[0] = '\0';
    for (int i = 0; i < 3; ++i) {
        char *text = NULL;
        int rc = gsn_h5_attr_read_string(file, names[i], &text);
        if (rc != GSN_OK) {
            gsn_h5_close(&file);
            return rc;
        }
        strncat(out, text, size - strlen(out) - 1);
        free(text);
    }
    gsn_h5_close(&file);
    return GSN_OK;
}

/* What a child found, as its exit status. */
enum outcome {
    SAME_DATA = 0,
    REPORTED,
    REPORTED_CHECKSUM,
    SILENT,
    UNNAMED,
    POSITION_CHECKSUM, /* a checksum mismatch naming particles/position */
    OUTCOMES
};

static int child_read(const char *path, const struct gsn_model *expected,
                      const char *attributes)
{
    alarm(20); /* a hang ends as SIGALRM */
    struct gsn_model m;
    int rc = gsn_model_read(path, &m);
    char text[8192];
    if (rc == GSN_OK) {
        int same = same_model(expected, &m);
        gsn_model_free(&m);
        if (!same)
            return SILENT;
        rc = read_attributes(path, text, sizeof text);
        if (rc == GSN_OK)
            return strcmp(text, attributes) == 0 ? SAME_DATA : SILENT;
    }
    const char *message = gsn_error_message();
    if (!strstr(message, path))
        return UNNAMED;
    if (!strstr(message, "checksum does not match"))
        return REPORTED;
    return strstr(message, "dataset 'particles/position'") ? POSITION_CHECKSUM
                                                           : REPORTED_CHECKSUM;
}

int main(int argc, char **argv)
{
    test_begin();
    long stride = argc > 1 ? atol(argv[1]) : 13;
    const char *keep = argc > 2 ? argv[2] : NULL; /* a copy of the file */
    if (stride < 1)
        stride = 1;
    char folder[] = "/tmp/geoscni-test-h5-damage-XXXXXX";
    TEST_TRUE(mkdtemp(folder) != NULL);
    char path[256], copy[256];
    snprintf(path, sizeof path, "%s/model.h5", folder);
    snprintf(copy, sizeof copy, "%s/flipped.h5", folder);
    struct gsn_case c;
    TEST_INT(gsn_case_load("cases/valid.yaml", &c), GSN_OK);
    struct gsn_model m;
    build_model(&m);
    TEST_INT(gsn_model_write(path, &m, &c), GSN_OK);
    char attributes[8192];
    TEST_INT(read_attributes(path, attributes, sizeof attributes), GSN_OK);
    if (keep) {
        char command[600];
        snprintf(command, sizeof command, "cp '%s' '%s'", path, keep);
        TEST_INT(system(command), 0);
    }

    /* the file's bytes, and where the data of position lies */
    size_t size = 0;
    unsigned char *bytes = test_file_bytes(path, &size);
    TEST_TRUE(bytes != NULL);
    if (!bytes)
        return test_end("test_h5_damage");
    haddr_t data_at = HADDR_UNDEF;
    hsize_t data_size = 0;
    {
        hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
        hid_t dataset = H5Dopen2(file, "particles/position", H5P_DEFAULT);
        data_at = H5Dget_offset(dataset);
        data_size = H5Dget_storage_size(dataset);
        H5Dclose(dataset);
        H5Fclose(file);
    }
    TEST_TRUE(data_at != HADDR_UNDEF && data_at + data_size <= size);

    long count[OUTCOMES] = {0}, crashes = 0, flips = 0;
    long data_reported = 0, data_flips = 0;
    for (size_t at = 0; at < size; at += (size_t)stride) {
        bytes[at] ^= (unsigned char)(1u << (at % 8));
        int fd = open(copy, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        TEST_TRUE(fd >= 0 && write(fd, bytes, size) == (ssize_t)size);
        close(fd);
        bytes[at] ^= (unsigned char)(1u << (at % 8));
        pid_t child = fork();
        if (child == 0)
            _exit(child_read(copy, &m, attributes));
        int status = 0;
        waitpid(child, &status, 0);
        flips++;
        int in_data = at >= data_at && at < data_at + data_size;
        data_flips += in_data;
        if (!WIFEXITED(status) || WEXITSTATUS(status) >= OUTCOMES) {
            crashes++;
            if (crashes <= 5)
                fprintf(stderr, "byte %zu: the reader crashed (status %d)\n",
                        at, status);
            continue;
        }
        int outcome = WEXITSTATUS(status);
        count[outcome]++;
        data_reported += in_data && outcome == POSITION_CHECKSUM;
        if ((outcome == SILENT || outcome == UNNAMED) && count[outcome] <= 5)
            fprintf(stderr, "byte %zu: %s\n", at,
                    outcome == SILENT ? "read changed without a word"
                                      : "the error does not name the file");
    }
    printf("%ld of %zu bytes flipped (a bit each): %ld read the same, %ld "
           "refused with a checksum mismatch, %ld refused otherwise, %ld "
           "read changed without a word, %ld refused without naming the "
           "file, %ld crashed or hung; of %ld in particles/position's data, "
           "%ld named its checksum and the dataset\n",
           flips, size, count[SAME_DATA],
           count[REPORTED_CHECKSUM] + count[POSITION_CHECKSUM], count[REPORTED],
           count[SILENT], count[UNNAMED], crashes, data_flips, data_reported);
    TEST_INT(count[SILENT], 0);
    TEST_INT(count[UNNAMED], 0);
    TEST_INT(crashes, 0);
    TEST_INT(data_reported, data_flips);
    TEST_TRUE(count[REPORTED_CHECKSUM] + count[POSITION_CHECKSUM] > 0);

    free(bytes);
    gsn_model_free(&m);
    unlink(copy);
    unlink(path);
    rmdir(folder);
    return test_end("test_h5_damage");
}
