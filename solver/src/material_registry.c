/* The registry of material models: a model is found by name (material.h).
 * To add a model, write material_NAME.c defining gsn_material_NAME_ops and
 * add X(NAME) to the list below. */
#include "material.h"

#include "geoscni/error.h"
#include "geoscni/model.h"
#include "overburden.h"

#include <math.h>

#include <stdlib.h>
#include <string.h>

#define GSN_MATERIAL_LIST(X)                                                   \
    X(elastic)                                                                 \
    X(damage_drucker_prager)

#define GSN_MATERIAL_DECLARE(name)                                             \
    extern const struct gsn_material_ops gsn_material_##name##_ops;
GSN_MATERIAL_LIST(GSN_MATERIAL_DECLARE)
#undef GSN_MATERIAL_DECLARE

static const struct gsn_material_ops *const material_registry[] = {
#define GSN_MATERIAL_ENTRY(name) &gsn_material_##name##_ops,
    GSN_MATERIAL_LIST(GSN_MATERIAL_ENTRY)
#undef GSN_MATERIAL_ENTRY
};

enum {
    MATERIAL_REGISTRY_COUNT =
        (int)(sizeof material_registry / sizeof material_registry[0])
};

int gsn_material_count(void)
{
    return MATERIAL_REGISTRY_COUNT;
}

const struct gsn_material_ops *gsn_material_at(int index)
{
    if (index < 0 || index >= MATERIAL_REGISTRY_COUNT)
        return NULL;
    return material_registry[index];
}

const struct gsn_material_ops *gsn_material_find(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < MATERIAL_REGISTRY_COUNT; ++i)
        if (strcmp(material_registry[i]->name, name) == 0)
            return material_registry[i];
    return NULL;
}

const char *gsn_material_name_for_case(const struct gsn_material *parameters)
{
    if (parameters->has_damage || parameters->has_plasticity)
        return "damage_drucker_prager";
    return "elastic";
}

int gsn_material_model_create(const char *name,
                              const struct gsn_material *parameters,
                              struct gsn_material_model **model)
{
    GSN_CHECK(model != NULL && parameters != NULL, GSN_ERR_INTERNAL,
              "gsn_material_model_create: NULL argument");
    *model = NULL;
    const struct gsn_material_ops *ops = gsn_material_find(name);
    if (!ops) {
        char known[256] = "";
        for (int i = 0; i < MATERIAL_REGISTRY_COUNT; ++i) {
            strncat(known, i ? ", " : "", sizeof known - strlen(known) - 1);
            strncat(known, material_registry[i]->name,
                    sizeof known - strlen(known) - 1);
        }
        GSN_CHECK(0, GSN_ERR_INPUT,
                  "unknown material model '%s' (known models: %s)",
                  name ? name : "(null)", known);
    }
    struct gsn_material_model *m = calloc(1, sizeof *m);
    GSN_CHECK(m != NULL, GSN_ERR_MEMORY, "material model '%s': out of memory",
              name);
    m->ops = ops;
    int rc = ops->create(parameters, &m->context);
    if (rc != GSN_OK) {
        free(m);
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "ops->create(parameters, &m->context)");
    }
    *model = m;
    return GSN_OK;
}

void gsn_material_model_destroy(struct gsn_material_model **model)
{
    if (!model || !*model)
        return;
    if ((*model)->ops && (*model)->ops->destroy)
        (*model)->ops->destroy(&(*model)->context);
    free(*model);
    *model = NULL;
}

int gsn_material_state_offset(const struct gsn_material_ops *ops,
                              const char *name)
{
    if (!ops || !name)
        return -1;
    int offset = 0;
    for (int v = 0; v < ops->state_variable_count; ++v) {
        if (strcmp(ops->state_variables[v].name, name) == 0)
            return offset;
        offset += (int)ops->state_variables[v].kind;
    }
    return -1;
}

int gsn_material_initialize(const struct gsn_material_model *model,
                            size_t count, const double *restrict stress,
                            double *restrict state)
{
    GSN_CALL(model->ops->initialize(model->context, count, stress, state));
    return GSN_OK;
}

