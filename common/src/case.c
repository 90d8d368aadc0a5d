/* Case file reader: libyaml's document API gives every node its line, so each
 * message can say file:line. Keys are checked against a list per mapping;
 * an unknown key gets a did-you-mean from the same list. */
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/schema.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml.h>

struct reader {
    const char *path;
    yaml_document_t document;
    char kind_text[96];
};

static const char *const component_names[3] = {"x", "y", "z"};

/* economy keys (docs/economy.md), defined at the end of the readers */
static int read_refinements(struct reader *r, const yaml_node_t *particles,
                            struct gsn_case *c);
static int read_symmetry(struct reader *r, const yaml_node_t *entry,
                         const char *context, struct gsn_boundary *b);
static int read_rigid(struct reader *r, const yaml_node_t *entry,
                      const char *context, struct gsn_boundary *b);
static int read_output_economy(struct reader *r, const yaml_node_t *output,
                               struct gsn_case *c);
static void write_refinements(const struct gsn_case *c, FILE *out);
static void write_output_economy(const struct gsn_case *c, FILE *out);

static int node_line(const yaml_node_t *node)
{
    return (int)node->start_mark.line + 1;
}

static yaml_node_t *node_get(struct reader *r, int index)
{
    return yaml_document_get_node(&r->document, index);
}

static const char *scalar_text(const yaml_node_t *node)
{
    return (const char *)node->data.scalar.value;
}

static int is_null_scalar(const yaml_node_t *node)
{
    if (node->type != YAML_SCALAR_NODE)
        return 0;
    if (node->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return 0;
    const char *t = scalar_text(node);
    return t[0] == '\0' || strcmp(t, "~") == 0 || strcmp(t, "null") == 0 ||
           strcmp(t, "Null") == 0 || strcmp(t, "NULL") == 0;
}

/* The number of items of a list node, -1 for any other node. */
static int sequence_length(const yaml_node_t *node)
{
    if (node->type != YAML_SEQUENCE_NODE)
        return -1;
    return (int)(node->data.sequence.items.top -
                 node->data.sequence.items.start);
}

/* "a list of 2", "a mapping", "nothing (null)" or the scalar quoted, for
 * messages; the text lives in the reader until the next call. */
static const char *node_kind(struct reader *r, const yaml_node_t *node)
{
    switch (node->type) {
    case YAML_SCALAR_NODE:
        if (is_null_scalar(node))
            return "nothing (null)";
        snprintf(r->kind_text, sizeof r->kind_text, "'%.80s'",
                 scalar_text(node));
        return r->kind_text;
    case YAML_SEQUENCE_NODE:
        snprintf(r->kind_text, sizeof r->kind_text, "a list of %d",
                 sequence_length(node));
        return r->kind_text;
    case YAML_MAPPING_NODE:
        return "a mapping";
    default:
        return "nothing";
    }
}

/* Levenshtein distance of two short keys (capped at 63 characters). */
static int edit_distance(const char *a, const char *b)
{
    enum { N = 64 };
    int la = (int)strlen(a), lb = (int)strlen(b);
    if (la >= N || lb >= N)
        return N;
    int previous[N], current[N];
    for (int j = 0; j <= lb; ++j)
        previous[j] = j;
    for (int i = 1; i <= la; ++i) {
        current[0] = i;
        for (int j = 1; j <= lb; ++j) {
            int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            int best = previous[j - 1] + cost;
            if (previous[j] + 1 < best)
                best = previous[j] + 1;
            if (current[j - 1] + 1 < best)
                best = current[j - 1] + 1;
            current[j] = best;
        }
        memcpy(previous, current, sizeof(int) * (size_t)(lb + 1));
    }
    return previous[lb];
}

static const char *closest_key(const char *key, const char *const allowed[])
{
    const char *best = NULL;
    int best_distance = 1 << 30;
    for (int i = 0; allowed[i]; ++i) {
        int d = edit_distance(key, allowed[i]);
        if (d < best_distance) {
            best_distance = d;
            best = allowed[i];
        }
    }
    int limit = (int)strlen(key) / 3 > 2 ? (int)strlen(key) / 3 : 2;
    return best_distance <= limit ? best : NULL;
}

static void join_keys(const char *const allowed[], char *out, size_t size)
{
    out[0] = '\0';
    for (int i = 0; allowed[i]; ++i) {
        size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", i ? ", " : "", allowed[i]);
    }
}

/* The context name of a mapping for messages: "" means the top level. */
enum { CONTEXT_NAME_SIZE = 96 };

static const char *context_name(const char *context,
                                char buffer[CONTEXT_NAME_SIZE])
{
    if (!context[0])
        return "the top level";
    snprintf(buffer, CONTEXT_NAME_SIZE, "'%s'", context);
    return buffer;
}

static int expect_mapping(struct reader *r, const yaml_node_t *node,
                          const char *context)
{
    GSN_CHECK(node->type == YAML_MAPPING_NODE || context[0], GSN_ERR_INPUT,
              "%s:%d: the case file must be a mapping of keys ('key: "
              "value' lines), got %s",
              r->path, node_line(node), node_kind(r, node));
    GSN_CHECK(node->type == YAML_MAPPING_NODE, GSN_ERR_INPUT,
              "%s:%d: '%s' must be a mapping of keys, got %s", r->path,
              node_line(node), context, node_kind(r, node));
    return GSN_OK;
}

/* Every key of a mapping must be a plain scalar, unique, and in allowed. */
static int check_keys(struct reader *r, const yaml_node_t *mapping,
                      const char *const allowed[], const char *context)
{
    char where[CONTEXT_NAME_SIZE];
    GSN_CALL(expect_mapping(r, mapping, context));
    for (yaml_node_pair_t *p = mapping->data.mapping.pairs.start;
         p < mapping->data.mapping.pairs.top; ++p) {
        yaml_node_t *key = node_get(r, p->key);
        GSN_CHECK(key->type == YAML_SCALAR_NODE, GSN_ERR_INPUT,
                  "%s:%d: a key in %s must be a plain name, got %s", r->path,
                  node_line(key), context_name(context, where),
                  node_kind(r, key));
        const char *name = scalar_text(key);
        for (yaml_node_pair_t *q = mapping->data.mapping.pairs.start; q < p;
             ++q) {
            yaml_node_t *earlier = node_get(r, q->key);
            GSN_CHECK(strcmp(scalar_text(earlier), name) != 0, GSN_ERR_INPUT,
                      "%s:%d: key '%s' appears twice in %s (first at line "
                      "%d); keep one",
                      r->path, node_line(key), name,
                      context_name(context, where), node_line(earlier));
        }
        if (!allowed)
            continue;
        int known = 0;
        for (int i = 0; allowed[i] && !known; ++i)
            known = strcmp(allowed[i], name) == 0;
        if (!known) {
            char list[512];
            join_keys(allowed, list, sizeof list);
            const char *guess = closest_key(name, allowed);
            if (guess)
                return gsn_error_raise(
                    GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                    "%s:%d: unknown key '%s' in %s; did you mean '%s'? "
                    "(expected one of: %s)",
                    r->path, node_line(key), name, context_name(context, where),
                    guess, list);
            return gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                                   "%s:%d: unknown key '%s' in %s (expected "
                                   "one of: %s)",
                                   r->path, node_line(key), name,
                                   context_name(context, where), list);
        }
    }
    return GSN_OK;
}

static yaml_node_t *mapping_find(struct reader *r, const yaml_node_t *mapping,
                                 const char *key)
{
    for (yaml_node_pair_t *p = mapping->data.mapping.pairs.start;
         p < mapping->data.mapping.pairs.top; ++p) {
        yaml_node_t *k = node_get(r, p->key);
        if (k->type == YAML_SCALAR_NODE && strcmp(scalar_text(k), key) == 0)
            return node_get(r, p->value);
    }
    return NULL;
}

static void key_path(char *out, size_t size, const char *context,
                     const char *key)
{
    if (context[0])
        snprintf(out, size, "%s.%s", context, key);
    else
        snprintf(out, size, "%s", key);
}

static int require_key(struct reader *r, const yaml_node_t *mapping,
                       const char *context, const char *key,
                       const char *expected, yaml_node_t **value)
{
    *value = mapping_find(r, mapping, key);
    char path[256];
    key_path(path, sizeof path, context, key);
    GSN_CHECK(*value != NULL || context[0], GSN_ERR_INPUT,
              "%s:%d: missing required key '%s'; expected %s", r->path,
              node_line(mapping), key, expected);
    GSN_CHECK(*value != NULL, GSN_ERR_INPUT,
              "%s:%d: missing required key '%s' in '%s'; expected %s", r->path,
              node_line(mapping), key, context, expected);
    return GSN_OK;
}

static int parse_number(struct reader *r, const yaml_node_t *node,
                        const char *name, double *value)
{
    int ok = node->type == YAML_SCALAR_NODE &&
             node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
             !is_null_scalar(node);
    if (ok) {
        const char *text = scalar_text(node);
        char *end = NULL;
        errno = 0;
        *value = strtod(text, &end);
        ok = end != text && *end == '\0' && errno == 0 && isfinite(*value);
    }
    if (!ok && node->type == YAML_SCALAR_NODE &&
        node->data.scalar.style != YAML_PLAIN_SCALAR_STYLE) {
        char *end = NULL;
        strtod(scalar_text(node), &end);
        GSN_CHECK(end == scalar_text(node) || *end != '\0', GSN_ERR_INPUT,
                  "%s:%d: '%s' must be a number, got the quoted text '%s'; "
                  "write numbers without quotes",
                  r->path, node_line(node), name, scalar_text(node));
    }
    GSN_CHECK(ok, GSN_ERR_INPUT, "%s:%d: '%s' must be a number, got %s",
              r->path, node_line(node), name, node_kind(r, node));
    return GSN_OK;
}

static int parse_integer(struct reader *r, const yaml_node_t *node,
                         const char *name, int *value)
{
    double number = 0.0;
    GSN_CALL(parse_number(r, node, name, &number));
    GSN_CHECK(number == floor(number) && fabs(number) < 1e9, GSN_ERR_INPUT,
              "%s:%d: '%s' must be a whole number, got '%s'", r->path,
              node_line(node), name, scalar_text(node));
    *value = (int)number;
    return GSN_OK;
}

static int parse_word(struct reader *r, const yaml_node_t *node,
                      const char *name, const char *const words[], int *index)
{
    char list[256];
    join_keys(words, list, sizeof list);
    GSN_CHECK(node->type == YAML_SCALAR_NODE && !is_null_scalar(node),
              GSN_ERR_INPUT, "%s:%d: '%s' must be one of %s, got %s", r->path,
              node_line(node), name, list, node_kind(r, node));
    for (int i = 0; words[i]; ++i) {
        if (strcmp(words[i], scalar_text(node)) == 0) {
            *index = i;
            return GSN_OK;
        }
    }
    const char *guess = closest_key(scalar_text(node), words);
    if (guess)
        return gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                               "%s:%d: '%s' must be one of %s, got '%s'; did "
                               "you mean '%s'?",
                               r->path, node_line(node), name, list,
                               scalar_text(node), guess);
    return gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                           "%s:%d: '%s' must be one of %s, got '%s'", r->path,
                           node_line(node), name, list, scalar_text(node));
}

