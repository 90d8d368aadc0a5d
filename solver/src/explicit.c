/* The explicit loop: see explicit.h for the algorithm and equations. */
#include "explicit.h"
#include "geoscni/error.h"
#include "geoscni/tensor.h"
#include "nonlocal.h"
#include "point_blocks.h"
#include "stress_update.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Steps between corrections of d and v to the constraints (see
 * gsn_explicit_step); the first step is always one. */
enum { CONSTRAINT_REFRESH = 64 };
/* Loops over fewer items than this run on one thread: the start-up of a
 * parallel region costs more than they do (and spin-waiting threads on a
 * loaded machine cost far more). */
enum { PARALLEL_MIN_ITEMS = 2048 };
/* Main points per block of the one-pass step (point_blocks.h), without
 * and with stabilization points; at most CHUNK. A larger block shares its
 * slots among more rows (SCNI Slope I: 5.6 instead of 7.7 a particle at 128;
 * the pass 10% faster than at 64, 256 another 3%); its increments, 4
 * doubles a slot, still fit the 32 kB L1. */
enum { BLOCK_POINTS = 128, BLOCK_POINTS_STABILIZED = 32 };
/* Particles (or points) per piece of the step's loops and sums
 * (step_loop). */
enum { SUM_PIECE = 1024 };
/* Columns of a block's distortion (explicit.h, block_distortion). */
enum { DISTORTION_COLUMNS = 6 };
/* Points per batch of the material update. */
enum { CHUNK = 128 };
_Static_assert((int)CHUNK <= (int)GSN_MATERIAL_MAX_COLUMN,
               "gsn_stress_update_columns takes at most "
               "GSN_MATERIAL_MAX_COLUMN points");
/* Doubles of per-thread work per batch (main_chunk), all in columns: H,
 * dH, new H, G, det F and det F_mid, strain, stress, old stress, strain
 * increment, old equivalent plastic strain, its step, the old and new pore
 * pressure; the state (state_size columns) besides. */
enum { CHUNK_WORK = CHUNK * (9 * 4 + 3 + 6 * 3 + 4) };
/* Lanczos steps of the stable-step estimate: at most LANCZOS_STEPS; it
 * stops when the largest Ritz value's residual bound is below
 * LANCZOS_TOLERANCE of it (the estimate is then that value plus the
 * bound: from above). */
enum { LANCZOS_STEPS = 120 };
#define LANCZOS_TOLERANCE 1e-4

/* The sums of a step over the particles (or points) of one range. */
struct gsn_step_sums {
    double dissipated, external, kinetic, internal; /* J */
    double kinetic_conserved; /* J, explicit.h: conserved_kinetic_energy */
    double released;     /* J: the work of the released force (release_force) */
    int first_nonfinite; /* the lowest particle whose velocity is not
                            finite, or -1 */
};

static size_t block_work_size(const struct gsn_explicit *e);

static int parallel_worth(int items)
{
    return items >= PARALLEL_MIN_ITEMS;
}

static int alloc_array(void **array, size_t count, size_t size)
{
    *array = calloc(count ? count : 1, size);
    GSN_CHECK(*array != NULL, GSN_ERR_MEMORY,
              "cannot allocate %zu values of %zu bytes", count, size);
    return GSN_OK;
}

void gsn_explicit_destroy(struct gsn_explicit **handle)
{
    if (!handle || !*handle)
        return;
    struct gsn_explicit *e = *handle;
    double *arrays[] = {e->mass,
                        e->lumped_mass,
                        e->particle_stiffness,
                        e->displacement,
                        e->velocity,
                        e->acceleration,
                        e->f_ext,
                        e->f_ext_full,
                        e->f_int,
                        e->reaction,
                        e->stress,
                        e->state,
                        e->previous_displacement,
                        e->previous_external,
                        e->new_acceleration,
                        e->piola,
                        e->point_energy,
                        e->thread_work,
                        e->thread_part_ticks,
                        e->damping_force,
                        e->point_mass,
                        e->reference_offset,
                        e->reference_gradient,
                        e->block_distortion,
                        e->contact_force,
                        e->pore_pressure,
                        e->release_force};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i)
        free(arrays[i]);
    free(e->point_failed);
    free(e->block_taken);
    free(e->block_deque);
    free(e->increment);
    free(e->displacement_gradient);
    free(e->slot_force);
    gsn_point_blocks_destroy(&e->blocks);
    gsn_nonlocal_destroy(&e->nonlocal);
    free(e->domain_offset);
    free(e->domain_point);
    free(e->domain_weight);
    free(e->point_owner);
    free(e->step_partial);
    free(e->constrained);
    free(e->point_dead);
    free(e->point_material);
    free(e);
    *handle = NULL;
}

/* sum_p P_p over the points of the nodal domain of particle `cell` (P
 * includes the weights): the nodal point's own P with nodal integration
 * (returned without a copy), else summed into sum. */
static const double *domain_piola(const struct gsn_explicit *e, int cell,
                                  double sum[9])
{
    int k0 = e->domain_offset[cell], k1 = e->domain_offset[cell + 1];
    const double *P = &e->piola[9 * (size_t)e->domain_point[k0]];
    if (k1 - k0 == 1)
        return P;
    memcpy(sum, P, 9 * sizeof(double));
    for (int k = k0 + 1; k < k1; ++k)
        for (int a = 0; a < 9; ++a)
            sum[a] += e->piola[9 * (size_t)e->domain_point[k] + a];
    return sum;
}

/* The nominal traction P N / V at boundary quadrature point b, from the
 * first-pass stress of the facet's nodal domain (its points' P summed over
 * their weights V): the nodal point's with nodal integration, the mean of
 * the domain's Gauss points with Gauss. */
static void boundary_traction(const struct gsn_explicit *e, int b, double t[3])
{
    const struct gsn_quadrature *q = e->quadrature;
    int f = q->boundary_point_facet[b];
    int cell = e->model->facet_owner[f];
    double sum[9];
    const double *P = domain_piola(e, cell, sum);
    const double *N = &e->model->facet_normal[3 * f];
    double scale = 1.0 / e->domain_weight[cell];
    for (int i = 0; i < 3; ++i)
        t[i] = scale *
               (P[3 * i] * N[0] + P[3 * i + 1] * N[1] + P[3 * i + 2] * N[2]);
}

/* The boundary term of before 2026-12-02 evening (explicit.h,
 * legacy_boundary_term), taken off f_int. */
static void legacy_boundary_term(struct gsn_explicit *e)
{
    const struct gsn_quadrature *q = e->quadrature;
    const struct gsn_shape_rows *values = &q->boundary_values;
    for (int b = 0; b < q->boundary_point_count && e->constraints; ++b) {
        int facet = q->boundary_point_facet[b];
        int mask = gsn_constraints_facet_mask(e->constraints,
                                              e->model->facet_surface[facet],
                                              e->model->facet_owner[facet]);
        if (!mask)
            continue;
        double t[3];
        boundary_traction(e, b, t);
        for (int k = values->offset[b]; k < values->offset[b + 1]; ++k)
            for (int i = 0; i < 3; ++i)
                if (mask & (1 << i))
                    e->f_int[3 * (size_t)values->index[k] + (size_t)i] -=
                        values->value[k] * t[i] * q->boundary_point_weight[b];
    }
}

void gsn_explicit_surface_force(const struct gsn_explicit *e, int surface,
                                int mask, double force[3])
{
    const struct gsn_quadrature *q = e->quadrature;
    force[0] = force[1] = force[2] = 0.0;
    for (int b = 0; b < q->boundary_point_count; ++b) {
        if (e->model->facet_surface[q->boundary_point_facet[b]] != surface)
            continue;
        double t[3];
        boundary_traction(e, b, t);
        /* a released particle's facets hold nothing (constraint.h) */
        int facet = q->boundary_point_facet[b];
        int held = e->constraints ? mask & gsn_constraints_facet_mask(
                                               e->constraints,
                                               e->model->facet_surface[facet],
                                               e->model->facet_owner[facet])
                                  : mask;
        for (int i = 0; i < 3; ++i)
            if (held & (1 << i))
                force[i] += t[i] * q->boundary_point_weight[b];
    }
}

/* k_I = sum_L w_L (K + 4/3 G)_L |grad Psi_I(X_L)|^2 over the main points,
 * N/m: the stiffness's diagonal block at particle I is at most this along
 * any direction (eq. (32) linearized; a measure, not the stabilization's
 * share). From the quadrature's gradient rows, which the caller frees once
 * the loop has packed them (reference.c), so made at creation. */
