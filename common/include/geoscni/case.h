/* The case file (DESIGN.md, "The case file"): YAML read with libyaml into one
 * struct of resolved parameters. Every key has a named default or is
 * required; every error names file:line and what is expected. */
#ifndef GEOSCNI_CASE_H
#define GEOSCNI_CASE_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { GSN_PATH_SIZE = 4096, GSN_NAME_SIZE = 64, GSN_MAX_BOUNDARIES = 32 };
/* Entries of materials: (one soil per gmsh physical volume) and points of
 * water.table. */
enum { GSN_MAX_MATERIALS = 16, GSN_MAX_WATER_POINTS = 64 };
/* Entries of output.times; regular frames take output.every. */
enum { GSN_MAX_OUTPUT_TIMES = 1000 };

/* Defaults of the optional keys. */
#define GSN_DEFAULT_KERNEL_SUPPORT 1.5   /* a/h, seed paper section 6 */
#define GSN_DEFAULT_KERNEL_BASIS_ORDER 1 /* linear basis */
/* kernel.window_cut: the window's corners below 1e-3 of its peak left out,
 * a third fewer gradient entries; 0 is the paper's whole window
 * (docs/kernels.md, "Window cut": the default since 2026-12-06) */
#define GSN_DEFAULT_KERNEL_WINDOW_CUT 1e-3
#define GSN_DEFAULT_FACET_POINTS 1       /* facet centroid rule */
#define GSN_DEFAULT_GAUSS_POINTS 2       /* per direction, per cell */
#define GSN_DEFAULT_TIME_STEP_SAFETY 0.8 /* fraction of the stable step */
/* MSCNI weight of the sub-cells: Puso et al. (2008) use 1 (elastic). */
#define GSN_DEFAULT_STABILIZATION_COEFFICIENT 1.0
/* output.every = end / this, when neither output.every nor output.times is
 * given */
#define GSN_DEFAULT_FRAMES 100
/* Reference-configuration updates (issue 15, docs/solver.md): a particle's
 * strain |E| = |F^T F - I| / 2 since the last update above this, or its
 * volume ratio det F outside the range below, triggers one. */
#define GSN_DEFAULT_REFERENCE_STRAIN 0.2
#define GSN_DEFAULT_REFERENCE_VOLUME_MIN 0.7
#define GSN_DEFAULT_REFERENCE_VOLUME_MAX 1.4
/* ... and at least this many steps pass between two updates. An update
 * costs some 200 to 250 steps (docs/solver.md); the strain spaces them:
 * 200 to 2,000 steps apart on the paper's slopes, 100 to 260 at the corner
 * of a footing pushed one width deep, where 500 lets |E| reach 1 to 3
 * between updates and the run break up at 0.34 B. */
#define GSN_DEFAULT_REFERENCE_MIN_STEPS 20
#define GSN_DEFAULT_MAX_PARTICLES 5000000 /* more needs --force */
/* The geostatic stage (docs/solver.md, "The soil's own weight"): at rest
 * when the unbalanced force is this fraction of the load, relaxed with this
 * local damping, within this many steps. */
#define GSN_DEFAULT_GEOSTATIC_RESIDUAL 1e-4
#define GSN_DEFAULT_GEOSTATIC_DAMPING 0.8
#define GSN_DEFAULT_GEOSTATIC_MAX_STEPS 200000

/* Defaults of the economy keys (docs/economy.md). */
#define GSN_DEFAULT_REFINE_BOX_DISTANCE 0.0 /* no transition layer */
#define GSN_DEFAULT_OUTPUT_FIELDS 0x3fu     /* every frame field (schema.h) */

/* Size of the buffer for gsn_case_pre_signature. */
#define GSN_PRE_SIGNATURE_SIZE (2 * GSN_PATH_SIZE)

