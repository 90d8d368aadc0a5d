/* Graded particle spacing (docs/economy.md, "Graded spacing"): each entry of
 * particles.refine becomes a gmsh size field (a Box field for a box, a
 * Distance field from points sampling the surface fed to a Threshold
 * field for a surface), combined with a Min field as the background mesh; gmsh
 * then meshes with the smallest of these sizes and particles.spacing
 * (Mesh.MeshSizeMax). gmsh 4.8 field options: Box VIn, VOut, XMin..ZMax,
 * Thickness; Distance PointsList; Threshold InField, SizeMin, SizeMax,
 * DistMin, DistMax; Min FieldsList. */
#include "refine.h"
#include "estimate.h"
#include "geoscni/error.h"
#include "geoscni/pre.h"

#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A symmetry surface is flat when its gmsh bounding box is thinner than
 * this fraction of the model's (gmsh pads boxes by about 1e-7 of it). */
#define SYMMETRY_FLATNESS 1e-6

#define GMSH_OK(ierr, ...) GSN_CHECK((ierr) == 0, GSN_ERR_LIBRARY, __VA_ARGS__)

/* The gmsh tag of a physical surface by name, or -1. */
static int physical_surface_tag(const char *name, int *tag)
{
    int *groups = NULL, ierr = 0;
    size_t count = 0;
    *tag = -1;
    gmshModelGetPhysicalGroups(&groups, &count, 2, &ierr);
    GMSH_OK(ierr, "cannot list the physical surfaces");
    for (size_t g = 0; g + 1 < count && *tag < 0; g += 2) {
        char *group_name = NULL;
        gmshModelGetPhysicalName(2, groups[g + 1], &group_name, &ierr);
        if (ierr == 0 && group_name && strcmp(group_name, name) == 0)
            *tag = groups[g + 1];
        gmshFree(group_name);
    }
    gmshFree(groups);
    return GSN_OK;
}

/* Bounding box (x0 y0 z0 x1 y1 z1) of the entities of a physical surface. */
static int physical_surface_box(int tag, double box[6])
{
    int *entities = NULL, ierr = 0;
    size_t count = 0;
    gmshModelGetEntitiesForPhysicalGroup(2, tag, &entities, &count, &ierr);
    GMSH_OK(ierr, "cannot list the entities of physical surface %d", tag);
    for (int k = 0; k < 3; ++k) {
        box[k] = HUGE_VAL;
        box[k + 3] = -HUGE_VAL;
    }
    for (size_t e = 0; e < count && ierr == 0; ++e) {
        double b[6];
        gmshModelGetBoundingBox(2, entities[e], &b[0], &b[1], &b[2], &b[3],
                                &b[4], &b[5], &ierr);
        for (int k = 0; k < 3; ++k) {
            box[k] = fmin(box[k], b[k]);
            box[k + 3] = fmax(box[k + 3], b[k + 3]);
        }
    }
    gmshFree(entities);
    GMSH_OK(ierr, "cannot get the bounding box of physical surface %d", tag);
    return GSN_OK;
}

int pre_refine_check(const struct gsn_case *c)
{
    for (int i = 0; i < c->refinement_count; ++i) {
        const struct gsn_refinement *f = &c->refinements[i];
        if (f->kind != GSN_REFINE_SURFACE)
            continue;
        int tag = -1;
        GSN_CALL(physical_surface_tag(f->surface, &tag));
        GSN_CHECK(tag >= 0, GSN_ERR_INPUT,
                  "%s:%d: 'particles.refine[%d].surface' is '%s', which is "
                  "not a physical surface of %s",
                  c->path, f->line, i, f->surface, c->geometry);
    }
    int ierr = 0;
    double model[6];
    gmshModelGetBoundingBox(-1, -1, &model[0], &model[1], &model[2], &model[3],
                            &model[4], &model[5], &ierr);
    GMSH_OK(ierr, "cannot get the bounding box of the geometry");
    double size = 0.0;
    for (int k = 0; k < 3; ++k)
        size = fmax(size, model[k + 3] - model[k]);
    for (int b = 0; b < c->boundary_count; ++b) {
        const struct gsn_boundary *entry = &c->boundaries[b];
        if (!entry->symmetry)
            continue;
        int tag = -1;
        double box[6] = {0, 0, 0, 0, 0, 0};
        GSN_CALL(physical_surface_tag(entry->name, &tag));
        if (tag < 0)
            continue; /* pre_check_boundaries names it */
        GSN_CALL(physical_surface_box(tag, box));
        int flat = 0;
        for (int k = 0; k < 3; ++k)
            flat |= box[k + 3] - box[k] <= SYMMETRY_FLATNESS * size;
        GSN_CHECK(flat, GSN_ERR_INPUT,
                  "%s:%d: 'boundary.%s.symmetry': surface '%s' is not one "
                  "plane normal to x, y or z (its bounding box is %.3g x "
                  "%.3g x %.3g m); symmetry needs an axis-aligned plane",
                  c->path, entry->line, entry->name, entry->name,
                  box[3] - box[0], box[4] - box[1], box[5] - box[2]);
    }
    return GSN_OK;
}

