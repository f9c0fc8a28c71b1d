#pragma once
// The parameters of the coverage stage (pipeline/coverage_stage.hpp) and the keys of
// [coverage].
#include <vector>

#include "core/config_key.hpp"

namespace tlsmon {

struct CoverageConfig {
    double margin = 1.0;            // m: the reference's bounding box grown on every side
    double min_inside_share = 0.0;  // 0..1: a smaller share inside -> rejected (0 = never)
};

// The keys of [coverage] (core/config_key.hpp).
std::vector<SectionKey<CoverageConfig>> coverage_keys();

}  // namespace tlsmon