int gsn_material_update(const struct gsn_material_model *model, size_t count,
                        const double *restrict strain_increment,
                        double *restrict stress, double *restrict state)
{
    enum { C = GSN_MATERIAL_COLUMN };
    const size_t ns = (size_t)model->ops->state_size;
    double de[6 * C], s[6 * C], *q = NULL;
    if (ns > 0) {
        q = malloc(sizeof(double) * ns * C);
        GSN_CHECK(q != NULL, GSN_ERR_MEMORY, "out of memory");
    }
    fenv_t caller;
    gsn_hold_exceptions(&caller);
    int rc = GSN_OK;
    for (size_t first = 0; first < count && rc == GSN_OK; first += C) {
        const size_t n = count - first < C ? count - first : C;
        gsn_material_to_columns(n, 6, strain_increment + 6 * first, 6, de, C);
        gsn_material_to_columns(n, 6, stress + 6 * first, 6, s, C);
        if (ns > 0)
            gsn_material_to_columns(n, (int)ns, state + ns * first, ns, q, C);
        rc = model->ops->update(model->context, n, C, de, s, q);
        gsn_material_from_columns(n, 6, s, C, stress + 6 * first, 6);
        if (ns > 0)
            gsn_material_from_columns(n, (int)ns, q, C, state + ns * first, ns);
    }
    gsn_release_exceptions(&caller);
    free(q);
    GSN_CALL(rc);
    return GSN_OK;
}

/* The largest shear stress ||dev s|| the soil carries at mean pressure p
 * (Pa, compression positive): R + 3 alpha p of seed eq. (8). */
static double soil_strength(const struct gsn_material *soil, double p)
{
    return soil->has_plasticity ? soil->dp_R + 3.0 * soil->dp_alpha * p
                                : INFINITY;
}

/* The soil with the elasticity and density of set->soil[body] and the
 * strength (damage, cone) of set->soil[weak]: found, or added. */
static int interface_soil(struct gsn_material_set *set, const char *kind,
                          int body, int weak, int *index)
{
    struct gsn_material soil = set->soil[body];
    const struct gsn_material *w = &set->soil[weak];
    soil.has_damage = w->has_damage;
    soil.damage_e0 = w->damage_e0;
    soil.damage_ef = w->damage_ef;
    soil.damage_length = w->damage_length;
    soil.has_plasticity = w->has_plasticity;
    soil.dp_alpha = w->dp_alpha;
    soil.dp_R = w->dp_R;
    soil.dp_dilatancy = w->dp_dilatancy;
    soil.dp_from_mohr_coulomb = w->dp_from_mohr_coulomb;
    soil.cohesion = w->cohesion;
    soil.friction_angle = w->friction_angle;
    soil.dilation_angle = w->dilation_angle;
    soil.dp_fit = w->dp_fit;
    for (int k = set->case_count; k < set->count; ++k)
        if (memcmp(&set->soil[k], &soil, sizeof soil) == 0) {
            *index = k;
            return GSN_OK;
        }
    GSN_CHECK(set->count < GSN_MAX_SOILS, GSN_ERR_INPUT,
              "more than %d pairs of soils meet", GSN_MAX_SOILS);
    int k = set->count;
    set->soil[k] = soil;
    set->parameters[k] = &set->soil[k];
    GSN_CALL(gsn_material_model_create(kind, &set->soil[k], &set->model[k]));
    set->count = k + 1;
    *index = k;
    return GSN_OK;
}

/* The particles where soils meet (their tetrahedra in more than one
 * volume) take an interface soil: the weakest soil there at the particle's
 * effective vertical stress under its weight (gsn_overburden; 0 without
 * gravity). */
