#pragma once
// Stage "coverage": does the epoch cover the part of the site the reference epoch covers?
// A scanner turned off its aim, a scan cut short or a file of another station gives points
// that mostly lie outside the reference's extent. The share inside is stored with every
// epoch; with `min_inside_share` set, an epoch below it is rejected before any analysis.
// The reference's extent is the first product of the reference cache.
#include <string>
#include <string_view>

#include "algorithms/extent.hpp"
#include "pipeline/coverage_config.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

// The reference's extent, as kept in the reference cache.
struct ReferenceExtent {
    static constexpr const char* kStage = "coverage.extent";
    static constexpr int kFormatVersion = 1;

    BoundingBox box;
    std::uint64_t points = 0;

    std::string encode() const;
    static ReferenceExtent decode(std::string_view payload);
};

class CoverageStage final : public ReferenceStage<ReferenceExtent> {
  public:
    explicit CoverageStage(CoverageConfig config) : config_(config) {}
    const char* name() const override { return "coverage"; }
    // The extent depends on nothing but the reference's points.
    std::string reference_parameters() const override { return ""; }
    ReferenceExtent prepare_reference(const std::vector<Scan>& reference_scans) const override;
    StageVerdict measure(StageContext& ctx, const ReferenceExtent& reference) const override;

  private:
    CoverageConfig config_;
};

}  // namespace tlsmon