/* Reads an optional number key; leaves *value (the default) if absent. */
static int read_number(struct reader *r, const yaml_node_t *mapping,
                       const char *context, const char *key, double *value,
                       int *line)
{
    yaml_node_t *node = mapping_find(r, mapping, key);
    if (!node)
        return GSN_OK;
    char path[256];
    key_path(path, sizeof path, context, key);
    GSN_CALL(parse_number(r, node, path, value));
    if (line)
        *line = node_line(node);
    return GSN_OK;
}

static int read_required_number(struct reader *r, const yaml_node_t *mapping,
                                const char *context, const char *key,
                                const char *expected, double *value, int *line)
{
    yaml_node_t *node = NULL;
    GSN_CALL(require_key(r, mapping, context, key, expected, &node));
    char path[256];
    key_path(path, sizeof path, context, key);
    GSN_CALL(parse_number(r, node, path, value));
    *line = node_line(node);
    return GSN_OK;
}

/* value must satisfy value > bound (strict) or value >= bound. */
static int check_lower(struct reader *r, int line, const char *name,
                       double value, double bound, int strict,
                       const char *units)
{
    int ok = strict ? value > bound : value >= bound;
    GSN_CHECK(ok, GSN_ERR_INPUT, "%s:%d: '%s' must be %s %g%s%s, got %g",
              r->path, line, name, strict ? ">" : ">=", bound,
              units[0] ? " " : "", units, value);
    return GSN_OK;
}

static int read_positive(struct reader *r, const yaml_node_t *mapping,
                         const char *context, const char *key,
                         const char *units, int required, double *value)
{
    int line = node_line(mapping);
    char path[256];
    key_path(path, sizeof path, context, key);
    if (required) {
        char expected[96];
        snprintf(expected, sizeof expected, "a positive number%s%s",
                 units[0] ? " in " : "", units);
        GSN_CALL(read_required_number(r, mapping, context, key, expected, value,
                                      &line));
    } else {
        if (!mapping_find(r, mapping, key))
            return GSN_OK;
        GSN_CALL(read_number(r, mapping, context, key, value, &line));
    }
    GSN_CALL(check_lower(r, line, path, *value, 0.0, 1, units));
    return GSN_OK;
}

static int read_geometry(struct reader *r, const yaml_node_t *root,
                         struct gsn_case *c)
{
    yaml_node_t *node = NULL;
    GSN_CALL(require_key(r, root, "", "geometry",
                         "the path of a gmsh geometry (.geo, .brep, .step)",
                         &node));
    c->geometry_line = node_line(node);
    GSN_CHECK(node->type == YAML_SCALAR_NODE && !is_null_scalar(node),
              GSN_ERR_INPUT,
              "%s:%d: 'geometry' must be the path of a gmsh file, got %s",
              r->path, node_line(node), node_kind(r, node));
    const char *name = scalar_text(node);
    if (name[0] == '/') {
        snprintf(c->geometry, sizeof c->geometry, "%s", name);
    } else {
        const char *slash = strrchr(r->path, '/');
        int folder = slash ? (int)(slash - r->path) + 1 : 0;
        int n = snprintf(c->geometry, sizeof c->geometry, "%.*s%s", folder,
                         r->path, name);
        GSN_CHECK(n < (int)sizeof c->geometry, GSN_ERR_INPUT,
                  "%s:%d: geometry path is too long", r->path, node_line(node));
    }
    GSN_CHECK(access(c->geometry, R_OK) == 0, GSN_ERR_INPUT,
              "%s:%d: geometry file '%s' not found or not readable (looked "
              "for '%s'; the path is relative to the case file's folder)",
              r->path, node_line(node), name, c->geometry);
    struct stat status;
    GSN_CHECK(stat(c->geometry, &status) == 0 && !S_ISDIR(status.st_mode),
              GSN_ERR_INPUT,
              "%s:%d: geometry '%s' is a folder; give the gmsh file in it "
              "(.geo, .brep, .step)",
              r->path, node_line(node), name);
    /* Absolute, so the resolved case stored in outputs reloads anywhere. */
    char absolute[PATH_MAX];
    if (realpath(c->geometry, absolute) && strlen(absolute) < GSN_PATH_SIZE)
        memcpy(c->geometry, absolute, strlen(absolute) + 1);
    return GSN_OK;
}

static int read_particles(struct reader *r, const yaml_node_t *root,
                          struct gsn_case *c)
{
    static const char *const keys[] = {"spacing", "facet_points", "refine",
                                       "mesher", NULL};
    static const char *const meshers[] = {"delaunay", "hxt", NULL};
    yaml_node_t *node = NULL;
    GSN_CALL(require_key(r, root, "", "particles",
                         "a mapping with 'spacing' (m)", &node));
    GSN_CALL(check_keys(r, node, keys, "particles"));
    GSN_CALL(read_positive(r, node, "particles", "spacing", "m", 1,
                           &c->particle_spacing));
    c->particle_spacing_line = node_line(mapping_find(r, node, "spacing"));
    yaml_node_t *points = mapping_find(r, node, "facet_points");
    if (points) {
        GSN_CALL(parse_integer(r, points, "particles.facet_points",
                               &c->facet_points));
        GSN_CHECK(c->facet_points == 1 || c->facet_points == 3, GSN_ERR_INPUT,
                  "%s:%d: 'particles.facet_points' must be 1 (facet centroid) "
                  "or 3 (three points per facet triangle), got %d",
                  r->path, node_line(points), c->facet_points);
    }
    yaml_node_t *mesher = mapping_find(r, node, "mesher");
    if (mesher) {
        int index = 0;
        GSN_CALL(parse_word(r, mesher, "particles.mesher", meshers, &index));
        c->mesher = (enum gsn_mesher)index;
        c->mesher_line = node_line(mesher);
    }
    GSN_CALL(read_refinements(r, node, c));
    return GSN_OK;
}

const char *gsn_mesher_name(enum gsn_mesher mesher)
{
    return mesher == GSN_MESHER_HXT ? "hxt" : "delaunay";
}

static int read_kernel(struct reader *r, const yaml_node_t *root,
                       struct gsn_case *c)
{
    static const char *const keys[] = {"support", "basis", "window_cut", NULL};
    static const char *const bases[] = {"linear", "quadratic", NULL};
    yaml_node_t *node = mapping_find(r, root, "kernel");
    if (!node)
        return GSN_OK;
    GSN_CALL(check_keys(r, node, keys, "kernel"));
    int line = node_line(node);
    GSN_CALL(
        read_number(r, node, "kernel", "support", &c->kernel_support, &line));
    GSN_CALL(check_lower(r, line, "kernel.support", c->kernel_support, 1.0, 1,
                         "(a/h; 1.5 is the paper's)"));
    yaml_node_t *basis = mapping_find(r, node, "basis");
    if (basis) {
        int index = 0;
        GSN_CALL(parse_word(r, basis, "kernel.basis", bases, &index));
        c->kernel_basis_order = index + 1;
    }
    if (mapping_find(r, node, "window_cut")) {
        GSN_CALL(read_number(r, node, "kernel", "window_cut",
                             &c->kernel_window_cut, &line));
        GSN_CHECK(c->kernel_window_cut >= 0.0 && c->kernel_window_cut <= 1e-3,
                  GSN_ERR_INPUT,
                  "%s:%d: 'kernel.window_cut' must be 0 to 0.001 (the "
                  "fraction of the window's peak below which it is cut; "
                  "0.01 halves NSNI's hold on checkerboards: "
                  "docs/kernels.md), got %g",
                  r->path, line, c->kernel_window_cut);
    }
    return GSN_OK;
}

static const char *const stabilization_names[] = {"none", "mscni", "nsni",
                                                  NULL};

static int read_integration(struct reader *r, const yaml_node_t *root,
                            struct gsn_case *c)
{
    static const char *const methods[] = {"scni", "dni", "gauss", NULL};
    static const char *const keys[] = {"method", "points", "stabilization",
                                       "coefficient", NULL};
    yaml_node_t *node = mapping_find(r, root, "integration");
    if (!node)
        return GSN_OK;
    int index = 0;
    if (node->type == YAML_SCALAR_NODE) {
        GSN_CALL(parse_word(r, node, "integration", methods, &index));
        c->integration = (enum gsn_integration)index;
        return GSN_OK;
    }
    GSN_CALL(check_keys(r, node, keys, "integration"));
    yaml_node_t *method = NULL;
    GSN_CALL(require_key(r, node, "integration", "method",
                         "one of scni, dni, gauss", &method));
    GSN_CALL(parse_word(r, method, "integration.method", methods, &index));
    c->integration = (enum gsn_integration)index;
    yaml_node_t *points = mapping_find(r, node, "points");
    if (points) {
        GSN_CALL(
            parse_integer(r, points, "integration.points", &c->gauss_points));
        GSN_CHECK(c->gauss_points >= 1 && c->gauss_points <= 6, GSN_ERR_INPUT,
                  "%s:%d: 'integration.points' (Gauss points per direction) "
                  "must be 1 to 6, got %d",
                  r->path, node_line(points), c->gauss_points);
        GSN_CHECK(c->integration == GSN_INTEGRATION_GAUSS, GSN_ERR_INPUT,
                  "%s:%d: 'integration.points' applies to method gauss only",
                  r->path, node_line(points));
    }
    yaml_node_t *stabilization = mapping_find(r, node, "stabilization");
    if (stabilization) {
        GSN_CALL(parse_word(r, stabilization, "integration.stabilization",
                            stabilization_names, &index));
        c->stabilization = (enum gsn_stabilization)index;
        GSN_CHECK(c->stabilization != GSN_STABILIZATION_NSNI ||
                      c->kernel_basis_order == 1,
                  GSN_ERR_INPUT,
                  "%s:%d: 'integration.stabilization: nsni' needs the linear "
                  "basis (its strain gradients are the second derivatives "
                  "of the linear RK functions): use 'kernel.basis: linear' "
                  "or stabilization mscni",
                  r->path, node_line(stabilization));
    }
    int line = node_line(node);
    GSN_CALL(read_number(r, node, "integration", "coefficient",
                         &c->stabilization_coefficient, &line));
    GSN_CHECK(c->stabilization_coefficient > 0.0 &&
                  c->stabilization_coefficient <= 1.0,
              GSN_ERR_INPUT,
              "%s:%d: 'integration.coefficient' (the weight of the "
              "stabilization: MSCNI's sub-cells, NSNI's strain gradients) "
              "must be in (0, 1], got %g",
              r->path, line, c->stabilization_coefficient);
    GSN_CHECK(c->stabilization != GSN_STABILIZATION_NONE ||
                  !mapping_find(r, node, "coefficient"),
              GSN_ERR_INPUT,
              "%s:%d: 'integration.coefficient' applies to stabilization: "
              "mscni or nsni only",
              r->path, line);
    return GSN_OK;
}

/* drucker_prager: {cohesion, friction_angle, dilation_angle, fit}: the
 * cone fitted to Mohr-Coulomb (gsn_drucker_prager_fit). context names the
 * block in messages ("material.drucker_prager"). */