static int particle_stiffness(struct gsn_explicit *e)
{
    const struct gsn_shape_rows *g = &e->quadrature->gradient;
    GSN_CHECK(g->gradient, GSN_ERR_INTERNAL,
              "mass scaling needs the gradient rows");
    GSN_CALL(alloc_array((void **)&e->particle_stiffness,
                         (size_t)e->particle_count, sizeof(double)));
    double *k = e->particle_stiffness;
    for (int p = 0; p < e->main_point_count; ++p) {
        int m = e->point_material[p];
        double modulus = e->quadrature->point_weight[p] *
                         (e->bulk_modulus[m] + 4.0 / 3.0 * e->shear_modulus[m]);
        for (int j = g->offset[p]; j < g->offset[p + 1]; ++j) {
            const double *d = &g->gradient[3 * (size_t)j];
            k[g->index[j]] +=
                modulus * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
    return GSN_OK;
}

struct mass_ratio {
    double ratio; /* m_I / k_I, s^2 */
    int particle;
};

static int by_ratio(const void *a, const void *b)
{
    const struct mass_ratio *x = a, *y = b;
    if (x->ratio != y->ratio)
        return x->ratio < y->ratio ? -1 : 1;
    return x->particle - y->particle;
}

/* Mass scaling (time.mass_scaling = F; docs/solver.md "Mass scaling"): the
 * particles whose lumped mass is small against their stiffness (cells cut
 * by the body's edges and corners) set the stable step; each gets
 * m_I' = max(m_I, s k_I) (particle_stiffness), s the largest for which the
 * added mass is F times the body's. Between two consecutive ratios
 * t_j = m_j / k_j (ascending) the added mass is s K_j - M_j (K_j, M_j the
 * sums of k and m up to j), linear in s. Particles whose three components
 * the constraints hold get none. The stable step then comes from Lanczos
 * on the new masses. */
static int scale_masses(struct gsn_explicit *e)
{
    const int n = e->particle_count;
    e->mass_scaled_count = 0;
    e->mass_scaled_largest = 1.0;
    if (!(e->mass_scaling > 0.0))
        return GSN_OK;
    if (!e->particle_stiffness)
        GSN_CALL(particle_stiffness(e));
    const double *k = e->particle_stiffness;
    struct mass_ratio *order = NULL;
    GSN_CALL(alloc_array((void **)&order, (size_t)n, sizeof *order));
    double body = 0.0;
    int stiff = 0;
    const unsigned held_axis = e->held_axis >= 0 ? 1u << e->held_axis : 0u;
    for (int i = 0; i < n; ++i) {
        body += e->mass[i];
        if ((e->constrained[i] | held_axis) == 7u)
            continue; /* held: the constraints move it, not its mass */
        if (k[i] > 0.0)
            order[stiff++] = (struct mass_ratio){e->mass[i] / k[i], i};
    }
    qsort(order, (size_t)stiff, sizeof *order, by_ratio);
    const double budget = e->mass_scaling * body;
    double K = 0.0, M = 0.0, s = 0.0;
    int count = 0;
    while (count < stiff) {
        K += k[order[count].particle];
        M += e->mass[order[count].particle];
        ++count;
        double next = count < stiff ? order[count].ratio : INFINITY;
        if (next * K - M >= budget) {
            s = (budget + M) / K;
            break;
        }
    }
    for (int j = 0; j < count; ++j) {
        int i = order[j].particle;
        double scaled = s * k[i];
        if (scaled > e->mass[i]) {
            e->mass_scaled_largest =
                fmax(e->mass_scaled_largest, scaled / e->mass[i]);
            e->mass[i] = scaled;
            e->mass_scaled_count++;
        }
    }
    free(order);
    return GSN_OK;
}

/* m_I = sum_p Psi_I(x_p) m_p over the main points (eq. (28) with the mass
 * m_p = rho0 w_p that point p carries from the first reference
 * configuration): the nodal points (x_p = X_L; Psi from particle_values)
 * or the Gauss points (Psi from their own rows); f_ext_I = m_I g. By the
 * partition of unity the masses add up to sum_p m_p, the body's mass, on
 * every reference configuration. These are lumped_mass; mass, the loop's,
 * adds mass scaling's share (scale_masses). */
static int build_mass(struct gsn_explicit *e)
{
    const struct gsn_quadrature *q = e->quadrature;
    GSN_CHECK(q->particle_values.row_count == e->particle_count &&
                  q->particle_values.value,
              GSN_ERR_INTERNAL, "shape values are not one row per particle");
    double *lumped = e->lumped_mass;
    memset(lumped, 0, sizeof(double) * (size_t)e->particle_count);
    for (int p = 0; p < e->main_point_count; ++p) {
        int particle = q->point_particle[p];
        const struct gsn_shape_rows *values =
            particle >= 0 ? &q->particle_values : &q->gradient;
        int row = particle >= 0 ? particle : p;
        GSN_CHECK(values->value, GSN_ERR_INTERNAL,
                  "no shape values at integration point %d", p);
        for (int k = values->offset[row]; k < values->offset[row + 1]; ++k)
            lumped[values->index[k]] += values->value[k] * e->point_mass[p];
    }
    for (int i = 0; i < e->particle_count; ++i) {
        GSN_CHECK(lumped[i] > 0.0 && isfinite(lumped[i]), GSN_ERR_NUMERICAL,
                  "the lumped mass of particle %d at (%g, %g, %g) is %g kg, "
                  "not positive: the kernel support is too small or too "
                  "large for the particle spacing",
                  i, q->rk->position[3 * i], q->rk->position[3 * i + 1],
                  q->rk->position[3 * i + 2], lumped[i]);
        for (int k = 0; k < 3; ++k) {
            e->f_ext_full[3 * i + k] = lumped[i] * e->gravity[k];
            e->f_ext[3 * i + k] = e->load_factor * e->f_ext_full[3 * i + k];
        }
    }
    memcpy(e->mass, lumped, sizeof(double) * (size_t)e->particle_count);
    GSN_CALL(scale_masses(e));
    /* the projection is mass-orthogonal: S = C M^-1 C^T with these */
    if (e->constraints)
        GSN_CALL(gsn_constraints_set_mass(e->constraints, e->mass));
    return GSN_OK;
}

void gsn_explicit_set_load_factor(struct gsn_explicit *e, double factor)
{
    if (factor == e->load_factor)
        return;
    for (size_t i = 0; i < 3 * (size_t)e->particle_count; ++i)
        e->f_ext[i] = factor * e->f_ext_full[i];
    e->load_factor = factor;
}

/* The nodal domain of every particle (explicit.h, domain_point): a nodal
 * point belongs to its particle; a Gauss point to the nearest particle of
 * its row (the particles whose kernels cover it: in practice the particle
 * whose Voronoi cell holds it; ties to the lowest index). A particle that
 * gets no Gauss point (possible with one point per tetrahedron) takes the
 * nearest point its kernel covers; every particle covers one, as its mass
 * is positive. Reads the gradient rows, so it runs before they are
 * freed. */
static int build_domains(struct gsn_explicit *e)
{
    const struct gsn_quadrature *q = e->quadrature;
    const struct gsn_shape_rows *g = &q->gradient;
    const double *X = q->rk->position, *x = q->point_position;
    int n = e->particle_count, main = e->main_point_count, rc = GSN_OK;
    int *nearest_point = NULL;
    double *nearest_distance = NULL;
    GSN_CALL(alloc_array((void **)&e->point_owner, (size_t)main, sizeof(int)));
    GSN_CALL(
        alloc_array((void **)&e->domain_offset, (size_t)n + 1, sizeof(int)));
    GSN_CALL(
        alloc_array((void **)&e->domain_weight, (size_t)n, sizeof(double)));
    GSN_CALL_GOTO(alloc_array((void **)&nearest_point, (size_t)n, sizeof(int)),
                  rc, done);
    GSN_CALL_GOTO(
        alloc_array((void **)&nearest_distance, (size_t)n, sizeof(double)), rc,
        done);
    for (int i = 0; i < n; ++i) {
        nearest_point[i] = -1;
        nearest_distance[i] = INFINITY;
    }
    for (int p = 0; p < main; ++p) {
        e->point_owner[p] = q->point_particle[p];
        double closest = INFINITY;
        for (int k = g->offset[p];
             q->point_particle[p] < 0 && k < g->offset[p + 1]; ++k) {
            int I = g->index[k];
            double d = 0.0;
            for (int a = 0; a < 3; ++a)
                d += (x[3 * p + a] - X[3 * I + a]) *
                     (x[3 * p + a] - X[3 * I + a]);
            if (d < closest) {
                closest = d;
                e->point_owner[p] = I;
            }
            if (d < nearest_distance[I]) {
                nearest_distance[I] = d;
                nearest_point[I] = p;
            }
        }
        GSN_CHECK_GOTO(e->point_owner[p] >= 0, rc, GSN_ERR_INTERNAL, done,
                       "integration point %d has no particle", p);
        e->domain_offset[e->point_owner[p] + 1]++;
    }
    for (int i = 0; i < n; ++i) {
        if (e->domain_offset[i + 1] == 0) {
            GSN_CHECK_GOTO(nearest_point[i] >= 0, rc, GSN_ERR_INTERNAL, done,
                           "particle %d covers no integration point", i);
            e->domain_offset[i + 1] = 1;
        }
        e->domain_offset[i + 1] += e->domain_offset[i];
    }
    GSN_CALL_GOTO(alloc_array((void **)&e->domain_point,
                              (size_t)e->domain_offset[n], sizeof(int)),
                  rc, done);
    /* nearest_point becomes the fill position of each domain */
    for (int i = 0; i < n; ++i) {
        int k0 = e->domain_offset[i], k1 = e->domain_offset[i + 1];
        if (k1 - k0 == 1)
            e->domain_point[k0] = nearest_point[i]; /* overwritten if owned */
        nearest_point[i] = k0;
    }
    for (int p = 0; p < main; ++p)
        e->domain_point[nearest_point[e->point_owner[p]]++] = p;
    for (int i = 0; i < n; ++i) {
        int k0 = e->domain_offset[i];
        e->domain_weight[i] = q->point_weight[e->domain_point[k0]];
        for (int k = k0 + 1; k < e->domain_offset[i + 1]; ++k)
            e->domain_weight[i] += q->point_weight[e->domain_point[k]];
        GSN_CHECK_GOTO(e->domain_weight[i] > 0.0, rc, GSN_ERR_NUMERICAL, done,
                       "the integration points of particle %d have no volume",
                       i);
    }
done:
    free(nearest_point);
    free(nearest_distance);
    return rc;
}

void gsn_explicit_set_constraints(struct gsn_explicit *e,
                                  struct gsn_constraints *constraints)
{
    e->constraints = constraints;
    for (int i = 0; i < e->particle_count; ++i) {
        e->constrained[i] = 0;
        for (int k = 0; k < 3 && constraints; ++k)
            if (gsn_constraints_is_constrained(constraints, i, k))
                e->constrained[i] |= (unsigned char)(1 << k);
    }
}

/* Each main point's material (its particle's), pore pressure (water:) and
 * mass: the density, saturated below the table, times its weight. */
static int point_soil(struct gsn_explicit *e, const struct gsn_case *c)
{
    const struct gsn_quadrature *q = e->quadrature;
    int main = e->main_point_count;
    if (c->water.present)
        GSN_CALL(alloc_array((void **)&e->pore_pressure, (size_t)main,
                             sizeof(double)));
    for (int p = 0; p < main; ++p) {
        int k = e->materials->particle_material[e->point_owner[p]];
        const struct gsn_material *soil = e->materials->parameters[k];
        double u = gsn_water_pressure(c, &q->point_position[3 * (size_t)p]);
        e->point_material[p] = (unsigned char)k;
        if (e->pore_pressure)
            e->pore_pressure[p] = u;
        e->point_mass[p] = (u > 0.0 ? soil->saturated_density : soil->density) *
                           q->point_weight[p];
    }
    return GSN_OK;
}

/* The averaging rows of nonlocal damage when a soil has damage.length,
 * on the points' reference positions. */
static int build_nonlocal(struct gsn_explicit *e)
{
    const struct gsn_material_set *set = e->materials;
    int any = 0;
    for (int k = 0; k < set->count; ++k)
        any |= set->parameters[k]->has_damage &&
               set->parameters[k]->damage_length > 0.0;
    if (!any)
        return GSN_OK;
    e->strain_offset =
        gsn_material_state_offset(e->material->ops, "equivalent_strain");
    e->nonlocal_offset =
        gsn_material_state_offset(e->material->ops, "nonlocal_strain");
    GSN_CHECK(e->strain_offset >= 0 && e->nonlocal_offset >= 0, GSN_ERR_INPUT,
              "damage.length: model %s has no nonlocal damage",
              e->material->ops->name);
    double *radius = NULL;
    GSN_CALL(alloc_array((void **)&radius, (size_t)e->main_point_count,
                         sizeof(double)));
    for (int p = 0; p < e->main_point_count; ++p) {
        const struct gsn_material *soil = set->parameters[e->point_material[p]];
        radius[p] = soil->has_damage ? soil->damage_length : 0.0;
    }
    int rc =
        gsn_nonlocal_create(e->main_point_count, e->quadrature->point_position,
                            e->quadrature->point_weight, radius, &e->nonlocal);
    free(radius);
    return rc;
}

int gsn_explicit_initialize_material(struct gsn_explicit *e)
{
    const unsigned char *k = e->point_material;
    for (int p0 = 0, p1 = 0; p0 < e->main_point_count; p0 = p1) {
        for (p1 = p0 + 1; p1 < e->main_point_count && k[p1] == k[p0]; ++p1)
            ;
        GSN_CALL(gsn_material_initialize(
            e->materials->model[k[p0]], (size_t)(p1 - p0),
            &e->stress[6 * (size_t)p0],
            &e->state[(size_t)e->state_size * (size_t)p0]));
    }
    return GSN_OK;
}

int gsn_explicit_create(const struct gsn_model *m,
                        const struct gsn_quadrature *quadrature,
                        const struct gsn_material_set *materials,
                        struct gsn_constraints *constraints,
                        const struct gsn_case *c, double dt,
                        struct gsn_explicit **out)
{
    *out = NULL;
    struct gsn_explicit *e = calloc(1, sizeof *e);
    GSN_CHECK(e, GSN_ERR_MEMORY, "out of memory");
    int rc = GSN_OK;
    e->model = m;
    e->quadrature = quadrature;
    e->materials = materials;
    e->material = materials->model[0];
    e->constraints = constraints;
    e->particle_count = quadrature->particle_count;
    e->point_count = quadrature->point_count;
    e->main_point_count = quadrature->main_point_count;
    e->state_size = e->material->ops->state_size;
    e->plastic_offset = gsn_material_state_offset(e->material->ops,
                                                  "equivalent_plastic_strain");
    for (int k = 0; k < materials->count; ++k) {
        e->bulk_modulus[k] = materials->parameters[k]->bulk_modulus;
        e->shear_modulus[k] = materials->parameters[k]->shear_modulus;
    }
    e->dt = dt;
    e->damping_local = c->damping_local;
    e->mass_scaling = c->time_mass_scaling;
    e->small_strain = c->small_strain;
    e->held_axis = c->plane_strain_axis;
    memcpy(e->gravity, c->gravity, sizeof e->gravity);
    e->load_factor = e->pore_factor = 1.0;
    e->thread_count = omp_get_max_threads();
    size_t n3 = 3 * (size_t)e->particle_count;
    size_t points = (size_t)e->point_count;
    size_t main = (size_t)e->main_point_count;
    struct {
        void **array;
        size_t count, size;
    } arrays[] = {
        {(void **)&e->mass, n3 / 3, sizeof(double)},
        {(void **)&e->lumped_mass, n3 / 3, sizeof(double)},
        {(void **)&e->displacement, n3, sizeof(double)},
        {(void **)&e->velocity, n3, sizeof(double)},
        {(void **)&e->acceleration, n3, sizeof(double)},
        {(void **)&e->f_ext, n3, sizeof(double)},
        {(void **)&e->f_ext_full, n3, sizeof(double)},
        {(void **)&e->f_int, n3, sizeof(double)},
        {(void **)&e->reaction, n3, sizeof(double)},
        {(void **)&e->stress, 6 * points, sizeof(double)},
        {(void **)&e->state, main * (size_t)e->state_size, sizeof(double)},
        {(void **)&e->previous_displacement, n3, sizeof(double)},
        {(void **)&e->previous_external, n3, sizeof(double)},
        {(void **)&e->new_acceleration, n3, sizeof(double)},
        {(void **)&e->piola, 9 * points, sizeof(double)},
        {(void **)&e->displacement_gradient, 9 * points, sizeof(double)},
        {(void **)&e->point_energy, points, sizeof(double)},
        {(void **)&e->point_failed, points, sizeof(int)},
        {(void **)&e->damping_force, n3, sizeof(double)},
        {(void **)&e->point_mass, main, sizeof(double)},
        {(void **)&e->reference_offset, n3, sizeof(double)},
        {(void **)&e->reference_gradient, 9 * main, sizeof(double)},
        {(void **)&e->point_dead, main, sizeof(int)},
        {(void **)&e->point_material, main, sizeof(unsigned char)},
    };
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i)
        GSN_CALL_GOTO(
            alloc_array(arrays[i].array, arrays[i].count, arrays[i].size), rc,
            fail);
    GSN_CALL_GOTO(
        gsn_point_blocks_create(
            quadrature,
            quadrature->point_count > quadrature->main_point_count &&
                    quadrature->stabilization != GSN_STABILIZATION_NSNI
                ? BLOCK_POINTS_STABILIZED
                : BLOCK_POINTS,
            &e->blocks),
        rc, fail);
    GSN_CALL_GOTO(
        alloc_array((void **)&e->block_distortion,
                    DISTORTION_COLUMNS * (size_t)e->blocks->block_count,
                    sizeof(double)),
        rc, fail);
    GSN_CALL_GOTO(
        alloc_array((void **)&e->slot_force,
                    3 * (size_t)e->blocks->block_slot[e->blocks->block_count],
                    sizeof(double)),
        rc, fail);
    {
        /* aligned_alloc takes whole multiples of the alignment */
        size_t bytes =
            (4 * sizeof(double) * (n3 / 3 ? n3 / 3 : 1) + 63) / 64 * 64;
        e->increment = aligned_alloc(64, bytes);
        GSN_CHECK_GOTO(e->increment, rc, GSN_ERR_MEMORY, fail,
                       "cannot allocate %zu bytes of increments", bytes);
        memset(e->increment, 0, bytes);
    }
    {
        /* 64-byte aligned, so the 4-double slots never straddle a line */
        size_t bytes =
            sizeof(double) * (size_t)e->thread_count * block_work_size(e);
        e->thread_work = aligned_alloc(64, bytes);
        GSN_CHECK_GOTO(e->thread_work, rc, GSN_ERR_MEMORY, fail,
                       "cannot allocate %zu bytes of thread work", bytes);
        memset(e->thread_work, 0, bytes);
        bytes = sizeof(double) * 8 * (size_t)e->thread_count;
        e->thread_part_ticks = aligned_alloc(64, bytes);
        GSN_CHECK_GOTO(e->thread_part_ticks, rc, GSN_ERR_MEMORY, fail,
                       "cannot allocate %zu bytes of thread timers", bytes);
        memset(e->thread_part_ticks, 0, bytes);
        bytes = sizeof(uint64_t) * 8 * (size_t)e->thread_count;
        e->block_deque = aligned_alloc(64, bytes);
        GSN_CHECK_GOTO(e->block_deque, rc, GSN_ERR_MEMORY, fail,
                       "cannot allocate %zu bytes of block ranges", bytes);
        memset(e->block_deque, 0, bytes);
        GSN_CALL_GOTO(alloc_array((void **)&e->block_taken,
                                  (size_t)e->thread_count,
                                  sizeof *e->block_taken),
                      rc, fail);
    }
    {
        size_t items = points > n3 / 3 ? points : n3 / 3;
        GSN_CALL_GOTO(alloc_array((void **)&e->step_partial,
                                  (items + SUM_PIECE - 1) / SUM_PIECE,
                                  sizeof *e->step_partial),
                      rc, fail);
        GSN_CALL_GOTO(alloc_array((void **)&e->constrained, n3 / 3,
                                  sizeof *e->constrained),
                      rc, fail);
        gsn_explicit_set_constraints(e, constraints);
    }
    GSN_CALL_GOTO(build_domains(e), rc, fail);
    GSN_CALL_GOTO(point_soil(e, c), rc, fail);
    GSN_CALL_GOTO(build_nonlocal(e), rc, fail);
    for (size_t p = 0; p < main; ++p)
        for (int a = 0; a < 9; ++a)
            e->reference_gradient[9 * p + a] = a % 4 == 0 ? 1.0 : 0.0;
    GSN_CALL_GOTO(build_mass(e), rc, fail);
    GSN_CALL_GOTO(gsn_explicit_initialize_material(e), rc, fail);
    GSN_CALL_GOTO(gsn_explicit_refresh(e), rc, fail);
    *out = e;
    return GSN_OK;
fail:
    gsn_explicit_destroy(&e);
    return rc;
}

/* Component i (3 I + k) of the contact force, 0 without bodies. */
static inline double contact_force(const struct gsn_explicit *e, int i)
{
    return e->contact ? e->contact_force[i] : 0.0;
}

/* Component i of the force that accelerates the coefficients before the
 * damping and the supports: the loads, the contact, less the internal
 * force, and the released force of the last update at `release` times its
 * full value. */
static inline double net_force(const struct gsn_explicit *e, int i,
                               double release)
{
    double f = e->f_ext[i] + contact_force(e, i) - e->f_int[i];
    return e->release_force ? f + release * e->release_force[i] : f;
}

/* Component i of the external force on the body that W_ext integrates:
 * the dead loads, the contact and the reactions. */
static inline double external_force(const struct gsn_explicit *e, int i)
{
    return e->f_ext[i] + contact_force(e, i) + e->reaction[i];
}

/* The external force of the present state, the start of the next step's
 * trapezoid. */
static void store_previous_external(struct gsn_explicit *e)
{
    for (int i = 0; i < 3 * e->particle_count; ++i)
        e->previous_external[i] = external_force(e, i);
}

void gsn_explicit_add_traction(struct gsn_explicit *e,
                               const struct gsn_model *m, int surface,
                               const double traction[3])
{
    const struct gsn_quadrature *q = e->quadrature;
    const struct gsn_shape_rows *values = &q->boundary_values;
    for (int b = 0; b < q->boundary_point_count; ++b) {
        if (m->facet_surface[q->boundary_point_facet[b]] != surface)
            continue;
        double w = q->boundary_point_weight[b];
        for (int k = values->offset[b]; k < values->offset[b + 1]; ++k)
            for (int c = 0; c < 3; ++c)
                e->f_ext_full[3 * values->index[k] + c] +=
                    values->value[k] * traction[c] * w;
    }
    for (int i = 0; i < 3 * e->particle_count; ++i)
        e->f_ext[i] = e->load_factor * e->f_ext_full[i];
    store_previous_external(e);
}

void gsn_explicit_add_water_pressure(struct gsn_explicit *e,
                                     const struct gsn_model *m,
                                     const struct gsn_case *c)
{
    const struct gsn_quadrature *q = e->quadrature;
    const struct gsn_shape_rows *values = &q->boundary_values;
    if (!c->water.present)
        return;
    for (int b = 0; b < q->boundary_point_count; ++b) {
        double u = gsn_water_pressure(c, &q->boundary_point_position[3 * b]);
        if (!(u > 0.0))
            continue;
        const double *n = &m->facet_normal[3 * q->boundary_point_facet[b]];
        double w = q->boundary_point_weight[b];
        for (int k = values->offset[b]; k < values->offset[b + 1]; ++k)
            for (int i = 0; i < 3; ++i)
                e->f_ext_full[3 * values->index[k] + i] -=
                    values->value[k] * u * n[i] * w;
    }
    for (int i = 0; i < 3 * e->particle_count; ++i)
        e->f_ext[i] = e->load_factor * e->f_ext_full[i];
    store_previous_external(e);
}

/* Small-strain elastic stress of the strain eps (Voigt, tensor shear). */
__attribute__((always_inline)) static inline void
elastic_stress(double bulk, double shear, const double eps[6], double sigma[6])
{
    double volumetric = (bulk - 2.0 * shear / 3.0) * gsn_voigt_trace(eps);
#pragma GCC unroll 6
    for (int a = 0; a < 6; ++a)
        sigma[a] = 2.0 * shear * eps[a] + (a < 3 ? volumetric : 0.0);
}

/* P = J sigma F^-T w = w sigma cof F (eq. (29)), from F (9) and sigma
 * (Voigt): no division. */
static inline void point_piola(const double F[9], const double sigma[6],
                               double w, double P[9])
{
    double C[9], S[9];
    gsn_matrix_cofactor(F, C);
    gsn_voigt_to_matrix(sigma, S);
#pragma GCC unroll 9
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 9
        for (int j = 0; j < 3; ++j)
            P[3 * i + j] = w * (S[3 * i] * C[j] + S[3 * i + 1] * C[3 + j] +
                                S[3 * i + 2] * C[6 + j]);
}

static inline double identity_entry(int a)
{
    return a % 4 == 0 ? 1.0 : 0.0;
}

/* The P of a nodal point (eq. (29)) from its H and nominal stress sigma'
 * (component c at x[c * s]) and its pore pressure u (explicit.h,
 * pore_pressure): w (sigma' - u I) cof F, with F = I + large H (large 0 for
 * kinematics: small, the forces on the reference configuration). */
static inline void nodal_piola(double large, const double *restrict H,
                               const double *restrict stress, size_t s,
                               double u, double w, double P[9])
{
    double F[9], sigma[6];
#pragma GCC unroll 9
    for (int a = 0; a < 9; ++a)
        F[a] = identity_entry(a) + large * H[a * s];
#pragma GCC unroll 9
    for (int a = 0; a < 6; ++a)
        sigma[a] = stress[a * s] - (a < 3 ? u : 0.0);
    point_piola(F, sigma, w, P);
}

static inline double voigt_contract(const double a[6], const double b[6])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] +
           2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

