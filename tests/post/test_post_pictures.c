/* post with pictures on a synthetic run folder (synthetic.h): when an X
 * display or Xvfb is available, the damage pictures, the clipped-half
 * pictures and the plots exist with a plausible size (a blank 1000 x 700
 * PNG compresses to a few kB; a drawn one is larger). Skipped (77) when
 * neither is available, after checking post still writes the .vtu files
 * and says why it skipped the pictures. Run again on fewer frames, post
 * leaves only the new run's pictures and plots beside files not its own. */
#include "synthetic.h"
#include "testing.h"

#include "geoscni/post.h"

#include <sys/stat.h>
#include <unistd.h>

enum { FRAMES = 7, FEWER_FRAMES = 4, SKIPPED = 77 };

/* Smallest plausible PNG: above what a blank picture compresses to. */
static const long MINIMUM_BYTES = 12000;

static int program_on_path(const char *name)
{
    char command[256];
    snprintf(command, sizeof command, "command -v %s >/dev/null 2>&1", name);
    return system(command) == 0;
}

/* An empty file folder/name. */
static void touch(const char *folder, const char *name)
{
    char path[GSN_PATH_SIZE];
    TEST_INT(gsn_path_join(path, sizeof path, folder, name), GSN_OK);
    FILE *file = fopen(path, "w");
    TEST_TRUE(file != NULL);
    if (file)
        fclose(file);
}

static long file_size(const char *folder, const char *name)
{
    char path[GSN_PATH_SIZE];
    struct stat info;
    if (gsn_path_join(path, sizeof path, folder, name) != GSN_OK)
        return -1;
    return stat(path, &info) == 0 ? (long)info.st_size : -1;
}

int main(void)
{
    test_begin();
    char root[] = "/tmp/geoscni-test-post-pictures-XXXXXX";
    TEST_TRUE(mkdtemp(root) != NULL);
    char folder[GSN_PATH_SIZE];
    TEST_INT(gsn_path_join(folder, sizeof folder, root, "run"), GSN_OK);
    TEST_INT(gsn_folder_prepare(folder), GSN_OK);
    TEST_INT(synthetic_folder_write(folder, FRAMES, "box_case"), GSN_OK);
    int can_render =
        (getenv("DISPLAY") && *getenv("DISPLAY")) || program_on_path("Xvfb");
    /* Mesa's software renderer raises floating-point flags of its own; the
     * traps guard geoscni's arithmetic, which the other tests cover. */
    fedisableexcept(FE_ALL_EXCEPT);
    const struct gsn_post_options options = {.no_pictures = 0, .quiet = 0};
    int rc = gsn_post_run(folder, &options);
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    TEST_TRUE(file_size(folder, "box_case.pvd") > 0);
    TEST_TRUE(file_size(folder, "vtu/frame_0006.vtu") > 0);
    if (!can_render) {
        printf("no X display and no Xvfb: pictures not checked\n");
        test_end("test_post_pictures");
        return test_failures ? 1 : SKIPPED;
    }
    /* Damage at the first, 3 evenly spaced and the last of 7 frames. */
    static const char *const pictures[] = {
        "pictures/damage_frame_0000.png",
        "pictures/damage_frame_0002.png",
        "pictures/damage_frame_0003.png",
        "pictures/damage_frame_0005.png",
        "pictures/damage_frame_0006.png",
        "pictures/clip_ux_frame_0006.png",
        "pictures/clip_uy_frame_0006.png",
        "pictures/clip_uz_frame_0006.png",
        "pictures/clip_equivalent_stress_frame_0006.png",
        "pictures/clip_displacement_frame_0006.png",
        "pictures/clip_equivalent_plastic_strain_frame_0006.png",
        "plots/energy.png",
        "plots/load_settlement_footing.png"};
    for (size_t k = 0; k < sizeof pictures / sizeof pictures[0]; ++k) {
        long size = file_size(folder, pictures[k]);
        TEST_TRUE(size > MINIMUM_BYTES);
        if (size <= MINIMUM_BYTES)
            fprintf(stderr, "%s: %ld bytes\n", pictures[k], size);
    }
    /* The fixed entry does not move: no curve for it. */
    TEST_TRUE(file_size(folder, "plots/load_settlement_bottom.png") < 0);
    TEST_TRUE(file_size(folder, "pictures/damage_frame_0001.png") < 0);

    /* again on 4 frames: the earlier run's pictures and plots go, files
     * post does not name stay */
    static const char *const foreign[] = {"pictures/notes.png",
                                          "pictures/damage_frame_0006.png.txt",
                                          "plots/energy_by_hand.png"};
    for (size_t k = 0; k < sizeof foreign / sizeof foreign[0]; ++k)
        touch(folder, foreign[k]);
    touch(folder, "plots/load_settlement_gone.png");
    TEST_INT(synthetic_folder_write(folder, FEWER_FRAMES, "box_case"), GSN_OK);
    rc = gsn_post_run(folder, &options);
    TEST_INT(rc, GSN_OK);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    static const char *const kept[] = {
        "pictures/damage_frame_0000.png",   "pictures/damage_frame_0001.png",
        "pictures/damage_frame_0002.png",   "pictures/damage_frame_0003.png",
        "pictures/clip_ux_frame_0003.png",  "plots/energy.png",
        "plots/load_settlement_footing.png"};
    for (size_t k = 0; k < sizeof kept / sizeof kept[0]; ++k)
        TEST_TRUE(file_size(folder, kept[k]) > MINIMUM_BYTES);
    static const char *const gone[] = {
        "pictures/damage_frame_0005.png",
        "pictures/damage_frame_0006.png",
        "pictures/clip_ux_frame_0006.png",
        "pictures/clip_uy_frame_0006.png",
        "pictures/clip_uz_frame_0006.png",
        "pictures/clip_equivalent_stress_frame_0006.png",
        "pictures/clip_displacement_frame_0006.png",
        "pictures/clip_equivalent_plastic_strain_frame_0006.png",
        "plots/load_settlement_gone.png"};
    for (size_t k = 0; k < sizeof gone / sizeof gone[0]; ++k) {
        TEST_TRUE(file_size(folder, gone[k]) < 0);
        if (file_size(folder, gone[k]) >= 0)
            fprintf(stderr, "%s: left from the earlier run\n", gone[k]);
    }
    for (size_t k = 0; k < sizeof foreign / sizeof foreign[0]; ++k)
        TEST_TRUE(file_size(folder, foreign[k]) == 0);
    char command[GSN_PATH_SIZE + 16];
    snprintf(command, sizeof command, "rm -rf '%s'", root);
    if (!test_failures && !getenv("GEOSCNI_KEEP_TEST_OUTPUT"))
        TEST_INT(system(command), 0);
    else
        fprintf(stderr, "output kept in %s\n", root);
    return test_end("test_post_pictures");
}
