/* Rigid bodies the soil cannot enter: see contact.h. */
#include "contact.h"
#include "constraint.h"
#include "geoscni/cells.h"
#include "geoscni/error.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The penalty stiffness over m_I / dt^2: the contact adds at most about
 * this to (omega dt)^2, which the explicit step keeps below 4; with
 * time.safety 0.8 the soil takes 2.56 of it. A particle pressed by a
 * stress sigma sinks about sigma / M h / CONTACT_STIFFNESS into the body
 * (M the constrained modulus, h the spacing): 1e-3 h for the footings'
 * clay. */
#define CONTACT_STIFFNESS 0.5
/* An edge whose outward normal lies within this cosine of a held
 * component's axis is not an exit (contact.h). */
#define EXIT_AXIS_COSINE 0.9
/* Bodies per case. */
enum { CONTACT_MAX_BODIES = 8 };
/* A footprint point within this much of a triangle's barycentric range is
 * in it (the base's own particles lie on its edges). */
#define FOOTPRINT_TOLERANCE 1e-9

struct body {
    int entry;          /* the case's boundary entry */
    int surface;        /* its surface on the models */
    double velocity[3]; /* m/s, 0 where not prescribed */
    double frame[3][3]; /* a, b across the motion, c against it */
    int triangle_count;
    double *triangle; /* x 9: the vertices' (a, b, c) at t = 0 */
    double *normal;   /* x 3: unit normal out of the body, world axes */
    int exit_count;
    double *exit; /* x 6: a0, b0, a1, b1 and the unit outward normal */
    double low[2], high[2]; /* the footprint's box in (a, b), m */
    double base_low;        /* the base's lowest c, m */
    /* the footprint's triangles by cell of a grid over its box (CSR) */
    int grid[2];
    double cell[2];
    int *cell_offset, *cell_triangle;
};

struct gsn_contact {
    int particle_count;
    double ramp; /* s, time.ramp */
    int body_count;
    struct body body[CONTACT_MAX_BODIES];
};