/* Four doubles as one SIMD register (GCC and Clang vector extension):
 * the gather and scatter below are written with it because the compilers
 * do not vectorize the 4-element loops by themselves. Loads and stores
 * through it need 8-byte alignment only; this file is compiled with
 * -ffp-contract=fast (solver/CMakeLists.txt), so a multiply and an add are
 * one fused multiply-add where the CPU has it. */
typedef double gsn_v4 __attribute__((vector_size(32), aligned(8), may_alias));

/* dH = sum_I u_I (x) g_I over packed row r (eq. (21) applied to the
 * increment). u is gathered into the block's slots with 4 doubles per slot
 * (the 4th zero), so every entry is three 4-wide multiply-adds into the
 * columns of dH. Two sets of sums, even and odd entries, added at the end,
 * so that consecutive entries do not wait for each other's additions. */
static inline void entries_gradient(const struct gsn_point_blocks *b, int k,
                                    const int end, const double *restrict u4,
                                    double dH[9])
{
    const uint16_t *restrict slot = b->entry_slot;
    const double *restrict g = b->entry_gradient;
    const gsn_v4 zero = {0.0, 0.0, 0.0, 0.0};
    gsn_v4 c0 = zero, c1 = zero, c2 = zero, d0 = zero, d1 = zero, d2 = zero;
    for (; k + 1 < end; k += 2) {
        /* The gather is the stream's first read (the scatter reads it again
         * from L2): ask for it ~3 kB ahead, as the hardware prefetcher
         * leaves the loop waiting (10% of the pass on Slope I). */
        __builtin_prefetch(&g[3 * k + 384]);
        __builtin_prefetch(&slot[k + 512]);
        const gsn_v4 u = *(const gsn_v4 *)&u4[4 * slot[k]];
        const gsn_v4 v = *(const gsn_v4 *)&u4[4 * slot[k + 1]];
        c0 += u * g[3 * k];
        c1 += u * g[3 * k + 1];
        c2 += u * g[3 * k + 2];
        d0 += v * g[3 * k + 3];
        d1 += v * g[3 * k + 4];
        d2 += v * g[3 * k + 5];
    }
    if (k < end) {
        const gsn_v4 u = *(const gsn_v4 *)&u4[4 * slot[k]];
        c0 += u * g[3 * k];
        c1 += u * g[3 * k + 1];
        c2 += u * g[3 * k + 2];
    }
    c0 += d0;
    c1 += d1;
    c2 += d2;
    for (int i = 0; i < 3; ++i) {
        dH[3 * i] += c0[i];
        dH[3 * i + 1] += c1[i];
        dH[3 * i + 2] += c2[i];
    }
}

/* dH of packed row r: entries_gradient over the whole row. */
static inline void row_gradient(const struct gsn_point_blocks *b, int r,
                                const double *restrict u4, double dH[9])
{
    memset(dH, 0, 9 * sizeof(double));
    entries_gradient(b, b->row_start[r], b->row_start[r + 1], u4, dH);
}

/* The pair index of the six second derivatives d_j d_k of a fused row
 * (point_blocks.h: d11 d22 d33 d12 d23 d13). */
static inline int hessian_pair(int j, int k)
{
    /* {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}} without a table: constants once
     * unrolled, where the vectorizer cannot load from a table */
    return j == k ? j : 3 + (j + k == 3) + 2 * (j + k == 2);
}

/* A fused row r (NSNI, point_blocks.h): dH of the nodal point as
 * row_gradient, and A[3 c + i] = sum_I u_Ii d_c Psi_I over the six second
 * derivatives c of its first entries, from which the increment of
 * stabilization point k is dH_k[i][j] = A[3 hessian_pair(k, j) + i]
 * (Hillman & Chen 2016: the gradient of the displacement gradient). */
static inline void fused_row_gradient(const struct gsn_point_blocks *b, int r,
                                      const double *restrict u4, double dH[9],
                                      double A[18])
{
    const uint16_t *restrict slot = b->entry_slot;
    const double *restrict g = b->entry_gradient;
    const int k0 = b->row_start[r];
    const int h0 = b->row_hessian_start[r];
    const int middle = k0 + (b->row_hessian_start[r + 1] - h0);
    const double *restrict d = &b->entry_hessian[6 * (size_t)h0];
    const gsn_v4 zero = {0.0, 0.0, 0.0, 0.0};
    gsn_v4 c0 = zero, c1 = zero, c2 = zero;
    gsn_v4 a0 = zero, a1 = zero, a2 = zero, a3 = zero, a4 = zero, a5 = zero;
    for (int k = k0; k < middle; ++k, d += 6) {
        __builtin_prefetch(&g[3 * k + 384]);
        __builtin_prefetch(&d[768]);
        const gsn_v4 u = *(const gsn_v4 *)&u4[4 * slot[k]];
        c0 += u * g[3 * k];
        c1 += u * g[3 * k + 1];
        c2 += u * g[3 * k + 2];
        a0 += u * d[0];
        a1 += u * d[1];
        a2 += u * d[2];
        a3 += u * d[3];
        a4 += u * d[4];
        a5 += u * d[5];
    }
    for (int i = 0; i < 3; ++i) {
        dH[3 * i] = c0[i];
        dH[3 * i + 1] = c1[i];
        dH[3 * i + 2] = c2[i];
        A[i] = a0[i];
        A[3 + i] = a1[i];
        A[6 + i] = a2[i];
        A[9 + i] = a3[i];
        A[12 + i] = a4[i];
        A[15 + i] = a5[i];
    }
    entries_gradient(b, middle, b->row_start[r + 1], u4, dH);
}

/* dH_k (9) of stabilization point k from a fused row's A. */
__attribute__((always_inline)) static inline void
fused_point_gradient(const double *A, size_t stride, int k, double dH[9])
{
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j)
            dH[3 * i + j] = A[(size_t)(3 * hessian_pair(k, j) + i) * stride];
}

/* The coefficients C[3 c + i] (at C[(3 c + i) stride]) of the six second
 * derivatives in the force of the three stabilization points with P_k
 * (row-major): f_Ii += sum_k sum_j P_k[i][j] d_k d_j Psi_I
 * = sum_c C[3 c + i] d_c Psi_I, c = hessian_pair(j, k). */
__attribute__((always_inline)) static inline void
fused_force_coefficients(const double P0[9], const double P1[9],
                         const double P2[9], double *C, size_t stride)
{
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
        C[(size_t)i * stride] = P0[3 * i];                            /* d11 */
        C[(size_t)(3 + i) * stride] = P1[3 * i + 1];                  /* d22 */
        C[(size_t)(6 + i) * stride] = P2[3 * i + 2];                  /* d33 */
        C[(size_t)(9 + i) * stride] = P1[3 * i] + P0[3 * i + 1];      /* d12 */
        C[(size_t)(12 + i) * stride] = P2[3 * i + 1] + P1[3 * i + 2]; /* d23 */
        C[(size_t)(15 + i) * stride] = P2[3 * i] + P0[3 * i + 2];     /* d13 */
    }
}

/* force_slot += P g_I over entries [k, end) (eq. (29) with
 * P = J sigma F^-T w), into slots of 4 doubles (the 4th stays zero). */
static inline void entries_scatter(const struct gsn_point_blocks *b, int k,
                                   const int end, const double P[9],
                                   double *restrict f4)
{
    const uint16_t *restrict slot = b->entry_slot;
    const double *restrict g = b->entry_gradient;
    const gsn_v4 p0 = {P[0], P[3], P[6], 0.0};
    const gsn_v4 p1 = {P[1], P[4], P[7], 0.0};
    const gsn_v4 p2 = {P[2], P[5], P[8], 0.0};
    for (; k < end; ++k) {
        gsn_v4 *f = (gsn_v4 *)&f4[4 * slot[k]];
        *f += p0 * g[3 * k] + p1 * g[3 * k + 1] + p2 * g[3 * k + 2];
    }
}

/* force_slot += P g_I over packed row r. */
static inline void row_scatter(const struct gsn_point_blocks *b, int r,
                               const double P[9], double *restrict f4)
{
    entries_scatter(b, b->row_start[r], b->row_start[r + 1], P, f4);
}

/* A fused row r: the nodal point's P g_I and, on its first entries, the
 * stabilization points' sum_c C_c d_c Psi_I (fused_force_coefficients; C[a]
 * at C[a stride]). */
static inline void fused_row_scatter(const struct gsn_point_blocks *b, int r,
                                     const double P[9], const double *C,
                                     size_t stride, double *restrict f4)
{
    const uint16_t *restrict slot = b->entry_slot;
    const double *restrict g = b->entry_gradient;
    const int k0 = b->row_start[r];
    const int h0 = b->row_hessian_start[r];
    const int middle = k0 + (b->row_hessian_start[r + 1] - h0);
    const double *restrict d = &b->entry_hessian[6 * (size_t)h0];
    const gsn_v4 p0 = {P[0], P[3], P[6], 0.0};
    const gsn_v4 p1 = {P[1], P[4], P[7], 0.0};
    const gsn_v4 p2 = {P[2], P[5], P[8], 0.0};
    gsn_v4 q[6];
    for (int c = 0; c < 6; ++c)
        q[c] = (gsn_v4){C[(size_t)(3 * c) * stride],
                        C[(size_t)(3 * c + 1) * stride],
                        C[(size_t)(3 * c + 2) * stride], 0.0};
    for (int k = k0; k < middle; ++k, d += 6) {
        gsn_v4 *f = (gsn_v4 *)&f4[4 * slot[k]];
        *f += p0 * g[3 * k] + p1 * g[3 * k + 1] + p2 * g[3 * k + 2] +
              q[0] * d[0] + q[1] * d[1] + q[2] * d[2] + q[3] * d[3] +
              q[4] * d[4] + q[5] * d[5];
    }
    entries_scatter(b, middle, b->row_start[r + 1], P, f4);
}

/* The elastic share of a nodal point's strain increment in this step,
 * 1 - d(eq. plastic strain) / (sqrt(2/3) ||dev d eps||) clamped to [0, 1]:
 * 1 for an elastic step, near 0 while the point flows plastically. Damage
 * is left out on purpose: it softens every mode of the continuum alike, and
 * a fully damaged particle still needs the stabilization's stiffness not to
 * invert (docs/solver.md, "Stabilization"). */
static inline double elastic_share(const double deps[6],
                                   double plastic_increment)
{
    const double trace = (deps[0] + deps[1] + deps[2]) / 3.0;
    double dev[6];
#pragma GCC unroll 9
    for (int a = 0; a < 6; ++a)
        dev[a] = deps[a] - (a < 3 ? trace : 0.0);
    const double total = sqrt(2.0 / 3.0 * voigt_contract(dev, dev));
    /* no branch (main_chunk's columns), and no division by 0 where the
     * share is not taken */
    double share = 1.0 - plastic_increment / (total > 0.0 ? total : 1.0);
    share = share < 0.0 ? 0.0 : share > 1.0 ? 1.0 : share;
    return total > 0.0 ? share : 1.0;
}

/* |E| = |F^T F - I| / 2 (Frobenius): the strain of F without its
 * rotation. */
static inline double green_strain_norm(const double F[9])
{
    double sum = 0.0;
#pragma GCC unroll 9
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 9
        for (int j = i; j < 3; ++j) {
            double c = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
            c -= i == j ? 1.0 : 0.0;
            sum += (i == j ? 1.0 : 2.0) * c * c;
        }
    return 0.5 * sqrt(sum);
}

/* A point that fails (allow_failure): it carries no stress from now on and
 * its F stays as it was; its mass stays with the particles (issue 15,
 * point 2). */
static void point_fail(struct gsn_explicit *e, int p)
{
    int S = e->blocks->subcells;
    e->point_dead[p] = 1;
    memset(&e->stress[6 * (size_t)p], 0, 6 * sizeof(double));
    /* its sub-cells are skipped from now on: no stress, and no energy
     * increment left over from their last step (the internal energy sums
     * every point's increment at every step) */
    for (int s = 0; s < S; ++s) {
        size_t q = (size_t)e->main_point_count + (size_t)S * p + (size_t)s;
        memset(&e->stress[6 * q], 0, 6 * sizeof(double));
        e->point_energy[q] = 0.0;
    }
}

/* The kinematics of one nodal point, component c of its arrays at
 * x[c * CHUNK] (the columns of a chunk, where the loop over points
 * vectorizes): Hnew = H + dH, det F_{n+1} (F_{n+1} = I + Hnew) and its
 * strain |E|, and on the mid-step configuration F_mid = I + H + dH/2 the
 * incremental gradient G = dH F_mid^-1 with Jmid = det F_mid; small strain:
 * G = sym dH, no rotation, the reference volume (Jmid = 1). */
__attribute__((always_inline)) static inline void
point_kinematics(int small_strain, const double *restrict H,
                 const double *restrict dH, double *restrict Hnew,
                 double *restrict G, double *restrict J1, double *restrict Jmid,
                 double *restrict strain)
{
    double d[9], F1[9], Fmid[9];
#pragma GCC unroll 9
    for (int a = 0; a < 9; ++a) {
        const double h = H[a * CHUNK];
        d[a] = dH[a * CHUNK];
        Hnew[a * CHUNK] = h + d[a];
        F1[a] = identity_entry(a) + (h + d[a]);
        Fmid[a] = identity_entry(a) + h + 0.5 * d[a];
    }
    *J1 = gsn_matrix_determinant(F1);
    *strain = green_strain_norm(F1);
    if (small_strain) {
#pragma GCC unroll 9
        for (int i = 0; i < 3; ++i)
#pragma GCC unroll 9
            for (int j = 0; j < 3; ++j)
                G[(3 * i + j) * CHUNK] = 0.5 * (d[3 * i + j] + d[3 * j + i]);
        *Jmid = 1.0;
        return;
    }
    double Fmid_inv[9], g[9];
    *Jmid = gsn_matrix_inverse(Fmid, Fmid_inv);
    gsn_matrix_multiply(d, Fmid_inv, g);
#pragma GCC unroll 9
    for (int a = 0; a < 9; ++a)
        G[a * CHUNK] = g[a];
}

/* The end of the step of one live nodal point, columns as
 * point_kinematics: the elastic share of its strain increment deps, the
 * work of the mean of its old and new total stress (the pore pressure u
 * rises from u_old to u_new) over the mid-step volume Jmid w, and
 * its P (nodal_piola, with u_new and Hnew). */