enum gsn_integration {
    GSN_INTEGRATION_SCNI = 0, /* stabilized conforming nodal integration */
    GSN_INTEGRATION_DNI,      /* direct nodal integration (comparison only) */
    GSN_INTEGRATION_GAUSS     /* background-cell Gauss (comparison only) */
};

enum gsn_stabilization {
    GSN_STABILIZATION_NONE = 0,
    GSN_STABILIZATION_MSCNI, /* sub-cell smoothing, Puso et al. 2008 */
    GSN_STABILIZATION_NSNI   /* strain gradients, Hillman & Chen 2016 */
};

/* Boundary entry: keys are gmsh physical surface names. Components are
 * x, y, z = 0, 1, 2. */
struct gsn_boundary {
    char name[GSN_NAME_SIZE];
    int line;            /* line of the entry in the case file */
    int fixed[3];        /* component held at zero displacement */
    int has_velocity[3]; /* component moved at a prescribed velocity */
    double velocity[3];  /* m/s, where has_velocity */
    int has_traction[3]; /* set when the entry has a traction */
    double traction[3];  /* dead load per reference area, Pa */
    int symmetry; /* symmetry plane: the normal component is held (solver) */
    int rigid;    /* the surface is the face of a rigid body moving at the
                     prescribed velocity: the body is the surface swept
                     against the motion, and no other particle may enter it
                     (solver/src/contact.h) */
};

/* Local refinement of the particle spacing (particles.refine), passed to
 * gmsh as size fields (docs/economy.md, "Graded spacing"). */
enum { GSN_MAX_REFINEMENTS = 16 };
enum gsn_refine_kind {
    GSN_REFINE_BOX = 0, /* spacing inside an axis-aligned box */
    GSN_REFINE_SURFACE  /* spacing on a physical surface */
};
struct gsn_refinement {
    enum gsn_refine_kind kind;
    int line;                    /* of the entry in the case file */
    double box[6];               /* x0 y0 z0 x1 y1 z1, m (BOX) */
    char surface[GSN_NAME_SIZE]; /* physical surface name (SURFACE) */
    double spacing;              /* m, inside the box / on the surface */
    double distance; /* m over which the spacing grows to particles.spacing */
    double width;    /* m from a surface within which spacing holds (SURFACE) */
};

/* How a Drucker-Prager cone is fitted to Mohr-Coulomb's c, phi, psi
 * (material.drucker_prager.fit; docs/material.md, "In engineers' terms"). */
enum gsn_dp_fit {
    GSN_DP_FIT_PLANE_STRAIN = 0, /* the same strength in plane strain, for
                                    the flow of the given dilation angle */
    GSN_DP_FIT_COMPRESSION       /* through the triaxial-compression corners
                                    (the outer cone) */
};

/* alpha, R and the dilatancy beta of seed eq. (8) (f = ||dev s|| + alpha
 * tr s - R, potential ||dev s|| + beta tr s, tension positive) from the
 * cohesion c (Pa) and the friction and dilation angles (degrees). */
void gsn_drucker_prager_fit(enum gsn_dp_fit fit, double cohesion,
                            double friction_angle, double dilation_angle,
                            double *alpha, double *R, double *beta);

struct gsn_material {
    double density;       /* rho0, kg/m^3 */
    double bulk_modulus;  /* K, Pa */
    double shear_modulus; /* mu, Pa */
    int has_damage;       /* seed eqs. (6)-(7) */
    double damage_e0;     /* initial damage threshold, - */
    double damage_ef;     /* final damage threshold, - */
    /* crack band (damage.length; Bazant & Oh 1983): the band width, m, at
     * which e0 and ef hold; at spacing h the softening follows the band's
     * opening h (e_t - e0), so that the energy a band dissipates does not
     * depend on the spacing (material_damage_drucker_prager.c). 0: the
     * seed paper's local law. */
    double damage_length;
    int has_plasticity;  /* seed eq. (8) */
    double dp_alpha;     /* friction coefficient alpha, - */
    double dp_R;         /* cohesion-like R, Pa */
    double dp_dilatancy; /* beta of the potential; = alpha: associated */
    /* given in engineers' terms (drucker_prager: {cohesion, ...}): those
     * values, from which alpha, R and beta were fitted; else 0 */
    int dp_from_mohr_coulomb;
    double cohesion;       /* c, Pa */
    double friction_angle; /* phi, degrees */
    double dilation_angle; /* psi, degrees */
    enum gsn_dp_fit dp_fit;
    /* rho_sat below the water table (water:), kg/m^3; = density if not
     * given */
    double saturated_density;
    /* materials: the gmsh physical volume the soil fills; "" for the one
     * soil of material: */
    char volume[GSN_NAME_SIZE];
    /* lines in the case file (0: not given), for messages: the entry and
     * some keys */
    struct {
        int entry, density, bulk_modulus, shear_modulus, R;
    } line;
};