static int read_mohr_coulomb(struct reader *r, const yaml_node_t *dp,
                             const char *context, struct gsn_material *m)
{
    static const char *const keys[] = {"cohesion", "friction_angle",
                                       "dilation_angle", "fit", NULL};
    static const char *const fits[] = {"plane_strain", "compression", NULL};
    char name[256];
    GSN_CALL(check_keys(r, dp, keys, context));
    int line_c = 0, line_phi = 0, line_psi = 0;
    GSN_CALL(read_required_number(r, dp, context, "cohesion",
                                  "the cohesion c in Pa (>= 0)", &m->cohesion,
                                  &line_c));
    GSN_CALL(read_required_number(r, dp, context, "friction_angle",
                                  "the friction angle phi in degrees (0 to 70)",
                                  &m->friction_angle, &line_phi));
    GSN_CALL(read_required_number(
        r, dp, context, "dilation_angle",
        "the dilation angle psi in degrees (0: no volume change in shear; "
        "equal to friction_angle: associated flow)",
        &m->dilation_angle, &line_psi));
    key_path(name, sizeof name, context, "cohesion");
    GSN_CALL(check_lower(r, line_c, name, m->cohesion, 0.0, 0, "Pa"));
    GSN_CHECK(m->friction_angle >= 0.0 && m->friction_angle <= 70.0,
              GSN_ERR_INPUT,
              "%s:%d: '%s.friction_angle' must be between 0 and 70 degrees, "
              "got %g",
              r->path, line_phi, context, m->friction_angle);
    GSN_CHECK(m->dilation_angle >= 0.0 &&
                  m->dilation_angle <= m->friction_angle,
              GSN_ERR_INPUT,
              "%s:%d: '%s.dilation_angle' must be between 0 and the friction "
              "angle (%g degrees), got %g",
              r->path, line_psi, context, m->friction_angle, m->dilation_angle);
    GSN_CHECK(m->cohesion > 0.0 || m->friction_angle > 0.0, GSN_ERR_INPUT,
              "%s:%d: '%s': a soil with no cohesion and no friction has no "
              "strength",
              r->path, line_c, context);
    m->dp_fit = GSN_DP_FIT_PLANE_STRAIN;
    yaml_node_t *fit = mapping_find(r, dp, "fit");
    if (fit) {
        int index = 0;
        key_path(name, sizeof name, context, "fit");
        GSN_CALL(parse_word(r, fit, name, fits, &index));
        m->dp_fit = (enum gsn_dp_fit)index;
    }
    gsn_drucker_prager_fit(m->dp_fit, m->cohesion, m->friction_angle,
                           m->dilation_angle, &m->dp_alpha, &m->dp_R,
                           &m->dp_dilatancy);
    m->line.R = line_c;
    m->dp_from_mohr_coulomb = 1;
    m->has_plasticity = 1;
    return GSN_OK;
}

/* drucker_prager: {alpha, R, dilatancy}: the cone of seed eq. (8). */
static int read_cone(struct reader *r, const yaml_node_t *dp,
                     const char *context, struct gsn_material *m)
{
    static const char *const keys[] = {"alpha", "R", "dilatancy", NULL};
    char name[256];
    GSN_CALL(check_keys(r, dp, keys, context));
    int line_alpha = 0, line_R = 0;
    GSN_CALL(read_required_number(r, dp, context, "alpha",
                                  "the friction coefficient (>= 0), or "
                                  "cohesion and friction_angle instead",
                                  &m->dp_alpha, &line_alpha));
    GSN_CALL(read_required_number(r, dp, context, "R",
                                  "the cohesion-like strength in Pa (>= 0)",
                                  &m->dp_R, &line_R));
    key_path(name, sizeof name, context, "alpha");
    GSN_CALL(check_lower(r, line_alpha, name, m->dp_alpha, 0.0, 0, ""));
    key_path(name, sizeof name, context, "R");
    GSN_CALL(check_lower(r, line_R, name, m->dp_R, 0.0, 0, "Pa"));
    m->line.R = line_R;
    m->dp_dilatancy = m->dp_alpha; /* associated flow by default */
    int line_beta = line_alpha;
    GSN_CALL(
        read_number(r, dp, context, "dilatancy", &m->dp_dilatancy, &line_beta));
    key_path(name, sizeof name, context, "dilatancy");
    GSN_CALL(check_lower(r, line_beta, name, m->dp_dilatancy, 0.0, 0, ""));
    m->has_plasticity = 1;
    return GSN_OK;
}

/* One soil: the mapping node named context ("material", "materials.clay"). */
static int read_one_material(struct reader *r, const yaml_node_t *node,
                             const char *context, struct gsn_material *m)
{
    static const char *const keys[] = {"density",
                                       "saturated_density",
                                       "bulk_modulus",
                                       "shear_modulus",
                                       "damage",
                                       "drucker_prager",
                                       NULL};
    static const char *const damage_keys[] = {"e0", "ef", "length", NULL};
    char name[256], sub[160];
    GSN_CALL(check_keys(r, node, keys, context));
    m->line.entry = node_line(node);
    GSN_CALL(
        read_positive(r, node, context, "density", "kg/m^3", 1, &m->density));
    m->saturated_density = m->density;
    GSN_CALL(read_positive(r, node, context, "saturated_density", "kg/m^3", 0,
                           &m->saturated_density));
    GSN_CALL(read_positive(r, node, context, "bulk_modulus", "Pa", 1,
                           &m->bulk_modulus));
    GSN_CALL(read_positive(r, node, context, "shear_modulus", "Pa", 1,
                           &m->shear_modulus));
    m->line.density = node_line(mapping_find(r, node, "density"));
    m->line.bulk_modulus = node_line(mapping_find(r, node, "bulk_modulus"));
    m->line.shear_modulus = node_line(mapping_find(r, node, "shear_modulus"));

    yaml_node_t *damage = mapping_find(r, node, "damage");
    if (damage) {
        key_path(sub, sizeof sub, context, "damage");
        GSN_CALL(check_keys(r, damage, damage_keys, sub));
        int line_e0 = 0, line_ef = 0;
        GSN_CALL(read_required_number(r, damage, sub, "e0",
                                      "the initial damage threshold (> 0)",
                                      &m->damage_e0, &line_e0));
        GSN_CALL(read_required_number(r, damage, sub, "ef",
                                      "the final damage threshold (> e0)",
                                      &m->damage_ef, &line_ef));
        key_path(name, sizeof name, sub, "e0");
        GSN_CALL(check_lower(r, line_e0, name, m->damage_e0, 0.0, 1, ""));
        GSN_CHECK(m->damage_e0 < m->damage_ef, GSN_ERR_INPUT,
                  "%s:%d: '%s.e0' (%g) must be less than '%s.ef' (%g): "
                  "damage grows from e0 to ef",
                  r->path, line_e0, sub, m->damage_e0, sub, m->damage_ef);
        GSN_CALL(
            read_positive(r, damage, sub, "length", "m", 0, &m->damage_length));
        m->has_damage = 1;
    }

    yaml_node_t *dp = mapping_find(r, node, "drucker_prager");
    key_path(sub, sizeof sub, context, "drucker_prager");
    if (dp && (mapping_find(r, dp, "cohesion") ||
               mapping_find(r, dp, "friction_angle")))
        GSN_CALL(read_mohr_coulomb(r, dp, sub, m));
    else if (dp)
        GSN_CALL(read_cone(r, dp, sub, m));
    return GSN_OK;
}

/* material: (one soil) or materials: (a soil per gmsh physical volume,
 * keyed by its name; pre checks the names against the geometry). */
static int read_material(struct reader *r, const yaml_node_t *root,
                         struct gsn_case *c)
{
    yaml_node_t *one = mapping_find(r, root, "material");
    yaml_node_t *many = mapping_find(r, root, "materials");
    GSN_CHECK(!(one && many), GSN_ERR_INPUT,
              "%s:%d: give either 'material' (one soil for the whole body) or "
              "'materials' (a soil for each gmsh physical volume), not both",
              r->path, node_line(many));
    if (!many) {
        yaml_node_t *node = NULL;
        GSN_CALL(require_key(r, root, "", "material",
                             "a mapping with density, bulk_modulus and "
                             "shear_modulus (or 'materials', a soil per gmsh "
                             "physical volume)",
                             &node));
        c->material_count = 1;
        return read_one_material(r, node, "material", &c->materials[0]);
    }
    GSN_CALL(check_keys(r, many, NULL, "materials"));
    int count =
        (int)(many->data.mapping.pairs.top - many->data.mapping.pairs.start);
    GSN_CHECK(count >= 1, GSN_ERR_INPUT,
              "%s:%d: 'materials' is empty; give each gmsh physical volume "
              "a soil: 'materials: {VOLUME: {density: ..., bulk_modulus: "
              "..., shear_modulus: ...}}'",
              r->path, node_line(many));
    GSN_CHECK(count <= GSN_MAX_MATERIALS, GSN_ERR_INPUT,
              "%s:%d: 'materials' has %d entries, at most %d", r->path,
              node_line(many), count, GSN_MAX_MATERIALS);
    int k = 0;
    for (yaml_node_pair_t *p = many->data.mapping.pairs.start;
         p < many->data.mapping.pairs.top; ++p, ++k) {
        const char *volume = scalar_text(node_get(r, p->key));
        GSN_CHECK(strlen(volume) < GSN_NAME_SIZE, GSN_ERR_INPUT,
                  "%s:%d: volume name '%s' is longer than %d characters",
                  r->path, node_line(node_get(r, p->key)), volume,
                  GSN_NAME_SIZE - 1);
        char context[GSN_NAME_SIZE + 16];
        snprintf(context, sizeof context, "materials.%s", volume);
        struct gsn_material *m = &c->materials[k];
        GSN_CALL(read_one_material(r, node_get(r, p->value), context, m));
        snprintf(m->volume, sizeof m->volume, "%s", volume);
    }
    c->material_count = count;
    c->materials_by_volume = 1;
    return GSN_OK;
}

/* A list of count numbers (or nulls where allow_null), shown in messages
 * as shape, e.g. "[x, y, z]". */
static int read_vector(struct reader *r, const yaml_node_t *node,
                       const char *name, int count, const char *shape,
                       int allow_null, int *present, double *value)
{
    int length = sequence_length(node);
    GSN_CHECK(length == count, GSN_ERR_INPUT,
              "%s:%d: '%s' must be a list of %d %s %s, got %s", r->path,
              node_line(node), name, count,
              allow_null ? "numbers or null" : "numbers", shape,
              node_kind(r, node));
    for (int k = 0; k < count; ++k) {
        yaml_node_t *item = node_get(r, node->data.sequence.items.start[k]);
        char item_name[128];
        snprintf(item_name, sizeof item_name, "%s[%d]", name, k);
        if (allow_null && is_null_scalar(item)) {
            present[k] = 0;
            continue;
        }
        GSN_CALL(parse_number(r, item, item_name, &value[k]));
        present[k] = 1;
    }
    return GSN_OK;
}

