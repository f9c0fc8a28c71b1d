#include "pipeline/campaign_epoch.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "pipeline/campaign_zones.hpp"

namespace tlsmon {

namespace {

namespace fs = std::filesystem;

std::optional<double> finite_or_none(double v) {
    return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

// The reference epoch's scan: where the archive put it, else where it was read.
fs::path reference_scan(const EpochDatabase& db, EpochId& id) {
    const auto reference = db.epochs().reference();
    if (!reference)
        throw Error("no reference epoch yet: a campaign is compared with the station's reference");
    id = *reference;
    const auto epoch = db.epochs().find(id);
    if (!epoch) throw Error("the reference epoch " + std::to_string(id) + " is not stored");
    for (const auto& path : {epoch->archive_path.value_or(""), epoch->file_path})
        if (!path.empty() && fs::is_regular_file(path)) return path;
    throw Error("the reference epoch's scan is gone (" +
                epoch->archive_path.value_or(epoch->file_path) + ")");
}

nlohmann::json parameters_json(const CampaignParameters& p) {
    return {{"metric", campaign::metric_name(p.icp.metric)},
            {"c2c", p.c2c == campaign::C2cModel::local_plane ? "local plane" : "nearest point"},
            {"thinning_m", p.thinning},
            {"registration_points", p.registration_points},
            {"remove_ground", p.remove_ground},
            {"verticality_radius_m", p.verticality.radius},
            {"plane_radius_m", p.surface.plane_radius},
            {"max_distance_m", p.surface.max_distance},
            {"min_segment_points", p.min_segment_points},
            {"min_planar_share", p.min_planar_share},
            {"min_overlap", p.min_overlap},
            {"range_sigma_m", p.range_sigma},
            {"cut_distance_m", p.cut_distance},
            {"alpha", p.alpha},
            {"coarse", coarse_name(p.coarse)},
            {"plane_spacing_m", p.planes.spacing},
            {"plane_radius_coarse_m", p.planes.radius}};
}

}  // namespace

std::vector<CampaignSegmentRow> segment_rows(const CampaignComparison& c) {
    std::vector<CampaignSegmentRow> rows;
    for (std::size_t s = 0; s < c.segments.size(); ++s) {
        const auto& r = c.segments[s];
        const auto& t = r.transform;
        const bool registered = t.registered();
        CampaignSegmentRow row;
        row.segment = std::int64_t(s);
        row.kind = campaign::class_name(r.segment.kind);
        row.cluster = r.segment.cluster;
        row.points = std::int64_t(r.segment.points);
        row.voxels = std::int64_t(r.segment.voxels);
        row.outcome = registered || t.points > 0 ? campaign::outcome_name(t.outcome) : "too small";
        if (r.reference.reference >= 0) row.reference_segment = r.reference.reference;
        if (r.reference.sampled > 0) row.reference_overlap = r.reference.overlap;
        row.pairs = std::int64_t(t.pairs);
        row.rank = t.rank();
        row.iterations = t.iterations;
        row.converged = t.converged;
        if (registered) {
            for (int k = 0; k < 3; ++k) row.centroid[k] = t.centroid(k);
            row.cut_fraction = r.cut_fraction;
            row.cut_bias = r.cut_bias;
            row.rmse = t.rmse;
        }
        // Empty where the segment's surfaces do not observe it: there it is the start.
        for (int k = 0; k < 6; ++k) {
            if (!registered || !t.parameter_observed(k)) continue;
            row.parameters[k] = t.parameters(k);
            row.sigmas[k] = std::sqrt(t.covariance(k, k));
        }
        const double T = c.consistency.segment_statistic[s];
        if (std::isfinite(T)) {
            row.test_statistic = T;
            row.test_dof = c.consistency.segment_dof[s];
            row.test_p = c.consistency.segment_p_value[s];
        }
        row.c2c_mean = finite_or_none(r.c2c.mean);
        row.c2c_sigma = finite_or_none(r.c2c.sigma);
        row.c2c_median = finite_or_none(r.c2c.median);
        row.c2c_p95 = finite_or_none(r.c2c.p95);
        row.c2c_max = finite_or_none(r.c2c.max);
        rows.push_back(std::move(row));
    }
    return rows;
}

CampaignRow campaign_row(const CampaignComparison& c, const CampaignParameters& p) {
    CampaignRow row;
    row.points = std::int64_t(c.registered.size());
    row.ground_points = std::int64_t(c.ground.ground_points);
    for (int k = 0; k < 6; ++k) row.global[std::size_t(k)] = c.global.parameters(k);
    row.global_pairs = std::int64_t(c.global.pairs);
    row.global_rmse = c.global.rmse;
    row.segments = std::int64_t(c.segments.size());
    for (const auto& s : c.segments) row.registered_segments += s.transform.registered();
    if (c.consistency.dof > 0) {
        row.test_statistic = c.consistency.statistic;
        row.test_dof = c.consistency.dof;
        row.test_p = c.consistency.p_value;
        row.segments_differ = c.consistency.differ;
    }
    row.alpha = p.alpha;
    row.c2c_mean = finite_or_none(c.c2c_all.mean);
    row.c2c_sigma = finite_or_none(c.c2c_all.sigma);
    row.c2c_median = finite_or_none(c.c2c_all.median);
    row.c2c_p95 = finite_or_none(c.c2c_all.p95);
    row.c2c_missing = std::int64_t(c.c2c_all.missing);
    row.parameters_json = parameters_json(p).dump();
    row.seconds = c.seconds.total();
    row.coarse = coarse_name(c.coarse.used);
    if (c.coarse.used == CoarseRegistration::planes)
        row.coarse_planes = std::int64_t(c.coarse.support);
    row.frame.emplace();
    const Eigen::Matrix4d M = c.frame();
    for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) (*row.frame)[std::size_t(4 * r + k)] = M(r, k);
    return row;
}

const CampaignReference& CampaignReferences::get(const EpochDatabase& db,
                                                 const CampaignParameters& p, EpochId& epoch) {
    const fs::path path = reference_scan(db, epoch);
    // Only what the prepared reference depends on (its surface, segments and planes): a batch
    // of instruments that differ in their range noise shares one.
    auto key = parameters_json(p);
    for (const char* unused : {"range_sigma_m", "cut_distance_m", "alpha", "metric", "c2c",
                               "registration_points", "min_overlap"})
        key.erase(unused);
    const std::string parameters = key.dump();
    if (reference_ && epoch == epoch_ && parameters == parameters_) return *reference_;
    reference_.reset();
    points_ = all_points(read_scans(path), path.string());
    reference_ = std::make_unique<CampaignReference>(points_, p);
    epoch_ = epoch;
    parameters_ = parameters;
    ++prepared_;
    return *reference_;
}

CampaignPoints stored_points(const CampaignComparison& c, double spacing, unsigned threads) {
    const campaign::VoxelThinning thin =
        campaign::thin_by_voxel(c.registered, spacing, {}, threads);
    CampaignPoints out;
    out.spacing = spacing;
    if (thin.kept.empty()) return out;
    // The origin on a whole metre near the points: float32 offsets keep 8 µm at 100 m.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto i : thin.kept) mean += c.registered[i];
    mean /= double(thin.kept.size());
    for (int k = 0; k < 3; ++k) out.origin[std::size_t(k)] = std::round(mean(k));
    for (const char* name : kCampaignPointArrays) out.arrays.push_back({name, {}});
    for (auto& a : out.arrays) a.values.reserve(thin.kept.size());
    for (const auto i : thin.kept) {
        for (int k = 0; k < 3; ++k)
            out.arrays[std::size_t(k)].values.push_back(
                float(c.registered[i](k) - out.origin[std::size_t(k)]));
        out.arrays[3].values.push_back(float(c.segmentation.segment[i]));
        for (int k = 0; k < 3; ++k) out.arrays[std::size_t(4 + k)].values.push_back(c.c2c[i](k));
    }
    return out;
}

StoredCampaign add_campaign(EpochDatabase& db, const CampaignSource& source,
                            const HashedBytes& bytes, const CampaignParameters& p,
                            double store_spacing, CampaignReferences& references,
                            const CampaignFeed* feed) {
    validate(p);
    StoredCampaign out;
    if (auto known = db.campaigns().find(bytes.sha256)) {
        out.known = true;
        out.row = std::move(*known);
        return out;
    }
    EpochId reference_id = 0;
    const CampaignReference& reference = references.get(db, p, reference_id);
    const std::vector<Eigen::Vector3d> cloud =
        all_points(parse_scans(bytes.bytes, source.file), source.file.string());
    out.comparison = compare_campaign(reference, cloud, p);
    out.row = campaign_row(*out.comparison, p);
    out.row.sha256 = bytes.sha256;
    out.row.instrument = source.instrument;
    out.row.kind = source.kind;
    out.row.acquired = source.acquired;
    out.row.added = now_utc();
    out.row.file_path = (source.stored_path.empty() ? source.file : source.stored_path).string();
    out.row.file_size = std::int64_t(bytes.bytes.size());
    out.row.reference_epoch = reference_id;
    const auto segments = segment_rows(*out.comparison);
    const auto points = stored_points(*out.comparison, store_spacing, p.threads);
    std::vector<ZoneResult> zones;
    CampaignStore::AlarmEvaluation evaluate;
    if (feed) {
        zones = campaign_zone_results(points, segments, feed->zones, feed->min_points);
        evaluate = [&](CampaignId id, const AlarmStore& alarms, const SeriesReader& series) {
            return evaluate_campaign_alarms(feed->rules, id, out.row.acquired, zones, alarms,
                                            series);
        };
    }
    out.row.id = db.campaigns().add(out.row, segments, points, zones, evaluate);
    return out;
}

}  // namespace tlsmon
