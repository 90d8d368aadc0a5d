/* The C interface of post's one VTK file (vtk_output.cpp): .vtu files,
 * rendered pictures of the deformed body and line charts. Every function
 * returns a geoscni error code; no C++ exception crosses it. Files are
 * written to exactly the path given: the caller passes a temporary name and
 * renames it (files.h). */
#ifndef GEOSCNI_POST_VTK_OUTPUT_H
#define GEOSCNI_POST_VTK_OUTPUT_H

#include "geoscni/results.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 if an X display can be opened (VTK aborts when it cannot), else 0. */
int gsn_vtk_display_usable(void);

/* One frame as a VTK unstructured grid: points at X + u, the tetrahedra as
 * cells, the frame fields as point arrays named as in schema.h. */
struct gsn_vtk_grid;

/* Builds the grid of a frame. reference (point_count x 3, m) and tetrahedra
 * (tetrahedron_count x 4, indices checked by the caller) are borrowed and
 * copied; the frame's fields are copied. */
int gsn_vtk_grid_create(int point_count, const double *reference,
                        int tetrahedron_count, const int *tetrahedra,
                        const struct gsn_frame *frame,
                        struct gsn_vtk_grid **grid);

/* Adds a scalar point array (point_count values, copied) named name: the
 * site's fields that no frame holds (post.c: volume, pore_pressure). */
int gsn_vtk_grid_add_point_field(struct gsn_vtk_grid *grid, const char *name,
                                 const double *values);

/* Adds an integer cell array (one value per tetrahedron, copied) whose
 * values index category_names (the physical volumes of post.c): the
 * pictures colour them apart with the names in the legend. */
int gsn_vtk_grid_add_cell_categories(struct gsn_vtk_grid *grid,
                                     const char *name, const int *values,
                                     int category_count,
                                     const char *const *category_names);

/* Frees the grid and sets *grid to NULL; accepts NULL. */
void gsn_vtk_grid_destroy(struct gsn_vtk_grid **grid);

/* Writes the grid as an XML .vtu file: binary appended data, zlib. */
int gsn_vtk_grid_write(const struct gsn_vtk_grid *grid, const char *path);

/* What a picture shows. */
enum gsn_vtk_picture {
    GSN_VTK_PICTURE_DAMAGE = 0, /* damage on the surface of the whole body */
    GSN_VTK_PICTURE_CLIP_UX,    /* u_x on the half y >= mid-plane */
    GSN_VTK_PICTURE_CLIP_UY,
    GSN_VTK_PICTURE_CLIP_UZ,
    GSN_VTK_PICTURE_CLIP_EQUIVALENT_STRESS,
    GSN_VTK_PICTURE_CLIP_DISPLACEMENT, /* |u| */
    GSN_VTK_PICTURE_CLIP_EQUIVALENT_PLASTIC_STRAIN,
    GSN_VTK_PICTURE_LAYERS,        /* the physical volumes, on the body */
    GSN_VTK_PICTURE_PORE_PRESSURE, /* the water table's u, on the body */
    GSN_VTK_PICTURE_COUNT
};

/* The frame field (enum gsn_frame_field) a picture shows, or -1 for the
 * site's pictures (layers, pore pressure: a point array of that name). */
int gsn_vtk_picture_field(enum gsn_vtk_picture picture);

/* Renders a picture of the grid to a PNG (needs an X display). bounds
 * (xmin xmax ymin ymax zmin zmax, m) are the reference body's: they fix the
 * camera and the clipping mid-plane y = (ymin + ymax) / 2 for every frame.
 * title is drawn above the picture. */
int gsn_vtk_grid_render(const struct gsn_vtk_grid *grid,
                        enum gsn_vtk_picture picture, const double bounds[6],
                        const char *title, const char *path);

/* How a chart differs from post's plots (NULL: linear axes, lines only, a
 * legend at the top left when there are two curves or more, the palette
 * in series order). */
struct gsn_chart_style {
    int log_axes;      /* both axes logarithmic */
    int markers;       /* a circle at every point */
    int always_legend; /* a legend even for one curve */
    int legend_right;  /* the legend at the top right */
    const int *colour; /* per series: its colour in the palette, or NULL */
};

/* Draws series_count curves y[s][0..n) against x[s][0..n) (borrowed) as a
 * line chart with a legend into a PNG (needs an X display); style may be
 * NULL. */
int gsn_vtk_chart_write(const char *path, const char *title,
                        const char *x_label, const char *y_label,
                        int series_count, const char *const *names,
                        const int *counts, const double *const *x,
                        const double *const *y,
                        const struct gsn_chart_style *style);

#ifdef __cplusplus
}
#endif
#endif