void gsn_contact_destroy(struct gsn_contact **handle)
{
    if (!handle || !*handle)
        return;
    struct gsn_contact *k = *handle;
    for (int b = 0; b < k->body_count; ++b) {
        free(k->body[b].triangle);
        free(k->body[b].normal);
        free(k->body[b].exit);
        free(k->body[b].cell_offset);
        free(k->body[b].cell_triangle);
    }
    free(k);
    *handle = NULL;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* c against the motion, a and b completing a right-handed frame. */
static void body_frame(const double velocity[3], double frame[3][3])
{
    double speed = sqrt(dot3(velocity, velocity));
    for (int k = 0; k < 3; ++k)
        frame[2][k] = -velocity[k] / speed;
    int least = 0; /* the world axis least aligned with c */
    for (int k = 1; k < 3; ++k)
        if (fabs(frame[2][k]) < fabs(frame[2][least]))
            least = k;
    double e[3] = {0, 0, 0};
    e[least] = 1.0;
    double along = dot3(e, frame[2]), norm = 0.0;
    for (int k = 0; k < 3; ++k) {
        frame[0][k] = e[k] - along * frame[2][k];
        norm += frame[0][k] * frame[0][k];
    }
    for (int k = 0; k < 3; ++k)
        frame[0][k] /= sqrt(norm);
    const double *c = frame[2], *a = frame[0];
    frame[1][0] = c[1] * a[2] - c[2] * a[1];
    frame[1][1] = c[2] * a[0] - c[0] * a[2];
    frame[1][2] = c[0] * a[1] - c[1] * a[0];
}

/* 1 if soil cannot leave through the edge (i, j) along the outward normal
 * n (world axes): a surface other than the body's own that carries both
 * particles holds the component n points along, or plane_strain does. */
static int edge_held(const struct gsn_model *m, const struct gsn_case *c,
                     int own, int i, int j, const double n[3])
{
    for (int k = 0; k < 3; ++k) {
        if (fabs(n[k]) < EXIT_AXIS_COSINE)
            continue;
        if (c->plane_strain_axis == k)
            return 1;
        for (int e = m->particle_surface_offset[i];
             e < m->particle_surface_offset[i + 1]; ++e) {
            int s = m->particle_surface[e];
            if (s == own || !gsn_model_particle_on_surface(m, j, s))
                continue;
            int entry = gsn_case_find_boundary(c, m->surface_name[s]);
            if (entry >= 0 && (c->boundaries[entry].fixed[k] ||
                               c->boundaries[entry].has_velocity[k]))
                return 1;
        }
    }
    return 0;
}

/* The surface's triangles (the tetrahedra's faces on it) in the body's
 * frame, with their normals out of the body (the faces' own normals point
 * out of the soil, into the body). */
static int collect_triangles(const struct gsn_model *m, int surface,
                             struct body *body, int **vertex)
{
    int count = 0;
    for (int t = 0; t < 4 * m->tetrahedron_count; ++t)
        count += m->tetrahedron_face[t] == surface;
    body->triangle = malloc(sizeof(double) * 9 * (size_t)(count + 1));
    body->normal = malloc(sizeof(double) * 3 * (size_t)(count + 1));
    *vertex = malloc(sizeof(int) * 3 * (size_t)(count + 1));
    GSN_CHECK(body->triangle && body->normal && *vertex, GSN_ERR_MEMORY,
              "out of memory");
    count = 0;
    for (int t = 0; t < m->tetrahedron_count; ++t)
        for (int f = 0; f < 4; ++f) {
            if (m->tetrahedron_face[4 * t + f] != surface)
                continue;
            const double *x[3];
            for (int v = 0; v < 3; ++v) {
                int i = m->tetrahedra[4 * t + gsn_cells_tetrahedron_face[f][v]];
                (*vertex)[3 * count + v] = i;
                x[v] = &m->position[3 * (size_t)i];
                for (int a = 0; a < 3; ++a)
                    body->triangle[9 * count + 3 * v + a] =
                        dot3(x[v], body->frame[a]);
            }
            double u[3], w[3], *n = &body->normal[3 * count];
            for (int a = 0; a < 3; ++a) {
                u[a] = x[1][a] - x[0][a];
                w[a] = x[2][a] - x[0][a];
            }
            n[0] = -(u[1] * w[2] - u[2] * w[1]);
            n[1] = -(u[2] * w[0] - u[0] * w[2]);
            n[2] = -(u[0] * w[1] - u[1] * w[0]);
            double norm = sqrt(dot3(n, n));
            for (int a = 0; a < 3; ++a)
                n[a] /= norm;
            ++count;
        }
    body->triangle_count = count;
    return GSN_OK;
}

/* The edges of the footprint (used by one triangle) that soil can leave
 * through, with their outward normals. */
static int collect_exits(const struct gsn_model *m, const struct gsn_case *c,
                         int surface, struct body *body, const int *vertex)
{
    int n = body->triangle_count;
    body->exit = malloc(sizeof(double) * 6 * (size_t)(3 * n + 1));
    GSN_CHECK(body->exit, GSN_ERR_MEMORY, "out of memory");
    body->exit_count = 0;
    for (int t = 0; t < n; ++t)
        for (int e = 0; e < 3; ++e) {
            int i = vertex[3 * t + e], j = vertex[3 * t + (e + 1) % 3];
            int shared = 0;
            for (int u = 0; u < n && !shared; ++u)
                for (int f = 0; f < 3 && u != t; ++f)
                    if ((vertex[3 * u + f] == i &&
                         vertex[3 * u + (f + 1) % 3] == j) ||
                        (vertex[3 * u + f] == j &&
                         vertex[3 * u + (f + 1) % 3] == i))
                        shared = 1;
            if (shared)
                continue;
            const double *p0 = &body->triangle[9 * t + 3 * e],
                         *p1 = &body->triangle[9 * t + 3 * ((e + 1) % 3)],
                         *p2 = &body->triangle[9 * t + 3 * ((e + 2) % 3)];
            double na = p1[1] - p0[1], nb = -(p1[0] - p0[0]);
            double norm = hypot(na, nb);
            if (norm == 0.0)
                continue;
            na /= norm;
            nb /= norm;
            if (na * (p2[0] - p0[0]) + nb * (p2[1] - p0[1]) > 0.0) {
                na = -na;
                nb = -nb;
            }
            double world[3];
            for (int k = 0; k < 3; ++k)
                world[k] = na * body->frame[0][k] + nb * body->frame[1][k];
            if (edge_held(m, c, surface, i, j, world))
                continue;
            double *x = &body->exit[6 * body->exit_count++];
            x[0] = p0[0];
            x[1] = p0[1];
            x[2] = p1[0];
            x[3] = p1[1];
            x[4] = na;
            x[5] = nb;
        }
    return GSN_OK;
}

/* The footprint's box and a grid of about two triangles a cell. */
static int build_grid(struct body *body)
{
    int n = body->triangle_count;
    body->low[0] = body->low[1] = body->base_low = DBL_MAX;
    body->high[0] = body->high[1] = -DBL_MAX;
    for (int v = 0; v < 3 * n; ++v) {
        const double *x = &body->triangle[3 * v];
        for (int a = 0; a < 2; ++a) {
            body->low[a] = fmin(body->low[a], x[a]);
            body->high[a] = fmax(body->high[a], x[a]);
        }
        body->base_low = fmin(body->base_low, x[2]);
    }
    int side = (int)ceil(sqrt(0.5 * n));
    for (int a = 0; a < 2; ++a) {
        body->grid[a] = side;
        body->cell[a] = (body->high[a] - body->low[a]) / side;
        if (!(body->cell[a] > 0.0))
            body->cell[a] = 1.0;
    }
    int cells = side * side;
    body->cell_offset = calloc((size_t)cells + 1, sizeof(int));
    GSN_CHECK(body->cell_offset, GSN_ERR_MEMORY, "out of memory");
    int *range = malloc(sizeof(int) * 4 * (size_t)(n + 1));
    GSN_CHECK(range, GSN_ERR_MEMORY, "out of memory");
    for (int pass = 0; pass < 2; ++pass) {
        for (int t = 0; t < n; ++t) {
            int *r = &range[4 * t];
            if (pass == 0)
                for (int a = 0; a < 2; ++a) {
                    double lo = DBL_MAX, hi = -DBL_MAX;
                    for (int v = 0; v < 3; ++v) {
                        lo = fmin(lo, body->triangle[9 * t + 3 * v + a]);
                        hi = fmax(hi, body->triangle[9 * t + 3 * v + a]);
                    }
                    r[2 * a] = (int)floor((lo - body->low[a]) / body->cell[a]);
                    r[2 * a + 1] =
                        (int)floor((hi - body->low[a]) / body->cell[a]);
                    r[2 * a] = r[2 * a] < 0 ? 0 : r[2 * a];
                    r[2 * a + 1] =
                        r[2 * a + 1] >= side ? side - 1 : r[2 * a + 1];
                }
            for (int i = r[0]; i <= r[1]; ++i)
                for (int j = r[2]; j <= r[3]; ++j) {
                    int cell = i * side + j;
                    if (pass == 0)
                        body->cell_offset[cell + 1]++;
                    else
                        body->cell_triangle[body->cell_offset[cell]++] = t;
                }
        }
        if (pass == 0) {
            for (int k = 0; k < cells; ++k)
                body->cell_offset[k + 1] += body->cell_offset[k];
            body->cell_triangle =
                malloc(sizeof(int) * ((size_t)body->cell_offset[cells] + 1));
            if (!body->cell_triangle) {
                free(range);
                GSN_CHECK(0, GSN_ERR_MEMORY, "out of memory");
            }
        }
    }
    for (int k = cells; k > 0; --k) /* the fill moved each offset one on */
        body->cell_offset[k] = body->cell_offset[k - 1];
    body->cell_offset[0] = 0;
    free(range);
    return GSN_OK;
}

int gsn_contact_create(const struct gsn_model *original,
                       const struct gsn_case *c, struct gsn_contact **out)
{
    *out = NULL;
    int rigid = 0;
    for (int b = 0; b < c->boundary_count; ++b)
        rigid += c->boundaries[b].rigid;
    if (!rigid)
        return GSN_OK;
    GSN_CHECK(rigid <= CONTACT_MAX_BODIES, GSN_ERR_INPUT,
              "%s: %d boundary entries are rigid; at most %d can be", c->path,
              rigid, CONTACT_MAX_BODIES);
    struct gsn_contact *k = calloc(1, sizeof *k);
    GSN_CHECK(k, GSN_ERR_MEMORY, "out of memory");
    k->particle_count = original->particle_count;
    k->ramp = c->time_ramp;
    int rc = GSN_OK;
    for (int e = 0; e < c->boundary_count && rc == GSN_OK; ++e) {
        const struct gsn_boundary *entry = &c->boundaries[e];
        if (!entry->rigid)
            continue;
        struct body *body = &k->body[k->body_count];
        body->entry = e;
        body->surface = gsn_model_find_surface(original, entry->name);
        for (int a = 0; a < 3; ++a)
            body->velocity[a] = entry->has_velocity[a] ? entry->velocity[a] : 0;
        body_frame(body->velocity, body->frame);
        int surface = body->surface, *vertex = NULL;
        rc = surface >= 0 ? collect_triangles(original, surface, body, &vertex)
                          : GSN_ERR_INPUT;
        if (rc == GSN_OK && body->triangle_count == 0)
            rc = GSN_ERR_INPUT;
        if (rc == GSN_ERR_INPUT)
            gsn_error_raise(rc, __FILE__, __LINE__, __func__,
                            "%s:%d: the rigid surface '%s' has no faces on "
                            "the model's boundary: name a physical surface "
                            "of the geometry",
                            c->path, entry->line, entry->name);
        if (rc == GSN_OK)
            rc = collect_exits(original, c, surface, body, vertex);
        free(vertex);
        ++k->body_count;
        if (rc == GSN_OK)
            rc = build_grid(body);
    }
    if (rc != GSN_OK) {
        gsn_contact_destroy(&k);
        return rc;
    }
    *out = k;
    return GSN_OK;
}

/* The base triangle under footprint point p, or -1; lambda its
 * barycentric coordinates. */
static int find_triangle(const struct body *body, const double p[2],
                         double lambda[3])
{
    int i = (int)floor((p[0] - body->low[0]) / body->cell[0]),
        j = (int)floor((p[1] - body->low[1]) / body->cell[1]);
    i = i < 0 ? 0 : i >= body->grid[0] ? body->grid[0] - 1 : i;
    j = j < 0 ? 0 : j >= body->grid[1] ? body->grid[1] - 1 : j;
    int cell = i * body->grid[1] + j;
    for (int k = body->cell_offset[cell]; k < body->cell_offset[cell + 1];
         ++k) {
        int t = body->cell_triangle[k];
        const double *x = &body->triangle[9 * t];
        double d1[2] = {x[3] - x[0], x[4] - x[1]},
               d2[2] = {x[6] - x[0], x[7] - x[1]},
               r[2] = {p[0] - x[0], p[1] - x[1]};
        double det = d1[0] * d2[1] - d1[1] * d2[0];
        if (det == 0.0)
            continue; /* a face along the motion: a wall, not a base */
        double l1 = (r[0] * d2[1] - r[1] * d2[0]) / det,
               l2 = (d1[0] * r[1] - d1[1] * r[0]) / det;
        if (l1 >= -FOOTPRINT_TOLERANCE && l2 >= -FOOTPRINT_TOLERANCE &&
            l1 + l2 <= 1.0 + FOOTPRINT_TOLERANCE) {
            lambda[0] = 1.0 - l1 - l2;
            lambda[1] = l1;
            lambda[2] = l2;
            return t;
        }
    }
    return -1;
}

/* Depth of point y (world axes, in the body's position at t = 0) inside
 * the body and the unit way out, or 0 outside. */
static double body_depth(const struct body *body, const double y[3],
                         double way[3])
{
    double p[2] = {dot3(y, body->frame[0]), dot3(y, body->frame[1])},
           s = dot3(y, body->frame[2]), lambda[3];
    if (s <= body->base_low || p[0] < body->low[0] || p[0] > body->high[0] ||
        p[1] < body->low[1] || p[1] > body->high[1])
        return 0.0;
    int t = find_triangle(body, p, lambda);
    if (t < 0)
        return 0.0;
    const double *x = &body->triangle[9 * t], *n = &body->normal[3 * t];
    double above = s - (lambda[0] * x[2] + lambda[1] * x[5] + lambda[2] * x[8]);
    if (above <= 0.0)
        return 0.0;
    double depth = above * fabs(dot3(n, body->frame[2]));
    for (int k = 0; k < 3; ++k)
        way[k] = n[k];
    for (int e = 0; e < body->exit_count; ++e) {
        const double *q = &body->exit[6 * e];
        double d[2] = {q[2] - q[0], q[3] - q[1]},
               r[2] = {p[0] - q[0], p[1] - q[1]};
        double length2 = d[0] * d[0] + d[1] * d[1];
        double f = length2 > 0.0 ? (r[0] * d[0] + r[1] * d[1]) / length2 : 0;
        f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
        double distance = hypot(r[0] - f * d[0], r[1] - f * d[1]);
        if (distance < depth) {
            depth = distance;
            for (int k = 0; k < 3; ++k)
                way[k] = q[4] * body->frame[0][k] + q[5] * body->frame[1][k];
        }
    }
    return depth;
}

/* Where body b has moved by time t: v D(t) (constraint.h). */
static void body_moved(const struct gsn_contact *contact, int b, double time,
                       double moved[3])
{
    const double travel =
        gsn_ramp_factor(contact->ramp, GSN_FIELD_DISPLACEMENT, time);
    for (int k = 0; k < 3; ++k)
        moved[k] = contact->body[b].velocity[k] * travel;
}

void gsn_contact_release(const struct gsn_contact *contact,
                         const struct gsn_model *m, double time,
                         unsigned *released)
{
    for (int b = 0; b < contact->body_count; ++b) {
        const struct body *body = &contact->body[b];
        double moved[3];
        body_moved(contact, b, time, moved);
        for (int i = 0; i < m->particle_count; ++i) {
            if (!gsn_model_particle_on_surface(m, i, body->surface))
                continue;
            double y[3], lambda[3];
            for (int k = 0; k < 3; ++k)
                y[k] = m->position[3 * (size_t)i + k] - moved[k];
            double p[2] = {dot3(y, body->frame[0]), dot3(y, body->frame[1])};
            if (find_triangle(body, p, lambda) < 0)
                released[i] |= 1u << body->entry;
        }
    }
}

int gsn_contact_forces(const struct gsn_contact *contact,
                       const struct gsn_constraints *constraints,
                       const double *position,
                       const struct gsn_shape_rows *values,
                       const double *displacement, const double *mass,
                       double dt, double time, double margin, double *force,
                       double resultant[][3], int *inside)
{
    const int n = contact->particle_count;
    GSN_CHECK(values->row_count == n, GSN_ERR_INTERNAL,
              "contact: shape values are not one row per particle");
    memset(force, 0, sizeof(double) * 3 * (size_t)n);
    double moved[CONTACT_MAX_BODIES][3];
    for (int b = 0; b < contact->body_count; ++b) {
        body_moved(contact, b, time, moved[b]);
        for (int k = 0; k < 3; ++k)
            resultant[contact->body[b].entry][k] = 0.0;
    }
    *inside = 0;
    const double stiffness = CONTACT_STIFFNESS / (dt * dt);
    for (int i = 0; i < n; ++i) {
        const double *X = &position[3 * (size_t)i],
                     *d = &displacement[3 * (size_t)i];
        double x[3] = {0, 0, 0};
        int exact = 0;
        for (int b = 0; b < contact->body_count; ++b) {
            const struct body *body = &contact->body[b];
            /* the coefficient's position within margin first: cheap */
            double y[3];
            for (int k = 0; k < 3; ++k)
                y[k] = X[k] + d[k] - moved[b][k];
            double p[2] = {dot3(y, body->frame[0]), dot3(y, body->frame[1])};
            if (dot3(y, body->frame[2]) <= body->base_low - margin ||
                p[0] < body->low[0] - margin || p[0] > body->high[0] + margin ||
                p[1] < body->low[1] - margin || p[1] > body->high[1] + margin)
                continue;
            if (!exact) { /* x = X + sum_J Psi_J(X_I) d_J */
                for (int k = 0; k < 3; ++k)
                    x[k] = X[k];
                for (int e = values->offset[i]; e < values->offset[i + 1]; ++e)
                    for (int k = 0; k < 3; ++k)
                        x[k] += values->value[e] *
                                displacement[3 * (size_t)values->index[e] + k];
                exact = 1;
            }
            if (constraints &&
                gsn_constraints_holds(constraints, i, body->entry))
                continue;
            for (int k = 0; k < 3; ++k)
                y[k] = x[k] - moved[b][k];
            double way[3];
            double depth = body_depth(body, y, way);
            if (depth <= 0.0)
                continue;
            ++*inside;
            double push = stiffness * mass[i] * depth;
            for (int k = 0; k < 3; ++k)
                resultant[body->entry][k] += push * way[k];
            for (int e = values->offset[i]; e < values->offset[i + 1]; ++e)
                for (int k = 0; k < 3; ++k)
                    force[3 * (size_t)values->index[e] + k] +=
                        values->value[e] * push * way[k];
        }
    }
    return GSN_OK;
}
