#include "daemon/http/campaign_api.hpp"

#include <array>
#include <cmath>

#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

template <class T>
Json or_null(const std::optional<T>& v) {
    return v ? Json(*v) : Json(nullptr);
}

// The campaign's own row: what the list shows, and with `whole` what its page shows besides.
Json campaign_row_json(const CampaignRow& c, bool whole) {
    Json j{{"id", c.id},
           {"acquired", time_or_null(c.acquired)},
           {"instrument", c.instrument},
           {"kind", c.kind},
           {"points", c.points},
           {"coarse", c.coarse},
           {"coarse_planes", or_null(c.coarse_planes)},
           {"segments", c.segments},
           {"registered_segments", c.registered_segments},
           {"segments_differ", or_null(c.segments_differ)},
           {"test_p", or_null(c.test_p)},
           {"alpha", c.alpha},
           {"c2c_mean_m", or_null(c.c2c_mean)},
           {"c2c_p95_m", or_null(c.c2c_p95)}};
    if (!whole) return j;
    j["added"] = time_or_null(c.added);
    j["file"] = c.file_path;
    j["sha256"] = c.sha256;
    j["reference_epoch"] = c.reference_epoch;
    j["ground_points"] = c.ground_points;
    j["global_pairs"] = c.global_pairs;
    j["global_rmse_m"] = c.global_rmse;
    j["test_statistic"] = or_null(c.test_statistic);
    j["test_dof"] = or_null(c.test_dof);
    j["c2c_sigma_m"] = or_null(c.c2c_sigma);
    j["c2c_median_m"] = or_null(c.c2c_median);
    j["frame"] = c.frame ? Json(*c.frame) : Json(nullptr);
    j["seconds"] = c.seconds;
    return j;
}

Json triple(const std::array<std::optional<double>, 3>& v) {
    return Json::array({or_null(v[0]), or_null(v[1]), or_null(v[2])});
}

Json segment_json(const CampaignSegmentRow& s, double alpha) {
    const auto& p = s.parameters;
    const auto& sp = s.sigmas;
    return Json{{"segment", s.segment},
                {"class", s.kind},
                {"points", s.points},
                {"outcome", s.outcome},
                {"reference_segment", or_null(s.reference_segment)},
                {"centroid", s.centroid[0] ? triple(s.centroid) : Json(nullptr)},
                // Translations (m) and rotations (rad), null where not observed.
                {"t", triple({p[3], p[4], p[5]})},
                {"sigma_t", triple({sp[3], sp[4], sp[5]})},
                {"r", triple({p[0], p[1], p[2]})},
                {"sigma_r", triple({sp[0], sp[1], sp[2]})},
                {"test_p", or_null(s.test_p)},
                {"differs", s.test_p ? Json(*s.test_p < alpha) : Json(nullptr)},
                {"c2c_mean_m", or_null(s.c2c_mean)},
                {"c2c_p95_m", or_null(s.c2c_p95)}};
}

// Rounded to 0.1 mm: what a drawing needs, a third of the text.
double rounded(double v) {
    return std::round(v * 1e4) / 1e4;
}

}  // namespace

Json campaigns_json(const EpochDatabase& db, const TimeRange& range) {
    Json out = Json::array();
    for (const auto& c : db.campaigns().in_range(range)) out.push_back(campaign_row_json(c, false));
    return out;
}

std::optional<Json> campaign_json(const EpochDatabase& db, CampaignId id) {
    const auto c = db.campaigns().get(id);
    if (!c) return std::nullopt;
    Json segments = Json::array();
    for (const auto& s : db.campaigns().segments(id)) segments.push_back(segment_json(s, c->alpha));
    return Json{{"campaign", campaign_row_json(*c, true)}, {"segments", std::move(segments)}};
}

std::optional<Json> campaign_points_json(const EpochDatabase& db, CampaignId id, std::size_t most,
                                         std::string& why) {
    if (!db.campaigns().get(id)) {
        why = "no campaign " + std::to_string(id);
        return std::nullopt;
    }
    const auto points = db.campaigns().points(id);
    if (!points) {
        why = "campaign " + std::to_string(id) + " kept no points";
        return std::nullopt;
    }
    const auto a = points->columns();
    const std::size_t n = points->size();
    const std::size_t step =
        std::max<std::size_t>(1, (n + most - 1) / std::max<std::size_t>(most, 1));
    Json x = Json::array(), y = Json::array(), z = Json::array(), segment = Json::array(),
         c2c = Json::array();
    for (std::size_t i = 0; i < n; i += step) {
        x.push_back(rounded((*a[0])[i]));
        y.push_back(rounded((*a[1])[i]));
        z.push_back(rounded((*a[2])[i]));
        segment.push_back(std::int64_t((*a[3])[i]));
        const double dx = (*a[4])[i], dy = (*a[5])[i], dz = (*a[6])[i];
        c2c.push_back(std::isfinite(dx) ? Json(rounded(std::sqrt(dx * dx + dy * dy + dz * dz)))
                                        : Json(nullptr));
    }
    const std::size_t shown = x.size();
    return Json{{"campaign", id},
                {"origin", Json::array({points->origin[0], points->origin[1], points->origin[2]})},
                {"spacing_m", points->spacing},
                {"total", n},
                {"shown", shown},
                {"x", std::move(x)},
                {"y", std::move(y)},
                {"z", std::move(z)},
                {"segment", std::move(segment)},
                {"c2c_m", std::move(c2c)}};
}

}  // namespace tlsmon
