/* post: the driver. Reads OUTDIR/model.h5 (reference positions and
 * tetrahedra) and OUTDIR/results.h5 one frame at a time, so memory stays
 * bounded by one frame, and writes OUTDIR/vtu/frame_NNNN.vtu, OUTDIR/CASE.pvd,
 * the pictures in OUTDIR/pictures/ and, from OUTDIR/history.csv, the plots in
 * OUTDIR/plots/ (DESIGN.md, "What a run leaves"). Every file is written under
 * a temporary name and renamed when complete (files.h). */
#include "geoscni/post.h"
#include "display.h"
#include "history.h"
#include "vtk_output.h"

#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/h5io.h"
#include "geoscni/model.h"
#include "geoscni/results.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum {
    PICTURE_FRAMES = 5, /* damage pictures: first, 3 evenly spaced, last */
    CASE_NAME_SIZE = 128,
    TITLE_SIZE = 256
};

/* What post needs of model.h5: reference positions and the tetrahedra. */
struct post_mesh {
    int point_count;
    double *reference; /* point_count x 3, m */
    int tetrahedron_count;
    int *tetrahedra;  /* tetrahedron_count x 4 */
    double bounds[6]; /* of the reference positions, m */
    /* the site (post_site_fields): each tetrahedron's physical volume
     * (its index) with the volumes' names, and each point's pore pressure
     * (Pa) at X; NULL without layers, water */
    int *volume, volume_count;
    char (*volume_name)[GSN_H5_STRING_SIZE];
    double *pore_pressure, *water_head; /* water_head: the table's height
                                           above the point, m (negative
                                           above the table) */
};

static void post_mesh_free(struct post_mesh *mesh)
{
    free(mesh->reference);
    free(mesh->tetrahedra);
    free(mesh->volume);
    free(mesh->volume_name);
    free(mesh->pore_pressure);
    free(mesh->water_head);
    memset(mesh, 0, sizeof *mesh);
}

static int post_mesh_read_file(hid_t file, const char *path,
                               struct post_mesh *mesh)
{
    const struct gsn_dataset_info *position =
        &gsn_model_datasets[GSN_MODEL_POSITION];
    const struct gsn_dataset_info *tetrahedra =
        &gsn_model_datasets[GSN_MODEL_TETRAHEDRA];
    size_t points = 0, cells = 0;
    GSN_CALL(gsn_h5_require(file, position, 1));
    GSN_CALL(gsn_h5_require(file, tetrahedra, 1));
    GSN_CALL(gsn_h5_rows(file, position, &points));
    GSN_CALL(gsn_h5_rows(file, tetrahedra, &cells));
    GSN_CHECK(points > 0 && points < (1u << 30) && cells < (1u << 29),
              GSN_ERR_INPUT,
              "%s: %zu particles and %zu tetrahedra: empty or "
              "too large a model",
              path, points, cells);
    mesh->point_count = (int)points;
    mesh->tetrahedron_count = (int)cells;
    mesh->reference = malloc(3 * points * sizeof(double));
    mesh->tetrahedra = malloc((4 * cells + 1) * sizeof(int));
    GSN_CHECK(mesh->reference && mesh->tetrahedra, GSN_ERR_MEMORY,
              "cannot allocate the mesh of %zu particles", points);
    GSN_CALL(gsn_h5_read(file, position, points, mesh->reference));
    GSN_CALL(gsn_h5_read(file, tetrahedra, cells, mesh->tetrahedra));
    for (size_t k = 0; k < 4 * cells; ++k)
        GSN_CHECK(mesh->tetrahedra[k] >= 0 && mesh->tetrahedra[k] < (int)points,
                  GSN_ERR_INPUT,
                  "%s: mesh/tetrahedra[%zu] = %d is not a particle index "
                  "(%zu particles); the file is damaged, run pre again",
                  path, k, mesh->tetrahedra[k], points);
    for (int j = 0; j < 3; ++j) {
        mesh->bounds[2 * j] = HUGE_VAL;
        mesh->bounds[2 * j + 1] = -HUGE_VAL;
    }
    for (size_t i = 0; i < points; ++i)
        for (int j = 0; j < 3; ++j) {
            double x = mesh->reference[3 * i + j];
            GSN_CHECK(isfinite(x), GSN_ERR_INPUT,
                      "%s: particle %zu has a non-finite position", path, i);
            mesh->bounds[2 * j] = fmin(mesh->bounds[2 * j], x);
            mesh->bounds[2 * j + 1] = fmax(mesh->bounds[2 * j + 1], x);
        }
    return GSN_OK;
}

static int post_mesh_read(const char *path, struct post_mesh *mesh)
{
    memset(mesh, 0, sizeof *mesh);
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(path, GSN_FILE_KIND_MODEL, 0, &file));
    int rc = post_mesh_read_file(file, path, mesh);
    gsn_h5_close(&file);
    if (rc != GSN_OK) {
        post_mesh_free(mesh);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "post_mesh_read_file(file, path, mesh)");
    }
    return GSN_OK;
}

/* ---- mirror of a half model (output.mirror, docs/economy.md) ----------- */

/* The reflection across the plane x_axis = offset: point i of the half
 * model has the image image[i] (i itself on the plane, else a new point
 * after the half model's). */
struct post_mirror {
    int active;
    int axis;
    double offset;  /* m */
    int half_count; /* particles of the half model (of results.h5) */
    int *image;     /* half_count */
};

static void post_mirror_free(struct post_mirror *mirror)
{
    free(mirror->image);
    memset(mirror, 0, sizeof *mirror);
}

static void post_mesh_bounds(struct post_mesh *mesh)
{
    for (int j = 0; j < 3; ++j) {
        mesh->bounds[2 * j] = HUGE_VAL;
        mesh->bounds[2 * j + 1] = -HUGE_VAL;
    }
    for (int i = 0; i < mesh->point_count; ++i)
        for (int j = 0; j < 3; ++j) {
            double x = mesh->reference[3 * i + j];
            mesh->bounds[2 * j] = fmin(mesh->bounds[2 * j], x);
            mesh->bounds[2 * j + 1] = fmax(mesh->bounds[2 * j + 1], x);
        }
}

/* The plane of surface `name` (gsn_model_surface_plane) and the particles
 * on it, from model.h5. */