static int read_vector3(struct reader *r, const yaml_node_t *node,
                        const char *name, int allow_null, int present[3],
                        double value[3])
{
    return read_vector(r, node, name, 3, "[x, y, z]", allow_null, present,
                       value);
}

static int read_boundary_entry(struct reader *r, const yaml_node_t *key,
                               const yaml_node_t *node, struct gsn_boundary *b)
{
    static const char *const keys[] = {"fix",      "velocity", "traction",
                                       "symmetry", "rigid",    NULL};
    static const char *const components[] = {"x", "y", "z", NULL};
    snprintf(b->name, sizeof b->name, "%s", scalar_text(key));
    GSN_CHECK(strlen(scalar_text(key)) < GSN_NAME_SIZE, GSN_ERR_INPUT,
              "%s:%d: surface name '%s' is longer than %d characters", r->path,
              node_line(key), scalar_text(key), GSN_NAME_SIZE - 1);
    b->line = node_line(key);
    char context[GSN_NAME_SIZE + 16];
    snprintf(context, sizeof context, "boundary.%s", b->name);
    GSN_CALL(check_keys(r, node, keys, context));

    yaml_node_t *fix = mapping_find(r, node, "fix");
    if (fix) {
        char name[GSN_NAME_SIZE + 32];
        snprintf(name, sizeof name, "%s.fix", context);
        GSN_CHECK(fix->type == YAML_SEQUENCE_NODE, GSN_ERR_INPUT,
                  "%s:%d: '%s' must be a list of components such as [x, y, "
                  "z], got %s",
                  r->path, node_line(fix), name, node_kind(r, fix));
        for (yaml_node_item_t *i = fix->data.sequence.items.start;
             i < fix->data.sequence.items.top; ++i) {
            int k = 0;
            GSN_CALL(parse_word(r, node_get(r, *i), name, components, &k));
            b->fixed[k] = 1;
        }
    }
    yaml_node_t *velocity = mapping_find(r, node, "velocity");
    if (velocity) {
        char name[GSN_NAME_SIZE + 32];
        snprintf(name, sizeof name, "%s.velocity", context);
        GSN_CALL(
            read_vector3(r, velocity, name, 1, b->has_velocity, b->velocity));
        for (int k = 0; k < 3; ++k)
            GSN_CHECK(!(b->has_velocity[k] && b->fixed[k]), GSN_ERR_INPUT,
                      "%s:%d: component %s of '%s' is both fixed and given a "
                      "velocity; use null for it in 'velocity' or drop it "
                      "from 'fix'",
                      r->path, node_line(velocity), component_names[k],
                      context);
    }
    yaml_node_t *traction = mapping_find(r, node, "traction");
    if (traction) {
        char name[GSN_NAME_SIZE + 32];
        snprintf(name, sizeof name, "%s.traction", context);
        GSN_CALL(
            read_vector3(r, traction, name, 0, b->has_traction, b->traction));
        for (int k = 0; k < 3; ++k)
            GSN_CHECK(
                b->traction[k] == 0.0 || !(b->fixed[k] || b->has_velocity[k]),
                GSN_ERR_INPUT,
                "%s:%d: component %s of '%s' is prescribed by 'fix' or "
                "'velocity' and also loaded by 'traction'; a traction "
                "acts only on free components",
                r->path, node_line(traction), component_names[k], context);
    }
    GSN_CALL(read_symmetry(r, node, context, b));
    GSN_CALL(read_rigid(r, node, context, b));
    return GSN_OK;
}

static int read_boundary(struct reader *r, const yaml_node_t *root,
                         struct gsn_case *c)
{
    yaml_node_t *node = mapping_find(r, root, "boundary");
    if (!node)
        return GSN_OK;
    GSN_CALL(check_keys(r, node, NULL, "boundary"));
    for (yaml_node_pair_t *p = node->data.mapping.pairs.start;
         p < node->data.mapping.pairs.top; ++p) {
        GSN_CHECK(c->boundary_count < GSN_MAX_BOUNDARIES, GSN_ERR_INPUT,
                  "%s:%d: more than %d boundary entries", r->path,
                  node_line(node_get(r, p->key)), GSN_MAX_BOUNDARIES);
        GSN_CALL(read_boundary_entry(r, node_get(r, p->key),
                                     node_get(r, p->value),
                                     &c->boundaries[c->boundary_count]));
        c->boundary_count++;
    }
    return GSN_OK;
}

static int read_time(struct reader *r, const yaml_node_t *root,
                     struct gsn_case *c)
{
    static const char *const keys[] = {"end",  "step",         "safety",
                                       "ramp", "mass_scaling", NULL};
    yaml_node_t *node = NULL;
    GSN_CALL(require_key(r, root, "", "time",
                         "a mapping with 'end' (s) and 'step' (s or auto)",
                         &node));
    GSN_CALL(check_keys(r, node, keys, "time"));
    GSN_CALL(read_positive(r, node, "time", "end", "s", 1, &c->time_end));
    yaml_node_t *step = mapping_find(r, node, "step");
    if (step && !(step->type == YAML_SCALAR_NODE &&
                  strcmp(scalar_text(step), "auto") == 0)) {
        if (step->type == YAML_SCALAR_NODE &&
            step->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
            !is_null_scalar(step)) {
            char *end = NULL;
            strtod(scalar_text(step), &end);
            GSN_CHECK(end != scalar_text(step) && *end == '\0', GSN_ERR_INPUT,
                      "%s:%d: 'time.step' must be a number (s) or auto, got "
                      "'%s'",
                      r->path, node_line(step), scalar_text(step));
        }
        GSN_CALL(read_positive(r, node, "time", "step", "s", 1, &c->time_step));
        c->time_step_auto = 0;
    }
    int line = node_line(node);
    GSN_CALL(
        read_number(r, node, "time", "safety", &c->time_step_safety, &line));
    GSN_CHECK(c->time_step_safety > 0.0 && c->time_step_safety <= 1.0,
              GSN_ERR_INPUT,
              "%s:%d: 'time.safety' must be in (0, 1] (fraction of the stable "
              "step), got %g",
              r->path, line, c->time_step_safety);
    line = node_line(node);
    GSN_CALL(read_number(r, node, "time", "mass_scaling", &c->time_mass_scaling,
                         &line));
    c->time_mass_scaling_given = mapping_find(r, node, "mass_scaling") != NULL;
    GSN_CHECK(c->time_mass_scaling >= 0.0 && c->time_mass_scaling <= 0.1,
              GSN_ERR_INPUT,
              "%s:%d: 'time.mass_scaling' must be in [0, 0.1]: the fraction "
              "of the body's mass that may be added where the stable step "
              "needs it (0.01 adds at most 1%%; for slow, quasi-static "
              "loads), got %g",
              r->path, line, c->time_mass_scaling);
    line = node_line(node);
    GSN_CALL(read_number(r, node, "time", "ramp", &c->time_ramp, &line));
    GSN_CHECK(c->time_ramp >= 0.0 && c->time_ramp <= c->time_end, GSN_ERR_INPUT,
              "%s:%d: 'time.ramp' must be between 0 and time.end (%g s): the "
              "time over which prescribed velocities rise to their values, "
              "got %g",
              r->path, line, c->time_end, c->time_ramp);
    return GSN_OK;
}

/* damping: {local: a}, Cundall's local damping (docs/solver.md). */
static int read_damping(struct reader *r, const yaml_node_t *root,
                        struct gsn_case *c)
{
    static const char *const keys[] = {"local", NULL};
    yaml_node_t *node = mapping_find(r, root, "damping");
    if (!node)
        return GSN_OK;
    GSN_CALL(check_keys(r, node, keys, "damping"));
    int line = node_line(node);
    GSN_CALL(
        read_number(r, node, "damping", "local", &c->damping_local, &line));
    GSN_CHECK(c->damping_local >= 0.0 && c->damping_local < 1.0, GSN_ERR_INPUT,
              "%s:%d: 'damping.local' must be in [0, 1) (a fraction of the "
              "unbalanced force; 0.05 to 0.2 is usual), got %g",
              r->path, line, c->damping_local);
    return GSN_OK;
}

/* kinematics: large (the paper's updated Lagrangian, default) or small
 * (gradients and forces on the reference configuration, no rotation: the
 * small-strain theory that limit loads are derived in; docs/solver.md). */
static int read_kinematics(struct reader *r, const yaml_node_t *root,
                           struct gsn_case *c)
{
    static const char *const kinds[] = {"large", "small", NULL};
    yaml_node_t *node = mapping_find(r, root, "kinematics");
    if (!node)
        return GSN_OK;
    int index = 0;
    GSN_CALL(parse_word(r, node, "kinematics", kinds, &index));
    c->small_strain = index == 1;
    return GSN_OK;
}

/* plane_strain: x, y or z: the displacement along that axis is zero at
 * every particle, not only on the faces that rollers hold (a slab that
 * stands for a plane-strain section; docs/solver.md, "Plane strain"). */
static int read_plane_strain(struct reader *r, const yaml_node_t *root,
                             struct gsn_case *c)
{
    static const char *const axes[] = {"x", "y", "z", NULL};
    yaml_node_t *node = mapping_find(r, root, "plane_strain");
    if (!node)
        return GSN_OK;
    GSN_CALL(parse_word(r, node, "plane_strain", axes, &c->plane_strain_axis));
    return GSN_OK;
}

/* reference_update: on, off or {strain, volume: [min, max], every,
 * min_steps} (docs/solver.md, "Large deformation"); with large kinematics
 * and nodal integration only. Absent, it is on where it applies
 * (gsn_case_reference_update_default). */
static int read_reference_update(struct reader *r, const yaml_node_t *root,
                                 struct gsn_case *c)
{
    static const char *const keys[] = {"strain", "volume", "every", "min_steps",
                                       NULL};
    static const char *const words[] = {"off", "on", NULL};
    yaml_node_t *node = mapping_find(r, root, "reference_update");
    c->reference_update = gsn_case_reference_update_default(c);
    if (!node)
        return GSN_OK;
    c->reference_update_line = node_line(node);
    int index = 1;
    if (node->type == YAML_SCALAR_NODE)
        GSN_CALL(parse_word(r, node, "reference_update", words, &index));
    else {
        GSN_CALL(check_keys(r, node, keys, "reference_update"));
        int line = node_line(node);
        GSN_CALL(read_number(r, node, "reference_update", "strain",
                             &c->reference_strain, &line));
        GSN_CHECK(c->reference_strain > 0.0, GSN_ERR_INPUT,
                  "%s:%d: 'reference_update.strain' (the strain since the "
                  "last update that triggers one) must be positive, got %g",
                  r->path, line, c->reference_strain);
        yaml_node_t *volume = mapping_find(r, node, "volume");
        if (volume) {
            int present[2] = {0, 0};
            GSN_CALL(read_vector(r, volume, "reference_update.volume", 2,
                                 "[min, max]", 0, present,
                                 c->reference_volume));
            GSN_CHECK(present[0] && present[1] &&
                          c->reference_volume[0] > 0.0 &&
                          c->reference_volume[0] < 1.0 &&
                          c->reference_volume[1] > 1.0,
                      GSN_ERR_INPUT,
                      "%s:%d: 'reference_update.volume' must be [min, max] "
                      "with 0 < min < 1 < max (volume ratios since the last "
                      "update), got [%g, %g]",
                      r->path, node_line(volume), c->reference_volume[0],
                      c->reference_volume[1]);
        }
        GSN_CALL(read_positive(r, node, "reference_update", "every", "s", 0,
                               &c->reference_every));
        yaml_node_t *steps = mapping_find(r, node, "min_steps");
        if (steps) {
            GSN_CALL(parse_integer(r, steps, "reference_update.min_steps",
                                   &c->reference_min_steps));
            GSN_CHECK(c->reference_min_steps >= 1, GSN_ERR_INPUT,
                      "%s:%d: 'reference_update.min_steps' (steps between "
                      "two updates at least) must be 1 or more, got %d",
                      r->path, node_line(steps), c->reference_min_steps);
        }
    }
    GSN_CHECK(index == 0 || !c->small_strain, GSN_ERR_INPUT,
              "%s:%d: 'reference_update' needs 'kinematics: large': with "
              "small kinematics the body stays on its reference "
              "configuration",
              r->path, c->reference_update_line);
    GSN_CHECK(index == 0 || c->integration != GSN_INTEGRATION_GAUSS,
              GSN_ERR_INPUT,
              "%s:%d: 'reference_update' works with nodal integration (scni, "
              "dni), not gauss: use 'reference_update: off'",
              r->path, c->reference_update_line);
    c->reference_update = index == 1;
    return GSN_OK;
}

