/* The HDF5 schema shared by all stages (DESIGN.md, "model.h5 and
 * results.h5"): every dataset by name, type, columns, units and description,
 * defined once here. A file records GSN_SCHEMA_VERSION, its kind, the
 * resolved case, and the code and library versions as root attributes. */
#ifndef GEOSCNI_SCHEMA_H
#define GEOSCNI_SCHEMA_H

#ifdef __cplusplus
extern "C" {
#endif

/* 2 (2026-12-02): model.h5 holds mesh/tetrahedron_face, the checkpoint the
 * reference configuration of the last update (issue 15); 3 (2026-12-03):
 * every dataset carries the CRC-32 of its data (attribute 'crc32') and the
 * metadata the 1.8 format's checksums (issue 19): no damaged file is read
 * unnoticed */
/* 4 (2026-12-03): model.h5 holds the physical volumes (volumes/, the
 * particles' and tetrahedra's; issue 22) */
#define GSN_SCHEMA_VERSION 4
#define GSN_FILE_KIND_MODEL "model"
#define GSN_FILE_KIND_RESULTS "results"

/* Root attribute names. */
#define GSN_ATTR_SCHEMA_VERSION "schema_version"
#define GSN_ATTR_FILE_KIND "file_kind"
#define GSN_ATTR_CASE "case_resolved_yaml"
#define GSN_ATTR_CODE_VERSION "code_version"
#define GSN_ATTR_LIBRARY_VERSIONS "library_versions"
#define GSN_ATTR_UNITS "units"
#define GSN_ATTR_DESCRIPTION "description"
#define GSN_ATTR_CHECKSUM "crc32" /* zlib's CRC-32 of the data (h5io.c) */
#define GSN_ATTR_PRE_SIGNATURE                                                 \
    "pre_inputs" /* model.h5: gsn_case_pre_signature */

enum gsn_h5_type { GSN_H5_DOUBLE, GSN_H5_INT, GSN_H5_STRING };

/* One dataset: rows x columns (columns 1 means a 1D dataset). */
struct gsn_dataset_info {
    const char *path;
    enum gsn_h5_type type;
    int columns;
    const char *units;
    const char *description;
};

/* model.h5, written by pre. Facets are stored once each: normal outward from
 * owner; an interior facet is used by its neighbour with the opposite normal
 * at the same quadrature points. Indices are 0-based.
 * X(id, path, type, columns, units, description) */
#define GSN_MODEL_DATASETS(X)                                                  \
    X(GSN_MODEL_POSITION, "particles/position", GSN_H5_DOUBLE, 3, "m",         \
      "reference position X_I of each particle")                               \
    X(GSN_MODEL_VOLUME, "particles/volume", GSN_H5_DOUBLE, 1, "m^3",           \
      "volume V_L of each nodal domain (Voronoi cell clipped to the body)")    \
    X(GSN_MODEL_CENTROID, "particles/centroid", GSN_H5_DOUBLE, 3, "m",         \
      "centroid of each nodal domain")                                         \
    X(GSN_MODEL_PARTICLE_SURFACE_OFFSET, "particles/surface_offset",           \
      GSN_H5_INT, 1, "1",                                                      \
      "CSR offsets (particle count + 1) into particles/surface")               \
    X(GSN_MODEL_PARTICLE_SURFACE, "particles/surface", GSN_H5_INT, 1, "1",     \
      "index into surfaces/ of every physical surface a particle lies on")     \
    X(GSN_MODEL_FACET_OWNER, "facets/owner", GSN_H5_INT, 1, "1",               \
      "particle whose nodal domain the facet bounds, normal outward from it")  \
    X(GSN_MODEL_FACET_NEIGHBOUR, "facets/neighbour", GSN_H5_INT, 1, "1",       \
      "particle on the other side of the facet, -1 on the body boundary")      \
    X(GSN_MODEL_FACET_SURFACE, "facets/surface", GSN_H5_INT, 1, "1",           \
      "index into surfaces/ of a boundary facet, -1 if none or interior")      \
    X(GSN_MODEL_FACET_AREA, "facets/area", GSN_H5_DOUBLE, 1, "m^2",            \
      "area of the facet")                                                     \
    X(GSN_MODEL_FACET_NORMAL, "facets/normal", GSN_H5_DOUBLE, 3, "1",          \
      "unit normal, outward from the owner's domain")                          \
    X(GSN_MODEL_FACET_POINT_OFFSET, "facets/point_offset", GSN_H5_INT, 1, "1", \
      "CSR offsets (facet count + 1) into facets/point and facets/weight")     \
    X(GSN_MODEL_FACET_POINT, "facets/point", GSN_H5_DOUBLE, 3, "m",            \
      "quadrature points of the facets")                                       \
    X(GSN_MODEL_FACET_WEIGHT, "facets/weight", GSN_H5_DOUBLE, 1, "m^2",        \
      "quadrature weights; they add up to the facet's area")                   \
    X(GSN_MODEL_SURFACE_NAME, "surfaces/name", GSN_H5_STRING, 1, "1",          \
      "gmsh physical surface names")                                           \
    X(GSN_MODEL_SURFACE_TAG, "surfaces/tag", GSN_H5_INT, 1, "1",               \
      "gmsh physical group tag of each surface")                               \
    X(GSN_MODEL_SURFACE_AREA, "surfaces/area", GSN_H5_DOUBLE, 1, "m^2",        \
      "area of each physical surface as gmsh measures it")                     \
    X(GSN_MODEL_TETRAHEDRA, "mesh/tetrahedra", GSN_H5_INT, 4, "1",             \
      "tetrahedra of the gmsh mesh as particle indices: the body's convex "    \
      "pieces and the cells of the pictures")                                  \
    X(GSN_MODEL_TETRAHEDRON_FACE, "mesh/tetrahedron_face", GSN_H5_INT, 4, "1", \
      "what the face opposite vertex k of each tetrahedron lies on: a "        \
      "surface index, -1 inside the body, -2 boundary without a surface")      \
    X(GSN_MODEL_VOLUME_NAME, "volumes/name", GSN_H5_STRING, 1, "1",            \
      "gmsh physical volume names")                                            \
    X(GSN_MODEL_VOLUME_TAG, "volumes/tag", GSN_H5_INT, 1, "1",                 \
      "gmsh physical group tag of each volume")                                \
    X(GSN_MODEL_PARTICLE_VOLUME, "particles/physical_volume", GSN_H5_INT, 1,   \
      "1",                                                                     \
      "index into volumes/ of each particle's volume (on an interface: the "   \
      "one with most of its tetrahedra), -1 in none")                          \
    X(GSN_MODEL_TETRAHEDRON_VOLUME, "mesh/tetrahedron_volume", GSN_H5_INT, 1,  \
      "1", "index into volumes/ of each tetrahedron's volume, -1 in none")

/* One frame of results.h5: a group GSN_FRAME_GROUP_FORMAT with attributes
 * "time" (s) and "step", holding these datasets (one row per particle). */
#define GSN_FRAME_FIELDS(X)                                                    \
    X(GSN_FRAME_DISPLACEMENT, "displacement", GSN_H5_DOUBLE, 3, "m",           \
      "displacement u(X_J) = sum_I Psi_I(X_J) d_I at the particles")           \
    X(GSN_FRAME_VELOCITY, "velocity", GSN_H5_DOUBLE, 3, "m/s",                 \
      "velocity at the particles")                                             \
    X(GSN_FRAME_STRESS, "stress", GSN_H5_DOUBLE, 6, "Pa",                      \
      "Cauchy stress, tension positive, Voigt xx yy zz xy yz xz")              \
    X(GSN_FRAME_DAMAGE, "damage", GSN_H5_DOUBLE, 1, "1",                       \
      "damage zeta of seed eq. (7), 0 intact to 1 failed")                     \
    X(GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN, "equivalent_plastic_strain",        \
      GSN_H5_DOUBLE, 1, "1", "accumulated equivalent plastic strain")          \
    X(GSN_FRAME_EQUIVALENT_STRESS, "equivalent_stress", GSN_H5_DOUBLE, 1,      \
      "Pa", "equivalent stress sqrt(3/2) ||dev sigma||")

#define GSN_FRAMES_GROUP "frames"
#define GSN_FRAME_GROUP_FORMAT "frames/%06d"
#define GSN_FRAME_ATTR_TIME "time"
#define GSN_FRAME_ATTR_STEP "step"
#define GSN_RESULTS_ATTR_FRAME_COUNT "frame_count"
#define GSN_RESULTS_ATTR_CASE_NAME "case_name"
#define GSN_RESULTS_ATTR_COMPLETE "complete" /* 1: the run reached its end */
/* The largest ratio of kinetic to internal energy of a loading run (the
 * quasi-static check); also on the checkpoint, with the time it occurred. */
#define GSN_RESULTS_ATTR_KINETIC_RATIO "kinetic_ratio_max"
#define GSN_CHECKPOINT_ATTR_RATIO_TIME "kinetic_ratio_time"
/* 1: a signal stopped the run (it waits for --restart; results.h5) */
#define GSN_RESULTS_ATTR_INTERRUPTED "interrupted"
/* The energy balance the stability check compares with (checkpoint) */
#define GSN_CHECKPOINT_ATTR_ENERGY_BASELINE "energy_baseline"
/* The inputs a file was made from, as gsn_file_hash texts (files.h), so
 * that run tells an up-to-date stage by contents, not by times: the
 * geometry file of model.h5, the model.h5 of results.h5. */
#define GSN_ATTR_GEOMETRY_HASH "geometry_hash"
#define GSN_RESULTS_ATTR_MODEL_HASH "model_hash"
/* The geostatic stage before the loading one (case key geostatic): its
 * steps, the unbalanced force over the weight it ended with, and its wall
 * time (s) */
#define GSN_RESULTS_ATTR_GEOSTATIC_STEPS "geostatic_steps"
#define GSN_RESULTS_ATTR_GEOSTATIC_RESIDUAL "geostatic_residual"
#define GSN_RESULTS_ATTR_GEOSTATIC_SECONDS "geostatic_seconds"
/* ... the largest displacement at a particle the stage ended with (m), and
 * whether it came to rest (1) or not (0: no rest within the step budget, or
 * displacements that kept growing) */
#define GSN_RESULTS_ATTR_GEOSTATIC_DISPLACEMENT "geostatic_displacement"
#define GSN_RESULTS_ATTR_GEOSTATIC_RESTED "geostatic_rested"

/* The restart checkpoint of results.h5: the group GSN_CHECKPOINT_GROUP with
 * attributes "time" (s) and "step", holding the whole state of the explicit
 * loop (one row per particle). Material state columns are named by the
 * attribute "names" of checkpoint/material_state.
 * X(id, path, type, columns, units, description) */
#define GSN_CHECKPOINT_GROUP "checkpoint"
#define GSN_CHECKPOINT_DATASETS(X)                                             \
    X(GSN_CHECKPOINT_COEFFICIENT_DISPLACEMENT,                                 \
      "checkpoint/coefficient_displacement", GSN_H5_DOUBLE, 3, "m",            \
      "RK coefficients d_I of the displacement (not u(X_I))")                  \
    X(GSN_CHECKPOINT_COEFFICIENT_VELOCITY, "checkpoint/coefficient_velocity",  \
      GSN_H5_DOUBLE, 3, "m/s", "RK coefficients of the velocity")              \
    X(GSN_CHECKPOINT_COEFFICIENT_ACCELERATION,                                 \
      "checkpoint/coefficient_acceleration", GSN_H5_DOUBLE, 3, "m/s^2",        \
      "RK coefficients of the acceleration")                                   \
    X(GSN_CHECKPOINT_DISPLACEMENT_GRADIENT,                                    \
      "checkpoint/displacement_gradient", GSN_H5_DOUBLE, 9, "1",               \
      "H = F - I at the integration points, row-major, accumulated from the "  \
      "increments")                                                            \
    X(GSN_CHECKPOINT_STRESS, "checkpoint/stress", GSN_H5_DOUBLE, 6, "Pa",      \
      "Cauchy stress at the integration points, Voigt xx yy zz xy yz xz")      \
    X(GSN_CHECKPOINT_REACTION, "checkpoint/reaction", GSN_H5_DOUBLE, 3, "N",   \
      "reaction C^T lambda of the constraints' mass-orthogonal projection "    \
      "(0 where it does not reach)")                                           \
    X(GSN_CHECKPOINT_ENERGY, "checkpoint/energy", GSN_H5_DOUBLE, 4, "J",       \
      "kinetic energy, internal energy, external work and damping work (one "  \
      "row)")                                                                  \
    X(GSN_CHECKPOINT_DAMPING_FORCE, "checkpoint/damping_force", GSN_H5_DOUBLE, \
      3, "N", "local damping force of the last step on the coefficients")      \
    X(GSN_CHECKPOINT_MATERIAL_STATE, "checkpoint/material_state",              \
      GSN_H5_DOUBLE, 0, "various",                                             \
      "state variables of the material model at the main integration points "  \
      "(nodal or Gauss points); columns: the model's state size, named by "    \
      "the attribute 'names'")                                                 \
    X(GSN_CHECKPOINT_REFERENCE_GRADIENT, "checkpoint/reference_gradient",      \
      GSN_H5_DOUBLE, 9, "1",                                                   \
      "F of the reference configuration at the main integration points, "      \
      "row-major: F = (I + H) F_ref")                                          \
    X(GSN_CHECKPOINT_POINT_FAILED, "checkpoint/point_failed", GSN_H5_INT, 1,   \
      "1", "1 where a main integration point has failed (no stress)")

/* The reference configuration of the last update (issue 15) in the
 * checkpoint: positions, and the body's tetrahedra where they were made
 * again; attributes with the update count, time, step and the kinetic
 * energy the updates added. */
#define GSN_CHECKPOINT_REFERENCE_DATASETS(X)                                   \
    X(GSN_CHECKPOINT_REFERENCE_POSITION, "checkpoint/reference_position",      \
      GSN_H5_DOUBLE, 3, "m",                                                   \
      "particle positions of the reference configuration of the last update")  \
    X(GSN_CHECKPOINT_BODY_TETRAHEDRA, "checkpoint/body_tetrahedra",            \
      GSN_H5_INT, 4, "1",                                                      \
      "the body's tetrahedra as particle indices, where made again")           \
    X(GSN_CHECKPOINT_BODY_FACE, "checkpoint/body_face", GSN_H5_INT, 4, "1",    \
      "what each face of the body's tetrahedra lies on, as "                   \
      "mesh/tetrahedron_face")                                                 \
    X(GSN_CHECKPOINT_RELEASE_FORCE, "checkpoint/release_force", GSN_H5_DOUBLE, \
      3, "N",                                                                  \
      "the force the last update left unbalanced, at full value, on the "      \
      "coefficients (0 once released)")
#define GSN_CHECKPOINT_ATTR_UPDATES "reference_updates"
#define GSN_CHECKPOINT_ATTR_REFERENCE_TIME "reference_time"
#define GSN_CHECKPOINT_ATTR_REFERENCE_STEP "reference_step"
#define GSN_CHECKPOINT_ATTR_UPDATE_ENERGY "reference_update_energy"
#define GSN_CHECKPOINT_ATTR_REMESHES "body_remeshes"
/* The release of the last update's unbalanced force: its start step, its
 * length in steps, the present factor, and the work of the released forces
 * so far (J); absent in checkpoints of before 2026-12-04, which had none */
#define GSN_CHECKPOINT_ATTR_RELEASE_START "release_start"
#define GSN_CHECKPOINT_ATTR_RELEASE_STEPS "release_steps"
#define GSN_CHECKPOINT_ATTR_RELEASE_FACTOR "release_factor"
#define GSN_CHECKPOINT_ATTR_RELEASE_WORK "release_work"
/* Deferred updates (their count, the run of them since the last update and
 * the step of the last attempt): absent in checkpoints of before 2026-12-03,
 * which had none */
#define GSN_CHECKPOINT_ATTR_DEFERRED "reference_deferred"
/* 1: the frame of the checkpoint's step is due but not written (a run
 * stopped for want of room before it); a restart writes it first */
#define GSN_CHECKPOINT_ATTR_FRAME_DUE "frame_due"
#define GSN_CHECKPOINT_ATTR_DEFERRED_RUN "reference_deferred_run"
#define GSN_CHECKPOINT_ATTR_ATTEMPT_STEP "reference_attempt_step"
/* The clock: the run's first time step, the present one (an update may
 * change it) and the time and step where it began (s, s, s, -) */
#define GSN_CHECKPOINT_ATTR_TIME_STEP_FIRST "time_step_first"
#define GSN_CHECKPOINT_ATTR_TIME_STEP "time_step"
#define GSN_CHECKPOINT_ATTR_TIME_BASE "time_base"
#define GSN_CHECKPOINT_ATTR_STEP_BASE "step_base"
/* How the essential boundaries were imposed (GSN_CHECKPOINT_BOUNDARIES): a
 * checkpoint without it was written before 2026-12-02 evening, with the
 * boundary term and reactions on B_c only, and cannot be continued. */
#define GSN_CHECKPOINT_ATTR_BOUNDARIES "boundaries"
#define GSN_CHECKPOINT_BOUNDARIES 2 /* held facets, mass-orthogonal */

#define GSN_DATASET_ENUM(id, path, type, columns, units, description) id,
enum gsn_model_dataset {
    GSN_MODEL_DATASETS(GSN_DATASET_ENUM) GSN_MODEL_DATASET_COUNT
};
enum gsn_frame_field {
    GSN_FRAME_FIELDS(GSN_DATASET_ENUM) GSN_FRAME_FIELD_COUNT
};
enum gsn_checkpoint_dataset {
    GSN_CHECKPOINT_DATASETS(GSN_DATASET_ENUM) GSN_CHECKPOINT_DATASET_COUNT
};
enum gsn_checkpoint_reference_dataset {
    GSN_CHECKPOINT_REFERENCE_DATASETS(GSN_DATASET_ENUM)
        GSN_CHECKPOINT_REFERENCE_DATASET_COUNT
};
#undef GSN_DATASET_ENUM

extern const struct gsn_dataset_info
    gsn_model_datasets[GSN_MODEL_DATASET_COUNT];
extern const struct gsn_dataset_info gsn_frame_fields[GSN_FRAME_FIELD_COUNT];
extern const struct gsn_dataset_info
    gsn_checkpoint_datasets[GSN_CHECKPOINT_DATASET_COUNT];
extern const struct gsn_dataset_info
    gsn_checkpoint_reference_datasets[GSN_CHECKPOINT_REFERENCE_DATASET_COUNT];

#ifdef __cplusplus
}
#endif
#endif