static int post_mirror_plane(const char *model_path, const char *name,
                             struct post_mirror *mirror, char **on_plane)
{
    struct gsn_model model;
    memset(&model, 0, sizeof model);
    GSN_CALL(gsn_model_read(model_path, &model));
    int rc = GSN_OK;
    int surface = gsn_model_find_surface(&model, name);
    GSN_CHECK_GOTO(surface >= 0, rc, GSN_ERR_INPUT, done,
                   "output.mirror: '%s' is not a surface of %s", name,
                   model_path);
    GSN_CALL_GOTO(gsn_model_surface_plane(&model, surface, &mirror->axis,
                                          &mirror->offset),
                  rc, done);
    *on_plane = calloc((size_t)model.particle_count + 1, 1);
    GSN_CHECK_GOTO(*on_plane, rc, GSN_ERR_MEMORY, done, "out of memory");
    for (int p = 0; p < model.particle_count; ++p)
        (*on_plane)[p] =
            (char)gsn_model_particle_on_surface(&model, p, surface);
done:
    gsn_model_free(&model);
    return rc;
}

/* Extends the mesh by its reflection across the plane of surface `name`:
 * particles on the plane are shared, the others get an image, and every
 * tetrahedron a reflected twin (two vertices swapped: positive volume). */
static int post_mirror_create(const char *model_path, const char *name,
                              struct post_mesh *mesh,
                              struct post_mirror *mirror)
{
    char *on_plane = NULL;
    GSN_CALL(post_mirror_plane(model_path, name, mirror, &on_plane));
    int n = mesh->point_count, t = mesh->tetrahedron_count, rc = GSN_OK;
    mirror->half_count = n;
    mirror->image = malloc(sizeof(int) * ((size_t)n + 1));
    GSN_CHECK_GOTO(mirror->image, rc, GSN_ERR_MEMORY, done, "out of memory");
    int total = n;
    for (int i = 0; i < n; ++i)
        mirror->image[i] = on_plane[i] ? i : total++;
    double *reference = realloc(mesh->reference, sizeof(double) * 3 * total);
    GSN_CHECK_GOTO(reference, rc, GSN_ERR_MEMORY, done, "out of memory");
    mesh->reference = reference;
    int *tetrahedra = realloc(mesh->tetrahedra, sizeof(int) * 8 * (size_t)t);
    GSN_CHECK_GOTO(tetrahedra, rc, GSN_ERR_MEMORY, done, "out of memory");
    mesh->tetrahedra = tetrahedra;
    for (int i = 0; i < n; ++i) {
        double *x = &reference[3 * mirror->image[i]];
        memcpy(x, &reference[3 * i], sizeof(double[3]));
        x[mirror->axis] = 2.0 * mirror->offset - x[mirror->axis];
    }
    static const int order[4] = {0, 1, 3, 2};
    for (size_t e = 0; e < (size_t)t; ++e)
        for (int k = 0; k < 4; ++k)
            tetrahedra[4 * ((size_t)t + e) + k] =
                mirror->image[tetrahedra[4 * e + order[k]]];
    mesh->point_count = total;
    mesh->tetrahedron_count = 2 * t;
    post_mesh_bounds(mesh);
    mirror->active = 1;
done:
    free(on_plane);
    return rc;
}

/* The whole body's frame from the half model's: images get the reflected
 * fields (signs: vector component `axis` and the shear stresses
 * with exactly one index `axis` change sign; scalars are even). */
static void post_mirror_frame(const struct post_mirror *mirror,
                              const struct gsn_frame *in, struct gsn_frame *out)
{
    static const int voigt_pair[6][2] = {{0, 0}, {1, 1}, {2, 2},
                                         {0, 1}, {1, 2}, {0, 2}};
    int a = mirror->axis;
    out->time = in->time;
    out->step = in->step;
    out->present = in->present;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f) {
        int columns = gsn_frame_fields[f].columns;
        double sign[6];
        for (int k = 0; k < columns; ++k) {
            if (columns == 3)
                sign[k] = k == a ? -1.0 : 1.0;
            else if (columns == 6)
                sign[k] = (voigt_pair[k][0] == a) != (voigt_pair[k][1] == a)
                              ? -1.0
                              : 1.0;
            else
                sign[k] = 1.0;
        }
        for (int i = 0; i < mirror->half_count; ++i) {
            const double *v = &in->field[f][(size_t)columns * i];
            memcpy(&out->field[f][(size_t)columns * i], v,
                   sizeof(double) * columns);
            double *w = &out->field[f][(size_t)columns * mirror->image[i]];
            if (mirror->image[i] != i)
                for (int k = 0; k < columns; ++k)
                    w[k] = sign[k] * v[k];
        }
    }
}

/* The case name: the results' "case_name" attribute, else the folder's
 * name; characters unsafe in a file name become '_'. */
static int post_case_name(hid_t results, const char *outdir, char *name,
                          size_t size)
{
    char *stored = NULL;
    if (H5Aexists(results, GSN_RESULTS_ATTR_CASE_NAME) > 0)
        GSN_CALL(gsn_h5_attr_read_string(results, GSN_RESULTS_ATTR_CASE_NAME,
                                         &stored));
    if (stored && *stored) {
        snprintf(name, size, "%s", stored);
    } else {
        size_t length = strlen(outdir);
        while (length > 1 && outdir[length - 1] == '/')
            --length;
        size_t start = length;
        while (start > 0 && outdir[start - 1] != '/')
            --start;
        snprintf(name, size, "%.*s", (int)(length - start), outdir + start);
    }
    free(stored);
    for (char *c = name; *c; ++c)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                    "0123456789._-",
                    *c))
            *c = '_';
    if (!*name || !strcmp(name, ".") || !strcmp(name, ".."))
        snprintf(name, size, "case");
    return GSN_OK;
}

/* The resolved case stored in results.h5, loaded with the case reader. Its
 * geometry is not needed here and may have moved: the geometry line is
 * pointed at the temporary copy itself, which exists. 0 if unavailable. */
static int post_case_load(hid_t results, struct gsn_case *c)
{
    char *yaml = NULL;
    if (H5Aexists(results, GSN_ATTR_CASE) <= 0)
        return 0;
    if (gsn_h5_attr_read_string(results, GSN_ATTR_CASE, &yaml) != GSN_OK) {
        gsn_error_clear();
        return 0;
    }
    char path[] = "/tmp/geoscni-post-case-XXXXXX";
    int fd = mkstemp(path);
    FILE *file = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!file) {
        if (fd >= 0)
            close(fd);
        free(yaml);
        return 0;
    }
    const char *base = strrchr(path, '/') + 1;
    for (char *line = yaml; line && *line;) {
        char *end = strchr(line, '\n');
        size_t length = end ? (size_t)(end - line) + 1 : strlen(line);
        if (strncmp(line, "geometry:", 9) == 0)
            fprintf(file, "geometry: '%s'\n", base);
        else
            fwrite(line, 1, length, file);
        line += length;
    }
    free(yaml);
    int ok = fclose(file) == 0 && gsn_case_load(path, c) == GSN_OK;
    if (!ok)
        gsn_error_clear();
    unlink(path);
    return ok;
}

