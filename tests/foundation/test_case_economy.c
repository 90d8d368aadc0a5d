/* The economy keys of the case file (docs/economy.md): boundary
 * symmetry, particles.refine, output.times, output.fields and
 * output.mirror land in the
 * struct, their defaults are the named constants, the resolved YAML reads
 * back to the same values bit for bit, and a refinement changes pre's
 * signature (a graded model is not mistaken for a uniform one). The
 * malformed variants are in cases/bad/ with their messages. */
#include "case_testing.h"
#include "geoscni/case.h"
#include "geoscni/error.h"
#include "geoscni/schema.h"
#include "testing.h"

#include <string.h>

static void check_economy(const struct gsn_case *c)
{
    TEST_INT(c->refinement_count, 2);
    const struct gsn_refinement *box = &c->refinements[0];
    const struct gsn_refinement *top = &c->refinements[1];
    TEST_INT(box->kind, GSN_REFINE_BOX);
    const double corners[6] = {0, 0, 0.5, 1, 1, 1};
    for (int k = 0; k < 6; ++k)
        TEST_NEAR(box->box[k], corners[k], 0.0);
    TEST_NEAR(box->spacing, 0.1, 0.0);
    TEST_NEAR(box->distance, GSN_DEFAULT_REFINE_BOX_DISTANCE, 0.0);
    TEST_INT(top->kind, GSN_REFINE_SURFACE);
    TEST_TRUE(strcmp(top->surface, "top") == 0);
    TEST_NEAR(top->spacing, 0.05, 0.0);
    TEST_NEAR(top->distance, 0.4, 0.0);
    TEST_NEAR(top->width, 0.2, 0.0);
    TEST_NEAR(box->width, 0.0, 0.0);
    int cut = gsn_case_find_boundary(c, "cut");
    TEST_INT(cut, 1);
    if (cut == 1) {
        TEST_INT(c->boundaries[cut].symmetry, 1);
        /* the normal component is resolved on the model, not here */
        TEST_INT(c->boundaries[cut].fixed[0] + c->boundaries[cut].fixed[1] +
                     c->boundaries[cut].fixed[2],
                 0);
    }
    TEST_INT(c->boundaries[0].symmetry, 0);
    TEST_INT(c->output_fields, (1u << GSN_FRAME_STRESS) |
                                   (1u << GSN_FRAME_DISPLACEMENT) |
                                   (1u << GSN_FRAME_DAMAGE));
    TEST_TRUE(strcmp(c->output_mirror, "cut") == 0);
    /* frames every 0.5 s and at the two listed times */
    TEST_NEAR(c->output_every, 0.5, 0.0);
    TEST_INT(c->output_time_count, 2);
    TEST_NEAR(c->output_times[0], 0.25, 0.0);
    TEST_NEAR(c->output_times[1], 1.2, 0.0);
}

int main(void)
{
    test_begin();
    static struct gsn_case c, again, plain;
    int rc = gsn_case_load("cases/economy.yaml", &c);
    if (rc != GSN_OK)
        gsn_error_print(stderr);
    TEST_INT(rc, GSN_OK);
    check_economy(&c);
    TEST_INT(c.refinements[1].line, 8); /* the line of the surface entry */

    /* Round trip through the resolved YAML. */
    round_trip(&c, &again);
    check_economy(&again);
    for (int i = 0; i < 2; ++i) {
        again.refinements[i].line = c.refinements[i].line;
        TEST_TRUE(memcmp(&c.refinements[i], &again.refinements[i],
                         sizeof c.refinements[i]) == 0);
    }

    /* Defaults: no refinement, every field, no mirror, no symmetry. */
    TEST_INT(gsn_case_load("cases/minimal.yaml", &plain), GSN_OK);
    TEST_INT(plain.refinement_count, 0);
    TEST_INT(plain.output_fields, GSN_DEFAULT_OUTPUT_FIELDS);
    TEST_INT(plain.output_fields, (1u << GSN_FRAME_FIELD_COUNT) - 1);
    TEST_INT(plain.output_mirror[0], '\0');
    TEST_INT(plain.output_time_count, 0);
    TEST_NEAR(plain.output_every, plain.time_end / GSN_DEFAULT_FRAMES, 0.0);

    /* output.times alone: frames at those times only (every = 0), also
     * after a round trip; the default every comes back without times. */
    c.output_every = 0.0;
    round_trip(&c, &again);
    TEST_NEAR(again.output_every, 0.0, 0.0);
    TEST_INT(again.output_time_count, 2);
    TEST_NEAR(again.output_times[1], 1.2, 0.0);
    again.output_time_count = 0;
    round_trip(&again, &plain);
    TEST_NEAR(plain.output_every, plain.time_end / GSN_DEFAULT_FRAMES, 0.0);

    /* pre's signature changes with a refinement's spacing and width. */
    char first[GSN_PRE_SIGNATURE_SIZE], second[GSN_PRE_SIGNATURE_SIZE];
    TEST_INT(gsn_case_pre_signature(&c, first, sizeof first), GSN_OK);
    c.refinements[1].width = 0.3;
    TEST_INT(gsn_case_pre_signature(&c, second, sizeof second), GSN_OK);
    TEST_TRUE(strcmp(first, second) != 0);
    c.refinements[1].spacing = 0.06;
    TEST_INT(gsn_case_pre_signature(&c, first, sizeof first), GSN_OK);
    TEST_TRUE(strcmp(first, second) != 0);
    c.refinement_count = 0;
    TEST_INT(gsn_case_pre_signature(&c, second, sizeof second), GSN_OK);
    TEST_TRUE(strstr(second, "refine") == NULL);
    return test_end("test_case_economy");
}
