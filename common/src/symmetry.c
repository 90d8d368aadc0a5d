/* Symmetry planes (docs/economy.md, "Symmetry"): a boundary entry with
 * symmetry: true holds the displacement component normal to its surface,
 * which must be one plane normal to a coordinate axis, because the
 * constraints hold x, y and z components (constraint.h). */
#include "geoscni/error.h"
#include "geoscni/model.h"

#include <math.h>

/* Planarity tolerance, relative to the body's bounding-box diagonal: gmsh
 * places nodes on a plane surface to round-off (about 1e-15 of the size). */
#define SURFACE_PLANE_TOLERANCE 1e-9

int gsn_model_surface_plane(const struct gsn_model *m, int surface, int *axis,
                            double *offset)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    double hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    double body_lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    double body_hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    int count = 0;
    for (int p = 0; p < m->particle_count; ++p) {
        const double *x = &m->position[3 * p];
        int on = gsn_model_particle_on_surface(m, p, surface);
        count += on;
        for (int k = 0; k < 3; ++k) {
            body_lo[k] = fmin(body_lo[k], x[k]);
            body_hi[k] = fmax(body_hi[k], x[k]);
            if (on) {
                lo[k] = fmin(lo[k], x[k]);
                hi[k] = fmax(hi[k], x[k]);
            }
        }
    }
    const char *name = surface >= 0 && surface < m->surface_count
                           ? m->surface_name[surface]
                           : "?";
    GSN_CHECK(count > 0, GSN_ERR_INPUT, "surface '%s' has no particles", name);
    double diagonal = 0.0;
    for (int k = 0; k < 3; ++k)
        diagonal += (body_hi[k] - body_lo[k]) * (body_hi[k] - body_lo[k]);
    double tolerance = SURFACE_PLANE_TOLERANCE * sqrt(diagonal);
    *axis = -1;
    for (int k = 0; k < 3 && *axis < 0; ++k)
        if (hi[k] - lo[k] <= tolerance)
            *axis = k;
    GSN_CHECK(*axis >= 0, GSN_ERR_INPUT,
              "surface '%s' is not a plane normal to x, y or z (its "
              "particles span %.3g x %.3g x %.3g m); a symmetry plane must "
              "be axis-aligned",
              name, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    *offset = 0.5 * (lo[*axis] + hi[*axis]);
    return GSN_OK;
}

int gsn_case_resolve_symmetry(struct gsn_case *c, const struct gsn_model *m)
{
    for (int b = 0; b < c->boundary_count; ++b) {
        struct gsn_boundary *entry = &c->boundaries[b];
        if (!entry->symmetry)
            continue;
        int surface = gsn_model_find_surface(m, entry->name);
        GSN_CHECK(surface >= 0, GSN_ERR_INPUT,
                  "%s:%d: boundary '%s' is not a physical surface of the "
                  "model",
                  c->path, entry->line, entry->name);
        int axis = -1;
        double offset = 0.0;
        int rc = gsn_model_surface_plane(m, surface, &axis, &offset);
        if (rc != GSN_OK) {
            gsn_error_clear();
            GSN_CHECK(0, GSN_ERR_INPUT,
                      "%s:%d: 'boundary.%s.symmetry': the surface is not "
                      "one plane normal to x, y or z; symmetry needs an "
                      "axis-aligned plane",
                      c->path, entry->line, entry->name);
        }
        entry->fixed[axis] = 1;
    }
    return GSN_OK;
}
