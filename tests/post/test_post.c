/* post without pictures on a synthetic run folder (synthetic.h): the .pvd
 * and .vtu files are checked by an independent reader (check_vtu.py:
 * meshio and h5py from Debian's /usr/bin/python3) against results.h5 and
 * model.h5, with a negative control that the reader catches a changed
 * field; every file is renamed into place (no .part left), stale frame
 * files of a longer earlier run are removed; a folder without results.h5
 * or model.h5, a results.h5 of another schema version and a model of
 * another run are input errors (exit status 2) with a message; the frames,
 * written in parallel, are the same bytes on 1 and 3 threads, and a frame
 * missing from results.h5 stops post with an error on any thread; and the
 * history.csv reader. */
#include "history.h"
#include "synthetic.h"
#include "testing.h"

#include "geoscni/post.h"

#include <dirent.h>
#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

enum { FRAMES = 4 };

static char root[] = "/tmp/geoscni-test-post-XXXXXX";

static void folder_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", root, name);
}

static int file_exists(const char *folder, const char *name)
{
    char path[GSN_PATH_SIZE];
    if (gsn_path_join(path, sizeof path, folder, name) != GSN_OK)
        return 0;
    return access(path, F_OK) == 0;
}

/* Files whose name ends in ".part" under folder and folder/vtu. */
static int count_partial(const char *folder)
{
    int count = 0;
    char vtu[GSN_PATH_SIZE];
    if (gsn_path_join(vtu, sizeof vtu, folder, "vtu") != GSN_OK)
        return -1;
    const char *folders[2] = {folder, vtu};
    for (int f = 0; f < 2; ++f) {
        DIR *dir = opendir(folders[f]);
        if (!dir)
            continue;
        struct dirent *entry;
        while ((entry = readdir(dir)) != NULL) {
            size_t n = strlen(entry->d_name);
            count += n > 5 && !strcmp(entry->d_name + n - 5, ".part");
        }
        closedir(dir);
    }
    return count;
}

static int run_checker(const char *folder, const char *case_name)
{
    char command[2 * GSN_PATH_SIZE];
    snprintf(command, sizeof command, "/usr/bin/python3 check_vtu.py '%s' '%s'",
             folder, case_name);
    return system(command);
}

static const struct gsn_post_options NO_PICTURES = {.no_pictures = 1,
                                                    .quiet = 1};

/* post's error for folder: code, exit status 2, and the message. */
static void expect_input_error(const char *folder, const char *message)
{
    int rc = gsn_post_run(folder, &NO_PICTURES);
    TEST_INT(rc, GSN_ERR_INPUT);
    TEST_INT(gsn_error_exit_status(rc), 2);
    TEST_TRUE(strstr(gsn_error_message(), message) != NULL);
    if (!strstr(gsn_error_message(), message))
        fprintf(stderr, "message: %s\n(expected '%s')\n", gsn_error_message(),
                message);
    gsn_error_clear();
}

static void test_output(void)
{
    char folder[GSN_PATH_SIZE / 2], path[GSN_PATH_SIZE];
    folder_path(folder, sizeof folder, "run");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, FRAMES, "box_case"), GSN_OK);
    /* A frame file left by an earlier, longer run. */
    TEST_INT(gsn_path_join(path, sizeof path, folder, "vtu"), GSN_OK);
    TEST_INT(gsn_folder_prepare(path), GSN_OK);
    TEST_INT(gsn_path_join(path, sizeof path, folder, "vtu/frame_0004.vtu"),
             GSN_OK); /* FRAMES = 4 */
    FILE *stale = fopen(path, "w");
    TEST_TRUE(stale != NULL);
    if (stale)
        fclose(stale);

    TEST_INT(gsn_post_run(folder, &NO_PICTURES), GSN_OK);
    TEST_TRUE(file_exists(folder, "box_case.pvd"));
    for (int k = 0; k < FRAMES; ++k) {
        char name[64];
        snprintf(name, sizeof name, "vtu/frame_%04d.vtu", k);
        TEST_TRUE(file_exists(folder, name));
    }
    TEST_TRUE(access(path, F_OK) != 0); /* the stale frame is gone */
    TEST_INT(count_partial(folder), 0);
    TEST_TRUE(!file_exists(folder, "pictures"));
    TEST_TRUE(!file_exists(folder, "plots"));
    TEST_INT(run_checker(folder, "box_case"), 0);

    /* Negative control: change one value of frame 2 in results.h5; the
     * reader must now find that frame's .vtu wrong. */
    TEST_INT(gsn_path_join(path, sizeof path, folder, "results.h5"), GSN_OK);
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    TEST_TRUE(file >= 0);
    hid_t set = H5Dopen2(file, "frames/000002/damage", H5P_DEFAULT);
    TEST_TRUE(set >= 0);
    double damage[SYNTHETIC_NX * SYNTHETIC_NY * SYNTHETIC_NZ];
    TEST_TRUE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                      damage) >= 0);
    damage[7] = nextafter(damage[7], 2.0);
    TEST_TRUE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                       damage) >= 0);
    H5Dclose(set);
    H5Fclose(file);
    TEST_TRUE(run_checker(folder, "box_case") != 0);

    /* Without the case_name attribute the .pvd takes the folder's name. */
    folder_path(folder, sizeof folder, "plain_run/");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, 2, NULL), GSN_OK);
    TEST_INT(gsn_post_run(folder, &NO_PICTURES), GSN_OK);
    TEST_TRUE(file_exists(folder, "plain_run.pvd"));
    TEST_INT(run_checker(folder, "plain_run"), 0);
}

