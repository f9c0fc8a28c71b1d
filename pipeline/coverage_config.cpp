#include "pipeline/coverage_config.hpp"

namespace tlsmon {

std::vector<SectionKey<CoverageConfig>> coverage_keys() {
    using K = Keys<CoverageConfig>;
    return {
        K::number(&CoverageConfig::margin, "margin", 0, 1000, "m",
                  "The reference epoch's bounding box is grown by this on every side before the "
                  "share of an epoch's points inside it is counted."),
        K::number(&CoverageConfig::min_inside_share, "min_inside_share", 0, 1, "",
                  "An epoch with a smaller share of its points inside the grown box is rejected "
                  "before any analysis (the scanner turned, the scan is cut short, a file of "
                  "another station). 0: never rejected; the share is stored either way."),
    };
}

}  // namespace tlsmon
