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

static void check_density(FILE *out, const struct gsn_case *c, int *count)
{
    const double rho = c->material.density;
    char text[512];
    if (rho >= DENSITY_LOW && rho <= DENSITY_HIGH)
        return;
    int n = snprintf(text, sizeof text,
                     "material.density = %g kg/m^3 is implausible for soil "
                     "(%g to %g kg/m^3)",
                     rho, DENSITY_LOW, DENSITY_HIGH);
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
    warn(out, c, c->material_line.density, text, count);
}

static void check_modulus(FILE *out, const struct gsn_case *c, const char *key,
                          double value, int line, int *count)
{
    char text[512];
    if (value >= MODULUS_LOW && value <= MODULUS_HIGH)
        return;
    int n = snprintf(text, sizeof text,
                     "material.%s = %g Pa is implausible for soil (%g to %g "
                     "Pa)",
                     key, value, MODULUS_LOW, MODULUS_HIGH);
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

int gsn_case_warn_implausible(const struct gsn_case *c, FILE *out)
{
    const struct gsn_material *m = &c->material;
    int count = 0;
    char text[512];
    check_density(out, c, &count);
    check_modulus(out, c, "bulk_modulus", m->bulk_modulus,
                  c->material_line.bulk_modulus, &count);
    check_modulus(out, c, "shear_modulus", m->shear_modulus,
                  c->material_line.shear_modulus, &count);
    /* Poisson's ratio (3K - 2mu) / (2 (3K + mu)) < 0: mu > 1.5 K */
    if (m->shear_modulus > 1.5 * m->bulk_modulus) {
        snprintf(text, sizeof text,
                 "material.shear_modulus (%g Pa) is over 1.5 times "
                 "bulk_modulus (%g Pa), a negative Poisson's ratio (%.3g), "
                 "which no soil has: are the two swapped?",
                 m->shear_modulus, m->bulk_modulus,
                 (3.0 * m->bulk_modulus - 2.0 * m->shear_modulus) /
                     (2.0 * (3.0 * m->bulk_modulus + m->shear_modulus)));
        warn(out, c, c->material_line.shear_modulus, text, &count);
    } else if (m->bulk_modulus > MODULUS_RATIO_HIGH * m->shear_modulus) {
        snprintf(text, sizeof text,
                 "material.bulk_modulus (%g Pa) is over %g times "
                 "shear_modulus (%g Pa): are both in Pa?",
                 m->bulk_modulus, MODULUS_RATIO_HIGH, m->shear_modulus);
        warn(out, c, c->material_line.bulk_modulus, text, &count);
    }
    /* the strength as given: the cohesion, or R of the cone */
    const char *strength_key = m->dp_from_mohr_coulomb ? "cohesion" : "R";
    double strength = m->dp_from_mohr_coulomb ? m->cohesion : m->dp_R;
    if (m->has_plasticity && strength > 0.0 && strength < STRENGTH_LOW) {
        snprintf(text, sizeof text,
                 "material.drucker_prager.%s = %g Pa is a very weak soil "
                 "(below %g Pa): if it is given in kPa, write %g",
                 strength_key, strength, STRENGTH_LOW, strength * 1e3);
        warn(out, c, c->material_line.R, text, &count);
    }
    return count;
}