static int post_frame_path(const char *outdir, int index, char *path,
                           size_t size)
{
    int n = snprintf(path, size, "%s/vtu/frame_%04d.vtu", outdir, index);
    GSN_CHECK(n > 0 && (size_t)n < size, GSN_ERR_INPUT, "path too long: %s",
              outdir);
    return GSN_OK;
}

static int post_vtu_write(const struct gsn_vtk_grid *grid, const char *path)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    int rc = gsn_vtk_grid_write(grid, temporary);
    if (rc == GSN_OK)
        rc = gsn_file_commit(path);
    if (rc != GSN_OK) {
        gsn_file_discard(path);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "gsn_vtk_grid_write(grid, temporary)");
    }
    return GSN_OK;
}

static int post_picture_write(const struct gsn_vtk_grid *grid,
                              enum gsn_vtk_picture picture,
                              const double bounds[6], const char *title,
                              const char *path)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    int rc = gsn_vtk_grid_render(grid, picture, bounds, title, temporary);
    if (rc == GSN_OK)
        rc = gsn_file_commit(path);
    if (rc != GSN_OK) {
        gsn_file_discard(path);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "gsn_vtk_grid_render(...)");
    }
    return GSN_OK;
}

/* The damage pictures' frames: first, evenly spaced, last. */
static int post_is_picture_frame(int index, int count)
{
    if (count <= PICTURE_FRAMES)
        return 1;
    for (int k = 0; k < PICTURE_FRAMES; ++k)
        if (index ==
            (int)lround((double)k * (count - 1) / (PICTURE_FRAMES - 1)))
            return 1;
    return 0;
}

/* 1 if the frame holds the field the picture shows; else 0, with a note
 * the first time (bit picture of *noted). */
static int post_picture_drawable(const struct gsn_frame *frame,
                                 enum gsn_vtk_picture picture, unsigned *noted)
{
    int field = gsn_vtk_picture_field(picture);
    if (frame->present & (1u << field))
        return 1;
    if (!(*noted & (1u << picture)))
        fprintf(stderr,
                "geoscni post: note: no %s pictures: the results hold no "
                "'%s' (output.fields)\n",
                picture == GSN_VTK_PICTURE_DAMAGE ? "damage" : "clip",
                gsn_frame_fields[field].path);
    *noted |= 1u << picture;
    return 0;
}

/* The clipped-half pictures, each in pictures/FILE_frame_NNNN.png. */
static const struct {
    enum gsn_vtk_picture picture;
    const char *file, *what;
} clips[] = {
    {GSN_VTK_PICTURE_CLIP_UX, "clip_ux", "u_x"},
    {GSN_VTK_PICTURE_CLIP_UY, "clip_uy", "u_y"},
    {GSN_VTK_PICTURE_CLIP_UZ, "clip_uz", "u_z"},
    {GSN_VTK_PICTURE_CLIP_EQUIVALENT_STRESS, "clip_equivalent_stress",
     "equivalent stress"},
    {GSN_VTK_PICTURE_CLIP_DISPLACEMENT, "clip_displacement", "|u|"},
    {GSN_VTK_PICTURE_CLIP_EQUIVALENT_PLASTIC_STRAIN,
     "clip_equivalent_plastic_strain", "equivalent plastic strain"},
};

/* The site's pictures, on the body at the last frame: the layers (with the
 * water table) and the pore pressure, where the model has them. */
static const struct {
    enum gsn_vtk_picture picture;
    const char *file, *what;
} sites[] = {
    {GSN_VTK_PICTURE_LAYERS, "layers", "the physical volumes (layers)"},
    {GSN_VTK_PICTURE_PORE_PRESSURE, "pore_pressure",
     "the water table's pore pressure"},
};

/* Picture `file` of frame index in folder (FILE_frame_NNNN.png), counted
 * in *written. */
static int post_frame_picture(const struct gsn_vtk_grid *grid,
                              enum gsn_vtk_picture picture,
                              const double bounds[6], const char *folder,
                              const char *file, int index, const char *title,
                              int *written)
{
    char path[GSN_PATH_SIZE];
    int n = snprintf(path, sizeof path, "%s/%s_frame_%04d.png", folder, file,
                     index);
    GSN_CHECK(n > 0 && (size_t)n < sizeof path, GSN_ERR_INPUT,
              "path too long: %s", folder);
    GSN_CALL(post_picture_write(grid, picture, bounds, title, path));
    ++*written;
    return GSN_OK;
}

/* Renders the pictures of a frame: damage on the body at the chosen frames;
 * u_x, u_y, u_z and equivalent stress on the clipped half at the last. */
static int post_frame_pictures(const struct gsn_vtk_grid *grid,
                               const struct post_mesh *mesh,
                               const struct gsn_frame *frame, int index,
                               int count, const char *folder,
                               const char *case_name, int *written,
                               unsigned *noted)
{
    char title[TITLE_SIZE];
    if (post_is_picture_frame(index, count) &&
        post_picture_drawable(frame, GSN_VTK_PICTURE_DAMAGE, noted)) {
        snprintf(title, sizeof title, "%s: damage at t = %.6g s", case_name,
                 frame->time);
        GSN_CALL(post_frame_picture(grid, GSN_VTK_PICTURE_DAMAGE, mesh->bounds,
                                    folder, "damage", index, title, written));
    }
    if (index != count - 1)
        return GSN_OK;
    const void *values[] = {mesh->volume, mesh->pore_pressure};
    for (size_t k = 0; k < sizeof sites / sizeof sites[0]; ++k) {
        if (!values[k])
            continue;
        snprintf(title, sizeof title, "%s: %s, t = %.6g s", case_name,
                 sites[k].what, frame->time);
        GSN_CALL(post_frame_picture(grid, sites[k].picture, mesh->bounds,
                                    folder, sites[k].file, index, title,
                                    written));
    }
    double middle = 0.5 * (mesh->bounds[2] + mesh->bounds[3]);
    for (size_t k = 0; k < sizeof clips / sizeof clips[0]; ++k) {
        if (!post_picture_drawable(frame, clips[k].picture, noted))
            continue;
        snprintf(title, sizeof title,
                 "%s: %s on the half y >= %.4g m, t = %.6g s", case_name,
                 clips[k].what, middle, frame->time);
        GSN_CALL(post_frame_picture(grid, clips[k].picture, mesh->bounds,
                                    folder, clips[k].file, index, title,
                                    written));
    }
    return GSN_OK;
}

