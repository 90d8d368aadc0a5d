/* Voronoi cells of arbitrary points clipped to an axis-aligned box: the
 * nodal domains of test models that need no gmsh (lattices, random sets). */
#include "geoscni/cells.h"
#include "geoscni/error.h"
#include "geoscni/pre.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const box_surface_names[6] = {"xmin", "xmax", "ymin",
                                                 "ymax", "zmin", "zmax"};

/* Bit s set when particle x lies on face s (within tolerance). */
static int box_faces_touched(const double x[3], const double lo[3],
                             const double hi[3], double tolerance)
{
    int mask = 0;
    for (int k = 0; k < 3; ++k) {
        if (fabs(x[k] - lo[k]) <= tolerance)
            mask |= 1 << (2 * k);
        if (fabs(x[k] - hi[k]) <= tolerance)
            mask |= 1 << (2 * k + 1);
    }
    return mask;
}

/* The Delaunay tetrahedra of the points when their hull is the box (else
 * none), each hull face named after the box face it lies on. */
static void box_body(const double *points, int n, const double lo[3],
                     const double hi[3], double tolerance,
                     struct gsn_body *body)
{
    if (gsn_body_of_points(points, n, body) != GSN_OK) {
        gsn_error_clear();
        return;
    }
    double volume = 0.0,
           box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    for (int t = 0; t < body->tetrahedron_count; ++t)
        volume += gsn_body_tetrahedron_volume(points, &body->tetrahedra[4 * t]);
    int fills = fabs(volume - box) <= 1e-12 * box;
    for (int f = 0; fills && f < 4 * body->tetrahedron_count; ++f) {
        if (body->face[f] == GSN_MODEL_FACE_INTERNAL)
            continue;
        const int *v = &body->tetrahedra[4 * (f / 4)];
        int mask = 63;
        for (int j = 0; j < 3; ++j)
            mask &= box_faces_touched(
                &points[3 * v[gsn_cells_tetrahedron_face[f % 4][j]]], lo, hi,
                tolerance);
        for (int s = 0; s < 6; ++s)
            if ((mask >> s) & 1) {
                body->face[f] = s;
                break;
            }
        fills = body->face[f] >= 0;
    }
    if (!fills)
        gsn_body_free(body);
}

int gsn_pre_domains_box_ex(const double *points, int n, const double lo[3],
                           const double hi[3], int facet_points, int threads,
                           struct gsn_model *m, struct gsn_cells_report *report)
{
    memset(m, 0, sizeof *m);
    struct gsn_cells_input in;
    memset(&in, 0, sizeof in);
    in.particle_count = n;
    in.position = points;
    memcpy(in.lo, lo, sizeof in.lo);
    memcpy(in.hi, hi, sizeof in.hi);
    for (int s = 0; s < 6; ++s)
        in.box_label[s] = -1 - s; /* surface s */
    in.facet_points = facet_points;
    in.threads = threads;
    struct gsn_cells_result r;
    struct gsn_cells_report check;
    memset(&check, 0, sizeof check);
    GSN_CALL(gsn_cells_build(&in, &r));

    double diagonal = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                           (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double tolerance = 1e-12 * diagonal;
    int entries = 0, rc = GSN_OK;
    for (int i = 0; i < n; ++i) {
        int mask = box_faces_touched(&points[3 * i], lo, hi, tolerance);
        for (int s = 0; s < 6; ++s)
            entries += (mask >> s) & 1;
    }
    /* The Delaunay tetrahedra of the points, where they fill the box (the
     * box's corners and faces carry particles), so the body can be followed
     * through reference updates; their hull faces take the box face they
     * lie on. */
    struct gsn_body body;
    memset(&body, 0, sizeof body);
    box_body(points, n, lo, hi, tolerance, &body);
    rc = gsn_cells_model_create(&r, entries, 6, body.tetrahedron_count, m);
    if (rc == GSN_OK && body.tetrahedron_count > 0) {
        memcpy(m->tetrahedra, body.tetrahedra,
               sizeof(int) * 4 * (size_t)body.tetrahedron_count);
        memcpy(m->tetrahedron_face, body.face,
               sizeof(int) * 4 * (size_t)body.tetrahedron_count);
    }
    gsn_body_free(&body);
    GSN_CALL_GOTO(rc, rc, fail);
    memcpy(m->position, points, sizeof(double) * 3 * (size_t)n);
    m->particle_surface_offset[0] = 0;
    int e = 0;
    for (int i = 0; i < n; ++i) {
        int mask = box_faces_touched(&points[3 * i], lo, hi, tolerance);
        for (int s = 0; s < 6; ++s)
            if ((mask >> s) & 1)
                m->particle_surface[e++] = s;
        m->particle_surface_offset[i + 1] = e;
    }
    double extent[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    for (int s = 0; s < 6; ++s) {
        int k = s / 2;
        snprintf(m->surface_name[s], sizeof m->surface_name[s], "%s",
                 box_surface_names[s]);
        m->surface_tag[s] = s + 1;
        m->surface_area[s] = extent[(k + 1) % 3] * extent[(k + 2) % 3];
    }
    check.twin_error = r.twin_error;
    GSN_CALL_GOTO(gsn_cells_check(m, extent[0] * extent[1] * extent[2], &check),
                  rc, fail);
    if (report)
        *report = check;
    gsn_cells_result_free(&r);
    return GSN_OK;
fail:
    if (report)
        *report = check;
    gsn_cells_result_free(&r);
    gsn_model_free(m);
    return rc;
}

int gsn_pre_domains_box(const double *points, int n, const double lo[3],
                        const double hi[3], int facet_points,
                        struct gsn_model *m)
{
    GSN_CALL(
        gsn_pre_domains_box_ex(points, n, lo, hi, facet_points, 0, m, NULL));
    return GSN_OK;
}