/* geostatic: off (the default), on, or {residual, damping, max_steps}. */
static int read_geostatic(struct reader *r, const yaml_node_t *root,
                          struct gsn_case *c)
{
    static const char *const keys[] = {"residual", "damping", "max_steps", "k0",
                                       NULL};
    static const char *const words[] = {"off", "on", NULL};
    c->geostatic_residual = GSN_DEFAULT_GEOSTATIC_RESIDUAL;
    c->geostatic_damping = GSN_DEFAULT_GEOSTATIC_DAMPING;
    c->geostatic_max_steps = GSN_DEFAULT_GEOSTATIC_MAX_STEPS;
    yaml_node_t *node = mapping_find(r, root, "geostatic");
    if (!node)
        return GSN_OK;
    c->geostatic_line = node_line(node);
    int index = 1;
    if (node->type == YAML_SCALAR_NODE)
        GSN_CALL(parse_word(r, node, "geostatic", words, &index));
    else {
        GSN_CALL(check_keys(r, node, keys, "geostatic"));
        int line = c->geostatic_line;
        GSN_CALL(read_number(r, node, "geostatic", "residual",
                             &c->geostatic_residual, &line));
        GSN_CHECK(c->geostatic_residual > 0.0 && c->geostatic_residual < 1.0,
                  GSN_ERR_INPUT,
                  "%s:%d: 'geostatic.residual' (the unbalanced force over "
                  "the weight at which the body is at rest) must be between "
                  "0 and 1, got %g",
                  r->path, line, c->geostatic_residual);
        line = c->geostatic_line;
        GSN_CALL(read_number(r, node, "geostatic", "damping",
                             &c->geostatic_damping, &line));
        GSN_CHECK(c->geostatic_damping >= 0.0 && c->geostatic_damping < 1.0,
                  GSN_ERR_INPUT,
                  "%s:%d: 'geostatic.damping' (the local damping while the "
                  "body settles) must be at least 0 and below 1, got %g",
                  r->path, line, c->geostatic_damping);
        line = c->geostatic_line;
        GSN_CALL(
            read_number(r, node, "geostatic", "k0", &c->geostatic_k0, &line));
        GSN_CHECK(c->geostatic_k0 >= 0.0 && c->geostatic_k0 <= 3.0,
                  GSN_ERR_INPUT,
                  "%s:%d: 'geostatic.k0' (the horizontal over the vertical "
                  "stress of level ground) must be between 0 and 3, got %g",
                  r->path, line, c->geostatic_k0);
        yaml_node_t *steps = mapping_find(r, node, "max_steps");
        if (steps) {
            int value = 0;
            GSN_CALL(parse_integer(r, steps, "geostatic.max_steps", &value));
            GSN_CHECK(value >= 1, GSN_ERR_INPUT,
                      "%s:%d: 'geostatic.max_steps' must be 1 or more, got %d",
                      r->path, node_line(steps), value);
            c->geostatic_max_steps = value;
        }
    }
    c->geostatic = index == 1;
    int weight =
        c->gravity[0] != 0.0 || c->gravity[1] != 0.0 || c->gravity[2] != 0.0;
    for (int b = 0; b < c->boundary_count; ++b)
        for (int k = 0; k < 3; ++k) {
            weight |= c->boundaries[b].traction[k] != 0.0;
            GSN_CHECK(!c->geostatic || !c->boundaries[b].rigid, GSN_ERR_INPUT,
                      "%s:%d: 'geostatic' with a rigid body ('%s': rigid: "
                      "true) is not supported yet: drop one of them",
                      r->path, c->geostatic_line, c->boundaries[b].name);
        }
    GSN_CHECK(!c->geostatic || weight, GSN_ERR_INPUT,
              "%s:%d: 'geostatic' brings the dead loads to equilibrium, but "
              "there are none: give gravity (e.g. [0, 0, -9.81]) or a "
              "traction",
              r->path, c->geostatic_line);
    return GSN_OK;
}

static int read_output(struct reader *r, const yaml_node_t *root,
                       struct gsn_case *c)
{
    static const char *const keys[] = {"every",  "times",         "fields",
                                       "mirror", "history_every", NULL};
    c->output_every = c->time_end / GSN_DEFAULT_FRAMES;
    c->output_every_default = 1;
    yaml_node_t *node = mapping_find(r, root, "output");
    if (!node)
        return GSN_OK;
    c->output_every_default =
        !mapping_find(r, node, "every") && !mapping_find(r, node, "times");
    GSN_CALL(check_keys(r, node, keys, "output"));
    GSN_CALL(
        read_positive(r, node, "output", "every", "s", 0, &c->output_every));
    GSN_CALL(read_positive(r, node, "output", "history_every", "s", 0,
                           &c->history_every));
    GSN_CALL(read_output_economy(r, node, c));
    return GSN_OK;
}

static int read_gravity(struct reader *r, const yaml_node_t *root,
                        struct gsn_case *c)
{
    yaml_node_t *node = mapping_find(r, root, "gravity");
    if (!node)
        return GSN_OK;
    int present[3];
    GSN_CALL(read_vector3(r, node, "gravity", 0, present, c->gravity));
    return GSN_OK;
}

/* water: {level: H | table: [[x, y, z], ...], unit_weight: gamma_w}. */
static int read_water(struct reader *r, const yaml_node_t *root,
                      struct gsn_case *c)
{
    static const char *const keys[] = {"level", "table", "unit_weight", NULL};
    yaml_node_t *node = mapping_find(r, root, "water");
    if (!node)
        return GSN_OK;
    struct gsn_water *w = &c->water;
    w->line = node_line(node);
    GSN_CALL(check_keys(r, node, keys, "water"));
    double up[3];
    GSN_CHECK(gsn_up(c, up), GSN_ERR_INPUT,
              "%s:%d: 'water' gives a water table, whose pore pressure is "
              "the water's weight: give gravity too",
              r->path, w->line);
    yaml_node_t *level = mapping_find(r, node, "level");
    yaml_node_t *table = mapping_find(r, node, "table");
    GSN_CHECK(!level != !table, GSN_ERR_INPUT,
              "%s:%d: 'water' needs one of 'level' (the table's height in m, "
              "along -gravity) or 'table' (a list of [x, y, z] points: a "
              "section's line, or spread over the site), %s",
              r->path, w->line, level ? "not both" : "got neither");
    if (level) {
        GSN_CALL(parse_number(r, level, "water.level", &w->points[0][0]));
        w->point_count = 1;
    } else {
        int count = sequence_length(table);
        GSN_CHECK(count >= 2 && count <= GSN_MAX_WATER_POINTS, GSN_ERR_INPUT,
                  "%s:%d: 'water.table' must be a list of 2 to %d points "
                  "[x, y, z] (or give 'level'), got %s",
                  r->path, node_line(table), GSN_MAX_WATER_POINTS,
                  node_kind(r, table));
        for (int i = 0; i < count; ++i) {
            char name[64];
            int present[3];
            snprintf(name, sizeof name, "water.table[%d]", i);
            GSN_CALL(read_vector3(
                r, node_get(r, table->data.sequence.items.start[i]), name, 0,
                present, w->points[i]));
        }
        w->point_count = count;
        int bad = 0;
        int shape = gsn_water_table_prepare(c, &bad);
        GSN_CHECK(shape != GSN_WATER_STACKED, GSN_ERR_INPUT,
                  "%s:%d: the points of 'water.table' lie above one another; "
                  "give them along a section, or spread over the site",
                  r->path, node_line(table));
        GSN_CHECK(shape != GSN_WATER_BACKWARDS, GSN_ERR_INPUT,
                  "%s:%d: 'water.table[%d]' does not go on from the "
                  "point before it along the section; give the points "
                  "in order, one way along it",
                  r->path, node_line(table), bad);
        GSN_CHECK(shape != GSN_WATER_TWICE, GSN_ERR_INPUT,
                  "%s:%d: 'water.table[%d]' stands on the place of an "
                  "earlier point (the table has one height there); give "
                  "one of them",
                  r->path, node_line(table), bad);
    }
    /* fresh water, 1000 kg/m^3, under the case's gravity */
    w->unit_weight = 1000.0 * sqrt(c->gravity[0] * c->gravity[0] +
                                   c->gravity[1] * c->gravity[1] +
                                   c->gravity[2] * c->gravity[2]);
    int line = w->line;
    GSN_CALL(
        read_number(r, node, "water", "unit_weight", &w->unit_weight, &line));
    GSN_CALL(check_lower(r, line, "water.unit_weight", w->unit_weight, 0.0, 1,
                         "N/m^3"));
    w->present = 1;
    return GSN_OK;
}

double gsn_case_slowest_wave(const struct gsn_case *c, int shear)
{
    double slowest = INFINITY;
    for (int k = 0; k < c->material_count; ++k) {
        const struct gsn_material *m = &c->materials[k];
        double modulus = shear ? m->shear_modulus
                               : m->bulk_modulus + 4.0 / 3.0 * m->shear_modulus;
        slowest = fmin(slowest, sqrt(modulus / m->saturated_density));
    }
    return slowest;
}

int gsn_case_reference_update_default(const struct gsn_case *c)
{
    int damage = 0;
    for (int k = 0; k < c->material_count; ++k)
        damage |= c->materials[k].has_damage;
    return !c->small_strain && c->integration != GSN_INTEGRATION_GAUSS &&
           c->stabilization != GSN_STABILIZATION_MSCNI && !damage;
}

int gsn_case_find_material(const struct gsn_case *c, const char *volume)
{
    if (!c->materials_by_volume)
        return 0;
    for (int k = 0; k < c->material_count; ++k)
        if (strcmp(c->materials[k].volume, volume) == 0)
            return k;
    return -1;
}

