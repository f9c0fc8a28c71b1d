#pragma once
// The stages a site runs, in the order of the data flow. Adding a stage: its files (a class
// with the Stage contract, pipeline/stage.hpp), one line here, its section in
// docs/pipeline.md.
#include "pipeline/epoch_pipeline.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

// coverage -> registration -> m3c2 (enabled, with zones) -> keypoints (enabled, with zones
// or bands) -> thermal (enabled).
StageList site_stages(const PipelineConfig& config);

}  // namespace tlsmon
