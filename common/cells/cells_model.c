/* The cells of a model's particles at any positions: what pre builds on the
 * reference configuration and the solver again on the current one (issue
 * 15). The body is the model's tetrahedra with their nodes at the given
 * positions; their boundary faces carry the physical surfaces, so the
 * boundary facets of the cells and their surface names follow the body. */
#include "geoscni/cells.h"
#include "geoscni/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int gsn_cells_label_from_face(int face)
{
    return face >= 0                         ? -1 - face
           : face == GSN_MODEL_FACE_INTERNAL ? GSN_CELLS_LABEL_INTERNAL
                                             : GSN_CELLS_LABEL_UNTAGGED;
}

int gsn_cells_face_from_label(int label)
{
    return label == GSN_CELLS_LABEL_INTERNAL   ? GSN_MODEL_FACE_INTERNAL
           : label == GSN_CELLS_LABEL_UNTAGGED ? GSN_MODEL_FACE_UNTAGGED
                                               : -1 - label;
}

/* The body's volume at positions x (its tetrahedra are positively
 * oriented where it was made) and the labels of its faces for the
 * clipping. A tetrahedron that x turns inside out or flat is an error:
 * the body would not be the union of the pieces. */
static int body_of_mesh(const struct gsn_body *body, const double *x,
                        int *label, double *volume)
{
    double ratio = 0.0, total = 0.0;
    int nt = body->tetrahedron_count;
    int worst = gsn_body_worst(body, x, &ratio);
    for (int t = 0; t < nt; ++t) {
        total += gsn_body_tetrahedron_volume(x, &body->tetrahedra[4 * t]);
        for (int k = 0; k < 4; ++k)
            label[4 * t + k] = gsn_cells_label_from_face(body->face[4 * t + k]);
    }
    if (nt > 0) {
        const double *a = &x[3 * body->tetrahedra[4 * worst]];
        GSN_CHECK(ratio > 1e-12, GSN_ERR_NUMERICAL,
                  "tetrahedron %d of the body (first node %d at %g, %g, %g) "
                  "is %s: %.3g of the mean volume",
                  worst, body->tetrahedra[4 * worst], a[0], a[1], a[2],
                  ratio < 0.0 ? "turned inside out" : "flat", ratio);
    }
    *volume = total;
    return GSN_OK;
}

/* Area of every physical surface: the body's boundary triangles at
 * positions x. */
static void surface_areas(const struct gsn_body *body, int surface_count,
                          const double *x, double *area)
{
    for (int s = 0; s < surface_count; ++s)
        area[s] = 0.0;
    for (int f = 0; f < 4 * body->tetrahedron_count; ++f) {
        int s = body->face[f];
        if (s < 0)
            continue;
        const int *v = &body->tetrahedra[4 * (f / 4)];
        const int *o = gsn_cells_tetrahedron_face[f % 4];
        area[s] += gsn_cells_triangle_area(&x[3 * v[o[0]]], &x[3 * v[o[1]]],
                                           &x[3 * v[o[2]]]);
    }
}

int gsn_cells_model_at(const struct gsn_model *m, const double *position,
                       const struct gsn_body *body,
                       const struct gsn_cells_options *options,
                       struct gsn_model *out, struct gsn_cells_report *report)
{
    memset(out, 0, sizeof *out);
    const double *x = position ? position : m->position;
    const struct gsn_body own = {m->tetrahedron_count, m->tetrahedra,
                                 m->tetrahedron_face};
    if (!body)
        body = &own;
    int n = m->particle_count, nt = body->tetrahedron_count;
    GSN_CHECK(nt > 0 && body->face, GSN_ERR_INPUT,
              "the model has no tetrahedra to clip its cells to");
    struct gsn_cells_input in;
    memset(&in, 0, sizeof in);
    struct gsn_cells_result r;
    memset(&r, 0, sizeof r);
    int *label = malloc(sizeof(int) * 4 * (size_t)nt);
    GSN_CHECK(label, GSN_ERR_MEMORY, "cannot allocate %d face labels", 4 * nt);
    double volume = 0.0;
    int rc = GSN_OK;
    GSN_CALL_GOTO(body_of_mesh(body, x, label, &volume), rc, done);
    in.particle_count = n;
    in.position = x;
    for (int k = 0; k < 3; ++k) {
        in.lo[k] = INFINITY;
        in.hi[k] = -INFINITY;
    }
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            in.lo[k] = fmin(in.lo[k], x[3 * i + k]);
            in.hi[k] = fmax(in.hi[k], x[3 * i + k]);
        }
    double diagonal = 0.0;
    for (int k = 0; k < 3; ++k)
        diagonal += (in.hi[k] - in.lo[k]) * (in.hi[k] - in.lo[k]);
    diagonal = sqrt(diagonal);
    /* a hull a little larger than the body: its faces never coincide with
     * the body's, so every cell that reaches them is cut by a piece */
    for (int k = 0; k < 3; ++k) {
        in.lo[k] -= 1e-6 * diagonal;
        in.hi[k] += 1e-6 * diagonal;
    }
    for (int s = 0; s < 6; ++s)
        in.box_label[s] = GSN_CELLS_LABEL_HULL;
    in.body.tetrahedron_count = nt;
    in.body.tetrahedra = body->tetrahedra;
    in.body.face_label = label;
    in.facet_points = options->facet_points;
    in.threads = options->threads;
    in.tetrahedra_only = options->tetrahedra_only;
    GSN_CALL_GOTO(gsn_cells_build(&in, &r), rc, done);
    int entries = m->particle_surface_offset[n];
    GSN_CALL_GOTO(
        gsn_cells_model_create(&r, entries, m->surface_count, nt, out), rc,
        done);
    memcpy(out->position, x, sizeof(double) * 3 * (size_t)n);
    memcpy(out->particle_surface_offset, m->particle_surface_offset,
           sizeof(int) * (size_t)(n + 1));
    memcpy(out->particle_surface, m->particle_surface,
           sizeof(int) * (size_t)entries);
    memcpy(out->surface_name, m->surface_name,
           sizeof *m->surface_name * (size_t)m->surface_count);
    memcpy(out->surface_tag, m->surface_tag,
           sizeof(int) * (size_t)m->surface_count);
    memcpy(out->tetrahedra, body->tetrahedra, sizeof(int) * 4 * (size_t)nt);
    memcpy(out->tetrahedron_face, body->face, sizeof(int) * 4 * (size_t)nt);
    /* the volumes' tetrahedra are m's own unless the body was made again */
    GSN_CALL_GOTO(gsn_model_copy_volumes(m, out), rc, done);
    if (nt != m->tetrahedron_count || body->tetrahedra != m->tetrahedra)
        for (int t = 0; t < nt; ++t)
            out->tetrahedron_volume[t] = -1;
    surface_areas(body, m->surface_count, x, out->surface_area);
    struct gsn_cells_report check;
    memset(&check, 0, sizeof check);
    check.twin_error = r.twin_error;
    GSN_CALL_GOTO(gsn_cells_check(out, volume, &check), rc, done);
    check.body_volume = volume;
    check.crossing_count = r.crossing_count;
    check.pieced_count = r.pieced_count;
    check.time_delaunay = r.time_delaunay;
    check.time_cells = r.time_cells;
    if (report)
        *report = check;
done:
    free(label);
    gsn_cells_result_free(&r);
    if (rc != GSN_OK)
        gsn_model_free(out);
    return rc;
}