/* The .pvd collection: each frame's file and time. */
/* The .pvd's second line: what post made it from (post_stamp), so that run
 * can tell whether post is up to date by the contents of results.h5. */
#define PVD_STAMP_START "<!-- geoscni post: "
#define PVD_STAMP_END " -->"

static void post_stamp(const char *results_hash, int pictures, char *out,
                       size_t size)
{
    snprintf(out, size, "made from results.h5 %s, pictures %s", results_hash,
             pictures ? "yes" : "no");
}

static int post_pvd_write(const char *path, hid_t results, int count,
                          const char *stamp)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    FILE *file = fopen(temporary, "w");
    if (!file)
        return GSN_WRITE_ERROR(temporary, errno, "cannot create");
    int rc = GSN_OK;
    fprintf(file,
            "<?xml version=\"1.0\"?>\n" PVD_STAMP_START "%s" PVD_STAMP_END
            "\n<VTKFile type=\"Collection\" version=\"0.1\" "
            "byte_order=\"LittleEndian\">\n  <Collection>\n",
            stamp);
    for (int k = 0; k < count; ++k) {
        char group_name[64];
        snprintf(group_name, sizeof group_name, GSN_FRAME_GROUP_FORMAT, k);
        hid_t group = H5I_INVALID_HID;
        GSN_CALL_GOTO(
            gsn_h5_group_open(results, group_name, "frame group", &group), rc,
            done);
        double time = 0.0;
        rc = gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, &time);
        gsn_h5_close(&group);
        GSN_CALL_GOTO(rc, rc, done);
        fprintf(file,
                "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" "
                "file=\"vtu/frame_%04d.vtu\"/>\n",
                time, k);
    }
    fprintf(file, "  </Collection>\n</VTKFile>\n");
done:
    if ((fflush(file) != 0 || ferror(file)) && rc == GSN_OK)
        rc = GSN_WRITE_ERROR(temporary, errno, "cannot write");
    if (fclose(file) != 0 && rc == GSN_OK)
        rc = GSN_WRITE_ERROR(temporary, errno, "cannot write");
    if (rc == GSN_OK)
        rc = gsn_file_commit(path);
    if (rc != GSN_OK) {
        gsn_file_discard(path);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "post_pvd_write");
    }
    return GSN_OK;
}

static int post_chart_write(const char *path, const char *title,
                            const char *x_label, const char *y_label,
                            int series_count, const char *const *names,
                            const int *counts, const double *const *x,
                            const double *const *y,
                            const struct gsn_chart_style *style)
{
    char temporary[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_temporary(temporary, sizeof temporary, path));
    int rc = gsn_vtk_chart_write(temporary, title, x_label, y_label,
                                 series_count, names, counts, x, y, style);
    if (rc == GSN_OK)
        rc = gsn_file_commit(path);
    if (rc != GSN_OK) {
        gsn_file_discard(path);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "gsn_vtk_chart_write(...)");
    }
    return GSN_OK;
}

/* The load-settlement curve of a moving boundary entry: the force on the
 * body through it along its prescribed velocity against the mean
 * displacement of its particles along it, both signed (a footing pushed
 * down plots up; where it holds the body back, as under gravity, the force
 * is negative and drawn so). */
static int post_load_settlement(const struct gsn_history *history,
                                const struct gsn_boundary *b, double factor,
                                const char *case_name, const char *path,
                                double *x, double *y, int *written)
{
    double direction[3];
    if (!gsn_boundary_motion(b, direction))
        return GSN_OK; /* does not move */
    GSN_CALL(
        gsn_history_motion_curve(history, b->name, direction, factor, x, y));
    char title[TITLE_SIZE], x_label[TITLE_SIZE], y_label[TITLE_SIZE];
    snprintf(title, sizeof title, "%s: load-settlement of '%s'%s", case_name,
             b->name,
             factor == 2.0 ? " (whole body: twice the half model's force)"
                           : "");
    snprintf(x_label, sizeof x_label,
             "mean displacement of '%s' along its motion [m]", b->name);
    snprintf(y_label, sizeof y_label,
             "force on the body along the motion, signed [kN]");
    const char *names[1] = {b->name};
    const double *xs[1] = {x}, *ys[1] = {y};
    GSN_CALL(post_chart_write(path, title, x_label, y_label, 1, names,
                              &history->row_count, xs, ys, NULL));
    ++*written;
    return GSN_OK;
}

/* The energies against time, in J, kJ or MJ by their size. */
static int post_energies(const struct gsn_history *history,
                         const char *case_name, const char *path,
                         double *values, int *written)
{
    static const char *const columns[3] = {"kinetic_energy", "internal_energy",
                                           "external_work"};
    static const char *const names[3] = {"kinetic energy", "internal energy",
                                         "external work"};
    int time_column = gsn_history_column(history, "time");
    GSN_CHECK(time_column >= 0, GSN_ERR_INPUT,
              "history.csv lacks the column 'time'");
    int n = history->row_count;
    double *time = values, *energy[3];
    gsn_history_copy_column(history, time_column, time);
    double largest = 0.0;
    for (int k = 0; k < 3; ++k) {
        int c = gsn_history_column(history, columns[k]);
        GSN_CHECK(c >= 0, GSN_ERR_INPUT, "history.csv lacks the column '%s'",
                  columns[k]);
        energy[k] = values + (size_t)(k + 1) * n;
        gsn_history_copy_column(history, c, energy[k]);
        for (int r = 0; r < n; ++r)
            largest = fmax(largest, fabs(energy[k][r]));
    }
    double scale = 1.0;
    const char *unit = "J";
    if (largest >= 1e6) {
        scale = 1e-6;
        unit = "MJ";
    } else if (largest >= 1e3) {
        scale = 1e-3;
        unit = "kJ";
    }
    for (int k = 0; k < 3; ++k)
        for (int r = 0; r < n; ++r)
            energy[k][r] *= scale;
    char title[TITLE_SIZE], y_label[TITLE_SIZE];
    snprintf(title, sizeof title, "%s: energies", case_name);
    snprintf(y_label, sizeof y_label, "energy [%s]", unit);
    const int counts[3] = {n, n, n};
    const double *xs[3] = {time, time, time};
    const double *ys[3] = {energy[0], energy[1], energy[2]};
    GSN_CALL(post_chart_write(path, title, "time [s]", y_label, 3, names,
                              counts, xs, ys, NULL));
    ++*written;
    return GSN_OK;
}