/* The bytes of file `name` in folder (test_file_bytes), or NULL. */
static unsigned char *frame_bytes(const char *folder, const char *name,
                                  size_t *size)
{
    char path[GSN_PATH_SIZE];
    if (gsn_path_join(path, sizeof path, folder, name) != GSN_OK)
        return NULL;
    return test_file_bytes(path, size);
}

/* post writes its frames in parallel (post.c post_frames): the same files
 * on 1 and on 3 threads (more threads than this machine's 2 cores, so that
 * the frames are taken in varying order), and a frame missing from
 * results.h5 fails the run with its error whichever thread reads it. */
static void test_threads(void)
{
    enum { MANY = 9 };
    char folder[GSN_PATH_SIZE / 2], path[GSN_PATH_SIZE];
    folder_path(folder, sizeof folder, "threads");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, MANY, "box_case"), GSN_OK);
    unsigned char *one[MANY];
    size_t one_size[MANY];
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    TEST_INT(gsn_post_run(folder, &NO_PICTURES), GSN_OK);
    for (int k = 0; k < MANY; ++k) {
        char name[64];
        snprintf(name, sizeof name, "vtu/frame_%04d.vtu", k);
        one[k] = frame_bytes(folder, name, &one_size[k]);
        TEST_TRUE(one[k] != NULL);
    }
    omp_set_num_threads(3);
    TEST_INT(gsn_post_run(folder, &NO_PICTURES), GSN_OK);
    for (int k = 0; k < MANY; ++k) {
        char name[64];
        size_t size = 0;
        snprintf(name, sizeof name, "vtu/frame_%04d.vtu", k);
        unsigned char *three = frame_bytes(folder, name, &size);
        TEST_TRUE(three && one[k] && size == one_size[k] &&
                  !memcmp(three, one[k], size));
        free(three);
        free(one[k]);
    }
    TEST_INT(run_checker(folder, "box_case"), 0);

    /* frame 5 removed from results.h5: an error, not a crash or a hang */
    TEST_INT(gsn_path_join(path, sizeof path, folder, "results.h5"), GSN_OK);
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    TEST_TRUE(file >= 0);
    TEST_TRUE(H5Ldelete(file, "frames/000005", H5P_DEFAULT) >= 0);
    H5Fclose(file);
    int rc = gsn_post_run(folder, &NO_PICTURES);
    TEST_TRUE(rc != GSN_OK);
    TEST_TRUE(strstr(gsn_error_message(), "000005") != NULL);
    if (!strstr(gsn_error_message(), "000005"))
        fprintf(stderr, "message: %s\n", gsn_error_message());
    gsn_error_clear();
    omp_set_num_threads(threads);
}

static void test_errors(void)
{
    char folder[GSN_PATH_SIZE / 2], path[GSN_PATH_SIZE];
    folder_path(folder, sizeof folder, "empty");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    expect_input_error(folder, "results.h5 not found");

    /* A results.h5 of another schema version. */
    folder_path(folder, sizeof folder, "old_schema");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, 2, "old"), GSN_OK);
    TEST_INT(gsn_path_join(path, sizeof path, folder, "results.h5"), GSN_OK);
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    TEST_TRUE(file >= 0);
    TEST_TRUE(H5Adelete(file, GSN_ATTR_SCHEMA_VERSION) >= 0);
    TEST_INT(gsn_h5_attr_write_int(file, GSN_ATTR_SCHEMA_VERSION,
                                   GSN_SCHEMA_VERSION + 1),
             GSN_OK);
    H5Fclose(file);
    expect_input_error(folder, "schema version");
    TEST_TRUE(!file_exists(folder, "old.pvd"));

    /* results.h5 without its model.h5. */
    folder_path(folder, sizeof folder, "no_model");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, 2, "no_model"), GSN_OK);
    TEST_INT(gsn_path_join(path, sizeof path, folder, "model.h5"), GSN_OK);
    TEST_INT(unlink(path), 0);
    expect_input_error(folder, "model.h5 not found");

    /* A model.h5 and a results.h5 of different particle counts. */
    folder_path(folder, sizeof folder, "mismatch");
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    struct gsn_case *c = calloc(1, sizeof *c);
    TEST_TRUE(c != NULL);
    TEST_INT(gsn_case_load("box.yaml", c), GSN_OK);
    TEST_INT(synthetic_model_write(folder, c), GSN_OK);
    TEST_INT(synthetic_results_write(folder, c, 1, 7, "mismatch"), GSN_OK);
    free(c);
    expect_input_error(folder, "different runs");
}