/* A static water table (water:; docs/material.md, "Water"): hydrostatic
 * pore pressure u = gamma_w (table height - height) below it, heights along
 * -gravity; the material sees the effective stress sigma' = sigma + u I. */
struct gsn_water {
    int present;
    double unit_weight; /* gamma_w, N/m^3 */
    /* 1: a level, the table at height points[0][0]; >= 2: points (x, y,
     * z) of the table, either a section's line (in order along one
     * horizontal direction, linear between them, level beyond the ends,
     * the same across the section) or spread over the site (linear on
     * their Delaunay triangles in plan, beyond them the height at the
     * nearest place of their hull): gsn_water_table_prepare */
    int point_count;
    double points[GSN_MAX_WATER_POINTS][3];
    int triangle_count; /* 0: a level or a section's line */
    int triangles[2 * GSN_MAX_WATER_POINTS][3];
    int line; /* of the key water */
};

/* Strength reduction (geoscni fos; docs/fos.md): the material with c and
 * tan(phi) divided by factor, psi kept but never above the reduced phi, the
 * cone fitted again as the case fitted it; damage left out (the factor
 * reduces the peak strength). The material must be given in engineers'
 * terms (dp_from_mohr_coulomb), or be elastic (kept as it is). */
void gsn_material_reduce_strength(const struct gsn_material *m, double factor,
                                  struct gsn_material *reduced);

/* gmsh's volume mesher, whose nodes are the particles: Delaunay (one
 * thread) gives the same particles on every run; HXT is several times
 * faster but, in gmsh 4.8, not reproducible (about 0.1% of the particles
 * differ from run to run). */
enum gsn_mesher { GSN_MESHER_DELAUNAY = 0, GSN_MESHER_HXT };

/* "delaunay" or "hxt" */
const char *gsn_mesher_name(enum gsn_mesher mesher);

