/* Warnings for case values that are legal but implausible for soil, each
 * with the unit mistake it most likely is (issue 21, point 7): SI units
 * throughout, so a density of 1.88 (t/m^3) or moduli in kPa run, but run
 * a different body. */
#include "geoscni/case.h"

#include <stdio.h>

/* Soil and rock lie within these (kg/m^3, Pa); outside, a value is
 * warned of. */
#define DENSITY_LOW 800.0
#define DENSITY_HIGH 3500.0
#define MODULUS_LOW 1.0e5
#define MODULUS_HIGH 1.0e11
/* R (Pa) of a soil with cohesion is kPa at least; below, likely kPa. */
#define STRENGTH_LOW 1.0e3
/* K / mu above this is a Poisson's ratio above 0.4995: moduli in two
 * units, more likely than such a soil. */
#define MODULUS_RATIO_HIGH 1.0e3

static void warn(FILE *out, const struct gsn_case *c, int line,
                 const char *text, int *count)
{
    if (line > 0)
        fprintf(out, "warning: %s:%d: %s\n", c->path, line, text);
    else
        fprintf(out, "warning: %s: %s\n", c->path, text);
    ++*count;
}

/* The name of a material's block in messages: "material" or
 * "materials.VOLUME". */
static const char *block_name(const struct gsn_material *m, char *out,
                              size_t size)
{
    if (m->volume[0])
        snprintf(out, size, "materials.%s", m->volume);
    else
        snprintf(out, size, "material");
    return out;
}

static void check_density(FILE *out, const struct gsn_case *c,
                          const struct gsn_material *m, const char *block,
                          int *count)
{
    const double rho = m->density;
    char text[512];
    if (m->saturated_density < rho) {
        snprintf(text, sizeof text,
                 "%s.saturated_density (%g kg/m^3) is less than its density "
                 "(%g kg/m^3): a saturated soil is the heavier one",
                 block, m->saturated_density, rho);
        warn(out, c, m->line.entry, text, count);
    }
    if (rho >= DENSITY_LOW && rho <= DENSITY_HIGH)
        return;
    int n = snprintf(text, sizeof text,
                     "%s.density = %g kg/m^3 is implausible for soil "
                     "(%g to %g kg/m^3)",
                     block, rho, DENSITY_LOW, DENSITY_HIGH);
    if (rho < 10.0)
        snprintf(text + n, sizeof text - (size_t)n,
                 ": probably given in t/m^3 or g/cm^3; in kg/m^3 write %g",
                 rho * 1e3);
    else if (rho < 30.0)
        snprintf(text + n, sizeof text - (size_t)n,
                 ": it looks like a unit weight in kN/m^3; the density is "
                 "that divided by g, %.4g kg/m^3",
                 rho * 1e3 / 9.81);
    else
        snprintf(text + n, sizeof text - (size_t)n,
                 ": check its unit (kg/m^3)");
    warn(out, c, m->line.density, text, count);
}

static void check_modulus(FILE *out, const struct gsn_case *c,
                          const char *block, const char *key, double value,
                          int line, int *count)
{
    char text[512];
    if (value >= MODULUS_LOW && value <= MODULUS_HIGH)
        return;
    int n = snprintf(text, sizeof text,
                     "%s.%s = %g Pa is implausible for soil (%g to %g "
                     "Pa)",
                     block, key, value, MODULUS_LOW, MODULUS_HIGH);
    if (value < 1e3)
        snprintf(text + n, sizeof text - (size_t)n,
                 ": probably given in MPa; in Pa write %g", value * 1e6);
    else if (value < MODULUS_LOW)
        snprintf(text + n, sizeof text - (size_t)n,
                 ": probably given in kPa; in Pa write %g", value * 1e3);
    else
        snprintf(text + n, sizeof text - (size_t)n, ": check its unit (Pa)");
    warn(out, c, line, text, count);
}

static int warn_material(const struct gsn_case *c, const struct gsn_material *m,
                         FILE *out)
{
    int count = 0;
    char text[512], block[GSN_NAME_SIZE + 16];
    block_name(m, block, sizeof block);
    check_density(out, c, m, block, &count);
    check_modulus(out, c, block, "bulk_modulus", m->bulk_modulus,
                  m->line.bulk_modulus, &count);
    check_modulus(out, c, block, "shear_modulus", m->shear_modulus,
                  m->line.shear_modulus, &count);
    /* Poisson's ratio (3K - 2mu) / (2 (3K + mu)) < 0: mu > 1.5 K */
    if (m->shear_modulus > 1.5 * m->bulk_modulus) {
        snprintf(text, sizeof text,
                 "%s.shear_modulus (%g Pa) is over 1.5 times "
                 "bulk_modulus (%g Pa), a negative Poisson's ratio (%.3g), "
                 "which no soil has: are the two swapped?",
                 block, m->shear_modulus, m->bulk_modulus,
                 (3.0 * m->bulk_modulus - 2.0 * m->shear_modulus) /
                     (2.0 * (3.0 * m->bulk_modulus + m->shear_modulus)));
        warn(out, c, m->line.shear_modulus, text, &count);
    } else if (m->bulk_modulus > MODULUS_RATIO_HIGH * m->shear_modulus) {
        snprintf(text, sizeof text,
                 "%s.bulk_modulus (%g Pa) is over %g times "
                 "shear_modulus (%g Pa): are both in Pa?",
                 block, m->bulk_modulus, MODULUS_RATIO_HIGH, m->shear_modulus);
        warn(out, c, m->line.bulk_modulus, text, &count);
    }
    /* the strength as given: the cohesion, or R of the cone */
    const char *strength_key = m->dp_from_mohr_coulomb ? "cohesion" : "R";
    double strength = m->dp_from_mohr_coulomb ? m->cohesion : m->dp_R;
    if (m->has_plasticity && strength > 0.0 && strength < STRENGTH_LOW) {
        snprintf(text, sizeof text,
                 "%s.drucker_prager.%s = %g Pa is a very weak soil "
                 "(below %g Pa): if it is given in kPa, write %g",
                 block, strength_key, strength, STRENGTH_LOW, strength * 1e3);
        warn(out, c, m->line.R, text, &count);
    }
    return count;
}

int gsn_case_warn_implausible(const struct gsn_case *c, FILE *out)
{
    int count = 0;
    for (int k = 0; k < c->material_count; ++k)
        count += warn_material(c, &c->materials[k], out);
    return count;
}