__attribute__((always_inline)) static inline void
point_end(double large, const double *restrict deps, const double *restrict old,
          const double *restrict stress, const double *restrict Hnew,
          double plastic_step, double u_old, double u_new, double Jmid,
          double w, double *restrict share, double *restrict energy,
          double *restrict P)
{
    double de[6], mean[6], Pp[9];
#pragma GCC unroll 9
    for (int a = 0; a < 6; ++a) {
        de[a] = deps[a * CHUNK];
        mean[a] = 0.5 * (old[a * CHUNK] + stress[a * CHUNK]) -
                  (a < 3 ? 0.5 * (u_old + u_new) : 0.0);
    }
    *share = elastic_share(de, plastic_step); /* 1 without plasticity */
    /* Internal work sigma : d eps over the mid-step volume. */
    *energy = voigt_contract(mean, de) * Jmid * w;
    nodal_piola(large, Hnew, stress, CHUNK, u_new, w, Pp);
#pragma GCC unroll 9
    for (int a = 0; a < 9; ++a)
        P[a * CHUNK] = Pp[a];
}

/* Nodal points [p0, p1) with their increments dH (9 each, from p0):
 * F_{n+1} = I + H + dH, the incremental gradient on the mid-step
 * configuration G = dH (I + H + dH/2)^-1, the objective update with the
 * material (Fig. 3), the work sigma : d eps, P, and each point's elastic
 * share of the step (share, from p0) for its stabilization points. A
 * failed point (point_dead) takes no increment and has no stress; a point
 * that turns inside out fails when allow_failure is set, else the step
 * fails. distortion (DISTORTION_COLUMNS) gets the block's largest |E| of
 * F_{n+1}, its point, the extremes of det F_{n+1} over the live points,
 * the points that failed in this step and the first of them (-1). The
 * arithmetic runs on columns of the chunk (point_kinematics, point_end);
 * the decisions between them point by point. */
static int main_chunk(struct gsn_explicit *e, int p0, int p1,
                      const double *dH_block, double *work, double *share,
                      double distortion[DISTORTION_COLUMNS])
{
    const double *w = e->quadrature->point_weight;
    const int n = p1 - p0, small = e->small_strain;
    const double large = small ? 0.0 : 1.0;
    const int plastic = e->plastic_offset >= 0;
    const size_t ns = (size_t)e->state_size;
    double *Hc = work, *dHc = Hc + 9 * CHUNK, *Hnew = dHc + 9 * CHUNK;
    double *Gc = Hnew + 9 * CHUNK, *J1 = Gc + 9 * CHUNK, *Jmid = J1 + CHUNK;
    double *strain = Jmid + CHUNK, *stress = strain + CHUNK;
    double *old = stress + 6 * CHUNK, *deps = old + 6 * CHUNK;
    double *old_plastic = deps + 6 * CHUNK, *plastic_step = old_plastic + CHUNK;
    double *u_old = plastic_step + CHUNK, *u_new = u_old + CHUNK;
    double *state = u_new + CHUNK; /* ns columns */
    double *Pc = Hc;               /* after the kinematics */
    gsn_material_to_columns((size_t)n, 9, &e->displacement_gradient[9 * p0], 9,
                            Hc, CHUNK);
    gsn_material_to_columns((size_t)n, 9, dH_block, 9, dHc, CHUNK);
    if (small) /* two loops: no branch inside either */
#pragma omp simd
        for (int b = 0; b < n; ++b)
            point_kinematics(1, &Hc[b], &dHc[b], &Hnew[b], &Gc[b], &J1[b],
                             &Jmid[b], &strain[b]);
    else
#pragma omp simd
        for (int b = 0; b < n; ++b)
            point_kinematics(0, &Hc[b], &dHc[b], &Hnew[b], &Gc[b], &J1[b],
                             &Jmid[b], &strain[b]);
    int failed = 0;
    double strain_max = 0.0, jacobian_min = INFINITY, jacobian_max = 0.0;
    int strain_point = p0, newly_failed = 0, first_failed = -1;
    for (int p = p0; p < p1; ++p) {
        const int b = p - p0;
        const int admissible =
            e->point_dead[p] ||
            (isfinite(J1[b]) && (small || (J1[b] > 0.0 && Jmid[b] > 0.0)));
        if (!admissible && e->allow_failure && isfinite(J1[b])) {
            point_fail(e, p);
            if (newly_failed++ == 0)
                first_failed = p;
        } else if (!admissible) {
            e->point_failed[p] = 1;
            failed = 1;
            continue;
        }
        if (e->point_dead[p]) {
            for (int a = 0; a < 9; ++a)
                Gc[a * CHUNK + b] = 0.0;
            Jmid[b] = 1.0;
        } else if (e->track_distortion) {
            if (strain[b] > strain_max) {
                strain_max = strain[b];
                strain_point = p;
            }
            jacobian_min = gsn_min(jacobian_min, J1[b]);
            jacobian_max = gsn_max(jacobian_max, J1[b]);
        }
    }
    distortion[0] = strain_max;
    distortion[1] = jacobian_min;
    distortion[2] = jacobian_max;
    distortion[3] = strain_point;
    distortion[4] = newly_failed;
    distortion[5] = first_failed;
    if (failed)
        return GSN_ERR_NUMERICAL;
    /* the stress and state in columns for the material, from its rows
     * (a point that failed above has no stress from now on) */
    gsn_material_to_columns((size_t)n, 6, &e->stress[6 * p0], 6, stress, CHUNK);
    gsn_material_to_columns((size_t)n, (int)ns, &e->state[ns * p0], ns, state,
                            CHUNK);
    memcpy(old, stress, sizeof(double) * 6 * CHUNK);
    if (plastic)
        memcpy(old_plastic, &state[(size_t)e->plastic_offset * CHUNK],
               sizeof(double) * (size_t)n);
    int rc = GSN_OK;
    const unsigned char *kind = e->point_material;
    for (int a = p0, z = p0; a < p1 && rc == GSN_OK; a = z) {
        for (z = a + 1; z < p1 && kind[z] == kind[a]; ++z)
            ;
        rc = gsn_stress_update_columns(
            e->materials->model[kind[a]], (size_t)(z - a), CHUNK, &Gc[a - p0],
            &stress[a - p0], &state[a - p0], &deps[a - p0]);
    }
    if (rc != GSN_OK) {
        for (int p = p0; p < p1; ++p)
            e->point_failed[p] = 1;
        return rc;
    }
    gsn_material_from_columns((size_t)n, 6, stress, CHUNK, &e->stress[6 * p0],
                              6);
    gsn_material_from_columns((size_t)n, (int)ns, state, CHUNK,
                              &e->state[ns * p0], ns);
    for (int p = p0; p < p1; ++p) {
        const int b = p - p0;
        plastic_step[b] =
            plastic
                ? state[(size_t)e->plastic_offset * CHUNK + b] - old_plastic[b]
                : 0.0;
        /* the total stress; u rises with the load factor */
        const double u = e->pore_pressure ? e->pore_pressure[p] : 0.0;
        u_old[b] = e->pore_factor * u;
        u_new[b] = e->load_factor * u;
    }
#pragma omp simd
    for (int b = 0; b < n; ++b)
        point_end(large, &deps[b], &old[b], &stress[b], &Hnew[b],
                  plastic_step[b], u_old[b], u_new[b], Jmid[b], w[p0 + b],
                  &share[b], &e->point_energy[p0 + b], &Pc[b]);
    gsn_material_from_columns((size_t)n, 9, Pc, CHUNK, &e->piola[9 * p0], 9);
    for (int p = p0; p < p1; ++p) {
        const int b = p - p0;
        if (!e->point_dead[p]) {
            for (int a = 0; a < 9; ++a)
                e->displacement_gradient[9 * p + a] = Hnew[a * CHUNK + b];
            continue;
        }
        memset(&e->stress[6 * p], 0, 6 * sizeof(double));
        memset(&e->piola[9 * p], 0, 9 * sizeof(double));
        e->point_energy[p] = 0.0;
        share[b] = 0.0;
    }
    return GSN_OK;
}

/* sigma w as a 3x3 matrix: the P of a stabilization point (small strain on
 * the reference configuration). */
__attribute__((always_inline)) static inline void
elastic_piola(const double sigma[6], double w, double P[9])
{
    gsn_voigt_to_matrix(sigma, P);
#pragma GCC unroll 9
    for (int a = 0; a < 9; ++a)
        P[a] *= w;
}

/* The force of a stabilization point's stress sigma (weight w) on packed
 * row r, scattered as P_s B_s into the slots, and with MSCNI -P_s B_L
 * folded into its nodal point's P (point_blocks.h). */
static void subcell_scatter(const struct gsn_point_blocks *b, int r,
                            const double sigma[6], double w, double fold[9],
                            double *f4)
{
    double P[9];
    elastic_piola(sigma, w, P);
    row_scatter(b, r, P, f4);
    for (int a = 0; a < 9 && b->relative; ++a)
        fold[a] -= P[a];
}

/* Stabilization point p of particle L, from its increment dH: the elastic
 * stress rate of its row, MSCNI's B_s - B_L (Puso et al. 2008) or NSNI's
 * strain gradient (Hillman & Chen 2016), both zero for every linear
 * displacement field; its new stress into sigma and e->stress, its work.
 * MSCNI's rate is scaled by the elastic share of L's nodal point in this
 * step: the sub-cell deviations then yield with the soil instead of
 * adding an elastic stiffness that grows without bound once it flows
 * (docs/solver.md, "Stabilization"); NSNI's shear part is, its volumetric
 * part stays elastic (a flowing particle keeps its bulk stiffness; with
 * the whole rate scaled, particles at the faces of a pressed soil block
 * collapse to det F 0.03, tests/solver/test_checkerboard.c). */
__attribute__((always_inline)) static inline void
stabilization_update(int relative, double bulk, double shear, double share,
                     const double dH[9], const double old[6], double w,
                     double sigma[6], double *energy)
{
    double deps[6], rate[6], mean[6];
    gsn_matrix_sym_to_voigt(dH, deps);
    elastic_stress(bulk, relative ? shear : share * shear, deps, rate);
    double scale = relative ? share : 1.0;
#pragma GCC unroll 6
    for (int a = 0; a < 6; ++a)
        sigma[a] = old[a] + scale * rate[a];
#pragma GCC unroll 6
    for (int a = 0; a < 6; ++a)
        mean[a] = 0.5 * (old[a] + sigma[a]);
    *energy = voigt_contract(mean, deps) * w;
}

/* stabilization_update of point p into e->stress and e->point_energy. */
static inline void stabilization_stress(struct gsn_explicit *e, int L, int p,
                                        const double dH[9], double share,
                                        double sigma[6])
{
    stabilization_update(
        e->blocks->relative, e->bulk_modulus[e->point_material[L]],
        e->shear_modulus[e->point_material[L]], share, dH, &e->stress[6 * p],
        e->quadrature->point_weight[p], sigma, &e->point_energy[p]);
    memcpy(&e->stress[6 * p], sigma, 6 * sizeof(double));
}

/* Stabilization point s of a nodal point on columns (fused_stabilization):
 * its stress and work, and the P of its stress (0 on a failed point, whose
 * stress is 0; a row without second derivatives does not use it). */
__attribute__((always_inline)) static inline void
stabilization_column(int on, int s, const double *A, double *stress,
                     const double *w, double *energy, double bulk, double shear,
                     double share, double P[9])
{
    double dH[9], old[6], sigma[6], work;
#pragma GCC unroll 6
    for (int i = 0; i < 6; ++i)
        old[i] = stress[(6 * s + i) * CHUNK];
    fused_point_gradient(A, CHUNK, s, dH);
    stabilization_update(0, bulk, shear, share, dH, old, w[s * CHUNK], sigma,
                         &work);
#pragma GCC unroll 6
    for (int i = 0; i < 6; ++i) {
        sigma[i] = on ? sigma[i] : old[i];
        stress[(6 * s + i) * CHUNK] = sigma[i];
    }
    energy[s * CHUNK] = on ? work : 0.0;
    elastic_piola(sigma, w[s * CHUNK], P);
}

/* The three stabilization points of a nodal point on columns, and their
 * force coefficients in A's place (fused_stabilization). The points are
 * written out (GCC leaves a loop over them rolled, and then does not
 * vectorize the loop over nodal points), and the arrays are this
 * function's (declared in the loop body, they become per-lane arrays the
 * vectorizer cannot store to). */
__attribute__((always_inline)) static inline void
stabilization_columns(int on, double *A, double *stress, const double *w,
                      double *energy, double bulk, double shear, double share)
{
    double P0[9], P1[9], P2[9];
    stabilization_column(on, 0, A, stress, w, energy, bulk, shear, share, P0);
    stabilization_column(on, 1, A, stress, w, energy, bulk, shear, share, P1);
    stabilization_column(on, 2, A, stress, w, energy, bulk, shear, share, P2);
    fused_force_coefficients(P0, P1, P2, A, CHUNK);
}

/* NSNI's three stabilization points of each nodal point of [p0, p1) on
 * columns (as main_chunk, so that the loop over points vectorizes): the
 * increments from the fused rows' sums A (rows of 18; fused_point_gradient
 * on their copy in the columns Ac), their stresses and work
 * (stabilization_update), and then in Ac, over the sums, the force
 * coefficients C of fused_coefficients, which the scatter reads there
 * (stride CHUNK). A failed point, or one whose row has no second
 * derivatives, keeps its stresses and does no work (its energy increment
 * is 0). */
static void fused_stabilization(struct gsn_explicit *e, int k, int p0, int p1,
                                const double *share, const double *A,
                                double *Ac, double *work)
{
    const struct gsn_point_blocks *b = e->blocks;
    const int n = p1 - p0;
    const size_t s0 = (size_t)e->main_point_count + 3 * (size_t)p0;
    double *stress = work, *w = stress + 18 * CHUNK;
    double *energy = w + 3 * CHUNK, *bulk = energy + 3 * CHUNK;
    double *shear = bulk + CHUNK, *live = shear + CHUNK;
    gsn_material_to_columns((size_t)n, 18, A, 18, Ac, CHUNK);
    gsn_material_to_columns((size_t)n, 18, &e->stress[6 * s0], 18, stress,
                            CHUNK);
    gsn_material_to_columns((size_t)n, 3, &e->quadrature->point_weight[s0], 3,
                            w, CHUNK);
    for (int L = p0; L < p1; ++L) {
        int r = gsn_point_blocks_main_row(b, k, L);
        bulk[L - p0] = e->bulk_modulus[e->point_material[L]];
        shear[L - p0] = e->shear_modulus[e->point_material[L]];
        live[L - p0] = !e->point_dead[L] &&
                       b->row_hessian_start[r + 1] > b->row_hessian_start[r];
    }
#pragma omp simd
    for (int c = 0; c < n; ++c)
        stabilization_columns(live[c] != 0.0, &Ac[c], &stress[c], &w[c],
                              &energy[c], bulk[c], shear[c], share[c]);
    gsn_material_from_columns((size_t)n, 18, stress, CHUNK, &e->stress[6 * s0],
                              18);
    gsn_material_from_columns((size_t)n, 3, energy, CHUNK, &e->point_energy[s0],
                              3);
}

/* Stabilization point s of particle L (block k) on its own packed row:
 * stabilization_stress of its increment, its force scattered. MSCNI:
 * (B_s - B_L) du = B_s du - dH_L with the increment dH_L of the nodal
 * point; the force P_s (B_s - B_L) is scattered as P_s B_s here and
 * -P_s B_L through fold, the nodal point's P. */
static void stabilization_point(struct gsn_explicit *e, int k, int L, int s,
                                const double *u4, const double dH_L[9],
                                double share, double fold[9], double *f4)
{
    const struct gsn_point_blocks *b = e->blocks;
    int p = e->main_point_count + b->subcells * L + s;
    int r = gsn_point_blocks_subcell_row(b, k, L, s);
    if (b->row_start[r] == b->row_start[r + 1])
        return; /* an empty sub-cell: weight 0, no entries */
    double dH[9], sigma[6];
    row_gradient(b, r, u4, dH);
    for (int a = 0; a < 9 && b->relative; ++a)
        dH[a] -= dH_L[a];
    stabilization_stress(e, L, p, dH, share, sigma);
    subcell_scatter(b, r, sigma, e->quadrature->point_weight[p], fold, f4);
}

/* The force coefficients of the three stabilization points of nodal point
 * L on a fused row (fused_force_coefficients) from their stresses
 * (stress: points x 6, the stabilization points' at main + 3 L + k). */
static void fused_coefficients(const struct gsn_explicit *e, int L,
                               const double *stress, double C[18])
{
    double P[27];
    for (int k = 0; k < 3; ++k) {
        int p = e->main_point_count + 3 * L + k;
        elastic_piola(&stress[6 * (size_t)p], e->quadrature->point_weight[p],
                      &P[9 * k]);
    }
    fused_force_coefficients(P, &P[9], &P[18], C, 1);
}