struct gsn_case {
    char path[GSN_PATH_SIZE];     /* the case file as given */
    char geometry[GSN_PATH_SIZE]; /* resolved against the case file folder */
    int geometry_line;
    int particle_spacing_line;
    double particle_spacing; /* m */
    int facet_points;        /* quadrature points per Voronoi facet */
    enum gsn_mesher mesher;  /* gmsh's volume mesher (particles.mesher) */
    int mesher_line;
    double kernel_support;    /* normalized support a/h */
    int kernel_basis_order;   /* 1 linear, 2 quadratic */
    double kernel_window_cut; /* the window is 0 below this fraction of its
                                 peak (0: the paper's whole support) */
    enum gsn_integration integration;
    int gauss_points; /* per direction, GAUSS only */
    enum gsn_stabilization stabilization;
    double stabilization_coefficient; /* MSCNI weight of the sub-cells */
    /* The soils: material: gives one for the whole body (material_count 1,
     * materials_by_volume 0); materials: one per gmsh physical volume, in
     * the case file's order. material is materials[0]. */
    int material_count;
    int materials_by_volume;
    union {
        struct gsn_material material;
        struct gsn_material materials[GSN_MAX_MATERIALS];
    };
    struct gsn_water water;
    double gravity[3]; /* m/s^2 */
    int boundary_count;
    struct gsn_boundary boundaries[GSN_MAX_BOUNDARIES];
    double time_end;             /* s */
    int time_step_auto;          /* step: auto */
    double time_step;            /* s, when not auto */
    double time_step_safety;     /* fraction of the stable step, auto only */
    double time_mass_scaling;    /* fraction of the body's mass that mass
                                    scaling may add (0: none) */
    int time_mass_scaling_given; /* the case file sets it (fos's default
                                    applies otherwise) */
    double time_ramp;            /* s over which prescribed velocities rise
                                    smoothly from 0 (0: at once) */
    double damping_local;  /* Cundall's local damping coefficient (0: none) */
    int small_strain;      /* kinematics: small (no geometry update) */
    int plane_strain_axis; /* plane_strain: x, y or z (0, 1, 2): the
                              displacement along it is zero everywhere;
                              -1: none */
    /* reference_update: the shape functions and cells built again on the
     * current configuration when the body has moved far enough from the
     * last one (large kinematics, nodal integration; docs/solver.md) */
    int reference_update;       /* 1: on (the default where it applies) */
    double reference_strain;    /* |E| since the last update */
    double reference_volume[2]; /* det F since the last update */
    double reference_every;     /* s between updates at most; 0: none */
    int reference_min_steps;    /* steps between two updates at least */
    int reference_update_line;  /* line of the key, 0 if absent */
    /* geostatic: the dead loads (gravity, tractions) brought to equilibrium
     * by damped relaxation before the loading stage, whose displacements
     * start from zero there (docs/solver.md, "The soil's own weight") */
    int geostatic;             /* 1: on */
    double geostatic_residual; /* |f_ext - f_int + reactions| / |f_ext| */
    double geostatic_damping;  /* Cundall's coefficient while relaxing */
    long geostatic_max_steps;  /* the step budget */
    double geostatic_k0;       /* > 0: the stresses set first as on level
                                  ground, sigma_h = K0 sigma_v; 0: none */
    int geostatic_line;        /* line of the key, 0 if absent */
    double output_every;       /* s between frames; 0: none (output.times
                                  alone) */
    int output_every_default;  /* output.every and .times not given: every
                                  is time_end / GSN_DEFAULT_FRAMES */
    double history_every;      /* s between history rows besides the frames'
                                  (0: at the frames only) */
    /* economy (docs/economy.md) */
    int refinement_count;
    struct gsn_refinement refinements[GSN_MAX_REFINEMENTS];
    unsigned output_fields; /* bit f: frame field f (schema.h) is written */
    char output_mirror[GSN_NAME_SIZE]; /* symmetry surface post mirrors
                                          across, or "" */
    /* output.times: frames at these times (s, increasing, in (0, end]) */
    int output_time_count;
    double output_times[GSN_MAX_OUTPUT_TIMES];
};

/* Reads and checks a case file. On error returns GSN_ERR_INPUT (or
 * GSN_ERR_IO) with a "path:line: message" in the error chain. */
int gsn_case_load(const char *path, struct gsn_case *out);

/* Writes the resolved parameters as YAML (every key, defaults included);
 * the text is stored in every output file. */
int gsn_case_write_yaml(const struct gsn_case *c, FILE *out);

/* The same as a malloc'ed string; the caller frees it. */
int gsn_case_to_yaml_string(const struct gsn_case *c, char **text);

/* A stored case text (malloc'ed) as this version writes it: a kernel line
 * without window_cut (written before 2026-12-06, night, when the key was
 * written only if not 0 and 0 was the default) gets ", window_cut: 0";
 * *text is reallocated (left as it was if that fails). */
void gsn_case_yaml_upgrade(char **text);

/* The case's name: its file name without the .yaml (or .yml) ending, e.g.
 * "slope_I" for geometries/slope_I.yaml; names the output folder and the
 * .pvd. */
void gsn_case_name(const char *path, char *out, size_t size);

