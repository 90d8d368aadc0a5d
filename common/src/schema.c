/* The dataset tables of schema.h. */
#include "geoscni/schema.h"

#define GSN_DATASET_ROW(id, path, type, columns, units, description)           \
    {path, type, columns, units, description},

const struct gsn_dataset_info gsn_model_datasets[GSN_MODEL_DATASET_COUNT] = {
    GSN_MODEL_DATASETS(GSN_DATASET_ROW)};

const struct gsn_dataset_info gsn_frame_fields[GSN_FRAME_FIELD_COUNT] = {
    GSN_FRAME_FIELDS(GSN_DATASET_ROW)};

const struct gsn_dataset_info
    gsn_checkpoint_datasets[GSN_CHECKPOINT_DATASET_COUNT] = {
        GSN_CHECKPOINT_DATASETS(GSN_DATASET_ROW)};

const struct gsn_dataset_info
    gsn_checkpoint_reference_datasets[GSN_CHECKPOINT_REFERENCE_DATASET_COUNT] =
        {GSN_CHECKPOINT_REFERENCE_DATASETS(GSN_DATASET_ROW)};