/* Per-thread work of one block: u and forces (4 per slot), the main
 * points' increments and folded P (9 per point), the elastic shares (1 per
 * point), a fused row's second-derivative sums (18 per point), the fused
 * force coefficients in columns (18 of CHUNK) and a chunk's material
 * work. */
static size_t block_work_size(const struct gsn_explicit *e)
{
    const struct gsn_point_blocks *b = e->blocks;
    size_t size = 8 * (size_t)b->max_block_slots +
                  37 * (size_t)b->max_block_points + 18 * CHUNK + CHUNK_WORK +
                  (size_t)e->state_size * CHUNK;
    return (size + 7) / 8 * 8; /* whole cache lines per thread */
}

static double *block_work(const struct gsn_explicit *e)
{
    return &e->thread_work[(size_t)omp_get_thread_num() * block_work_size(e)];
}

/* Gathers x (n x 3) into the slots of block k, 4 doubles per slot. */
static void block_gather(const struct gsn_explicit *e, int k, const double *x,
                         double *restrict local)
{
    const struct gsn_point_blocks *b = e->blocks;
    for (int s = b->block_slot[k]; s < b->block_slot[k + 1]; ++s) {
        const size_t I = 3 * (size_t)b->slot_particle[s];
        double *l = &local[4 * (size_t)(s - b->block_slot[k])];
        for (int i = 0; i < 3; ++i)
            l[i] = x[I + i];
        l[3] = 0.0;
    }
}

/* Gathers the step's increments d - d_n (e->increment, 4 doubles a
 * particle) into the slots of block k: one aligned 4-double copy a slot. */
static void block_gather_increment(const struct gsn_explicit *e, int k,
                                   double *restrict local)
{
    const struct gsn_point_blocks *b = e->blocks;
    const int s0 = b->block_slot[k], s1 = b->block_slot[k + 1];
    for (int s = s0; s < s1; ++s)
        *(gsn_v4 *)&local[4 * (size_t)(s - s0)] =
            *(const gsn_v4 *)&e->increment[4 * (size_t)b->slot_particle[s]];
}

/* Copies the block's forces (4 per slot) to its slots of e->slot_force. */
static void block_store(struct gsn_explicit *e, int k, const double *f4)
{
    const struct gsn_point_blocks *b = e->blocks;
    double *out = &e->slot_force[3 * (size_t)b->block_slot[k]];
    int slots = b->block_slot[k + 1] - b->block_slot[k];
    for (int s = 0; s < slots; ++s)
        for (int i = 0; i < 3; ++i)
            out[3 * s + i] = f4[4 * s + i];
}

/* A clock for the shares of the pass's parts: the time stamp counter
 * where there is one (a few cycles), else the wall clock. */
static inline double pass_clock(void)
{
#if defined(__x86_64__)
    return (double)__builtin_ia32_rdtsc();
#else
    return omp_get_wtime();
#endif
}

/* Adds the ticks since *mark to this thread's part `part` and moves the
 * mark (summed into pass_part_ticks after each pass). */
static inline void part_end(const struct gsn_explicit *e,
                            enum gsn_pass_part part, double *mark)
{
    double now = pass_clock();
    e->thread_part_ticks[8 * (size_t)omp_get_thread_num() + part] +=
        now - *mark;
    *mark = now;
}

/* Asks for every cache line of x[0 .. count): an element every 8 (64
 * bytes) and the last. */
static inline void prefetch_span(const double *x, size_t count, int write)
{
    for (size_t i = 0; i < count; i += 8)
        if (write)
            __builtin_prefetch(x + i, 1);
        else
            __builtin_prefetch(x + i, 0);
    if (write)
        __builtin_prefetch(x + count - 1, 1);
    else
        __builtin_prefetch(x + count - 1, 0);
}

/* Asks for what main point L's update reads and writes after the block's
 * gather (its H, stress, state and P, and its stabilization points'
 * stresses), during the gather of its row: main_chunk's first reads of
 * them waited on memory (docs/solver.md, "Speed": the material part 0.64
 * times with it; all of a block's asked for at once at its start gave
 * nothing). */
static inline void prefetch_point_state(const struct gsn_explicit *e, int L)
{
    const size_t p = (size_t)L, S = (size_t)e->blocks->subcells;
    const size_t ns = (size_t)e->state_size;
    prefetch_span(&e->displacement_gradient[9 * p], 9, 0);
    prefetch_span(&e->stress[6 * p], 6, 0);
    if (ns > 0)
        prefetch_span(&e->state[ns * p], ns, 0);
    prefetch_span(&e->piola[9 * p], 9, 1);
    if (S > 0)
        prefetch_span(&e->stress[6 * ((size_t)e->main_point_count + S * p)],
                      6 * S, 0);
}

/* The step's pass over block k: kinematics, stress and forces of its
 * points from the increments d - d_n, reading its rows once. */
static int block_step(struct gsn_explicit *e, int k)
{
    const struct gsn_point_blocks *b = e->blocks;
    const int S = b->subcells;
    const int p0 = b->block_point[k], p1 = b->block_point[k + 1];
    const int slots = b->block_slot[k + 1] - b->block_slot[k];
    double *u4 = block_work(e), *f4 = u4 + 4 * (size_t)b->max_block_slots;
    double *dH = f4 + 4 * (size_t)b->max_block_slots;
    double *fold = dH + 9 * (size_t)b->max_block_points;
    double *share = fold + 9 * (size_t)b->max_block_points;
    double *A = share + (size_t)b->max_block_points;
    double *C = A + 18 * (size_t)b->max_block_points; /* columns */
    double *work = C + 18 * CHUNK;
    double mark = pass_clock();
    block_gather_increment(e, k, u4);
    memset(f4, 0, sizeof(double) * 4 * (size_t)slots);
    memset(&e->point_failed[p0], 0, sizeof(int) * (size_t)(p1 - p0));
    /* the sums in rows, copied into columns after: the gather storing
     * them into columns directly was 25% slower (Slope I, NSNI) */
    for (int L = p0; L < p1; ++L) {
        int r = gsn_point_blocks_main_row(b, k, L);
        prefetch_point_state(e, L);
        if (b->fused)
            fused_row_gradient(b, r, u4, &dH[9 * (L - p0)], &A[18 * (L - p0)]);
        else
            row_gradient(b, r, u4, &dH[9 * (L - p0)]);
    }
    part_end(e, GSN_PASS_GATHER, &mark);
    fenv_t caller; /* the column loops' lanes (material.h) */
    gsn_hold_exceptions(&caller);
    const int rc =
        main_chunk(e, p0, p1, dH, work, share,
                   &e->block_distortion[DISTORTION_COLUMNS * (size_t)k]);
    part_end(e, GSN_PASS_MATERIAL, &mark);
    if (rc == GSN_OK && b->fused) {
        /* NSNI on fused rows: each point's three strain gradients, then
         * (below) its four points' forces in one scatter */
        fused_stabilization(e, k, p0, p1, share, A, C, work);
        part_end(e, GSN_PASS_STABILIZATION, &mark);
    }
    gsn_release_exceptions(&caller);
    if (rc != GSN_OK)
        return GSN_ERR_NUMERICAL;
    const double *P = &e->piola[9 * (size_t)p0];
    if (b->fused) {
        for (int L = p0; L < p1; ++L)
            fused_row_scatter(b, gsn_point_blocks_main_row(b, k, L),
                              &P[9 * (L - p0)], &C[L - p0], CHUNK, f4);
        block_store(e, k, f4);
        part_end(e, GSN_PASS_SCATTER, &mark);
        return GSN_OK;
    }
    if (S > 0) { /* MSCNI folds its sub-cells' -P_s B_L into a copy */
        memcpy(fold, P, sizeof(double) * 9 * (size_t)(p1 - p0));
        P = fold;
    }
    for (int L = p0; L < p1; ++L)
        for (int s = 0; s < S && !e->point_dead[L]; ++s)
            stabilization_point(e, k, L, s, u4, &dH[9 * (L - p0)],
                                share[L - p0], &fold[9 * (L - p0)], f4);
    part_end(e, GSN_PASS_STABILIZATION, &mark);
    for (int L = p0; L < p1; ++L)
        row_scatter(b, gsn_point_blocks_main_row(b, k, L), &P[9 * (L - p0)],
                    f4);
    block_store(e, k, f4);
    part_end(e, GSN_PASS_SCATTER, &mark);
    return GSN_OK;
}

/* The linear elastic pass over block k for y = K x (the stable step), with
 * the stabilization split as in block_step. */
static void block_stiffness(struct gsn_explicit *e, int k, const double *x)
{
    const struct gsn_quadrature *q = e->quadrature;
    const struct gsn_point_blocks *b = e->blocks;
    const double *w = q->point_weight;
    const int S = b->subcells;
    const int p0 = b->block_point[k], p1 = b->block_point[k + 1];
    const int slots = b->block_slot[k + 1] - b->block_slot[k];
    double *u4 = block_work(e), *f4 = u4 + 4 * (size_t)b->max_block_slots;
    double *H = f4 + 4 * (size_t)b->max_block_slots;
    double *fold = H + 9 * (size_t)b->max_block_points;
    block_gather(e, k, x, u4);
    memset(f4, 0, sizeof(double) * 4 * (size_t)slots);
    for (int L = p0; L < p1; ++L) {
        double eps[6], sigma[6];
        double *HL = &H[9 * (L - p0)];
        int row = gsn_point_blocks_main_row(b, k, L);
        double A[18], P[27], C[18];
        if (b->fused)
            fused_row_gradient(b, row, u4, HL, A);
        else
            row_gradient(b, row, u4, HL);
        gsn_matrix_sym_to_voigt(HL, eps);
        double bulk = e->bulk_modulus[e->point_material[L]],
               shear = e->shear_modulus[e->point_material[L]];
        elastic_stress(bulk, shear, eps, sigma);
        elastic_piola(sigma, w[L], &fold[9 * (L - p0)]);
        if (b->fused) {
            for (int s = 0; s < 3; ++s) {
                double Hs[9];
                fused_point_gradient(A, 1, s, Hs);
                gsn_matrix_sym_to_voigt(Hs, eps);
                elastic_stress(bulk, shear, eps, sigma);
                elastic_piola(sigma, w[e->main_point_count + 3 * L + s],
                              &P[9 * s]);
            }
            fused_force_coefficients(P, &P[9], &P[18], C, 1);
            fused_row_scatter(b, row, &fold[9 * (L - p0)], C, 1, f4);
            continue;
        }
        for (int s = 0; s < S; ++s) {
            int p = e->main_point_count + S * L + s;
            int r = gsn_point_blocks_subcell_row(b, k, L, s);
            if (b->row_start[r] == b->row_start[r + 1])
                continue; /* an empty sub-cell */
            double Hs[9];
            row_gradient(b, r, u4, Hs);
            for (int a = 0; a < 9 && b->relative; ++a)
                Hs[a] -= HL[a];
            gsn_matrix_sym_to_voigt(Hs, eps);
            elastic_stress(bulk, shear, eps, sigma);
            subcell_scatter(b, r, sigma, w[p], &fold[9 * (L - p0)], f4);
        }
    }
    for (int L = p0; L < p1 && !b->fused; ++L)
        row_scatter(b, gsn_point_blocks_main_row(b, k, L), &fold[9 * (L - p0)],
                    f4);
    block_store(e, k, f4);
}

/* The lowest failed point, as a message naming step, time and particle. */
static int report_failure(const struct gsn_explicit *e, const char *what)
{
    const struct gsn_quadrature *q = e->quadrature;
    for (int p = 0; p < e->point_count; ++p) {
        if (!e->point_failed[p])
            continue;
        int particle =
            p < e->main_point_count ? e->point_owner[p] : q->point_particle[p];
        const double *x = &q->point_position[3 * p];
        double F[9];
        for (int a = 0; a < 9; ++a)
            F[a] = identity_entry(a) + e->displacement_gradient[9 * p + a];
        double J = gsn_matrix_determinant(F);
        return gsn_error_raise(
            GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
            "step %ld, t = %.6g s: %s at particle %d%s (reference position "
            "%g, %g, %g; det F before the step %.3g); the particle is "
            "inverted or the step is unstable: reduce time.step or check "
            "the boundary conditions",
            e->step + 1, (e->step + 1) * e->dt, what, particle,
            q->point_particle[p] < 0 ? ", at a Gauss point of its domain" : "",
            x[0], x[1], x[2], J);
    }
    return GSN_OK;
}

/* The rigid bodies' penalty forces at time t on the present coefficients
 * (contact.h); nothing without bodies. */
static int contact_forces(struct gsn_explicit *e, double t)
{
    if (!e->contact)
        return GSN_OK;
    return gsn_contact_forces(
        e->contact, e->constraints, e->quadrature->rk->position,
        &e->quadrature->particle_values, e->displacement, e->mass, e->dt, t,
        e->quadrature->rk->max_radius, e->contact_force, e->contact_resultant,
        &e->contact_count);
}

int gsn_explicit_set_contact(struct gsn_explicit *e,
                             const struct gsn_contact *contact)
{
    e->contact = contact;
    if (!contact)
        return GSN_OK;
    if (!e->contact_force)
        GSN_CALL(alloc_array((void **)&e->contact_force,
                             3 * (size_t)e->particle_count, sizeof(double)));
    GSN_CALL(contact_forces(e, e->time));
    store_previous_external(e);
    return GSN_OK;
}

int gsn_explicit_refresh(struct gsn_explicit *e)
{
    const double *w = e->quadrature->point_weight;
    e->pore_factor = e->load_factor;
    e->dead_count = 0;
    for (int p = 0; p < e->main_point_count; ++p)
        e->dead_count += e->point_dead[p];
#pragma omp parallel for if (parallel_worth(e->point_count))
    for (int p = 0; p < e->point_count; ++p) {
        double *P = &e->piola[9 * p];
        if (p < e->main_point_count) {
            nodal_piola(e->small_strain ? 0.0 : 1.0,
                        &e->displacement_gradient[9 * (size_t)p],
                        &e->stress[6 * (size_t)p], 1,
                        e->pore_pressure ? e->load_factor * e->pore_pressure[p]
                                         : 0.0,
                        w[p], P);
        } else {
            gsn_voigt_to_matrix(&e->stress[6 * p], P);
            for (int a = 0; a < 9; ++a)
                P[a] *= w[p];
        }
    }
    GSN_CALL(contact_forces(e, e->time));
    store_previous_external(e);
    return GSN_OK;
}

/* The step's distortion over the blocks (explicit.h) and the failed points
 * counted from the blocks' new ones; more than FAILED_SHARE of them is an
 * unstable run or a body that has broken up, and stops it, naming the
 * first point of the step's failures. */
#define FAILED_SHARE 0.01
static int gather_distortion(struct gsn_explicit *e)
{
    e->distortion_strain = 0.0;
    e->distortion_jacobian_min = INFINITY;
    e->distortion_jacobian_max = 0.0;
    e->distortion_point = 0;
    int newly_failed = 0, first_failed = -1;
    for (int k = 0; k < e->blocks->block_count; ++k) {
        const double *d = &e->block_distortion[DISTORTION_COLUMNS * (size_t)k];
        if (d[0] > e->distortion_strain) {
            e->distortion_strain = d[0];
            e->distortion_point = (int)d[3];
        }
        e->distortion_jacobian_min = fmin(e->distortion_jacobian_min, d[1]);
        e->distortion_jacobian_max = fmax(e->distortion_jacobian_max, d[2]);
        if (d[4] > 0.0 && newly_failed == 0)
            first_failed = (int)d[5];
        newly_failed += (int)d[4];
    }
    e->dead_count += newly_failed;
    int limit = (int)fmax(10.0, FAILED_SHARE * e->main_point_count);
    if (newly_failed == 0 || e->dead_count <= limit)
        return GSN_OK;
    const double *x = &e->quadrature->point_position[3 * (size_t)first_failed];
    return gsn_error_raise(
        GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
        "step %ld, t = %.6g s: det F <= 0 at %d integration points, more "
        "than %.0f%% of them (%d in this step, the first at particle %d, "
        "reference position %g, %g, %g): the run is unstable (reduce "
        "time.step) or the body has broken up",
        e->step + 1, gsn_explicit_time_of(e, e->step + 1), e->dead_count,
        100.0 * FAILED_SHARE, newly_failed, e->point_owner[first_failed], x[0],
        x[1], x[2]);
}

/* The pass's ranges of blocks for `threads` threads (explicit.h,
 * block_deque), one after the other: as long as the blocks each thread
 * took in the last pass, or equal when the thread count is new. */
