#include "pipeline/coverage_stage.hpp"

#include <fmt/format.h>

#include <limits>

#include "core/payload.hpp"

namespace tlsmon {

namespace {

std::uint64_t point_count(const std::vector<Scan>& scans) {
    std::uint64_t n = 0;
    for (const auto& s : scans) n += s.size();
    return n;
}

// The share of all points of a multi-scan file inside the grown box.
double share_inside(const std::vector<Scan>& scans, const BoundingBox& box, double margin) {
    double inside = 0;
    for (const auto& s : scans) {
        if (!s.xyz.empty()) inside += share_inside(s.xyz, box, margin) * double(s.size());
    }
    const auto n = point_count(scans);
    return n == 0 ? std::numeric_limits<double>::quiet_NaN() : inside / double(n);
}

}  // namespace

std::string ReferenceExtent::encode() const {
    PayloadWriter w;
    for (int k = 0; k < 3; ++k) w.put(box.min[k]);
    for (int k = 0; k < 3; ++k) w.put(box.max[k]);
    w.put(points);
    return w.take();
}

ReferenceExtent ReferenceExtent::decode(std::string_view payload) {
    PayloadReader r(payload);
    ReferenceExtent e;
    for (int k = 0; k < 3; ++k) e.box.min[k] = r.get<double>();
    for (int k = 0; k < 3; ++k) e.box.max[k] = r.get<double>();
    e.points = r.get<std::uint64_t>();
    r.finish();
    return e;
}

ReferenceExtent CoverageStage::prepare_reference(const std::vector<Scan>& reference_scans) const {
    ReferenceExtent e;
    for (const auto& s : reference_scans) {
        for (const auto& p : s.xyz) e.box.extend(p);
    }
    e.points = point_count(reference_scans);
    return e;
}

StageVerdict CoverageStage::measure(StageContext& ctx, const ReferenceExtent& reference) const {
    const double inside_share = share_inside(*ctx.input.scans, reference.box, config_.margin);
    StageVerdict verdict;
    verdict.note =
        fmt::format("{:.1f} % of the points inside the reference extent", 100 * inside_share);
    if (!(inside_share >= config_.min_inside_share)) {
        verdict.rejected = fmt::format(
            "only {:.1f} % of the points lie within the reference epoch's extent (grown by {} m; "
            "at least {:.1f} % required): the scanner may have turned, or the scan is cut short",
            100 * inside_share, config_.margin, 100 * config_.min_inside_share);
    }
    return verdict;
}

}  // namespace tlsmon
