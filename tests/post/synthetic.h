/* A synthetic run folder for the post tests: a box of tetrahedra on a
 * lattice (model.h5), frames of known analytic fields (results.h5) and a
 * history.csv with a footing pushed down at a prescribed velocity. */
#ifndef GEOSCNI_TESTS_POST_SYNTHETIC_H
#define GEOSCNI_TESTS_POST_SYNTHETIC_H

#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/model.h"
#include "geoscni/results.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Lattice points per direction and their spacing (m): a 4 x 1.5 x 1.6 box. */
enum { SYNTHETIC_NX = 6, SYNTHETIC_NY = 4, SYNTHETIC_NZ = 5 };
static const double SYNTHETIC_SPACING[3] = {0.8, 0.5, 0.4};
static const double SYNTHETIC_FRAME_INTERVAL = 0.5; /* s between frames */

static int synthetic_index(int i, int j, int k)
{
    return i + SYNTHETIC_NX * (j + SYNTHETIC_NY * k);
}

/* model.h5: lattice points, each cube cut into 6 tetrahedra around its main
 * diagonal (Kuhn), no facets or surfaces (post does not read them). */
static int synthetic_model_write(const char *folder, const struct gsn_case *c)
{
    const int n = SYNTHETIC_NX * SYNTHETIC_NY * SYNTHETIC_NZ;
    const int cubes =
        (SYNTHETIC_NX - 1) * (SYNTHETIC_NY - 1) * (SYNTHETIC_NZ - 1);
    struct gsn_model m;
    GSN_CALL(gsn_model_allocate(&m, n, 0, 0, 0, 0, 6 * cubes));
    for (int k = 0; k < SYNTHETIC_NZ; ++k)
        for (int j = 0; j < SYNTHETIC_NY; ++j)
            for (int i = 0; i < SYNTHETIC_NX; ++i) {
                int p = synthetic_index(i, j, k);
                m.position[3 * p] = SYNTHETIC_SPACING[0] * i;
                m.position[3 * p + 1] = SYNTHETIC_SPACING[1] * j;
                m.position[3 * p + 2] = SYNTHETIC_SPACING[2] * k;
                m.volume[p] = SYNTHETIC_SPACING[0] * SYNTHETIC_SPACING[1] *
                              SYNTHETIC_SPACING[2];
            }
    /* The six paths from corner 000 to 111 along the cube's edges. */
    static const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                    {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int t = 0;
    for (int k = 0; k + 1 < SYNTHETIC_NZ; ++k)
        for (int j = 0; j + 1 < SYNTHETIC_NY; ++j)
            for (int i = 0; i + 1 < SYNTHETIC_NX; ++i)
                for (int p = 0; p < 6; ++p, ++t) {
                    int corner[3] = {i, j, k};
                    m.tetrahedra[4 * t] = synthetic_index(i, j, k);
                    for (int s = 0; s < 3; ++s) {
                        ++corner[paths[p][s]];
                        m.tetrahedra[4 * t + 1 + s] =
                            synthetic_index(corner[0], corner[1], corner[2]);
                    }
                }
    char path[GSN_PATH_SIZE];
    int rc = gsn_path_join(path, sizeof path, folder, "model.h5");
    if (rc == GSN_OK)
        rc = gsn_model_write(path, &m, c);
    gsn_model_free(&m);
    return rc;
}

/* The analytic fields of frame time t at reference position X. Displacement:
 * a stretch diag(1 + 0.1 t, 1, 1 - 0.05 t) then a rotation by 0.2 t about
 * z, minus X. The others are smooth functions of X and t. */
static void synthetic_fields(const double *X, double t, double *u, double *v,
                             double *stress, double *damage, double *plastic,
                             double *equivalent)
{
    double theta = 0.2 * t, c = cos(theta), s = sin(theta);
    double stretched[3] = {(1.0 + 0.1 * t) * X[0], X[1],
                           (1.0 - 0.05 * t) * X[2]};
    u[0] = c * stretched[0] - s * stretched[1] - X[0];
    u[1] = s * stretched[0] + c * stretched[1] - X[1];
    u[2] = stretched[2] - X[2];
    v[0] = 0.1 * X[1];
    v[1] = -0.2 * X[0];
    v[2] = 0.01 * t;
    stress[0] = -1e5 * (1.0 + X[2]) * t;
    stress[1] = 2e4 * X[0];
    stress[2] = -5e4 * t;
    stress[3] = 1e3 * X[1];
    stress[4] = -2e3 * t;
    stress[5] = 3e3 * X[0] * X[2];
    *damage = fmin(1.0, 0.5 * t * X[0] / 4.0 * exp(-X[2]));
    *plastic = 0.02 * t * X[2];
    /* sqrt(3/2) ||dev sigma||, tensor shear counted twice. */
    double p = (stress[0] + stress[1] + stress[2]) / 3.0;
    double d = 0.0;
    for (int a = 0; a < 3; ++a)
        d += (stress[a] - p) * (stress[a] - p);
    for (int a = 3; a < 6; ++a)
        d += 2.0 * stress[a] * stress[a];
    *equivalent = sqrt(1.5 * d);
}

/* results.h5 with frames frames of particle_count particles (the model's
 * count unless a mismatch is wanted); case_name NULL leaves the attribute
 * out. */
static int synthetic_results_write(const char *folder, const struct gsn_case *c,
                                   int frames, int particle_count,
                                   const char *case_name)
{
    char path[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, folder, "results.h5"));
    char *yaml = NULL;
    GSN_CALL(gsn_case_to_yaml_string(c, &yaml));
    hid_t file = H5I_INVALID_HID;
    int rc = gsn_h5_create(path, GSN_FILE_KIND_RESULTS, yaml, &file);
    free(yaml);
    GSN_CALL(rc);
    if (case_name)
        GSN_CALL_GOTO(gsn_h5_attr_write_string(file, GSN_RESULTS_ATTR_CASE_NAME,
                                               case_name),
                      rc, done);
    struct gsn_frame frame;
    GSN_CALL_GOTO(gsn_frame_allocate(&frame, particle_count), rc, done);
    for (int f = 0; f < frames && rc == GSN_OK; ++f) {
        frame.time = SYNTHETIC_FRAME_INTERVAL * f;
        frame.step = 500 * f;
        for (int p = 0; p < particle_count; ++p) {
            int i = p % SYNTHETIC_NX, j = p / SYNTHETIC_NX % SYNTHETIC_NY;
            int k = p / (SYNTHETIC_NX * SYNTHETIC_NY);
            double X[3] = {SYNTHETIC_SPACING[0] * i, SYNTHETIC_SPACING[1] * j,
                           SYNTHETIC_SPACING[2] * k};
            synthetic_fields(
                X, frame.time, frame.field[GSN_FRAME_DISPLACEMENT] + 3 * p,
                frame.field[GSN_FRAME_VELOCITY] + 3 * p,
                frame.field[GSN_FRAME_STRESS] + 6 * p,
                frame.field[GSN_FRAME_DAMAGE] + p,
                frame.field[GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN] + p,
                frame.field[GSN_FRAME_EQUIVALENT_STRESS] + p);
        }
        rc = gsn_results_frame_write(file, f, &frame);
    }
    gsn_frame_free(&frame);
done:
    gsn_h5_close(&file);
    return rc;
}