static void plan_block_ranges(struct gsn_explicit *e, int threads)
{
    const long blocks = e->blocks->block_count;
    const int same = e->block_range_threads == threads;
    e->block_range_threads = threads;
    uint64_t start = 0;
    for (int t = 0; t < threads; ++t) {
        uint64_t count =
            same
                ? (uint64_t)e->block_taken[t]
                : (uint64_t)(blocks * (t + 1) / threads - blocks * t / threads);
        e->block_deque[8 * t] = start << 32 | (start + count);
        start += count;
    }
}

/* Block index from deque *word: its front (the owner) or its back (a
 * thief); -1 if it is empty. The compare-and-swap makes every block taken
 * once; what the blocks write is published by the barrier after them. */
static int take_block(uint64_t *word, int from_back)
{
    uint64_t old = __atomic_load_n(word, __ATOMIC_RELAXED);
    for (;;) {
        uint64_t front = old >> 32, back = old & 0xffffffffu;
        if (front >= back)
            return -1;
        uint64_t taken =
            from_back ? front << 32 | (back - 1) : (front + 1) << 32 | back;
        if (__atomic_compare_exchange_n(word, &old, taken, 1, __ATOMIC_RELAXED,
                                        __ATOMIC_RELAXED))
            return (int)(from_back ? back - 1 : front);
    }
}

/* Thread t's next block: its own range's front, else the back of the
 * range with the most blocks left; -1 when none is left. */
static int next_block(struct gsn_explicit *e, int t, int threads)
{
    int k = take_block(&e->block_deque[8 * t], 0);
    while (k < 0) {
        int victim = -1;
        uint64_t most = 0;
        for (int v = 0; v < threads; ++v) {
            uint64_t w =
                __atomic_load_n(&e->block_deque[8 * v], __ATOMIC_RELAXED);
            uint64_t front = w >> 32, back = w & 0xffffffffu;
            if (back > front && back - front > most) {
                most = back - front;
                victim = v;
            }
        }
        if (victim < 0)
            return -1;
        k = take_block(&e->block_deque[8 * victim], 1);
    }
    return k;
}

/* gsn_explicit_update_stress from the increments already in e->increment
 * (the step writes them with d_{n+1}). */
static int update_stress_from_increments(struct gsn_explicit *e)
{
    int failed = 0;
    int parallel = parallel_worth(e->point_count);
    /* One parallel region for the blocks and the reduction (a region costs a
     * wake-up of the threads; the reduction needs the barrier anyway). */
#pragma omp parallel if (parallel)
    {
        const int t = omp_get_thread_num(), threads = omp_get_num_threads();
#pragma omp single
        plan_block_ranges(e, threads);
        int taken = 0, failed_here = 0;
        for (int k; (k = next_block(e, t, threads)) >= 0; ++taken)
            failed_here |= block_step(e, k) != GSN_OK;
        e->block_taken[t] = taken;
        if (failed_here) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp barrier
        /* the next step's damage from this step's e_t (nonlocal.h) */
        if (e->nonlocal) {
            const size_t stride = (size_t)e->state_size;
#pragma omp for
            for (int p = 0; p < e->main_point_count; ++p)
                gsn_nonlocal_average(
                    e->nonlocal, p, e->state + e->strain_offset, stride,
                    &e->state[stride * (size_t)p + e->nonlocal_offset]);
        }
#pragma omp for
        for (int i = 0; i < e->particle_count; ++i)
            gsn_point_blocks_reduce_one(e->blocks, i, e->slot_force,
                                        &e->f_int[3 * (size_t)i]);
    }
    for (int t = 0; t < e->thread_count; ++t)
        for (int part = 0; part < GSN_PASS_PART_COUNT; ++part) {
            e->pass_part_ticks[part] += e->thread_part_ticks[8 * t + part];
            e->thread_part_ticks[8 * t + part] = 0.0;
        }
    if (failed) {
        GSN_CALL(report_failure(e, "det F <= 0 or the material update failed"));
        GSN_CHECK(0, GSN_ERR_NUMERICAL, "step %ld: the stress update failed",
                  e->step + 1);
    }
    GSN_CALL(gather_distortion(e));
    return GSN_OK;
}

/* Adds the wall time since *mark to phase `phase` and moves the mark. */
static void phase_end(struct gsn_explicit *e, enum gsn_explicit_phase phase,
                      double *mark)
{
    double now = omp_get_wtime();
    e->phase_seconds[phase] += now - *mark;
    *mark = now;
}

/* A range of particles or points [i0, i1) of a step loop; adds what it
 * sums into sums. */
typedef void (*step_range_fn)(struct gsn_explicit *e, int i0, int i1,
                              struct gsn_step_sums *sums);

/* Runs range over [0, count) in fixed pieces of SUM_PIECE, in parallel
 * when worth it, each piece summing in order and the pieces added in
 * order: the sums do not depend on the thread count. */
static struct gsn_step_sums step_loop(struct gsn_explicit *e, int count,
                                      step_range_fn range)
{
    int pieces = (count + SUM_PIECE - 1) / SUM_PIECE;
    struct gsn_step_sums *partial = e->step_partial,
                         total = {0, 0, 0, 0, 0, 0, -1};
#pragma omp parallel for schedule(static) if (parallel_worth(count))
    for (int k = 0; k < pieces; ++k) {
        int i0 = k * SUM_PIECE,
            i1 = i0 + SUM_PIECE < count ? i0 + SUM_PIECE : count;
        partial[k] = (struct gsn_step_sums){0, 0, 0, 0, 0, 0, -1};
        range(e, i0, i1, &partial[k]);
    }
    for (int k = 0; k < pieces; ++k) {
        total.dissipated += partial[k].dissipated;
        total.released += partial[k].released;
        total.external += partial[k].external;
        total.kinetic += partial[k].kinetic;
        total.kinetic_conserved += partial[k].kinetic_conserved;
        total.internal += partial[k].internal;
        if (total.first_nonfinite < 0)
            total.first_nonfinite = partial[k].first_nonfinite;
    }
    return total;
}

/* The step's increments d - d_n, 4 doubles a particle (the 4th zero), as
 * the pass gathers them (block_gather_increment). */
static void store_increment(struct gsn_explicit *e, int i0, int i1,
                            struct gsn_step_sums *sums)
{
    (void)sums;
    for (int i = i0; i < i1; ++i) {
        double *to = &e->increment[4 * (size_t)i];
        for (int k = 0; k < 3; ++k)
            to[k] = e->displacement[3 * i + k] -
                    e->previous_displacement[3 * i + k];
        to[3] = 0.0;
    }
}

/* d_{n+1} = d_n + dt v_n + dt^2/2 a_n (eq. (33)) and the increments
 * d_{n+1} - d_n (store_increment's); d_n is kept in previous_displacement
 * only where `keep` (a step that corrects d_{n+1} after, and recomputes the
 * increments): the other steps do not write it (24 bytes a particle). */
__attribute__((always_inline)) static inline void
predict_range(struct gsn_explicit *e, int i0, int i1, int keep)
{
    const double dt = e->dt;
    for (int i = i0; i < i1; ++i) {
        double *to = &e->increment[4 * (size_t)i];
        for (int k = 0; k < 3; ++k) {
            const size_t at = 3 * (size_t)i + (size_t)k;
            const double old = e->displacement[at];
            const double d = old + (dt * e->velocity[at] +
                                    0.5 * dt * dt * e->acceleration[at]);
            if (keep)
                e->previous_displacement[at] = old;
            e->displacement[at] = d;
            to[k] = d - old;
        }
        to[3] = 0.0;
    }
}

static void predict_displacement(struct gsn_explicit *e, int i0, int i1,
                                 struct gsn_step_sums *sums)
{
    (void)sums;
    predict_range(e, i0, i1, 1);
}

static void predict_increments(struct gsn_explicit *e, int i0, int i1,
                               struct gsn_step_sums *sums)
{
    (void)sums;
    predict_range(e, i0, i1, 0);
}

int gsn_explicit_update_stress(struct gsn_explicit *e)
{
    step_loop(e, e->particle_count, store_increment);
    return update_stress_from_increments(e);
}

/* a_{n+1} = M^-1 (f_ext - f_int) (eq. (32)), with the local damping on
 * free components (explicit.h); the constraints correct it after. The
 * works over the step read its increments d_{n+1} - d_n (e->increment). */
static void new_accelerations(struct gsn_explicit *e, int i0, int i1,
                              struct gsn_step_sums *sums)
{
    const double dt = e->dt;
    double *a1 = e->new_acceleration;
    double released = 0.0, dissipated = 0.0; /* (as reactions_and_energies) */
    for (int i = i0; i < i1; ++i) {
        for (int k = 0; k < 3; ++k) {
            int at = 3 * i + k;
            double f = net_force(e, at, e->release_next);
            if (e->release_force)
                released += 0.5 * (e->release_factor + e->release_next) *
                            e->release_force[at] *
                            e->increment[4 * (size_t)i + (size_t)k];
            if (e->damping_local > 0.0) {
                double damping = 0.0;
                if (!(e->constrained[i] & (1 << k))) {
                    double v_half =
                        e->velocity[at] + 0.5 * dt * e->acceleration[at];
                    /* with damping_net, on the force the supports leave
                     * unbalanced (the last step's reaction added) */
                    double net = fabs(e->damping_net ? f + e->reaction[at] : f);
                    damping = v_half > 0.0   ? -e->damping_local * net
                              : v_half < 0.0 ? e->damping_local * net
                                             : 0.0;
                }
                dissipated -= 0.5 * (e->damping_force[at] + damping) *
                              e->increment[4 * (size_t)i + (size_t)k];
                e->damping_force[at] = damping;
                f += damping;
            }
            a1[at] = k == e->held_axis ? 0.0 : f / e->mass[i];
        }
    }
    sums->released += released;
    sums->dissipated += dissipated;
}

/* v_{n+1} = v_n + dt/2 (a_n + a_{n+1}) (eq. (34)); plane_strain holds one
 * component at zero in every coefficient (its a, v and u stay 0: so does
 * the approximation's, sum_I Psi_I d_I, at every point, and an update's
 * interpolation of that zero field returns 0 before any iteration). */
static void new_velocities(struct gsn_explicit *e, int i0, int i1,
                           struct gsn_step_sums *sums)
{
    (void)sums;
    const double dt = e->dt;
    for (int i = 3 * i0; i < 3 * i1; ++i) {
        e->velocity[i] +=
            0.5 * dt * (e->acceleration[i] + e->new_acceleration[i]);
        e->acceleration[i] = e->new_acceleration[i];
    }
}

/* Component at's share of the kinetic energies (explicit.h), added to
 * kinetic and conserved. */
static inline void add_kinetic(const struct gsn_explicit *e, int at,
                               double half_step2, double *kinetic,
                               double *conserved)
{
    double v = e->velocity[at], a = e->acceleration[at], m = e->mass[at / 3];
    *kinetic += 0.5 * m * v * v;
    /* v_{n-1/2} v_{n+1/2} = v^2 - (dt/2)^2 a^2 */
    *conserved += 0.5 * m * (v * v - half_step2 * a * a);
}

/* The kinetic energies of particles [i0, i1). */
static void kinetic_energies(struct gsn_explicit *e, int i0, int i1,
                             struct gsn_step_sums *sums)
{
    const double half_step2 = 0.25 * e->dt * e->dt;
    double kinetic = 0.0, conserved = 0.0;
    for (int at = 3 * i0; at < 3 * i1; ++at)
        add_kinetic(e, at, half_step2, &kinetic, &conserved);
    sums->kinetic += kinetic;
    sums->kinetic_conserved += conserved;
}

/* The external work (trapezoid; the reactions C^T lambda come from the
 * constraints' correction of a), the kinetic energies, and a check that v
 * is finite. The sums run in locals: the stores to previous_external could
 * alias *sums. */
static void reactions_and_energies(struct gsn_explicit *e, int i0, int i1,
                                   struct gsn_step_sums *sums)
{
    const double half_step2 = 0.25 * e->dt * e->dt;
    double external = 0.0, kinetic = 0.0, conserved = 0.0;
    for (int i = i0; i < i1; ++i) {
        for (int k = 0; k < 3; ++k) {
            int at = 3 * i + k;
            double total = external_force(e, at);
            external += 0.5 * (e->previous_external[at] + total) *
                        e->increment[4 * (size_t)i + (size_t)k];
            e->previous_external[at] = total;
            add_kinetic(e, at, half_step2, &kinetic, &conserved);
        }
        if (sums->first_nonfinite < 0 &&
            !isfinite(e->velocity[3 * i] + e->velocity[3 * i + 1] +
                      e->velocity[3 * i + 2]))
            sums->first_nonfinite = i;
    }
    sums->external += external;
    sums->kinetic += kinetic;
    sums->kinetic_conserved += conserved;
}

/* The loop's kinetic energies from a pass's sums. */
static void keep_kinetic(struct gsn_explicit *e, const struct gsn_step_sums *s)
{
    e->kinetic_energy = s->kinetic;
    e->conserved_kinetic_energy = s->kinetic_conserved;
}

void gsn_explicit_kinetic_energies(struct gsn_explicit *e)
{
    struct gsn_step_sums sums =
        step_loop(e, e->particle_count, kinetic_energies);
    keep_kinetic(e, &sums);
}

/* new_velocities and reactions_and_energies on one piece, while it is in
 * cache (the steps that leave v to eq. (34) alone). */
static void velocities_and_energies(struct gsn_explicit *e, int i0, int i1,
                                    struct gsn_step_sums *sums)
{
    new_velocities(e, i0, i1, sums);
    reactions_and_energies(e, i0, i1, sums);
}

/* The internal energy increments of points [p0, p1). */
static void internal_work(struct gsn_explicit *e, int p0, int p1,
                          struct gsn_step_sums *sums)
{
    for (int p = p0; p < p1; ++p)
        sums->internal += e->point_energy[p];
}

int gsn_explicit_step(struct gsn_explicit *e)
{
    double mark = omp_get_wtime();
    const double factor0 =
        e->constraints ? gsn_constraints_factor_seconds(e->constraints) : 0.0;
    const double t1 = gsn_explicit_time_of(e, e->step + 1);
    const int n = e->particle_count;
    /* The constraints are linear, so once v and a satisfy them, eqs. (33)
     * and (34) keep d and v satisfying them: only a is corrected every step;
     * d and v at the first step (a prescribed velocity starts with a jump)
     * and every CONSTRAINT_REFRESH steps against round-off drift; every
     * step while a ramp changes the prescribed accelerations (eq. (33) is
     * then exact only to O(dt^3)). */
    int refresh =
        e->step % CONSTRAINT_REFRESH == 0 ||
        (e->constraints && gsn_constraints_ramping(e->constraints, e->time));
    step_loop(e, n,
              e->constraints && refresh ? predict_displacement
                                        : predict_increments);
    phase_end(e, GSN_PHASE_UPDATES, &mark);
    if (e->constraints && refresh) {
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values,
            GSN_FIELD_DISPLACEMENT, t1, e->displacement, NULL));
        phase_end(e, GSN_PHASE_CONSTRAINTS, &mark);
        step_loop(e, n, store_increment);
        phase_end(e, GSN_PHASE_UPDATES, &mark);
    }

    GSN_CALL(update_stress_from_increments(e));
    phase_end(e, GSN_PHASE_PASS, &mark);
    GSN_CALL(contact_forces(e, t1));
    if (e->legacy_boundary_term)
        legacy_boundary_term(e);
    phase_end(e, GSN_PHASE_CONSTRAINTS, &mark);

    if (e->release_force)
        e->release_next =
            fmax(0.0, 1.0 - (double)(e->step + 1 - e->release_start) /
                                (double)e->release_steps);
    struct gsn_step_sums forces = step_loop(e, n, new_accelerations);
    e->release_work += forces.released;
    if (e->release_force) {
        e->release_factor = e->release_next;
        if (e->release_factor == 0.0) {
            free(e->release_force);
            e->release_force = NULL;
        }
    }
    double dissipated = forces.dissipated;
    phase_end(e, GSN_PHASE_UPDATES, &mark);
    if (e->constraints)
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values,
            GSN_FIELD_ACCELERATION, t1, e->new_acceleration, e->reaction));
    phase_end(e, GSN_PHASE_CONSTRAINTS, &mark);
    struct gsn_step_sums sums;
    if (e->constraints && refresh) {
        step_loop(e, n, new_velocities);
        phase_end(e, GSN_PHASE_UPDATES, &mark);
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values, GSN_FIELD_VELOCITY,
            t1, e->velocity, NULL));
        phase_end(e, GSN_PHASE_CONSTRAINTS, &mark);
        sums = step_loop(e, n, reactions_and_energies);
    } else {
        sums = step_loop(e, n, velocities_and_energies);
    }
    GSN_CHECK(sums.first_nonfinite < 0, GSN_ERR_NUMERICAL,
              "step %ld, t = %.6g s: the velocity of particle %d is not "
              "finite; the step is unstable: reduce time.step",
              e->step + 1, t1, sums.first_nonfinite);
    keep_kinetic(e, &sums);
    e->internal_energy += step_loop(e, e->point_count, internal_work).internal;
    e->external_work += sums.external;
    e->damping_work += dissipated;
    e->pore_factor = e->load_factor;
    e->step++;
    e->time = t1;
    phase_end(e, GSN_PHASE_UPDATES, &mark);
    /* a factorization is not a step's cost: kept apart */
    if (e->constraints) {
        double factor =
            gsn_constraints_factor_seconds(e->constraints) - factor0;
        e->phase_seconds[GSN_PHASE_CONSTRAINTS] -= factor;
        e->factor_seconds += factor;
    }
    return GSN_OK;
}

