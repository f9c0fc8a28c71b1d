#include "pipeline/campaign_epoch.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace {

namespace fs = std::filesystem;

std::optional<double> finite_or_none(double v) {
    return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::vector<Eigen::Vector3d> points_of(const std::vector<Scan>& scans) {
    std::vector<Eigen::Vector3d> out;
    for (const Scan& scan : scans) out.insert(out.end(), scan.xyz.begin(), scan.xyz.end());
    return out;
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
            {"alpha", p.alpha}};
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
    return row;
}

StoredCampaign add_campaign(EpochDatabase& db, const CampaignSource& source,
                            const HashedBytes& bytes, const CampaignParameters& p) {
    validate(p);
    StoredCampaign out;
    if (auto known = db.campaigns().find(bytes.sha256)) {
        out.known = true;
        out.row = std::move(*known);
        return out;
    }
    EpochId reference_id = 0;
    const fs::path reference_path = reference_scan(db, reference_id);
    const std::vector<Eigen::Vector3d> cloud = points_of(parse_scans(bytes.bytes, source.file));
    if (cloud.empty()) throw Error(source.file.string() + ": no points");
    const std::vector<Eigen::Vector3d> reference = points_of(read_scans(reference_path));
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
    out.row.id = db.campaigns().add(out.row, segment_rows(*out.comparison));
    return out;
}

}  // namespace tlsmon