static int interface_soils(struct gsn_material_set *set, const char *kind,
                           const struct gsn_case *c, const struct gsn_model *m,
                           const int *of_volume)
{
    int n = m->particle_count, rc = GSN_OK;
    unsigned *touches = calloc((size_t)n + 1, sizeof *touches);
    double *vertical = calloc((size_t)n + 1, sizeof *vertical);
    GSN_CHECK_GOTO(touches && vertical, rc, GSN_ERR_MEMORY, done,
                   "out of memory");
    for (int t = 0; t < m->tetrahedron_count; ++t) {
        int v = m->tetrahedron_volume[t];
        for (int k = 0; k < 4 && v >= 0; ++k)
            touches[m->tetrahedra[4 * t + k]] |= 1u << of_volume[v];
    }
    int gravity =
        c->gravity[0] != 0.0 || c->gravity[1] != 0.0 || c->gravity[2] != 0.0;
    if (gravity)
        GSN_CALL_GOTO(gsn_overburden(m, c, n, m->position, vertical), rc, done);
    for (int i = 0; i < n; ++i) {
        unsigned soils = touches[i];
        if (!(soils & (soils - 1)))
            continue; /* one soil */
        const double *x = &m->position[3 * (size_t)i];
        double p = fmax(0.0, -(vertical[i] + gsn_water_pressure(c, x)));
        int body = set->particle_material[i], weak = body;
        for (int k = 0; k < set->case_count; ++k)
            if ((soils & (1u << k)) && soil_strength(&set->soil[k], p) <
                                           soil_strength(&set->soil[weak], p))
                weak = k;
        if (weak == body)
            continue;
        GSN_CALL_GOTO(
            interface_soil(set, kind, body, weak, &set->particle_material[i]),
            rc, done);
        set->interface_count++;
    }
done:
    free(touches);
    free(vertical);
    return rc;
}

int gsn_material_set_create(const struct gsn_case *c, const struct gsn_model *m,
                            struct gsn_material_set **out)
{
    *out = NULL;
    struct gsn_material_set *set = calloc(1, sizeof *set);
    GSN_CHECK(set, GSN_ERR_MEMORY, "out of memory");
    int rc = GSN_OK, n = m->particle_count;
    set->particle_count = n;
    set->particle_material = calloc((size_t)n + 1, sizeof(int));
    GSN_CHECK_GOTO(set->particle_material, rc, GSN_ERR_MEMORY, fail,
                   "cannot allocate %d particles' materials", n);
    /* one kind for all: the one with damage and plasticity if any asks */
    const char *kind = "elastic";
    for (int k = 0; k < c->material_count; ++k)
        if (strcmp(gsn_material_name_for_case(&c->materials[k]), "elastic"))
            kind = gsn_material_name_for_case(&c->materials[k]);
    for (int k = 0; k < c->material_count; ++k) {
        set->soil[k] = c->materials[k];
        set->parameters[k] = &set->soil[k];
        GSN_CALL_GOTO(
            gsn_material_model_create(kind, &set->soil[k], &set->model[k]), rc,
            fail);
        set->count = set->case_count = k + 1;
    }
    /* each volume's material, then each particle's */
    int of_volume[256];
    GSN_CHECK_GOTO(m->volume_count <= 256, rc, GSN_ERR_INPUT, fail,
                   "%d physical volumes, at most 256", m->volume_count);
    for (int v = 0; v < m->volume_count; ++v)
        of_volume[v] = gsn_case_find_material(c, m->volume_name[v]);
    for (int i = 0; i < n && c->materials_by_volume; ++i) {
        int v = m->particle_volume[i];
        GSN_CHECK_GOTO(v >= 0, rc, GSN_ERR_INPUT, fail,
                       "%s: particle %d at (%g, %g, %g) lies in no physical "
                       "volume, so 'materials' gives it no soil; run pre "
                       "again (the model may be older than the case)",
                       c->path, i, m->position[3 * i], m->position[3 * i + 1],
                       m->position[3 * i + 2]);
        GSN_CHECK_GOTO(of_volume[v] >= 0, rc, GSN_ERR_INPUT, fail,
                       "%s: physical volume '%s' has no soil under "
                       "'materials'; add it",
                       c->path, m->volume_name[v]);
        set->particle_material[i] = of_volume[v];
    }
    if (c->materials_by_volume && c->material_count > 1)
        GSN_CALL_GOTO(interface_soils(set, kind, c, m, of_volume), rc, fail);
    *out = set;
    return GSN_OK;
fail:
    gsn_material_set_destroy(&set);
    return rc;
}

void gsn_material_set_destroy(struct gsn_material_set **set)
{
    if (!set || !*set)
        return;
    for (int k = 0; k < (*set)->count; ++k)
        gsn_material_model_destroy(&(*set)->model[k]);
    free((*set)->particle_material);
    free(*set);
    *set = NULL;
}