/* The plots from history.csv. A missing history is noted, not an error. */
static int post_plots(const char *outdir, const struct gsn_case *c,
                      int have_case, const char *case_name, int *written)
{
    char path[GSN_PATH_SIZE], folder[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "history.csv"));
    if (access(path, F_OK) != 0) {
        fprintf(stderr, "geoscni post: no plots: %s not found\n", path);
        return GSN_OK;
    }
    struct gsn_history history;
    GSN_CALL(gsn_history_read(path, &history));
    int rc = GSN_OK;
    double *values = NULL;
    if (history.row_count < 2) { /* a curve needs two points */
        fprintf(stderr, "geoscni post: no plots: %s has %d row%s\n", path,
                history.row_count, history.row_count == 1 ? "" : "s");
        goto done;
    }
    values = malloc(4 * (size_t)history.row_count * sizeof(double));
    GSN_CHECK_GOTO(values != NULL, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %d history rows", history.row_count);
    GSN_CALL_GOTO(gsn_path_join(folder, sizeof folder, outdir, "plots"), rc,
                  done);
    GSN_CALL_GOTO(gsn_folder_prepare(folder), rc, done);
    GSN_CALL_GOTO(gsn_path_join(path, sizeof path, folder, "energy.png"), rc,
                  done);
    GSN_CALL_GOTO(post_energies(&history, case_name, path, values, written), rc,
                  done);
    if (!have_case) {
        fprintf(stderr,
                "geoscni post: no load-settlement plots: the resolved case "
                "in results.h5 could not be read\n");
        goto done;
    }
    for (int b = 0; b < c->boundary_count; ++b) {
        char name[GSN_PATH_SIZE];
        snprintf(name, sizeof name, "load_settlement_%s.png",
                 c->boundaries[b].name);
        GSN_CALL_GOTO(gsn_path_join(path, sizeof path, folder, name), rc, done);
        /* a model mirrored across a symmetry plane carries half the load
         * of the whole body: the plot shows the whole body's */
        double factor = c->output_mirror[0] ? 2.0 : 1.0;
        GSN_CALL_GOTO(post_load_settlement(&history, &c->boundaries[b], factor,
                                           case_name, path, values,
                                           values + history.row_count, written),
                      rc, done);
    }
done:
    free(values);
    gsn_history_free(&history);
    return rc;
}

/* Removes the frame files a longer earlier run left beyond count. */
static void post_remove_stale_frames(const char *outdir, int count)
{
    char path[GSN_PATH_SIZE];
    for (int k = count;; ++k) {
        if (post_frame_path(outdir, k, path, sizeof path) != GSN_OK) {
            gsn_error_clear();
            return;
        }
        if (unlink(path) != 0)
            return;
    }
}

/* 1 if name is a picture post writes: damage_frame_NNNN.png or
 * clip_*_frame_NNNN.png in pictures/ (plots 0), energy.png or
 * load_settlement_*.png in plots/ (plots 1). */
static int post_owns_picture(const char *name, int plots)
{
    size_t length = strlen(name);
    if (length < 4 || strcmp(name + length - 4, ".png") != 0)
        return 0;
    if (plots)
        return strcmp(name, "energy.png") == 0 ||
               strncmp(name, "load_settlement_", 16) == 0;
    const char *rest = NULL;
    if (strncmp(name, "damage", 6) == 0)
        rest = name + 6;
    for (size_t k = 0; !rest && k < sizeof clips / sizeof clips[0]; ++k)
        if (strncmp(name, clips[k].file, strlen(clips[k].file)) == 0)
            rest = name + strlen(clips[k].file);
    for (size_t k = 0; !rest && k < sizeof sites / sizeof sites[0]; ++k)
        if (strncmp(name, sites[k].file, strlen(sites[k].file)) == 0)
            rest = name + strlen(sites[k].file);
    if (!rest || strncmp(rest, "_frame_", 7) != 0)
        return 0;
    rest += 7;
    size_t digits = strspn(rest, "0123456789");
    return digits >= 4 && strcmp(rest + digits, ".png") == 0;
}

/* Removes the pictures (plots 0) or plots (plots 1) an earlier run left in
 * folder, so that it holds this run's only; other files stay. */
static int post_remove_old_pictures(const char *folder, int plots)
{
    DIR *directory = opendir(folder);
    if (!directory && errno == ENOENT)
        return GSN_OK;
    GSN_CHECK(directory != NULL, GSN_ERR_IO, "cannot read the folder %s: %s",
              folder, strerror(errno));
    int rc = GSN_OK;
    for (struct dirent *entry = readdir(directory); entry && rc == GSN_OK;
         entry = readdir(directory)) {
        if (!post_owns_picture(entry->d_name, plots))
            continue;
        char path[GSN_PATH_SIZE];
        rc = gsn_path_join(path, sizeof path, folder, entry->d_name);
        if (rc == GSN_OK && unlink(path) != 0 && errno != ENOENT)
            rc = gsn_error_raise(GSN_ERR_IO, __FILE__, __LINE__, __func__,
                                 "cannot remove %s, a picture of an earlier "
                                 "run: %s; remove it or make the folder "
                                 "writable",
                                 path, strerror(errno));
    }
    closedir(directory);
    return rc;
}

/* A results.h5.part beside (or instead of) results.h5 is the newest run,
 * stopped while it wrote it (killed: the lock of the folder says no solve
 * runs now): post refuses it and says how to finish it. */
static int post_refuse_partial(const char *outdir, const char *results_path)
{
    char part[GSN_PATH_SIZE], where[128] = "";
    GSN_CALL(gsn_path_temporary(part, sizeof part, results_path));
    if (access(part, F_OK) != 0)
        return GSN_OK;
    hid_t file = H5I_INVALID_HID, group = H5I_INVALID_HID;
    int step = 0;
    double time = 0.0;
    if (gsn_h5_open(part, GSN_FILE_KIND_RESULTS, 0, &file) == GSN_OK &&
        gsn_h5_exists(file, GSN_CHECKPOINT_GROUP) &&
        (group = H5Gopen2(file, GSN_CHECKPOINT_GROUP, H5P_DEFAULT)) >= 0 &&
        gsn_h5_attr_read_int(group, GSN_FRAME_ATTR_STEP, &step) == GSN_OK &&
        gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, &time) == GSN_OK)
        snprintf(where, sizeof where,
                 " (its last checkpoint: step %d, t = %g s)", step, time);
    if (group >= 0)
        H5Gclose(group);
    gsn_h5_close(&file);
    gsn_error_clear();
    GSN_CHECK(0, GSN_ERR_INPUT,
              "%s: the results are incomplete: the solve that wrote them "
              "stopped before its end without finishing the file (killed)%s%s; "
              "continue it with 'geoscni run CASE.yaml -o %s --restart', or "
              "start over with 'geoscni run CASE.yaml -o %s --rerun'",
              part, where,
              access(results_path, F_OK) == 0
                  ? ", and results.h5 beside it is an older run's"
                  : "",
              outdir, outdir);
    return GSN_OK;
}