static void test_history(void)
{
    char path[GSN_PATH_SIZE];
    folder_path(path, sizeof path, "history.csv");
    FILE *file = fopen(path, "w");
    TEST_TRUE(file != NULL);
    if (!file)
        return;
    /* Two rows, then a last row cut short by a run still writing. */
    fputs("time, step,a_ux\n0,0,1.5\r\n0.5,500,-2e-3\n1.0,10", file);
    fclose(file);
    struct gsn_history h;
    TEST_INT(gsn_history_read(path, &h), GSN_OK);
    TEST_INT(h.column_count, 3);
    TEST_INT(h.row_count, 2);
    TEST_INT(gsn_history_column(&h, "step"), 1);
    TEST_INT(gsn_history_column(&h, "a_ux"), 2);
    TEST_INT(gsn_history_column(&h, "b_ux"), -1);
    if (h.row_count == 2) {
        TEST_NEAR(h.values[2], 1.5, 0.0);   /* decimal text read exactly */
        TEST_NEAR(h.values[5], -2e-3, 0.0); /* strtod rounds correctly */
    }
    gsn_history_free(&h);

    /* A malformed row inside the file is an error naming its line. */
    file = fopen(path, "w");
    TEST_TRUE(file != NULL);
    if (!file)
        return;
    fputs("time,step\n0,0\n0.5,x\n1,1000\n", file);
    fclose(file);
    TEST_INT(gsn_history_read(path, &h), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "history.csv:3") != NULL);
    gsn_error_clear();
    TEST_INT(h.row_count, 0);
    unlink(path);
}

/* Units after the column names (solve's header) are found by the bare
 * names; the load-settlement curve keeps the force's sign along the
 * motion: a footing moved down (-z) that first holds the body back (its
 * force on the body up, +z) plots below zero, as does a heave. */
static void test_history_signed_curve(void)
{
    char path[GSN_PATH_SIZE];
    folder_path(path, sizeof path, "history.csv");
    FILE *file = fopen(path, "w");
    TEST_TRUE(file != NULL);
    if (!file)
        return;
    fputs("time_s,step,f_ux_m,f_uy_m,f_uz_m,f_fx_N,f_fy_N,f_fz_N,"
          "kinetic_energy_J\n"
          "0,0,0,0,0,0,0,0,0\n"
          "0.1,10,0,0,0.0005,0,0,1000,1\n"
          "0.2,20,0,0,-0.001,0,0,-2000,2\n",
          file);
    fclose(file);
    struct gsn_history h;
    TEST_INT(gsn_history_read(path, &h), GSN_OK);
    TEST_INT(gsn_history_column(&h, "time"), 0);
    TEST_INT(gsn_history_column(&h, "f_fz"), 7);
    TEST_INT(gsn_history_column(&h, "kinetic_energy"), 8);
    TEST_INT(gsn_history_column(&h, "f_f"), -1); /* not a unit after it */
    TEST_INT(gsn_history_column(&h, "tim"), -1);
    const double down[3] = {0.0, 0.0, -1.0};
    double x[3] = {0}, y[3] = {0};
    TEST_INT(gsn_history_motion_curve(&h, "f", down, 1.0, x, y), GSN_OK);
    /* exact: a product with -1 and a scaling by 1e-3 of decimal values */
    TEST_NEAR(x[1], -0.0005, 0.0);
    TEST_NEAR(y[1], -1.0, 1e-15);
    TEST_NEAR(x[2], 0.001, 0.0);
    TEST_NEAR(y[2], 2.0, 1e-15);
    TEST_INT(gsn_history_motion_curve(&h, "g", down, 1.0, x, y), GSN_ERR_INPUT);
    TEST_TRUE(strstr(gsn_error_message(), "g_ux") != NULL);
    gsn_error_clear();
    gsn_history_free(&h);
    unlink(path);
}

int main(void)
{
    test_begin();
    TEST_TRUE(mkdtemp(root) != NULL);
    test_history();
    test_history_signed_curve();
    test_output();
    test_threads();
    test_errors();
    char command[GSN_PATH_SIZE + 16];
    snprintf(command, sizeof command, "rm -rf '%s'", root);
    if (!test_failures)
        TEST_INT(system(command), 0);
    else
        fprintf(stderr, "output kept in %s\n", root);
    return test_end("test_post");
}
