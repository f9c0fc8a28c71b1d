#pragma once
// What the primitives stage needs of the site (docs/primitives.md): the zones that name a
// primitive (`primitive = "cylinder"` in a [[zone]]), the parameters of [primitives] for the
// coarse step (RANSAC on a thinned sample with normals) and the fine step (the weighted
// adjustment on every point, algorithms/primitives/primitive_fit.hpp), the test level, and
// the scanner's stochastic model of [station].
#include <vector>

#include "algorithms/primitives/primitive_fit.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon {

struct PrimitiveZone {
    ZoneShape shape;
    primitives::Kind kind = primitives::Kind::cylinder;
};

struct PrimitivesConfig {
    bool enabled = true;             // runs when enabled, with at least one zone naming a primitive
    double sample_voxel = 0.05;      // m, RANSAC's sample: one point per cube
    double normal_radius = 0.15;     // m, the sample's normals
    double ransac_threshold = 0.02;  // m
    int ransac_iterations = 2000;
    double band = 0.05;               // m
    double max_incidence_deg = 75.0;  // °
    double clip_k = 3.5;
    int min_points = 500;
    double alpha = 0.05;
    int threads = 0;
    std::vector<PrimitiveZone> zones;  // set from the [[zone]] tables by pipeline_config
    ScannerNoise noise;                // set from [station] by pipeline_config

    primitives::FitParameters fit_parameters() const;
};

// The keys of [primitives] (core/config_key.hpp).
std::vector<SectionKey<PrimitivesConfig>> primitives_keys();

}  // namespace tlsmon