/* A warning when results.h5 holds a run that did not reach its end
 * (interrupted, or stopped by a numerical failure): post writes its frames,
 * and says so. */
static void post_note_incomplete(hid_t results, const char *path,
                                 const struct gsn_case *c, int have_case,
                                 int count)
{
    int complete = 1, interrupted = 0;
    if (gsn_h5_attr_read_int(results, GSN_RESULTS_ATTR_COMPLETE, &complete) !=
            GSN_OK ||
        complete) {
        gsn_error_clear();
        return;
    }
    if (H5Aexists(results, GSN_RESULTS_ATTR_INTERRUPTED) > 0 &&
        gsn_h5_attr_read_int(results, GSN_RESULTS_ATTR_INTERRUPTED,
                             &interrupted) != GSN_OK)
        interrupted = 0;
    double last = 0.0;
    char group_name[64], end[64] = "";
    snprintf(group_name, sizeof group_name, GSN_FRAME_GROUP_FORMAT, count - 1);
    hid_t group = H5Gopen2(results, group_name, H5P_DEFAULT);
    if (group < 0 ||
        gsn_h5_attr_read_double(group, GSN_FRAME_ATTR_TIME, &last) != GSN_OK)
        last = NAN;
    if (group >= 0)
        H5Gclose(group);
    gsn_error_clear();
    if (have_case)
        snprintf(end, sizeof end, " of its %g s", c->time_end);
    fprintf(stderr,
            "geoscni post: warning: %s is incomplete: its run %s before its "
            "end%s; post writes the %d frames it has, to t = %g s%s\n",
            path,
            interrupted ? "was interrupted" : "stopped (a numerical failure)",
            end, count, last,
            interrupted ? " (continue the run with --restart, then post again)"
                        : "");
}

/* The site's fields (mirrored ones too): the physical volume of each
 * tetrahedron with the volumes' names (model.h5, when it has layers: two
 * volumes or more) and the water table's pore pressure at each point's
 * reference position (the case's water:). */
static int post_site_fields(const char *model_path, const struct gsn_case *c,
                            int have_case, const struct post_mirror *mirror,
                            struct post_mesh *mesh)
{
    const struct gsn_dataset_info *names =
        &gsn_model_datasets[GSN_MODEL_VOLUME_NAME];
    const struct gsn_dataset_info *owner =
        &gsn_model_datasets[GSN_MODEL_TETRAHEDRON_VOLUME];
    int n = mesh->point_count, rc = GSN_OK;
    size_t t = (size_t)mesh->tetrahedron_count / (mirror->active ? 2 : 1);
    size_t volumes = 0, rows = 0;
    hid_t file = H5I_INVALID_HID;
    GSN_CALL(gsn_h5_open(model_path, GSN_FILE_KIND_MODEL, 0, &file));
    GSN_CALL_GOTO(gsn_h5_rows(file, names, &volumes), rc, done);
    if (volumes > 1) {
        GSN_CALL_GOTO(gsn_h5_rows(file, owner, &rows), rc, done);
        GSN_CHECK_GOTO(rows == t && volumes < 256, rc, GSN_ERR_INPUT, done,
                       "%s: %s has %zu rows for %zu tetrahedra; run pre "
                       "again",
                       model_path, owner->path, rows, t);
        mesh->volume = malloc(sizeof(int) * (2 * t + 1));
        mesh->volume_name = calloc(volumes, sizeof *mesh->volume_name);
        GSN_CHECK_GOTO(mesh->volume && mesh->volume_name, rc, GSN_ERR_MEMORY,
                       done, "out of memory");
        GSN_CALL_GOTO(gsn_h5_read(file, owner, rows, mesh->volume), rc, done);
        GSN_CALL_GOTO(gsn_h5_read(file, names, volumes, mesh->volume_name), rc,
                      done);
        mesh->volume_count = (int)volumes;
        for (size_t v = 0; v < volumes; ++v)
            mesh->volume_name[v][GSN_H5_STRING_SIZE - 1] = '\0';
        for (size_t e = 0; e < t; ++e) {
            GSN_CHECK_GOTO(mesh->volume[e] >= -1 &&
                               mesh->volume[e] < (int)volumes,
                           rc, GSN_ERR_INPUT, done,
                           "%s: %s[%zu] = %d is out of range; run pre again",
                           model_path, owner->path, e, mesh->volume[e]);
            if (mirror->active)
                mesh->volume[t + e] = mesh->volume[e];
        }
    }
    if (have_case && c->water.present) {
        mesh->pore_pressure = malloc(sizeof(double) * ((size_t)n + 1));
        mesh->water_head = malloc(sizeof(double) * ((size_t)n + 1));
        GSN_CHECK_GOTO(mesh->pore_pressure && mesh->water_head, rc,
                       GSN_ERR_MEMORY, done, "out of memory");
        for (int i = 0; i < n; ++i) {
            const double *x = &mesh->reference[3 * (size_t)i];
            mesh->pore_pressure[i] = gsn_water_pressure(c, x);
            mesh->water_head[i] =
                gsn_water_table_height(c, x) - gsn_height(c, x);
        }
    }
done:
    gsn_h5_close(&file);
    return rc;
}

/* The grid of a frame with the site's fields. */
static int post_grid(const struct post_mesh *mesh,
                     const struct gsn_frame *frame, struct gsn_vtk_grid **grid)
{
    GSN_CALL(gsn_vtk_grid_create(mesh->point_count, mesh->reference,
                                 mesh->tetrahedron_count, mesh->tetrahedra,
                                 frame, grid));
    if (mesh->volume) {
        const char *names[256];
        for (int v = 0; v < mesh->volume_count; ++v)
            names[v] = mesh->volume_name[v];
        GSN_CALL(gsn_vtk_grid_add_cell_categories(*grid, "volume", mesh->volume,
                                                  mesh->volume_count, names));
    }
    if (mesh->pore_pressure) {
        GSN_CALL(gsn_vtk_grid_add_point_field(*grid, "pore_pressure",
                                              mesh->pore_pressure));
        GSN_CALL(gsn_vtk_grid_add_point_field(*grid, "water_head",
                                              mesh->water_head));
    }
    return GSN_OK;
}

struct post_state {
    hid_t results;
    struct post_mesh mesh;
    struct gsn_display display;
    struct gsn_case *c;
    struct post_mirror mirror;
};