/* history.csv (units after the column names, as solve writes it): the
 * footing moves down at 0.01 m/s pushing the body with a force that grows
 * and levels off, which the bottom carries; the energies are smooth
 * functions of time. */
static int synthetic_history_write(const char *folder, int rows)
{
    char path[GSN_PATH_SIZE];
    GSN_CALL(gsn_path_join(path, sizeof path, folder, "history.csv"));
    FILE *file = fopen(path, "w");
    GSN_CHECK(file != NULL, GSN_ERR_IO, "cannot write %s", path);
    fprintf(file, "time_s,step,bottom_ux_m,bottom_uy_m,bottom_uz_m,"
                  "bottom_fx_N,bottom_fy_N,bottom_fz_N,footing_ux_m,"
                  "footing_uy_m,footing_uz_m,footing_fx_N,footing_fy_N,"
                  "footing_fz_N,kinetic_energy_J,internal_energy_J,"
                  "external_work_J,max_damage\n");
    for (int r = 0; r < rows; ++r) {
        double t = 1.5 * r / (rows - 1), settlement = 0.01 * t;
        double force = 4e5 * (1.0 - exp(-settlement / 0.004));
        fprintf(file,
                "%.17g,%d,0,0,0,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                t, 1000 * r, 1e2 * t, -2e2 * t, force, 1e-5 * t, -2e-5 * t,
                -settlement, 3e2 * t, 5e1 * t, -force, 0.5 * 1880 * 9.6 * 1e-4,
                0.8 * force * settlement, 0.9 * force * settlement,
                fmin(1.0, t / 1.5));
    }
    GSN_CHECK(fclose(file) == 0, GSN_ERR_IO, "cannot write %s", path);
    return GSN_OK;
}

/* The whole folder. */
static int synthetic_folder_write(const char *folder, int frames,
                                  const char *case_name)
{
    struct gsn_case *c = calloc(1, sizeof *c);
    GSN_CHECK(c != NULL, GSN_ERR_MEMORY, "cannot allocate a case");
    int rc = gsn_case_load("box.yaml", c);
    if (rc == GSN_OK)
        rc = synthetic_model_write(folder, c);
    if (rc == GSN_OK)
        rc = synthetic_results_write(folder, c, frames,
                                     SYNTHETIC_NX * SYNTHETIC_NY * SYNTHETIC_NZ,
                                     case_name);
    if (rc == GSN_OK)
        rc = synthetic_history_write(folder, 31);
    free(c);
    return rc;
}

#endif
