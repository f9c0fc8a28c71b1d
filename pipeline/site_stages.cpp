#include "pipeline/site_stages.hpp"

#include <memory>

#include "pipeline/coverage_stage.hpp"
#include "pipeline/keypoint_stage.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "pipeline/primitive_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/thermal_stage.hpp"
#include "pipeline/vector_stage.hpp"

namespace tlsmon {

StageList site_stages(const PipelineConfig& config) {
    StageList stages;
    // Does the epoch cover the reference's extent?
    stages.push_back(std::make_shared<CoverageStage>(config.coverage));
    // Its datum: targets, ICP on stable regions, the reference's own frame, or none.
    stages.push_back(std::make_shared<RegistrationStage>(config.registration));
    // Change along the surface normal at the core points.
    if (config.m3c2.enabled && !config.m3c2.zones.empty())
        stages.push_back(std::make_shared<M3c2Stage>(config.m3c2));
    // Change along the normal of each patch of plane (the reference's supervoxels).
    if (config.pbm3c2.enabled && !config.pbm3c2.zones.empty())
        stages.push_back(std::make_shared<PbM3c2Stage>(config.pbm3c2));
    // The change of the primitives (a round pier's axis, a plane, a sphere) the zones name.
    if (config.primitives.enabled && !config.primitives.zones.empty())
        stages.push_back(std::make_shared<PrimitivesStage>(config.primitives));
    // A 3-D vector per patch of plane: each registered on its own (heights and intensities).
    if (config.vectors.enabled && !config.vectors.zones.empty())
        stages.push_back(std::make_shared<VectorStage>(config.vectors));
    // Movement along the surface from the intensity images.
    const KeypointConfig& kp = config.keypoints;
    if (kp.enabled && (kp.segments == KeypointSegments::bands || !kp.zones.empty()))
        stages.push_back(std::make_shared<KeypointStage>(kp));
    // The thermal response of the zone quantities above, and what is left of them.
    if (config.thermal.enabled) stages.push_back(std::make_shared<ThermalStage>(config.thermal));
    return stages;
}

}  // namespace tlsmon