/* Makes gmsh mesh only the given surface entities (and their curves and
 * points), or, with none, everything again. */
static int only_visible(const int *surfaces, size_t count)
{
    int *all = NULL, ierr = 0;
    size_t all_count = 0;
    gmshModelGetEntities(&all, &all_count, -1, &ierr);
    if (ierr == 0)
        gmshModelSetVisibility(all, all_count, count == 0, 0, &ierr);
    gmshFree(all);
    for (size_t e = 0; ierr == 0 && e < count; ++e) {
        int dim_tag[2] = {2, surfaces[e]};
        gmshModelSetVisibility(dim_tag, 2, 1, 1, &ierr);
    }
    if (ierr == 0)
        gmshOptionSetNumber("Mesh.MeshOnlyVisible", count > 0, &ierr);
    GMSH_OK(ierr, "cannot set which surfaces gmsh meshes");
    return GSN_OK;
}

/* Point entities sampling a physical surface at spacing: the nodes of a
 * triangle mesh of its entities alone (made at that size and cleared again),
 * added to the model as free points, which no tetrahedron uses. gmsh 4.8's
 * Distance field ignores SurfacesList on surfaces of the built-in kernel
 * (a 0.7 m refinement near Slope I's footing came out at the background
 * 1.4 m); PointsList works with either kernel. The caller frees *points. */
static int surface_sample(const struct gsn_case *c,
                          const struct gsn_refinement *f, double **points,
                          size_t *count)
{
    int tag = -1, ierr = 0, rc = GSN_OK;
    GSN_CALL(physical_surface_tag(f->surface, &tag));
    int *entities = NULL;
    size_t entity_count = 0;
    gmshModelGetEntitiesForPhysicalGroup(2, tag, &entities, &entity_count,
                                         &ierr);
    GMSH_OK(ierr, "cannot list the entities of surface %s", f->surface);
    *points = NULL;
    *count = 0;
    /* only this surface (and its curves): the others at its spacing could
     * hold far more nodes than the whole volume mesh */
    GSN_CALL(only_visible(entities, entity_count));
    gmshOptionSetNumber("Mesh.MeshSizeMax", f->spacing, &ierr);
    gmshModelMeshGenerate(2, &ierr);
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_INPUT, done,
                   "%s:%d: gmsh cannot mesh surface '%s' to sample it for "
                   "particles.refine",
                   c->path, f->line, f->surface);
    size_t capacity = 0;
    double *sample = NULL;
    for (size_t e = 0; e < entity_count && rc == GSN_OK; ++e) {
        size_t *tags = NULL, tag_count = 0, coord_n = 0, parametric_n = 0;
        double *coord = NULL, *parametric = NULL;
        gmshModelMeshGetNodes(&tags, &tag_count, &coord, &coord_n, &parametric,
                              &parametric_n, 2, entities[e], 1, 0, &ierr);
        if (ierr == 0 && *count + tag_count > capacity) {
            capacity = 2 * (*count + tag_count);
            double *grown = realloc(sample, sizeof(double) * 3 * capacity);
            if (!grown)
                rc = GSN_ERR_MEMORY;
            else
                sample = grown;
        }
        if (ierr == 0 && rc == GSN_OK) {
            memcpy(sample + 3 * *count, coord, sizeof(double) * coord_n);
            *count += coord_n / 3;
        }
        gmshFree(tags);
        gmshFree(coord);
        gmshFree(parametric);
    }
    *points = sample;
    GSN_CHECK_GOTO(rc == GSN_OK, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                   "cannot read the mesh of surface %s", f->surface);
