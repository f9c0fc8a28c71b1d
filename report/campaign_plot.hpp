#pragma once
// The segments' parameters of a campaign comparison drawn as the segment-based study draws
// them: each segment's translation as an arrow from its centroid, in plan (x, y) and in
// elevation (x, z), over a thinned view of the campaign's points. Only what a segment's
// surfaces observe is drawn: a component not observed is left out of its arrow, and a
// segment that observes neither of a view's two directions gets a cross, not an arrow of
// zero. Segments the consistency test sets apart (p < α against the others) are red.
#include <filesystem>
#include <optional>
#include <string>

#include "pipeline/campaign_comparison.hpp"

namespace tlsmon::report {

// Writes `png` (and its data and script beside it in `work`); the reason when gnuplot could
// not draw it, nothing when it did.
std::optional<std::string> draw_segment_parameters(const CampaignComparison& comparison,
                                                   double alpha, const std::filesystem::path& work,
                                                   const std::filesystem::path& png);

}  // namespace tlsmon::report