static void case_set_defaults(struct gsn_case *c)
{
    memset(c, 0, sizeof *c);
    c->facet_points = GSN_DEFAULT_FACET_POINTS;
    c->kernel_support = GSN_DEFAULT_KERNEL_SUPPORT;
    c->kernel_basis_order = GSN_DEFAULT_KERNEL_BASIS_ORDER;
    c->kernel_window_cut = GSN_DEFAULT_KERNEL_WINDOW_CUT;
    c->integration = GSN_INTEGRATION_SCNI;
    c->gauss_points = GSN_DEFAULT_GAUSS_POINTS;
    c->stabilization = GSN_STABILIZATION_NONE;
    c->stabilization_coefficient = GSN_DEFAULT_STABILIZATION_COEFFICIENT;
    c->time_step_auto = 1;
    c->time_step_safety = GSN_DEFAULT_TIME_STEP_SAFETY;
    c->plane_strain_axis = -1;
    c->output_fields = GSN_DEFAULT_OUTPUT_FIELDS;
    c->reference_strain = GSN_DEFAULT_REFERENCE_STRAIN;
    c->reference_volume[0] = GSN_DEFAULT_REFERENCE_VOLUME_MIN;
    c->reference_volume[1] = GSN_DEFAULT_REFERENCE_VOLUME_MAX;
    c->reference_min_steps = GSN_DEFAULT_REFERENCE_MIN_STEPS;
}

static int read_document(struct reader *r, struct gsn_case *c)
{
    static const char *const keys[] = {"geometry",
                                       "particles",
                                       "kernel",
                                       "integration",
                                       "material",
                                       "materials",
                                       "gravity",
                                       "boundary",
                                       "time",
                                       "damping",
                                       "kinematics",
                                       "output",
                                       "reference_update",
                                       "plane_strain",
                                       "geostatic",
                                       "water",
                                       NULL};
    yaml_node_t *root = yaml_document_get_root_node(&r->document);
    GSN_CHECK(root != NULL, GSN_ERR_INPUT,
              "%s:1: the case file is empty; expected a mapping with "
              "geometry, particles, material and time",
              r->path);
    GSN_CALL(check_keys(r, root, keys, ""));
    GSN_CALL(read_geometry(r, root, c));
    GSN_CALL(read_particles(r, root, c));
    GSN_CALL(read_kernel(r, root, c));
    GSN_CALL(read_integration(r, root, c));
    GSN_CALL(read_material(r, root, c));
    GSN_CALL(read_gravity(r, root, c));
    GSN_CALL(read_water(r, root, c));
    GSN_CALL(read_boundary(r, root, c));
    GSN_CALL(read_time(r, root, c));
    GSN_CALL(read_damping(r, root, c));
    GSN_CALL(read_kinematics(r, root, c));
    GSN_CALL(read_plane_strain(r, root, c));
    GSN_CALL(read_reference_update(r, root, c));
    GSN_CALL(read_geostatic(r, root, c));
    GSN_CALL(read_output(r, root, c));
    return GSN_OK;
}

int gsn_case_load(const char *path, struct gsn_case *out)
{
    case_set_defaults(out);
    GSN_CHECK(strlen(path) < GSN_PATH_SIZE, GSN_ERR_INPUT,
              "case file path is too long");
    snprintf(out->path, sizeof out->path, "%s", path);
    FILE *file = fopen(path, "rb");
    GSN_CHECK(file != NULL, GSN_ERR_IO, "%s: cannot open the case file: %s",
              path, strerror(errno));

    struct reader r = {.path = path};
    yaml_parser_t parser;
    int rc = GSN_OK;
    if (!yaml_parser_initialize(&parser)) {
        fclose(file);
        GSN_CHECK(0, GSN_ERR_MEMORY, "cannot initialize the YAML parser");
    }
    yaml_parser_set_input_file(&parser, file);
    if (!yaml_parser_load(&parser, &r.document)) {
        const char *problem = parser.problem ? parser.problem : "syntax error";
        rc = gsn_error_raise(
            GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
            "%s:%d: YAML syntax error: %s%s%s; expected well-formed YAML "
            "(indent with spaces, 'key: value')",
            path, (int)parser.problem_mark.line + 1, problem,
            parser.context ? " " : "", parser.context ? parser.context : "");
        yaml_parser_delete(&parser);
        fclose(file);
        return rc;
    }
    /* A second document in the same file is an error too. */
    yaml_document_t extra;
    int has_extra = 0;
    int extra_line = 0;
    if (yaml_parser_load(&parser, &extra)) {
        if (yaml_document_get_root_node(&extra)) {
            has_extra = 1;
            extra_line = (int)extra.start_mark.line + 1;
        }
        yaml_document_delete(&extra);
    }
    yaml_parser_delete(&parser);
    fclose(file);

    if (has_extra)
        rc = gsn_error_raise(GSN_ERR_INPUT, __FILE__, __LINE__, __func__,
                             "%s:%d: a second YAML document ('---'); a case "
                             "file holds exactly one",
                             path, extra_line);
    else
        rc = read_document(&r, out);
    yaml_document_delete(&r.document);
    if (rc != GSN_OK)
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "read_document(&r, out)");
    return GSN_OK;
}

void gsn_case_name(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    size_t length = strlen(name);
    if (length > 5 && strcmp(name + length - 5, ".yaml") == 0)
        length -= 5;
    else if (length > 4 && strcmp(name + length - 4, ".yml") == 0)
        length -= 4;
    snprintf(out, size, "%.*s", (int)length, name);
}

int gsn_case_pre_signature(const struct gsn_case *c, char *out, size_t size)
{
    int n = snprintf(out, size,
                     "geometry=%s;spacing=%.17g;facet_points=%d;mesher=%s",
                     c->geometry, c->particle_spacing, c->facet_points,
                     gsn_mesher_name(c->mesher));
    GSN_CHECK(n > 0 && (size_t)n < size, GSN_ERR_INTERNAL,
              "pre signature too long");
    for (int i = 0; i < c->refinement_count; ++i) {
        const struct gsn_refinement *f = &c->refinements[i];
        size_t used = strlen(out);
        if (f->kind == GSN_REFINE_BOX)
            n = snprintf(out + used, size - used,
                         ";refine=box:%.17g,%.17g,%.17g,%.17g,%.17g,%.17g:"
                         "%.17g:%.17g",
                         f->box[0], f->box[1], f->box[2], f->box[3], f->box[4],
                         f->box[5], f->spacing, f->distance);
        else
            n = snprintf(out + used, size - used,
                         ";refine=surface:%s:%.17g:%.17g:%.17g", f->surface,
                         f->spacing, f->distance, f->width);
        GSN_CHECK(n > 0 && (size_t)n < size - used, GSN_ERR_INTERNAL,
                  "pre signature too long");
    }
    return GSN_OK;
}

int gsn_case_find_boundary(const struct gsn_case *c, const char *name)
{
    for (int i = 0; i < c->boundary_count; ++i)
        if (strcmp(c->boundaries[i].name, name) == 0)
            return i;
    return -1;
}

const char *gsn_closest_word(const char *word, const char *const words[])
{
    return closest_key(word, words);
}

const char *gsn_integration_name(enum gsn_integration integration)
{
    static const char *const names[] = {"scni", "dni", "gauss"};
    return (unsigned)integration < 3 ? names[integration] : "unknown";
}

const char *gsn_stabilization_name(enum gsn_stabilization stabilization)
{
    return (unsigned)stabilization < 3 ? stabilization_names[stabilization]
                                       : "unknown";
}

static void write_components(FILE *out, const int present[3],
                             const double value[3])
{
    fputc('[', out);
    for (int k = 0; k < 3; ++k) {
        if (present[k])
            fprintf(out, "%.17g", value[k]);
        else
            fputs("null", out);
        fputs(k < 2 ? ", " : "]", out);
    }
}

/* One soil's keys, each line indented by indent. */
static void write_material(const struct gsn_material *m, const char *indent,
                           FILE *out)
{
    fprintf(out,
            "%sdensity: %.17g\n%ssaturated_density: %.17g\n"
            "%sbulk_modulus: %.17g\n%sshear_modulus: %.17g\n",
            indent, m->density, indent, m->saturated_density, indent,
            m->bulk_modulus, indent, m->shear_modulus);
    if (m->has_damage && m->damage_length > 0.0)
        fprintf(out, "%sdamage: {e0: %.17g, ef: %.17g, length: %.17g}\n",
                indent, m->damage_e0, m->damage_ef, m->damage_length);
    else if (m->has_damage)
        fprintf(out, "%sdamage: {e0: %.17g, ef: %.17g}\n", indent, m->damage_e0,
                m->damage_ef);
    if (m->has_plasticity && m->dp_from_mohr_coulomb)
        fprintf(out,
                "%sdrucker_prager: {cohesion: %.17g, friction_angle: %.17g, "
                "dilation_angle: %.17g, fit: %s}   # alpha %.17g, R %.17g, "
                "dilatancy %.17g\n",
                indent, m->cohesion, m->friction_angle, m->dilation_angle,
                m->dp_fit == GSN_DP_FIT_COMPRESSION ? "compression"
                                                    : "plane_strain",
                m->dp_alpha, m->dp_R, m->dp_dilatancy);
    else if (m->has_plasticity)
        fprintf(out,
                "%sdrucker_prager: {alpha: %.17g, R: %.17g, dilatancy: "
                "%.17g}\n",
                indent, m->dp_alpha, m->dp_R, m->dp_dilatancy);
}