done:
    gmshFree(entities);
    ierr = 0;
    gmshModelMeshClear(NULL, 0, &ierr);
    if (rc == GSN_OK)
        rc = only_visible(NULL, 0);
    else
        (void)only_visible(NULL, 0);
    gmshOptionSetNumber("Mesh.MeshSizeMax", c->particle_spacing, &ierr);
    if (rc == GSN_OK && ierr != 0)
        rc =
            gsn_error_raise(GSN_ERR_LIBRARY, __FILE__, __LINE__, __func__,
                            "cannot clear the sampling mesh of %s", f->surface);
    if (rc != GSN_OK) {
        free(*points);
        *points = NULL;
    }
    return rc;
}

/* The Threshold field of a surface refinement: spacing within f->width of
 * the surface, growing linearly to particles.spacing over f->distance
 * beyond. */
static int surface_field(const struct gsn_case *c,
                         const struct gsn_refinement *f, int *field)
{
    double *sample = NULL;
    size_t count = 0;
    GSN_CALL(surface_sample(c, f, &sample, &count));
    double *list = malloc(sizeof(double) * (count + 1));
    int ierr = 0;
    for (size_t i = 0; list && i < count && ierr == 0; ++i)
        list[i] = gmshModelGeoAddPoint(sample[3 * i], sample[3 * i + 1],
                                       sample[3 * i + 2], 0.0, -1, &ierr);
    free(sample);
    if (list && ierr == 0)
        gmshModelGeoSynchronize(&ierr);
    if (!list || ierr != 0)
        free(list);
    GSN_CHECK(list != NULL, GSN_ERR_MEMORY, "out of memory");
    GMSH_OK(ierr, "cannot add the sample points of surface %s", f->surface);
    int distance = gmshModelMeshFieldAdd("Distance", -1, &ierr);
    if (ierr == 0)
        gmshModelMeshFieldSetNumbers(distance, "PointsList", list, count,
                                     &ierr);
    free(list);
    GMSH_OK(ierr, "cannot add the Distance field of surface %s", f->surface);
    *field = gmshModelMeshFieldAdd("Threshold", -1, &ierr);
    gmshModelMeshFieldSetNumber(*field, "InField", distance, &ierr);
    gmshModelMeshFieldSetNumber(*field, "SizeMin", f->spacing, &ierr);
    gmshModelMeshFieldSetNumber(*field, "SizeMax", c->particle_spacing, &ierr);
    gmshModelMeshFieldSetNumber(*field, "DistMin", f->width, &ierr);
    gmshModelMeshFieldSetNumber(*field, "DistMax", f->width + f->distance,
                                &ierr);
    GMSH_OK(ierr, "cannot add the Threshold field of surface %s", f->surface);
    return GSN_OK;
}

static int box_field(const struct gsn_case *c, const struct gsn_refinement *f,
                     int *field)
{
    static const char *const corners[6] = {"XMin", "YMin", "ZMin",
                                           "XMax", "YMax", "ZMax"};
    int ierr = 0;
    *field = gmshModelMeshFieldAdd("Box", -1, &ierr);
    gmshModelMeshFieldSetNumber(*field, "VIn", f->spacing, &ierr);
    gmshModelMeshFieldSetNumber(*field, "VOut", c->particle_spacing, &ierr);
    for (int k = 0; k < 6; ++k)
        gmshModelMeshFieldSetNumber(*field, corners[k], f->box[k], &ierr);
    gmshModelMeshFieldSetNumber(*field, "Thickness", f->distance, &ierr);
    GMSH_OK(ierr, "cannot add the Box field of particles.refine");
    return GSN_OK;
}

int pre_refine_fields(const struct gsn_case *c)
{
    if (c->refinement_count == 0)
        return GSN_OK;
    double fields[GSN_MAX_REFINEMENTS];
    int ierr = 0;
    for (int i = 0; i < c->refinement_count; ++i) {
        const struct gsn_refinement *f = &c->refinements[i];
        int field = -1;
        if (f->kind == GSN_REFINE_BOX)
            GSN_CALL(box_field(c, f, &field));
        else
            GSN_CALL(surface_field(c, f, &field));
        fields[i] = field;
    }
    int minimum = gmshModelMeshFieldAdd("Min", -1, &ierr);
    gmshModelMeshFieldSetNumbers(minimum, "FieldsList", fields,
                                 (size_t)c->refinement_count, &ierr);
    gmshModelMeshFieldSetAsBackgroundMesh(minimum, &ierr);
    GMSH_OK(ierr, "cannot set the refinement fields as the background mesh");
    return GSN_OK;
}

