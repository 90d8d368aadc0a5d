/* The registry of material models: a model is found by name (material.h).
 * To add a model, write material_NAME.c defining gsn_material_NAME_ops and
 * add X(NAME) to the list below. */
#include "material.h"

#include "geoscni/error.h"

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
    GSN_CALL(model->ops->update(model->context, count, strain_increment, stress,
                                state));
    return GSN_OK;
}