/* The inputs of pre as one line (geometry, spacing, facet points): pre's
 * output is up to date when the model it wrote carries the same line and
 * is newer than the geometry file. */
int gsn_case_pre_signature(const struct gsn_case *c, char *out, size_t size);

/* The case at another resolution (geoscni converge): particles.spacing
 * and every refinement's spacing times factor, and a fixed time step with
 * them (the stable step scales with the spacing); the refinements' zones
 * (boxes, distances, widths) are the geometry's and stay. */
void gsn_case_scale_spacing(struct gsn_case *c, double factor);

/* The unit vector against gravity; 0 (and up zero) without gravity. */
int gsn_up(const struct gsn_case *c, double up[3]);

/* Two orthonormal horizontal axes (normal to gravity): the coordinate axis
 * least along up made normal to it, and up x that. */
void gsn_plan_axes(const struct gsn_case *c, double e[2][3]);

/* What gsn_water_table_prepare found of water.table's points. */
enum gsn_water_shape {
    GSN_WATER_SECTION = 0, /* along one line in plan, in order */
    GSN_WATER_SURFACE,     /* spread: triangulated */
    GSN_WATER_STACKED,     /* all at one place in plan */
    GSN_WATER_BACKWARDS,   /* on one line, point *bad out of order */
    GSN_WATER_TWICE        /* spread, point *bad at an earlier one's place */
};

/* Makes the table of c->water.points ready (its triangles when spread)
 * and says what it is; the last three shapes are errors. */
int gsn_water_table_prepare(struct gsn_case *c, int *bad);

/* The water table's pore pressure u at position x (Pa, compression
 * positive; 0 above the table or without water:), and the table's height
 * above x's place and x's own height (m, along -gravity). */
double gsn_water_pressure(const struct gsn_case *c, const double x[3]);
double gsn_water_table_height(const struct gsn_case *c, const double x[3]);
double gsn_height(const struct gsn_case *c, const double x[3]);

/* The slowest wave speed over the case's materials (m/s): shear waves
 * sqrt(mu / rho) (shear 1) or P waves sqrt((K + 4 mu / 3) / rho) (0);
 * the period and transit times of the body's response. */
double gsn_case_slowest_wave(const struct gsn_case *c, int shear);

/* Whether reference-configuration updates are on when the case file does
 * not say: with large kinematics and nodal integration, except with MSCNI,
 * whose sub-cells stiffen under plastic flow on an updated reference, and
 * with damage, which sums |d eps| (seed paper eq. (7)) and so the noise of
 * each new discretization: on the coarse Slope I 51% of the particles end
 * with damage above 0.1 with updates, 31% without (docs/solver.md,
 * "Reference-configuration updates"). */
int gsn_case_reference_update_default(const struct gsn_case *c);

/* Index into c->materials of the material of a gmsh physical volume, or -1
 * (material: gives every volume its one material: 0). */
int gsn_case_find_material(const struct gsn_case *c, const char *volume);

/* Writes a warning for each value that is legal but implausible for soil,
 * with the unit mistake it likely is (a density of 1.88, t/m^3 for kg/m^3;
 * moduli in kPa or MPa for Pa; swapped moduli): "warning: FILE:LINE:
 * ...". Returns the number of warnings. */
int gsn_case_warn_implausible(const struct gsn_case *c, FILE *out);

/* Index of a boundary entry by surface name, or -1. */
int gsn_case_find_boundary(const struct gsn_case *c, const char *name);

/* The word of a NULL-terminated list closest to word (edit distance at most
 * a third of its length, or 2), or NULL: the case file's did-you-mean, for
 * names checked elsewhere (pre: the geometry's surfaces). */
const char *gsn_closest_word(const char *word, const char *const words[]);

const char *gsn_integration_name(enum gsn_integration integration);
const char *gsn_stabilization_name(enum gsn_stabilization stabilization);

#ifdef __cplusplus
}
#endif
#endif