double gsn_explicit_step_bytes(const struct gsn_explicit *e)
{
    const double word = sizeof(double);
    const struct gsn_point_blocks *b = e->blocks;
    double slots = b->block_slot[b->block_count];
    double particles = 3 * (2 + 2 + 2) + 1 + 3 + 3 * 2;
    double points = 9 * 2 + 6 * 2 + 2.0 * e->state_size + 9 + 1;
    return (double)gsn_point_blocks_bytes(b) + slots * 3 * 2 * word +
           e->particle_count * particles * word +
           e->main_point_count * points * word +
           (e->point_count - e->main_point_count) * 6 * 2 * word;
}

double gsn_explicit_time_of(const struct gsn_explicit *e, long step)
{
    return e->time_base + (double)(step - e->step_base) * e->dt;
}

void gsn_explicit_set_time_step(struct gsn_explicit *e, double dt)
{
    e->time_base = e->time;
    e->step_base = e->step;
    e->dt = dt;
}

/* y = K x of the linear elastic system at the reference configuration. */
static void apply_stiffness(struct gsn_explicit *e, const double *x, double *y)
{
#pragma omp parallel for schedule(dynamic,                                     \
                                  2) if (parallel_worth(e->point_count))
    for (int k = 0; k < e->blocks->block_count; ++k)
        block_stiffness(e, k, x);
    gsn_point_blocks_reduce(e->blocks, e->particle_count, e->slot_force, y,
                            parallel_worth(e->particle_count));
}

/* The largest eigenvalue of the symmetric tridiagonal matrix (diagonal
 * a[0..m), off-diagonal b[0..m-1)) by Sturm bisection, and the last
 * component of its unit eigenvector (inverse iteration), for the Ritz
 * residual. */
static double tridiagonal_largest(const double *a, const double *b, int m,
                                  double *last, double *work)
{
    double lo = a[0], hi = a[0];
    for (int i = 0; i < m; ++i) { /* Gershgorin */
        double r =
            (i > 0 ? fabs(b[i - 1]) : 0.0) + (i < m - 1 ? fabs(b[i]) : 0.0);
        lo = fmin(lo, a[i] - r);
        hi = fmax(hi, a[i] + r);
    }
    for (int k = 0; k < 200 && hi - lo > 1e-15 * fabs(hi); ++k) {
        double mid = 0.5 * (lo + hi), d = 1.0;
        int below = 0; /* eigenvalues below mid: negative pivots of T - mid */
        for (int i = 0; i < m; ++i) {
            d = a[i] - mid - (i > 0 ? b[i - 1] * b[i - 1] / d : 0.0);
            if (d == 0.0)
                d = 1e-300;
            below += d < 0.0;
        }
        if (below < m) /* the largest lies above mid */
            lo = mid;
        else
            hi = mid;
    }
    double theta = hi;
    /* inverse iteration (T - theta') v = v with theta' just above theta:
     * the Thomas algorithm, two sweeps */
    double shift = theta * (1.0 + 1e-10) + 1e-300, *c = work, *v = work + m;
    for (int i = 0; i < m; ++i)
        v[i] = 1.0;
    for (int sweep = 0; sweep < 2; ++sweep) {
        double pivot = a[0] - shift;
        c[0] = m > 1 ? b[0] / pivot : 0.0;
        v[0] /= pivot;
        for (int i = 1; i < m; ++i) {
            pivot = a[i] - shift - b[i - 1] * c[i - 1];
            c[i] = i < m - 1 ? b[i] / pivot : 0.0;
            v[i] = (v[i] - b[i - 1] * v[i - 1]) / pivot;
        }
        for (int i = m - 2; i >= 0; --i)
            v[i] -= c[i] * v[i + 1];
        double norm = 0.0;
        for (int i = 0; i < m; ++i)
            norm += v[i] * v[i];
        norm = sqrt(norm);
        for (int i = 0; i < m; ++i)
            v[i] /= norm;
    }
    *last = fabs(v[m - 1]);
    return theta;
}

/* x (n x 3) projected onto the motions the constraints allow, as the loop
 * projects a: the plane-strain axis held, then the constraints' rows. */
static int project_homogeneous(struct gsn_explicit *e, double *x)
{
    if (e->held_axis >= 0)
        for (int i = 0; i < e->particle_count; ++i)
            x[3 * (size_t)i + (size_t)e->held_axis] = 0.0;
    if (!e->constraints)
        return GSN_OK;
    return gsn_constraints_apply(e->constraints,
                                 &e->quadrature->particle_values,
                                 GSN_FIELD_HOMOGENEOUS, 0.0, x, NULL);
}

int gsn_explicit_stable_step(struct gsn_explicit *e, double *dt)
{
    const size_t n3 = 3 * (size_t)e->particle_count;
    double *v = NULL, *previous = NULL, *y = NULL;
    double alpha[LANCZOS_STEPS], beta[LANCZOS_STEPS], work[2 * LANCZOS_STEPS];
    int rc = GSN_OK;
    GSN_CALL_GOTO(alloc_array((void **)&v, n3, sizeof(double)), rc, done);
    GSN_CALL_GOTO(alloc_array((void **)&previous, n3, sizeof(double)), rc,
                  done);
    GSN_CALL_GOTO(alloc_array((void **)&y, n3, sizeof(double)), rc, done);
    /* Lanczos on P M^-1 K P in the mass inner product <x, y> = x^T M y,
     * with P the constraints' mass-orthogonal projection (constraint.h):
     * the loop corrects every acceleration by it, so central differences
     * are stable up to 2 / sqrt(lambda_max) of the motions it allows, and
     * the stiffest modes of M^-1 K (held particles of small mass, on the
     * edges of held faces) are not among them: Slope I's step 1.7 times
     * the unconstrained estimate (docs/solver.md, "Time step"). P is
     * M-self-adjoint, so projecting the start and every new vector keeps
     * the recurrence. From a deterministic start with every mode present
     * (a hashed sequence); the Ritz values approach the largest eigenvalue
     * from below, so the estimate adds the residual bound beta_m |s_m|. */
    unsigned state = 12345u;
    for (size_t i = 0; i < n3; ++i) {
        state = state * 1664525u + 1013904223u;
        v[i] = (double)(state >> 8) / 16777216.0 - 0.5;
    }
    GSN_CALL_GOTO(project_homogeneous(e, v), rc, done);
    double norm = 0.0;
    for (size_t i = 0; i < n3; ++i)
        norm += e->mass[i / 3] * v[i] * v[i];
    norm = sqrt(norm);
    for (size_t i = 0; i < n3; ++i)
        v[i] /= norm;
    double lambda = 0.0;
    for (int m = 0; m < LANCZOS_STEPS; ++m) {
        apply_stiffness(e, v, y); /* y = K v */
        double a = 0.0;
        for (size_t i = 0; i < n3; ++i)
            a += v[i] * y[i];
        alpha[m] = a;
        /* w = P M^-1 K v - a v - beta_(m-1) v_(m-1), into y */
        for (size_t i = 0; i < n3; ++i)
            y[i] = y[i] / e->mass[i / 3] - a * v[i] -
                   (m > 0 ? beta[m - 1] * previous[i] : 0.0);
        GSN_CALL_GOTO(project_homogeneous(e, y), rc, done);
        double b2 = 0.0;
        for (size_t i = 0; i < n3; ++i)
            b2 += e->mass[i / 3] * y[i] * y[i];
        beta[m] = sqrt(b2);
        double last;
        double theta = tridiagonal_largest(alpha, beta, m + 1, &last, work);
        double bound = beta[m] * last;
        lambda = theta + bound;
        GSN_CHECK_GOTO(isfinite(lambda), rc, GSN_ERR_NUMERICAL, done,
                       "the stable step estimate broke down");
        if (bound <= LANCZOS_TOLERANCE * theta || !(beta[m] > 0.0))
            break;
        for (size_t i = 0; i < n3; ++i) {
            previous[i] = v[i];
            v[i] = y[i] / beta[m];
        }
    }
    GSN_CHECK_GOTO(lambda > 0.0, rc, GSN_ERR_NUMERICAL, done,
                   "the stiffness has no positive eigenvalue");
    /* (explicit.h: the local damping's stiffening) */
    *dt = 2.0 / sqrt((1.0 + e->damping_local) * lambda);
done:
    free(v);
    free(previous);
    free(y);
    /* The iteration used the first-pass arrays as scratch. */
    if (rc == GSN_OK)
        rc = gsn_explicit_refresh(e);
    return rc;
}

void gsn_explicit_particle_field(const struct gsn_explicit *e,
                                 const double *coefficients, double *out)
{
    const struct gsn_shape_rows *values = &e->quadrature->particle_values;
#pragma omp parallel for if (parallel_worth(e->particle_count))
    for (int j = 0; j < e->particle_count; ++j) {
        double u[3] = {0.0, 0.0, 0.0};
        for (int k = values->offset[j]; k < values->offset[j + 1]; ++k)
            for (int c = 0; c < 3; ++c)
                u[c] +=
                    values->value[k] * coefficients[3 * values->index[k] + c];
        memcpy(&out[3 * j], u, sizeof u);
    }
}

/* out_J (count values) = sum_p (w_p / W_J) values[stride p .. + count]
 * over the points p of J's nodal domain, W_J their total weight: the
 * nodal point's own values (a share of exactly 1) with nodal
 * integration. */
static void domain_mean(const struct gsn_explicit *e, const double *values,
                        int stride, int count, double *out)
{
    const double *w = e->quadrature->point_weight;
#pragma omp parallel for if (parallel_worth(e->particle_count))
    for (int j = 0; j < e->particle_count; ++j) {
        double *o = &out[(size_t)count * j];
        for (int k = e->domain_offset[j]; k < e->domain_offset[j + 1]; ++k) {
            int p = e->domain_point[k];
            double share = w[p] / e->domain_weight[j];
            const double *v = &values[(size_t)stride * p];
            for (int a = 0; a < count; ++a)
                o[a] = k == e->domain_offset[j] ? share * v[a]
                                                : o[a] + share * v[a];
        }
    }
}

void gsn_explicit_particle_stress(const struct gsn_explicit *e, double *out)
{
    domain_mean(e, e->stress, 6, 6, out);
}

void gsn_explicit_particle_state(const struct gsn_explicit *e, int offset,
                                 double *out)
{
    domain_mean(e, e->state + offset, e->state_size, 1, out);
}

int gsn_explicit_set_point_mass(struct gsn_explicit *e, const double *mass)
{
    memcpy(e->point_mass, mass, sizeof(double) * (size_t)e->main_point_count);
    return build_mass(e);
}

void gsn_explicit_particle_displacement(const struct gsn_explicit *e,
                                        double *out)
{
    gsn_explicit_particle_field(e, e->displacement, out);
    for (size_t i = 0; i < 3 * (size_t)e->particle_count; ++i)
        out[i] += e->reference_offset[i];
}

/* The forces of block k from the present stress alone (no increment, no
 * material): the nodal points' P (piola, from gsn_explicit_refresh) and
 * the stabilization points' sigma w, folded and scattered as in
 * block_step. */
static void block_forces(struct gsn_explicit *e, int k)
{
    const struct gsn_point_blocks *b = e->blocks;
    const double *w = e->quadrature->point_weight;
    const int S = b->subcells;
    const int p0 = b->block_point[k], p1 = b->block_point[k + 1];
    const int slots = b->block_slot[k + 1] - b->block_slot[k];
    double *f4 = block_work(e) + 4 * (size_t)b->max_block_slots;
    double *fold = f4 + 4 * (size_t)b->max_block_slots;
    memset(f4, 0, sizeof(double) * 4 * (size_t)slots);
    memcpy(fold, &e->piola[9 * (size_t)p0],
           sizeof(double) * 9 * (size_t)(p1 - p0));
    for (int L = p0; L < p1 && b->fused; ++L) {
        double C[18] = {0};
        if (!e->point_dead[L])
            fused_coefficients(e, L, e->stress, C);
        fused_row_scatter(b, gsn_point_blocks_main_row(b, k, L),
                          &fold[9 * (L - p0)], C, 1, f4);
    }
    for (int L = p0; L < p1 && !b->fused; ++L)
        for (int s = 0; s < S && !e->point_dead[L]; ++s) {
            int p = e->main_point_count + S * L + s;
            int r = gsn_point_blocks_subcell_row(b, k, L, s);
            if (b->row_start[r] == b->row_start[r + 1])
                continue;
            subcell_scatter(b, r, &e->stress[6 * (size_t)p], w[p],
                            &fold[9 * (L - p0)], f4);
        }
    for (int L = p0; L < p1 && !b->fused; ++L)
        row_scatter(b, gsn_point_blocks_main_row(b, k, L), &fold[9 * (L - p0)],
                    f4);
    block_store(e, k, f4);
}

int gsn_explicit_settle(struct gsn_explicit *e)
{
    const int n = e->particle_count;
    if (e->constraints) {
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values, GSN_FIELD_VELOCITY,
            e->time, e->velocity, NULL));
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values,
            GSN_FIELD_DISPLACEMENT, e->time, e->displacement, NULL));
    }
    GSN_CALL(gsn_explicit_refresh(e)); /* P */
#pragma omp parallel if (parallel_worth(e->point_count))
    {
#pragma omp for schedule(dynamic, 2)
        for (int k = 0; k < e->blocks->block_count; ++k)
            block_forces(e, k);
#pragma omp for
        for (int i = 0; i < n; ++i)
            gsn_point_blocks_reduce_one(e->blocks, i, e->slot_force,
                                        &e->f_int[3 * (size_t)i]);
    }
    /* no motion: d_{n+1} = d_n, so no work is done below */
    memcpy(e->previous_displacement, e->displacement,
           sizeof(double) * 3 * (size_t)n);
    step_loop(e, n, new_accelerations);
    if (e->constraints)
        GSN_CALL(gsn_constraints_apply(
            e->constraints, &e->quadrature->particle_values,
            GSN_FIELD_ACCELERATION, e->time, e->new_acceleration, e->reaction));
    memcpy(e->acceleration, e->new_acceleration,
           sizeof(double) * 3 * (size_t)n);
    /* reactions and the kinetic energy; the external force of this state
     * starts the next trapezoid (no work: d does not move) */
    struct gsn_step_sums sums = step_loop(e, n, reactions_and_energies);
    keep_kinetic(e, &sums);
    return GSN_OK;
}

/* gsn_explicit_interpolate: at most this many conjugate-gradient
 * iterations, to a residual of INTERPOLATE_TOLERANCE of the right-hand side
 * (max norm). */
enum { INTERPOLATE_MAX_ITERATIONS = 2000 };
#define INTERPOLATE_TOLERANCE 1e-12

/* lambda_apply for a constant count (inlined: the sums stay in registers). */
static inline void lambda_apply_fixed(const struct gsn_shape_rows *rows, int n,
                                      const int count, const double *const *x,
                                      double *const *y)
{
    const double *x0 = x[0], *x1 = count > 1 ? x[1] : x[0],
                 *x2 = count > 2 ? x[2] : x[0];
#pragma omp parallel for if (parallel_worth(n))
    for (int J = 0; J < n; ++J) {
        double s0 = 0.0, s1 = 0.0, s2 = 0.0;
        for (int k = rows->offset[J]; k < rows->offset[J + 1]; ++k) {
            const double v = rows->value[k];
            const int I = rows->index[k];
            /* fma pinned: the compiler contracted some variants, not all */
            s0 = fma(v, x0[I], s0);
            if (count > 1)
                s1 = fma(v, x1[I], s1);
            if (count > 2)
                s2 = fma(v, x2[I], s2);
        }
        y[0][J] = s0;
        if (count > 1)
            y[1][J] = s1;
        if (count > 2)
            y[2][J] = s2;
    }
}