int gsn_case_write_yaml(const struct gsn_case *c, FILE *out)
{
    static const char *const basis_names[] = {"", "linear", "quadratic"};
    fprintf(out, "# resolved parameters of %s\n", c->path);
    fprintf(out, "geometry: '%s'\n", c->geometry);
    fprintf(out, "particles: {spacing: %.17g, facet_points: %d, mesher: %s",
            c->particle_spacing, c->facet_points, gsn_mesher_name(c->mesher));
    write_refinements(c, out);
    fputs("}\n", out);
    fprintf(out, "kernel: {support: %.17g, basis: %s, window_cut: %.17g}\n",
            c->kernel_support, basis_names[c->kernel_basis_order == 2 ? 2 : 1],
            c->kernel_window_cut);
    fprintf(out, "integration: {method: %s, ",
            gsn_integration_name(c->integration));
    if (c->integration == GSN_INTEGRATION_GAUSS)
        fprintf(out, "points: %d, ", c->gauss_points);
    fprintf(out, "stabilization: %s", stabilization_names[c->stabilization]);
    if (c->stabilization != GSN_STABILIZATION_NONE)
        fprintf(out, ", coefficient: %.17g", c->stabilization_coefficient);
    fputs("}\n", out);
    if (c->materials_by_volume) {
        fputs("materials:\n", out);
        for (int k = 0; k < c->material_count; ++k) {
            fprintf(out, "  '%s':\n", c->materials[k].volume);
            write_material(&c->materials[k], "    ", out);
        }
    } else {
        fputs("material:\n", out);
        write_material(&c->material, "  ", out);
    }
    fprintf(out, "gravity: [%.17g, %.17g, %.17g]\n", c->gravity[0],
            c->gravity[1], c->gravity[2]);
    if (c->water.present) {
        const struct gsn_water *w = &c->water;
        if (w->point_count == 1)
            fprintf(out, "water: {level: %.17g", w->points[0][0]);
        else {
            fputs("water: {table: [", out);
            for (int i = 0; i < w->point_count; ++i)
                fprintf(out, "%s[%.17g, %.17g, %.17g]", i ? ", " : "",
                        w->points[i][0], w->points[i][1], w->points[i][2]);
            fputs("]", out);
        }
        fprintf(out, ", unit_weight: %.17g}\n", w->unit_weight);
    }
    fprintf(out, "boundary:%s\n", c->boundary_count ? "" : " {}");
    for (int i = 0; i < c->boundary_count; ++i) {
        const struct gsn_boundary *b = &c->boundaries[i];
        if (b->symmetry) {
            fprintf(out, "  '%s': {symmetry: true}\n", b->name);
            continue;
        }
        fprintf(out, "  '%s': {fix: [", b->name);
        int first = 1;
        for (int k = 0; k < 3; ++k) {
            if (b->fixed[k]) {
                fprintf(out, "%s%s", first ? "" : ", ", component_names[k]);
                first = 0;
            }
        }
        fputs("], velocity: ", out);
        write_components(out, b->has_velocity, b->velocity);
        fprintf(out, ", traction: [%.17g, %.17g, %.17g]%s}\n", b->traction[0],
                b->traction[1], b->traction[2],
                b->rigid ? ", rigid: true" : "");
    }
    if (c->time_step_auto)
        fprintf(out, "time: {end: %.17g, step: auto, safety: %.17g",
                c->time_end, c->time_step_safety);
    else
        fprintf(out, "time: {end: %.17g, step: %.17g", c->time_end,
                c->time_step);
    if (c->time_mass_scaling > 0.0)
        fprintf(out, ", mass_scaling: %.17g", c->time_mass_scaling);
    fprintf(out, ", ramp: %.17g}\n", c->time_ramp);
    fprintf(out, "damping: {local: %.17g}\n", c->damping_local);
    fprintf(out, "kinematics: %s\n", c->small_strain ? "small" : "large");
    if (c->plane_strain_axis >= 0)
        fprintf(out, "plane_strain: %c\n", "xyz"[c->plane_strain_axis]);
    if (c->reference_update) {
        fprintf(out, "reference_update: {strain: %.17g, volume: [%.17g, %.17g]",
                c->reference_strain, c->reference_volume[0],
                c->reference_volume[1]);
        if (c->reference_every > 0.0)
            fprintf(out, ", every: %.17g", c->reference_every);
        fprintf(out, ", min_steps: %d}\n", c->reference_min_steps);
    } else
        fprintf(out, "reference_update: off\n");
    if (c->geostatic)
        fprintf(out,
                "geostatic: {residual: %.17g, damping: %.17g, max_steps: "
                "%ld, k0: %.17g}\n",
                c->geostatic_residual, c->geostatic_damping,
                c->geostatic_max_steps, c->geostatic_k0);
    fputs("output: {", out);
    if (c->output_every > 0.0)
        fprintf(out, "every: %.17g, ", c->output_every);
    if (c->history_every > 0.0)
        fprintf(out, "history_every: %.17g, ", c->history_every);
    write_output_economy(c, out);
    fputs("}\n", out);
    GSN_CHECK(!ferror(out), GSN_ERR_IO, "cannot write the resolved case");
    return GSN_OK;
}

int gsn_case_to_yaml_string(const struct gsn_case *c, char **text)
{
    size_t size = 0;
    *text = NULL;
    FILE *stream = open_memstream(text, &size);
    GSN_CHECK(stream != NULL, GSN_ERR_MEMORY, "cannot open a memory stream");
    int rc = gsn_case_write_yaml(c, stream);
    fclose(stream);
    if (rc != GSN_OK) {
        free(*text);
        *text = NULL;
        return gsn_error_pass(rc, __FILE__, __LINE__, __func__,
                              "gsn_case_write_yaml(c, stream)");
    }
    return GSN_OK;
}

void gsn_case_yaml_upgrade(char **text)
{
    static const char name[] = "window_cut", key[] = ", window_cut: 0";
    const char *line = strstr(*text, "\nkernel: {");
    if (!line)
        return;
    const char *close = strchr(line + 1, '}');
    const char *end = strchr(line + 1, '\n');
    if (!close || (end && end < close))
        return;
    for (const char *k = line; k + strlen(name) <= close; ++k)
        if (!strncmp(k, name, strlen(name)))
            return;
    size_t at = (size_t)(close - *text), length = strlen(*text);
    char *grown = realloc(*text, length + strlen(key) + 1);
    if (!grown)
        return;
    memmove(grown + at + strlen(key), grown + at, length - at + 1);
    memcpy(grown + at, key, strlen(key));
    *text = grown;
}

/* ---- economy keys (docs/economy.md) ------------------------------------ */

_Static_assert(GSN_DEFAULT_OUTPUT_FIELDS == (1u << GSN_FRAME_FIELD_COUNT) - 1,
               "GSN_DEFAULT_OUTPUT_FIELDS must name every frame field");

/* One entry of particles.refine: {box: [x0, y0, z0, x1, y1, z1], spacing,
 * distance} or {surface: NAME, spacing, distance}. */
static int read_refinement(struct reader *r, const yaml_node_t *node, int index,
                           double background, struct gsn_refinement *f)
{
    static const char *const keys[] = {"box",      "surface", "spacing",
                                       "distance", "width",   NULL};
    char context[64];
    snprintf(context, sizeof context, "particles.refine[%d]", index);
    GSN_CALL(check_keys(r, node, keys, context));
    f->line = node_line(node);
    yaml_node_t *box = mapping_find(r, node, "box");
    yaml_node_t *surface = mapping_find(r, node, "surface");
    GSN_CHECK(!box != !surface, GSN_ERR_INPUT,
              "%s:%d: '%s' must have exactly one of 'box' ([x0, y0, z0, x1, "
              "y1, z1], m) and 'surface' (a physical surface name)",
              r->path, f->line, context);
    if (box) {
        f->kind = GSN_REFINE_BOX;
        int count = sequence_length(box);
        GSN_CHECK(count == 6, GSN_ERR_INPUT,
                  "%s:%d: '%s.box' must be a list of 6 numbers [x0, y0, z0, "
                  "x1, y1, z1] (m), got %s",
                  r->path, node_line(box), context, node_kind(r, box));
        for (int k = 0; k < 6; ++k) {
            char name[96];
            snprintf(name, sizeof name, "%s.box[%d]", context, k);
            GSN_CALL(
                parse_number(r, node_get(r, box->data.sequence.items.start[k]),
                             name, &f->box[k]));
        }
        for (int k = 0; k < 3; ++k)
            GSN_CHECK(f->box[k] < f->box[k + 3], GSN_ERR_INPUT,
                      "%s:%d: '%s.box': the lower corner's %s (%g) must be "
                      "below the upper corner's (%g)",
                      r->path, node_line(box), context, component_names[k],
                      f->box[k], f->box[k + 3]);
        f->distance = GSN_DEFAULT_REFINE_BOX_DISTANCE;
    } else {
        f->kind = GSN_REFINE_SURFACE;
        GSN_CHECK(surface->type == YAML_SCALAR_NODE &&
                      !is_null_scalar(surface) &&
                      strlen(scalar_text(surface)) < GSN_NAME_SIZE,
                  GSN_ERR_INPUT,
                  "%s:%d: '%s.surface' must be a physical surface name, got "
                  "%s",
                  r->path, node_line(surface), context, node_kind(r, surface));
        snprintf(f->surface, sizeof f->surface, "%s", scalar_text(surface));
    }
    GSN_CALL(read_positive(r, node, context, "spacing", "m", 1, &f->spacing));
    yaml_node_t *spacing = mapping_find(r, node, "spacing");
    GSN_CHECK(f->spacing < background, GSN_ERR_INPUT,
              "%s:%d: '%s.spacing' (%g m) must be smaller than "
              "particles.spacing (%g m): a refinement makes particles finer",
              r->path, node_line(spacing), context, f->spacing, background);
    if (f->kind == GSN_REFINE_SURFACE) {
        GSN_CALL(
            read_positive(r, node, context, "distance", "m", 1, &f->distance));
        int line = f->line;
        char name[96];
        snprintf(name, sizeof name, "%s.width", context);
        GSN_CALL(read_number(r, node, context, "width", &f->width, &line));
        GSN_CALL(check_lower(r, line, name, f->width, 0.0, 0, "m"));
    } else {
        GSN_CHECK(!mapping_find(r, node, "width"), GSN_ERR_INPUT,
                  "%s:%d: '%s.width' applies to a surface refinement only; "
                  "a box's spacing holds inside the box",
                  r->path, node_line(mapping_find(r, node, "width")), context);
        int line = f->line;
        char name[96];
        snprintf(name, sizeof name, "%s.distance", context);
        GSN_CALL(
            read_number(r, node, context, "distance", &f->distance, &line));
        GSN_CALL(check_lower(r, line, name, f->distance, 0.0, 0, "m"));
    }
    return GSN_OK;
}

static int read_refinements(struct reader *r, const yaml_node_t *particles,
                            struct gsn_case *c)
{
    yaml_node_t *node = mapping_find(r, particles, "refine");
    if (!node)
        return GSN_OK;
    GSN_CHECK(node->type == YAML_SEQUENCE_NODE, GSN_ERR_INPUT,
              "%s:%d: 'particles.refine' must be a list of {box: [x0, y0, z0, "
              "x1, y1, z1], spacing: ...} or {surface: NAME, spacing: ..., "
              "distance: ...} entries, got %s",
              r->path, node_line(node), node_kind(r, node));
    int count = sequence_length(node);
    GSN_CHECK(count <= GSN_MAX_REFINEMENTS, GSN_ERR_INPUT,
              "%s:%d: 'particles.refine' has %d entries, at most %d", r->path,
              node_line(node), count, GSN_MAX_REFINEMENTS);
    for (int i = 0; i < count; ++i) {
        yaml_node_t *item = node_get(r, node->data.sequence.items.start[i]);
        char context[64];
        snprintf(context, sizeof context, "particles.refine[%d]", i);
        GSN_CALL(expect_mapping(r, item, context));
        GSN_CALL(read_refinement(r, item, i, c->particle_spacing,
                                 &c->refinements[i]));
    }
    c->refinement_count = count;
    return GSN_OK;
}

/* boundary.NAME.symmetry: true holds the normal component of an
 * axis-aligned plane surface (resolved on the model, symmetry.c); it
 * excludes every other key of the entry. */
/* boundary.NAME.KEY: true or false into *flag (left as it is when the key
 * is absent); *node gets the key's value node, or NULL. */
static int read_entry_flag(struct reader *r, const yaml_node_t *entry,
                           const char *context, const char *key, int *flag,
                           yaml_node_t **node)
{
    *node = mapping_find(r, entry, key);
    if (!*node)
        return GSN_OK;
    static const char *const truth[] = {"false", "true", NULL};
    char name[GSN_NAME_SIZE + 32];
    snprintf(name, sizeof name, "%s.%s", context, key);
    return parse_word(r, *node, name, truth, flag);
}