/* Frame k: read from results.h5 into frame (through the mirror's half frame
 * `half` where the body is mirrored), its .vtu written, and its pictures
 * rendered where `folder` is given. HDF5 is called by one thread at a time
 * (Debian's library is not built thread-safe). */
static int post_frame_out(struct post_state *s, const char *outdir, int k,
                          int count, struct gsn_frame *half,
                          struct gsn_frame *frame, const char *folder,
                          const char *case_name, int *written, unsigned *noted)
{
    int rc;
#pragma omp critical(post_hdf5)
    rc = gsn_results_frame_read(s->results, k, s->mirror.active ? half : frame);
    GSN_CALL(rc);
    if (s->mirror.active)
        post_mirror_frame(&s->mirror, half, frame);
    struct gsn_vtk_grid *grid = NULL;
    char path[GSN_PATH_SIZE];
    rc = post_grid(&s->mesh, frame, &grid);
    if (rc == GSN_OK)
        rc = post_frame_path(outdir, k, path, sizeof path);
    if (rc == GSN_OK)
        rc = post_vtu_write(grid, path);
    if (rc == GSN_OK && folder)
        rc = post_frame_pictures(grid, &s->mesh, frame, k, count, folder,
                                 case_name, written, noted);
    gsn_vtk_grid_destroy(&grid);
    return rc;
}

/* One thread's part of post_frames: where `render`, the picture frames
 * (their .vtu and pictures) first; then the other frames, taken from *next
 * until none is left; a failure stops every thread at its next frame
 * (*failed). */
static int post_frames_thread(struct post_state *s, const char *outdir,
                              int count, const char *folder, int render,
                              const char *case_name, int *written,
                              unsigned *noted, int *next, int *failed)
{
    struct gsn_frame frame, half;
    memset(&frame, 0, sizeof frame);
    memset(&half, 0, sizeof half);
    int rc = gsn_frame_allocate(&frame, s->mesh.point_count);
    if (rc == GSN_OK && s->mirror.active)
        rc = gsn_frame_allocate(&half, s->mirror.half_count);
    for (int k = 0; folder && render && rc == GSN_OK && k < count; ++k)
        if (post_is_picture_frame(k, count))
            rc = post_frame_out(s, outdir, k, count, &half, &frame, folder,
                                case_name, written, noted);
    for (;;) {
        int k, stop;
#pragma omp atomic read
        stop = *failed;
        if (rc != GSN_OK || stop)
            break;
#pragma omp atomic capture
        k = (*next)++;
        if (k >= count)
            break;
        if (!folder || !post_is_picture_frame(k, count))
            rc = post_frame_out(s, outdir, k, count, &half, &frame, NULL,
                                case_name, written, noted);
    }
    if (rc != GSN_OK) {
#pragma omp atomic write
        *failed = 1;
    }
    gsn_frame_free(&frame);
    gsn_frame_free(&half);
    return rc;
}

/* Writes every frame's .vtu and, where `folder` is given, the pictures:
 * the frames in parallel (zlib's compression is most of post's time), the
 * picture frames on the first thread (VTK renders on one thread) while the
 * others write the rest. The files do not depend on the thread count. */
static int post_frames(struct post_state *s, const char *outdir, int count,
                       const char *folder, const char *case_name, int *written,
                       unsigned *noted)
{
    int next = 0, failed = 0, rc = GSN_OK;
#pragma omp parallel
    {
        int own = post_frames_thread(s, outdir, count, folder,
                                     omp_get_thread_num() == 0, case_name,
                                     written, noted, &next, &failed);
        if (own != GSN_OK)
#pragma omp critical(post_rc)
            if (rc == GSN_OK)
                rc = own;
    }
    return rc;
}

static int post_run(const char *outdir, const struct gsn_post_options *o,
                    struct post_state *s)
{
    char path[GSN_PATH_SIZE], folder[GSN_PATH_SIZE];
    char results_path[GSN_PATH_SIZE], case_name[CASE_NAME_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "results.h5"));
    GSN_CALL(post_refuse_partial(outdir, path));
    GSN_CHECK(access(path, F_OK) == 0, GSN_ERR_INPUT,
              "%s not found: post needs the results of 'geoscni solve' in "
              "%s",
              path, outdir);
    GSN_CALL(gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &s->results));
    int count = 0;
    GSN_CALL(gsn_results_frame_count(s->results, &count));
    GSN_CHECK(count > 0, GSN_ERR_INPUT, "%s holds no frames", path);
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, "model.h5"));
    GSN_CHECK(access(path, F_OK) == 0, GSN_ERR_INPUT,
              "%s not found: post needs the model of 'geoscni pre' in %s", path,
              outdir);
    GSN_CALL(post_mesh_read(path, &s->mesh));
    size_t rows = 0;
    hid_t first = H5I_INVALID_HID;
    GSN_CALL(
        gsn_h5_group_open(s->results, "frames/000000", "frame group", &first));
    int field = 0; /* the first field written (output.fields) */
    while (field + 1 < GSN_FRAME_FIELD_COUNT &&
           !gsn_h5_exists(first, gsn_frame_fields[field].path))
        ++field;
    int rc = gsn_h5_rows(first, &gsn_frame_fields[field], &rows);
    gsn_h5_close(&first);
    GSN_CALL(rc);
    GSN_CHECK(rows == (size_t)s->mesh.point_count, GSN_ERR_INPUT,
              "%s/results.h5 has %zu particles but model.h5 has %d: they "
              "come from different runs; run 'geoscni solve' again",
              outdir, rows, s->mesh.point_count);
    GSN_CALL(post_case_name(s->results, outdir, case_name, sizeof case_name));
    int have_case = post_case_load(s->results, s->c);
    GSN_CALL(
        gsn_path_join(results_path, sizeof results_path, outdir, "results.h5"));
    post_note_incomplete(s->results, results_path, s->c, have_case, count);
    if (have_case && s->c->output_mirror[0]) {
        GSN_CALL(post_mirror_create(path, s->c->output_mirror, &s->mesh,
                                    &s->mirror));
        if (!o->quiet)
            printf("post: mirrored across '%s' (%c = %g m): %d particles, %d "
                   "tetrahedra\n",
                   s->c->output_mirror, "xyz"[s->mirror.axis],
                   s -> mirror.offset, s->mesh.point_count,
                   s->mesh.tetrahedron_count);
    }

    GSN_CALL(post_site_fields(path, s->c, have_case, &s->mirror, &s->mesh));
    int pictures = !o->no_pictures;
    if (pictures) {
        GSN_CALL(gsn_display_open(&s->display));
        if (!s->display.available) {
            fprintf(stderr,
                    "geoscni post: skipped the pictures and plots (PNG): "
                    "%s\n",
                    s->display.reason);
            pictures = 0;
        }
    }
    GSN_CALL(gsn_path_join(folder, sizeof folder, outdir, "vtu"));
    GSN_CALL(gsn_folder_prepare(folder));
    char picture_folder[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(picture_folder, sizeof picture_folder, outdir,
                           "pictures"));
    if (pictures) {
        GSN_CALL(gsn_folder_prepare(picture_folder));
        GSN_CALL(post_remove_old_pictures(picture_folder, 0));
        GSN_CALL(gsn_path_join(path, sizeof path, outdir, "plots"));
        GSN_CALL(post_remove_old_pictures(path, 1));
    }

    int picture_count = 0;
    unsigned noted = 0;
    GSN_CALL(post_frames(s, outdir, count, pictures ? picture_folder : NULL,
                         case_name, &picture_count, &noted));
    post_remove_stale_frames(outdir, count);
    int plot_count = 0;
    if (pictures)
        GSN_CALL(post_plots(outdir, s->c, have_case, case_name, &plot_count));
    /* the .pvd last: its stamp says post is done (gsn_post_up_to_date) */
    char pvd[CASE_NAME_SIZE + 8], stamp[GSN_FILE_HASH_SIZE + 64];
    snprintf(pvd, sizeof pvd, "%s.pvd", case_name);
    GSN_CALL(gsn_path_join(path, sizeof path, outdir, pvd));
    char hash[GSN_FILE_HASH_SIZE];
    GSN_CALL(gsn_file_hash(results_path, hash));
    post_stamp(hash, pictures, stamp, sizeof stamp);
    GSN_CALL(post_pvd_write(path, s->results, count, stamp));
    if (!o->quiet)
        printf("post: %s with %d frames (vtu/frame_0000.vtu to "
               "frame_%04d.vtu)\n",
               path, count, count - 1);
    if (pictures && !o->quiet)
        printf("post: %d pictures in %s, %d plots in %s/plots\n", picture_count,
               picture_folder, plot_count, outdir);
    return GSN_OK;
}

