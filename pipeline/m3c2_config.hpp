#pragma once
// What the M3C2 stage needs of the site: the method's parameters ([m3c2], docs/configuration.md;
// their defaults are the kernel's, algorithms/m3c2/parameters.hpp) and the zones whose core
// points it aggregates.
#include <vector>

#include "algorithms/m3c2/parameters.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"

namespace tlsmon {

struct M3c2Config : m3c2::Parameters {
    bool enabled = true;  // runs when there is at least one zone
    std::vector<ZoneShape> zones;
};

// The keys of [m3c2] (core/config_key.hpp).
std::vector<SectionKey<M3c2Config>> m3c2_keys();

}  // namespace tlsmon