static int read_symmetry(struct reader *r, const yaml_node_t *entry,
                         const char *context, struct gsn_boundary *b)
{
    yaml_node_t *node;
    GSN_CALL(
        read_entry_flag(r, entry, context, "symmetry", &b->symmetry, &node));
    if (!node)
        return GSN_OK;
    GSN_CHECK(!b->symmetry || (!mapping_find(r, entry, "fix") &&
                               !mapping_find(r, entry, "velocity") &&
                               !mapping_find(r, entry, "traction")),
              GSN_ERR_INPUT,
              "%s:%d: '%s' is a symmetry plane: it takes no 'fix', "
              "'velocity' or 'traction' (the component normal to the plane "
              "is held)",
              r->path, node_line(node), context);
    return GSN_OK;
}

/* boundary.NAME.rigid: true makes the surface the face of a rigid body
 * (solver/src/contact.h): it needs a velocity that moves it. */
static int read_rigid(struct reader *r, const yaml_node_t *entry,
                      const char *context, struct gsn_boundary *b)
{
    yaml_node_t *node;
    GSN_CALL(read_entry_flag(r, entry, context, "rigid", &b->rigid, &node));
    if (!node)
        return GSN_OK;
    double speed = 0.0;
    for (int k = 0; k < 3; ++k)
        if (b->has_velocity[k])
            speed += b->velocity[k] * b->velocity[k];
    GSN_CHECK(!b->rigid || speed > 0.0, GSN_ERR_INPUT,
              "%s:%d: '%s' is a rigid body, which moves at its 'velocity': "
              "give it a nonzero velocity, such as velocity: [null, null, "
              "-0.1] (the body is the surface swept against the motion)",
              r->path, node_line(node), context);
    return GSN_OK;
}

/* output.times: frames at the listed times, increasing, in (0, time.end];
 * alone they replace output.every's default (docs/economy.md, "Outputs"). */
static int read_output_times(struct reader *r, const yaml_node_t *output,
                             struct gsn_case *c)
{
    yaml_node_t *times = mapping_find(r, output, "times");
    if (!times)
        return GSN_OK;
    int count = sequence_length(times);
    GSN_CHECK(count > 0, GSN_ERR_INPUT,
              "%s:%d: 'output.times' must be a list of one or more times in "
              "s, e.g. [0.5, 1.0, 2.5], got %s",
              r->path, node_line(times), node_kind(r, times));
    GSN_CHECK(count <= GSN_MAX_OUTPUT_TIMES, GSN_ERR_INPUT,
              "%s:%d: 'output.times' lists %d times, at most %d; use "
              "'output.every' for regular frames",
              r->path, node_line(times), count, GSN_MAX_OUTPUT_TIMES);
    for (int i = 0; i < count; ++i) {
        yaml_node_t *item = node_get(r, times->data.sequence.items.start[i]);
        char name[64];
        snprintf(name, sizeof name, "output.times[%d]", i);
        double t = 0.0;
        GSN_CALL(parse_number(r, item, name, &t));
        GSN_CHECK(t > 0.0, GSN_ERR_INPUT,
                  "%s:%d: '%s' must be > 0 s, got %g; the frame at t = 0 is "
                  "always written",
                  r->path, node_line(item), name, t);
        GSN_CHECK(i == 0 || t > c->output_times[i - 1], GSN_ERR_INPUT,
                  "%s:%d: '%s' is %g s, not after output.times[%d] = %g s; "
                  "list the times once each, in increasing order",
                  r->path, node_line(item), name, t, i - 1,
                  i ? c->output_times[i - 1] : 0.0);
        GSN_CHECK(t <= c->time_end, GSN_ERR_INPUT,
                  "%s:%d: '%s' is %g s, after time.end = %g s; list times up "
                  "to time.end, or raise time.end",
                  r->path, node_line(item), name, t, c->time_end);
        c->output_times[i] = t;
    }
    c->output_time_count = count;
    if (!mapping_find(r, output, "every"))
        c->output_every = 0.0; /* the listed times alone */
    return GSN_OK;
}

/* output.times (above); output.fields: which frame fields are written;
 * output.mirror: the symmetry entry post mirrors the half model across. */
static int read_output_economy(struct reader *r, const yaml_node_t *output,
                               struct gsn_case *c)
{
    GSN_CALL(read_output_times(r, output, c));
    static const char *names[GSN_FRAME_FIELD_COUNT + 1];
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        names[f] = gsn_frame_fields[f].path;
    names[GSN_FRAME_FIELD_COUNT] = NULL;
    yaml_node_t *fields = mapping_find(r, output, "fields");
    if (fields) {
        char list[256];
        join_keys(names, list, sizeof list);
        int count = sequence_length(fields);
        GSN_CHECK(count > 0, GSN_ERR_INPUT,
                  "%s:%d: 'output.fields' must be a list of one or more of "
                  "%s, got %s",
                  r->path, node_line(fields), list, node_kind(r, fields));
        c->output_fields = 0;
        for (int i = 0; i < count; ++i) {
            yaml_node_t *item =
                node_get(r, fields->data.sequence.items.start[i]);
            int f = 0;
            GSN_CALL(parse_word(r, item, "output.fields", names, &f));
            GSN_CHECK(!(c->output_fields & (1u << f)), GSN_ERR_INPUT,
                      "%s:%d: 'output.fields' names '%s' twice", r->path,
                      node_line(item), names[f]);
            c->output_fields |= 1u << f;
        }
    }
    yaml_node_t *mirror = mapping_find(r, output, "mirror");
    if (mirror) {
        GSN_CHECK(mirror->type == YAML_SCALAR_NODE && !is_null_scalar(mirror),
                  GSN_ERR_INPUT,
                  "%s:%d: 'output.mirror' must name a boundary entry with "
                  "symmetry: true, got %s",
                  r->path, node_line(mirror), node_kind(r, mirror));
        int b = gsn_case_find_boundary(c, scalar_text(mirror));
        GSN_CHECK(b >= 0 && c->boundaries[b].symmetry, GSN_ERR_INPUT,
                  "%s:%d: 'output.mirror' is '%s', which is not a boundary "
                  "entry with symmetry: true",
                  r->path, node_line(mirror), scalar_text(mirror));
        snprintf(c->output_mirror, sizeof c->output_mirror, "%s",
                 c->boundaries[b].name);
    }
    return GSN_OK;
}

static void write_refinements(const struct gsn_case *c, FILE *out)
{
    if (!c->refinement_count)
        return;
    fputs(", refine: [", out);
    for (int i = 0; i < c->refinement_count; ++i) {
        const struct gsn_refinement *f = &c->refinements[i];
        if (f->kind == GSN_REFINE_BOX)
            fprintf(out, "{box: [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g], ",
                    f->box[0], f->box[1], f->box[2], f->box[3], f->box[4],
                    f->box[5]);
        else
            fprintf(out, "{surface: '%s', width: %.17g, ", f->surface,
                    f->width);
        fprintf(out, "spacing: %.17g, distance: %.17g}%s", f->spacing,
                f->distance, i + 1 < c->refinement_count ? ", " : "]");
    }
}

static void write_output_economy(const struct gsn_case *c, FILE *out)
{
    if (c->output_time_count) {
        fputs("times: [", out);
        for (int i = 0; i < c->output_time_count; ++i)
            fprintf(out, "%s%.17g", i ? ", " : "", c->output_times[i]);
        fputs("], ", out);
    }
    fputs("fields: [", out);
    int first = 1;
    for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f)
        if (c->output_fields & (1u << f)) {
            fprintf(out, "%s%s", first ? "" : ", ", gsn_frame_fields[f].path);
            first = 0;
        }
    fputc(']', out);
    if (c->output_mirror[0])
        fprintf(out, ", mirror: '%s'", c->output_mirror);
}

void gsn_case_scale_spacing(struct gsn_case *c, double factor)
{
    c->particle_spacing *= factor;
    for (int k = 0; k < c->refinement_count; ++k)
        c->refinements[k].spacing *= factor;
    if (!c->time_step_auto)
        c->time_step *= factor;
}

/* Seed eq. (8) in sqrt(J2) reads sqrt(J2) + a I1 - k (a = alpha / sqrt 2,
 * k = R / sqrt 2, b = beta / sqrt 2 of the potential). Plane strain with
 * the out-of-plane plastic strain zero (s_yy = -2 b sqrt(J2)) turns the
 * cone into t (1 - 3 a b) / sqrt(1 - 3 b^2) = k - 3 a s (t, s: radius and
 * centre of the in-plane Mohr circle, tension positive), which is
 * Mohr-Coulomb's t = c cos(phi) - s sin(phi) for the a and k below; the
 * dilation of that flow is sin(psi) = 3 b / sqrt(1 - 3 b^2). With b = a
 * these are Drucker and Prager's (1952) a = tan(phi) / sqrt(9 + 12
 * tan^2(phi)), k = 3 c / sqrt(9 + 12 tan^2(phi)); with psi = 0, a =
 * sin(phi) / 3, k = c cos(phi). The compression cone passes through the
 * triaxial-compression corners of the hexagon. */
void gsn_drucker_prager_fit(enum gsn_dp_fit fit, double cohesion,
                            double friction_angle, double dilation_angle,
                            double *alpha, double *R, double *beta)
{
    const double degree = acos(-1.0) / 180.0;
    double sp = sin(friction_angle * degree), cp = cos(friction_angle * degree);
    double ss = sin(dilation_angle * degree), a, k, b;
    if (fit == GSN_DP_FIT_COMPRESSION) {
        a = 2.0 * sp / (sqrt(3.0) * (3.0 - sp));
        k = 6.0 * cohesion * cp / (sqrt(3.0) * (3.0 - sp));
        b = 2.0 * ss / (sqrt(3.0) * (3.0 - ss));
    } else {
        b = ss / sqrt(9.0 + 3.0 * ss * ss);
        double root = sqrt(1.0 - 3.0 * b * b);
        a = sp / (3.0 * root + 3.0 * b * sp);
        k = cohesion * cp * (1.0 - 3.0 * a * b) / root;
    }
    *alpha = sqrt(2.0) * a;
    *R = sqrt(2.0) * k;
    *beta = sqrt(2.0) * b;
}

void gsn_material_reduce_strength(const struct gsn_material *m, double factor,
                                  struct gsn_material *reduced)
{
    const double degree = acos(-1.0) / 180.0;
    *reduced = *m;
    reduced->has_damage = 0;
    if (!m->has_plasticity)
        return; /* elastic (bedrock): no strength to reduce */
    reduced->cohesion = m->cohesion / factor;
    reduced->friction_angle =
        atan(tan(m->friction_angle * degree) / factor) / degree;
    reduced->dilation_angle = fmin(m->dilation_angle, reduced->friction_angle);
    gsn_drucker_prager_fit(m->dp_fit, reduced->cohesion,
                           reduced->friction_angle, reduced->dilation_angle,
                           &reduced->dp_alpha, &reduced->dp_R,
                           &reduced->dp_dilatancy);
}