int pre_refine_estimate(const struct gsn_case *c, const struct coarse_mesh *m,
                        const struct estimate_coefficients *k, double cap,
                        double *estimate, int *at_least)
{
    struct estimate_refinement r[GSN_MAX_REFINEMENTS];
    int *triangles[GSN_MAX_REFINEMENTS] = {NULL}, rc = GSN_OK;
    memset(r, 0, sizeof r);
    for (int i = 0; i < c->refinement_count; ++i) {
        const struct gsn_refinement *f = &c->refinements[i];
        r[i].kind = f->kind;
        memcpy(r[i].box, f->box, sizeof r[i].box);
        r[i].spacing = f->spacing;
        r[i].width = f->width;
        r[i].distance = f->distance;
        if (f->kind != GSN_REFINE_SURFACE)
            continue;
        /* the coarse triangles of the surface's entities */
        int tag = -1, ierr = 0, *entities = NULL;
        size_t entity_count = 0;
        GSN_CALL_GOTO(physical_surface_tag(f->surface, &tag), rc, done);
        gmshModelGetEntitiesForPhysicalGroup(2, tag, &entities, &entity_count,
                                             &ierr);
        triangles[i] =
            malloc(sizeof(int) * 3 * ((size_t)m->triangle_count + 1));
        int count = 0;
        for (int t = 0; ierr == 0 && triangles[i] && t < m->triangle_count; ++t)
            for (size_t e = 0; e < entity_count; ++e)
                if (entities[e] == m->triangle_surface[t]) {
                    memcpy(&triangles[i][3 * count++], &m->triangles[3 * t],
                           sizeof(int[3]));
                    break;
                }
        gmshFree(entities);
        GSN_CHECK_GOTO(ierr == 0, rc, GSN_ERR_LIBRARY, done,
                       "cannot list the entities of surface %s", f->surface);
        GSN_CHECK_GOTO(triangles[i] != NULL, rc, GSN_ERR_MEMORY, done,
                       "out of memory");
        r[i].triangles = triangles[i];
        r[i].triangle_count = count;
    }
    struct estimate_body body = {
        m->node_count,     m->position,  m->tetrahedron_count, m->tetrahedra,
        m->triangle_count, m->triangles, m->segment_count,     m->segments};
    GSN_CALL_GOTO(estimate_particles(&body, c->particle_spacing, r,
                                     c->refinement_count, k, cap, estimate,
                                     at_least),
                  rc, done);
done:
    for (int i = 0; i < c->refinement_count; ++i)
        free(triangles[i]);
    return rc;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int particle_tagged(const struct gsn_model *m, int p)
{
    return m->particle_surface_offset[p + 1] > m->particle_surface_offset[p];
}

/* Distance from x to the nearest particle of surface s (brute force). */
static double distance_to_surface(const struct gsn_model *m, const int *on,
                                  int on_count, const double *x)
{
    double best = HUGE_VAL;
    for (int i = 0; i < on_count; ++i) {
        const double *y = &m->position[3 * on[i]];
        double d = (x[0] - y[0]) * (x[0] - y[0]) +
                   (x[1] - y[1]) * (x[1] - y[1]) +
                   (x[2] - y[2]) * (x[2] - y[2]);
        best = fmin(best, d);
    }
    return sqrt(best);
}

/* in[p]: 2 if particle p is in the core of the region (where its spacing
 * holds: inside a box, within the width and a quarter of the distance of a
 * surface), 1 if in its transition (a box grown by its distance, the rest
 * of a surface's width + distance), else 0. region -1: outside every region and
 * transition. */
static int region_members(const struct gsn_case *c, const struct gsn_model *m,
                          int region, char *in)
{
    int n = m->particle_count;
    if (region < 0) {
        memset(in, 2, (size_t)n);
        for (int r = 0; r < c->refinement_count; ++r) {
            char *other = malloc((size_t)n + 1);
            GSN_CHECK(other, GSN_ERR_MEMORY, "out of memory");
            int rc = region_members(c, m, r, other);
            for (int p = 0; rc == GSN_OK && p < n; ++p)
                if (other[p])
                    in[p] = 0;
            free(other);
            GSN_CALL(rc);
        }
        return GSN_OK;
    }
    const struct gsn_refinement *f = &c->refinements[region];
    if (f->kind == GSN_REFINE_BOX) {
        for (int p = 0; p < n; ++p) {
            const double *x = &m->position[3 * p];
            int inside = 1, near = 1;
            for (int k = 0; k < 3; ++k) {
                inside &= x[k] >= f->box[k] && x[k] <= f->box[k + 3];
                near &= x[k] >= f->box[k] - f->distance &&
                        x[k] <= f->box[k + 3] + f->distance;
            }
            in[p] = (char)(inside ? 2 : near ? 1 : 0);
        }
        return GSN_OK;
    }
    int surface = gsn_model_find_surface(m, f->surface);
    GSN_CHECK(surface >= 0, GSN_ERR_INPUT,
              "%s:%d: refinement surface '%s' is not in the model", c->path,
              f->line, f->surface);
    int *on = malloc(sizeof(int) * ((size_t)n + 1)), on_count = 0;
    GSN_CHECK(on, GSN_ERR_MEMORY, "out of memory");
    for (int p = 0; p < n; ++p)
        if (gsn_model_particle_on_surface(m, p, surface))
            on[on_count++] = p;
    double core = f->width + 0.25 * f->distance;
    for (int p = 0; p < n; ++p) {
        double d = distance_to_surface(m, on, on_count, &m->position[3 * p]);
        in[p] = (char)(d <= core ? 2 : d <= f->width + f->distance ? 1 : 0);
    }
    free(on);
    return GSN_OK;
}

int gsn_pre_refinement_stats(const struct gsn_case *c,
                             const struct gsn_model *m, int region, int *count,
                             double *cell_size)
{
    GSN_CHECK(region >= -1 && region < c->refinement_count, GSN_ERR_INTERNAL,
              "refinement region %d of %d", region, c->refinement_count);
    int n = m->particle_count;
    char *in = malloc((size_t)n + 1);
    double *size = malloc(sizeof(double) * ((size_t)n + 1));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(in && size, rc, GSN_ERR_MEMORY, done, "out of memory");
    GSN_CALL_GOTO(region_members(c, m, region, in), rc, done);
    int sizes = 0;
    *count = 0;
    for (int p = 0; p < n; ++p) {
        *count += in[p] != 0;
        if (in[p] == 2 && !particle_tagged(m, p))
            size[sizes++] = cbrt(m->volume[p]);
    }
    qsort(size, (size_t)sizes, sizeof(double), compare_doubles);
    *cell_size = sizes ? size[sizes / 2] : 0.0;
done:
    free(in);
    free(size);
    return rc;
}

int pre_refine_report(const struct gsn_case *c, const struct gsn_model *m)
{
    if (c->refinement_count == 0)
        return GSN_OK;
    for (int r = -1; r < c->refinement_count; ++r) {
        int count = 0;
        double size = 0.0;
        GSN_CALL(gsn_pre_refinement_stats(c, m, r, &count, &size));
        if (r < 0) {
            printf("pre: outside the refinements: %d particles, median cell "
                   "size %.3g m (spacing %g m)\n",
                   count, size, c->particle_spacing);
            continue;
        }
        const struct gsn_refinement *f = &c->refinements[r];
        if (f->kind == GSN_REFINE_BOX)
            printf("pre: refine[%d] box [%g, %g, %g]-[%g, %g, %g]: %d "
                   "particles, median cell size %.3g m (spacing %g m)\n",
                   r, f->box[0], f->box[1], f->box[2], f->box[3], f->box[4],
                   f->box[5], count, size, f->spacing);
        else
            printf("pre: refine[%d] within %g m of surface '%s': %d "
                   "particles, median cell size %.3g m within %g m (spacing "
                   "%g m)\n",
                   r, f->width + f->distance, f->surface, count, size,
                   f->width + 0.25 * f->distance, f->spacing);
    }
    return GSN_OK;
}