int gsn_post_convergence_chart(const char *path, const char *title,
                               int level_count, const double *cpu_seconds,
                               const double *error_percent, int predicted_count,
                               const double *predicted_seconds,
                               const double *predicted_percent,
                               double tolerance_percent)
{
    struct gsn_display display = {0};
    GSN_CALL(gsn_display_open(&display));
    if (!display.available) {
        fprintf(stderr, "geoscni converge: no chart: %s\n", display.reason);
        gsn_display_close(&display);
        return GSN_OK;
    }
    double low = cpu_seconds[0], high = cpu_seconds[0];
    for (int i = 1; i < level_count; ++i) {
        low = fmin(low, cpu_seconds[i]);
        high = fmax(high, cpu_seconds[i]);
    }
    for (int i = 0; i < predicted_count; ++i)
        high = fmax(high, predicted_seconds[i]);
    const double tolerance_x[2] = {low, high};
    const double tolerance_y[2] = {tolerance_percent, tolerance_percent};
    const char *names[3] = {"levels: |value - converged| + its error",
                            "tolerance",
                            "a study ending finer (observed order)"};
    const int counts[3] = {level_count, 2, predicted_count};
    const double *xs[3] = {cpu_seconds, tolerance_x, predicted_seconds};
    const double *ys[3] = {error_percent, tolerance_y, predicted_percent};
    const struct gsn_chart_style style = {
        .log_axes = 1, .markers = 1, .always_legend = 1, .legend_right = 1};
    int rc = post_chart_write(
        path, title, "CPU time of the level [s]", "estimated error [%]",
        predicted_count > 1 ? 3 : 2, names, counts, xs, ys, &style);
    gsn_display_close(&display);
    GSN_CALL(rc);
    return GSN_OK;
}

int gsn_post_up_to_date(const char *outdir,
                        const struct gsn_post_options *options)
{
    char path[GSN_PATH_SIZE], case_name[CASE_NAME_SIZE];
    char pvd[GSN_PATH_SIZE + CASE_NAME_SIZE], line[512], stamp[512];
    char hash[GSN_FILE_HASH_SIZE];
    hid_t results = H5I_INVALID_HID;
    int current = 0;
    if (gsn_path_join(path, sizeof path, outdir, "results.h5") != GSN_OK ||
        gsn_h5_open(path, GSN_FILE_KIND_RESULTS, 0, &results) != GSN_OK ||
        post_case_name(results, outdir, case_name, sizeof case_name) !=
            GSN_OK ||
        snprintf(pvd, sizeof pvd, "%s/%s.pvd", outdir, case_name) >=
            (int)sizeof pvd ||
        gsn_file_hash(path, hash) != GSN_OK)
        goto done;
    /* made with pictures serves a run without them too */
    for (int pictures = 1; pictures >= (options->no_pictures ? 0 : 1);
         --pictures) {
        FILE *file = fopen(pvd, "r");
        if (!file)
            goto done;
        post_stamp(hash, pictures, stamp, sizeof stamp);
        int lines = 0;
        while (!current && lines++ < 3 && fgets(line, sizeof line, file))
            current =
                strncmp(line, PVD_STAMP_START, strlen(PVD_STAMP_START)) == 0 &&
                strncmp(line + strlen(PVD_STAMP_START), stamp, strlen(stamp)) ==
                    0 &&
                strncmp(line + strlen(PVD_STAMP_START) + strlen(stamp),
                        PVD_STAMP_END, strlen(PVD_STAMP_END)) == 0;
        fclose(file);
        if (current)
            break;
    }
done:
    gsn_h5_close(&results);
    gsn_error_clear();
    return current;
}

int gsn_post_run(const char *outdir, const struct gsn_post_options *options)
{
    static const struct gsn_post_options defaults = {0, 0};
    struct post_state s;
    memset(&s, 0, sizeof s);
    s.results = H5I_INVALID_HID;
    s.c = calloc(1, sizeof *s.c); /* large: not on the stack */
    GSN_CHECK(s.c != NULL, GSN_ERR_MEMORY, "cannot allocate a case");
    int rc = post_run(outdir, options ? options : &defaults, &s);
    post_mesh_free(&s.mesh);
    post_mirror_free(&s.mirror);
    gsn_h5_close(&s.results);
    gsn_display_close(&s.display);
    free(s.c);
    if (rc != GSN_OK)
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "post_run(outdir, options, &s)");
    return GSN_OK;
}