/* y_a = Lambda x_a (rows: Lambda_JI = Psi_I(X_J)) for the `count` (1 to 3)
 * vectors x_a, reading the rows once for all. */
static void lambda_apply(const struct gsn_shape_rows *rows, int n, int count,
                         const double *const *x, double *const *y)
{
    if (count == 3)
        lambda_apply_fixed(rows, n, 3, x, y);
    else if (count == 2)
        lambda_apply_fixed(rows, n, 2, x, y);
    else
        lambda_apply_fixed(rows, n, 1, x, y);
}

/* a . b over n values, in fixed pieces added in order: the same bits on
 * any thread count. */
static double dot_ordered(const double *a, const double *b, int n,
                          double *partial)
{
    int pieces = (n + SUM_PIECE - 1) / SUM_PIECE;
#pragma omp parallel for if (parallel_worth(n))
    for (int k = 0; k < pieces; ++k) {
        int i1 = (k + 1) * SUM_PIECE < n ? (k + 1) * SUM_PIECE : n;
        double sum = 0.0;
        for (int i = k * SUM_PIECE; i < i1; ++i)
            sum += a[i] * b[i];
        partial[k] = sum;
    }
    double total = 0.0;
    for (int k = 0; k < pieces; ++k)
        total += partial[k];
    return total;
}

static double max_abs(const double *a, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i)
        m = gsn_max(m, fabs(a[i]));
    return m;
}

/* The rows of Lambda^T: for each I, Psi_I(X_J) over the J that see it, in
 * the order of J (lambda_apply on them gives Lambda^T x, the same bits on
 * any thread count). */
static int lambda_transpose(const struct gsn_shape_rows *rows, int n,
                            struct gsn_shape_rows *columns)
{
    int entries = rows->offset[n];
    columns->row_count = n;
    columns->offset = calloc((size_t)n + 1, sizeof(int));
    columns->index = malloc(sizeof(int) * (size_t)(entries ? entries : 1));
    columns->value = malloc(sizeof(double) * (size_t)(entries ? entries : 1));
    int *next = malloc(sizeof(int) * (size_t)(n ? n : 1));
    if (!columns->offset || !columns->index || !columns->value || !next) {
        free(next);
        return gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__, __func__,
                               "cannot allocate %d entries", entries);
    }
    for (int k = 0; k < entries; ++k)
        ++columns->offset[rows->index[k] + 1];
    for (int I = 0; I < n; ++I)
        columns->offset[I + 1] += columns->offset[I];
    memcpy(next, columns->offset, sizeof(int) * (size_t)n);
    for (int J = 0; J < n; ++J)
        for (int k = rows->offset[J]; k < rows->offset[J + 1]; ++k) {
            int at = next[rows->index[k]]++;
            columns->index[at] = J;
            columns->value[at] = rows->value[k];
        }
    free(next);
    return GSN_OK;
}

/* The weights of the interpolation: W, the particles' masses (at the
 * values), and M, the lumped masses (at the coefficients), M = Lambda^T W 1. */
struct interpolation_weights {
    const double *particle; /* W */
    const double *lumped;   /* M */
};

/* y_a = A x_a = (Lambda^T W Lambda + eps M) x_a for `count` components;
 * work_a holds n each. */
static void normal_apply(const struct gsn_shape_rows *rows,
                         const struct gsn_shape_rows *columns, int n, int count,
                         struct interpolation_weights weights,
                         const double *const *x, double *const *work,
                         double *const *y)
{
    lambda_apply(rows, n, count, x, work);
    for (int a = 0; a < count; ++a)
        for (int J = 0; J < n; ++J)
            work[a][J] *= weights.particle[J];
    lambda_apply(columns, n, count, (const double *const *)work, y);
    for (int a = 0; a < count; ++a)
        for (int I = 0; I < n; ++I)
            y[a][I] +=
                GSN_INTERPOLATE_REGULARIZATION * weights.lumped[I] * x[a][I];
}

/* The conjugate-gradient state of one component (interpolate_components). */
struct interpolation_cg {
    double *r, *z, *p, *q, *delta, *scratch;
    double rz, goal, residual;
    int iterations, done;
};

/* Coefficients c for the values b of one component: c = b + delta with
 * delta minimizing |Lambda c - b|_W^2 + eps |delta|_M^2 with the momentum
 * kept, 1^T W Lambda c = 1^T W b. Unconstrained,
 * (Lambda^T W Lambda + eps M) delta = Lambda^T W (b - Lambda b), by
 * conjugate gradients with the diagonal as preconditioner from delta = 0;
 * as A 1 = (1 + eps) M 1 = (1 + eps) Lambda^T W 1 (partition of unity),
 * the constraint's multiplier adds a uniform shift. The three components
 * run side by side, each with its own iteration (the same arithmetic as
 * one at a time), so that the rows are read once for all. b and c: n x 3;
 * work holds 18 n + pieces doubles. Returns the most iterations, or -1
 * without convergence; *residual and *failed get the residual (max norm)
 * and the component of a failure. */
static int interpolate_components(const struct gsn_shape_rows *rows,
                                  const struct gsn_shape_rows *columns, int n,
                                  struct interpolation_weights weights,
                                  const double *diagonal, const double *b,
                                  double *c, double *work, double *residual,
                                  int *failed)
{
    struct interpolation_cg cg[3];
    double *partial = work + 18 * (size_t)n;
    const double *in[3];
    double *out[3], *scratch[3];
    for (int a = 0; a < 3; ++a) {
        struct interpolation_cg *g = &cg[a];
        double *w = work + 6 * (size_t)n * (size_t)a;
        g->r = w;
        g->z = w + n;
        g->p = w + 2 * (size_t)n;
        g->q = w + 3 * (size_t)n;
        g->delta = w + 4 * (size_t)n;
        g->scratch = w + 5 * (size_t)n;
        for (int J = 0; J < n; ++J)
            g->z[J] = b[3 * J + a]; /* b of this component */
        in[a] = g->z;
        out[a] = g->scratch;
        scratch[a] = g->q;
    }
    /* r = Lambda^T W (b - Lambda b) */
    lambda_apply(rows, n, 3, in, out);
    for (int a = 0; a < 3; ++a)
        for (int J = 0; J < n; ++J)
            cg[a].scratch[J] =
                weights.particle[J] * (cg[a].z[J] - cg[a].scratch[J]);
    for (int a = 0; a < 3; ++a) {
        in[a] = cg[a].scratch;
        out[a] = cg[a].r;
    }
    lambda_apply(columns, n, 3, in, out);
    int most = 0;
    for (int a = 0; a < 3; ++a) {
        struct interpolation_cg *g = &cg[a];
        memset(g->delta, 0, sizeof(double) * (size_t)n);
        memset(g->p, 0, sizeof(double) * (size_t)n); /* beta p is 0 at first */
        g->residual = max_abs(g->r, n);
        g->goal = INTERPOLATE_TOLERANCE * g->residual;
        g->iterations = 0;
        g->rz = 0.0;
        g->done = !(g->residual > g->goal);
    }
    for (;;) {
        int active[3], count = 0;
        for (int a = 0; a < 3; ++a)
            if (!cg[a].done)
                active[count++] = a;
        if (count == 0)
            break;
        for (int k = 0; k < count; ++k) {
            struct interpolation_cg *g = &cg[active[k]];
            if (++g->iterations > INTERPOLATE_MAX_ITERATIONS) {
                *residual = g->residual;
                *failed = active[k];
                return -1;
            }
            for (int I = 0; I < n; ++I)
                g->z[I] = g->r[I] / diagonal[I];
            double rz1 = dot_ordered(g->r, g->z, n, partial);
            double beta = g->iterations > 1 ? rz1 / g->rz : 0.0;
            g->rz = rz1;
            for (int I = 0; I < n; ++I)
                g->p[I] = g->z[I] + beta * g->p[I];
            in[k] = g->p;
            out[k] = g->q;
            scratch[k] = g->scratch;
        }
        normal_apply(rows, columns, n, count, weights, in, scratch, out);
        for (int k = 0; k < count; ++k) {
            struct interpolation_cg *g = &cg[active[k]];
            double pq = dot_ordered(g->p, g->q, n, partial);
            if (!(pq > 0.0)) {
                *residual = g->residual;
                *failed = active[k];
                return -1;
            }
            double alpha = g->rz / pq;
            for (int I = 0; I < n; ++I) {
                g->delta[I] += alpha * g->p[I];
                g->r[I] -= alpha * g->q[I];
            }
            g->residual = max_abs(g->r, n);
            g->done = !(g->residual > g->goal);
        }
    }
    for (int a = 0; a < 3; ++a) {
        struct interpolation_cg *g = &cg[a];
        most = g->iterations > most ? g->iterations : most;
        double *x = g->scratch, *one = g->q;
        for (int I = 0; I < n; ++I)
            x[I] = b[3 * I + a] + g->delta[I];
        for (int J = 0; J < n; ++J)
            one[J] = 1.0;
        for (int J = 0; J < n; ++J)
            g->z[J] = b[3 * J + a];
        double shift = (dot_ordered(weights.particle, g->z, n, partial) -
                        dot_ordered(weights.lumped, x, n, partial)) /
                       dot_ordered(weights.lumped, one, n, partial);
        for (int I = 0; I < n; ++I)
            c[3 * I + a] = x[I] + shift;
    }
    return most;
}

int gsn_explicit_interpolate(const struct gsn_explicit *e, const double *values,
                             double *c, int *iterations)
{
    const struct gsn_shape_rows *rows = &e->quadrature->particle_values;
    const int n = e->particle_count;
    const int pieces = (n + SUM_PIECE - 1) / SUM_PIECE;
    struct gsn_shape_rows columns;
    memset(&columns, 0, sizeof columns);
    double *work =
        malloc(sizeof(double) * (20 * (size_t)n + (size_t)pieces + 1));
    int rc = work
                 ? lambda_transpose(rows, n, &columns)
                 : gsn_error_raise(GSN_ERR_MEMORY, __FILE__, __LINE__, __func__,
                                   "cannot allocate %d values", 20 * n);
    double *diagonal = work, *W = diagonal + n, *scratch = W + n;
    /* M = Lambda^T W 1 holds for the lumped masses, not with the mass that
     * mass scaling adds */
    struct interpolation_weights weights = {W, e->lumped_mass};
    int most = 0;
    if (rc == GSN_OK) {
        memset(W, 0, sizeof(double) * (size_t)n);
        for (int p = 0; p < e->main_point_count; ++p)
            if (e->quadrature->point_particle[p] >= 0)
                W[e->quadrature->point_particle[p]] += e->point_mass[p];
        for (int I = 0; I < n; ++I) {
            double sum = 0.0;
            for (int k = columns.offset[I]; k < columns.offset[I + 1]; ++k)
                sum +=
                    W[columns.index[k]] * columns.value[k] * columns.value[k];
            diagonal[I] =
                sum + GSN_INTERPOLATE_REGULARIZATION * e->lumped_mass[I];
        }
        double residual = 0.0;
        int failed = -1;
        most = interpolate_components(rows, &columns, n, weights, diagonal,
                                      values, c, scratch, &residual, &failed);
        if (most < 0)
            rc = gsn_error_raise(
                GSN_ERR_NUMERICAL, __FILE__, __LINE__, __func__,
                "the coefficients of a field at %d particles "
                "did not converge (component %d: residual "
                "%.3g after %d iterations)",
                n, failed, residual, INTERPOLATE_MAX_ITERATIONS);
    }
    gsn_shape_rows_free(&columns);
    free(work);
    if (iterations)
        *iterations = most > 0 ? most : 0;
    return rc;
}

/* The acceleration of every coefficient from net_force alone (no damping,
 * no supports) at the present step. */
static void undamped_acceleration(const struct gsn_explicit *e, double *a)
{
    for (int i = 0; i < e->particle_count; ++i)
        for (int k = 0; k < 3; ++k) {
            int at = 3 * i + k;
            a[at] = k == e->held_axis
                        ? 0.0
                        : net_force(e, at, e->release_factor) / e->mass[i];
        }
}

int gsn_explicit_release_unbalanced(struct gsn_explicit *to,
                                    const struct gsn_explicit *from, long steps)
{
    const int n = to->particle_count;
    const size_t n3 = 3 * (size_t)n;
    double *a = malloc(sizeof(double) * n3),
           *field = malloc(sizeof(double) * n3);
    double *target = calloc(n3, sizeof(double));
    int rc = GSN_OK;
    GSN_CHECK_GOTO(a && field && target, rc, GSN_ERR_MEMORY, done,
                   "cannot allocate %zu values", 3 * n3);
    undamped_acceleration(from, a);
    gsn_explicit_particle_field(from, a, field);
    int iterations = 0;
    GSN_CALL_GOTO(gsn_explicit_interpolate(to, field, target, &iterations), rc,
                  done);
    free(to->release_force);
    to->release_force = NULL;
    to->release_factor = to->release_next = 1.0;
    undamped_acceleration(to, a);
    for (size_t at = 0; at < n3; ++at)
        target[at] = to->mass[at / 3] * (target[at] - a[at]);
    to->release_force = target;
    target = NULL;
    to->release_start = to->step;
    to->release_steps = steps > 0 ? steps : 1;
    GSN_CALL_GOTO(gsn_explicit_settle(to), rc, done);
done:
    free(a);
    free(field);
    free(target);
    return rc;
}

int gsn_explicit_carry_over(struct gsn_explicit *to,
                            const struct gsn_explicit *from)
{
    const int n = from->particle_count, main = from->main_point_count;
    GSN_CHECK(to->particle_count == n && to->point_count == from->point_count &&
                  to->main_point_count == main &&
                  to->state_size == from->state_size &&
                  from->quadrature->point_particle[0] >= 0,
              GSN_ERR_INTERNAL,
              "a reference update needs nodal integration with the same "
              "points (%d particles, %d and %d points)",
              n, from->point_count, to->point_count);
    double *field = malloc(sizeof(double) * 3 * (size_t)(n ? n : 1));
    GSN_CHECK(field, GSN_ERR_MEMORY, "cannot allocate %d values", 3 * n);
    int rc = GSN_OK;
    /* the masses first: they weigh the interpolation */
    GSN_CALL_GOTO(gsn_explicit_set_point_mass(to, from->point_mass), rc, done);
    /* the velocity of every particle, carried (regularized) */
    gsn_explicit_particle_field(from, from->velocity, field);
    GSN_CALL_GOTO(gsn_explicit_interpolate(to, field, to->velocity,
                                           &to->interpolation_iterations),
                  rc, done);
    memset(to->displacement, 0, sizeof(double) * 3 * (size_t)n);
    to->load_factor = from->load_factor;
    to->pore_factor = from->pore_factor;
    memcpy(to->stress, from->stress,
           sizeof(double) * 6 * (size_t)from->point_count);
    memcpy(to->state, from->state,
           sizeof(double) * (size_t)from->state_size * (size_t)main);
    memcpy(to->point_dead, from->point_dead, sizeof(int) * (size_t)main);
    to->dead_count = from->dead_count;
    for (int p = 0; p < main; ++p) {
        double F[9];
        for (int a = 0; a < 9; ++a)
            F[a] = identity_entry(a) + from->displacement_gradient[9 * p + a];
        gsn_matrix_multiply(F, &from->reference_gradient[9 * p],
                            &to->reference_gradient[9 * p]);
    }
    memset(to->displacement_gradient, 0,
           sizeof(double) * 9 * (size_t)to->point_count);
    to->step = from->step;
    to->time = from->time;
    to->dt = from->dt;
    to->time_base = from->time_base;
    to->step_base = from->step_base;
    to->internal_energy = from->internal_energy;
    to->external_work = from->external_work;
    to->damping_work = from->damping_work;
    to->release_work = from->release_work;
    to->kinetic_energy = from->kinetic_energy;
    to->conserved_kinetic_energy = from->conserved_kinetic_energy;
    to->allow_failure = from->allow_failure;
    to->distortion_strain = 0.0;
    to->distortion_jacobian_min = to->distortion_jacobian_max = 1.0;
    memcpy(to->phase_seconds, from->phase_seconds, sizeof to->phase_seconds);
    memcpy(to->pass_part_ticks, from->pass_part_ticks,
           sizeof to->pass_part_ticks);
    to->factor_seconds = from->factor_seconds;
done:
    free(field);
    return rc;
}
