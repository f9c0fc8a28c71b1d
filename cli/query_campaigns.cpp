// `tlsmon query campaigns`, `tlsmon query campaign-segments --campaign N` and `tlsmon query
// campaign-points --campaign N`: the campaign epochs (docs/campaigns.md, "Campaign epochs";
// docs/schema.md, "campaigns"), read-only.
#include <array>
#include <cmath>
#include <iostream>

#include "cli/campaign_tables.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

Table campaigns_table(const std::vector<CampaignRow>& campaigns) {
    Table t{{"campaign",       "acquired",
             "instrument",     "kind",
             "points",         "ground_points",
             "coarse",         "coarse_planes",
             "global_tx_m",    "global_ty_m",
             "global_tz_m",    "global_rx_rad",
             "global_ry_rad",  "global_rz_rad",
             "global_pairs",   "global_rmse_m",
             "segments",       "registered_segments",
             "test_statistic", "test_dof",
             "test_p",         "segments_differ",
             "alpha",          "c2c_mean_m",
             "c2c_sigma_m",    "c2c_median_m",
             "c2c_p95_m",      "c2c_missing",
             "seconds",        "reference_epoch",
             "added",          "file",
             "size",           "sha256"},
            {}};
    for (const auto& c : campaigns) {
        const auto& g = c.global;
        t.rows.push_back({c.id,
                          format_utc(c.acquired),
                          c.instrument,
                          c.kind,
                          c.points,
                          c.ground_points,
                          c.coarse,
                          optional_cell(c.coarse_planes),
                          g[3],
                          g[4],
                          g[5],
                          g[0],
                          g[1],
                          g[2],
                          c.global_pairs,
                          c.global_rmse,
                          c.segments,
                          c.registered_segments,
                          optional_cell(c.test_statistic),
                          optional_cell(c.test_dof),
                          optional_cell(c.test_p),
                          c.segments_differ ? Cell(*c.segments_differ) : Cell(),
                          c.alpha,
                          optional_cell(c.c2c_mean),
                          optional_cell(c.c2c_sigma),
                          optional_cell(c.c2c_median),
                          optional_cell(c.c2c_p95),
                          c.c2c_missing,
                          c.seconds,
                          c.reference_epoch,
                          format_utc(c.added),
                          c.file_path,
                          c.file_size,
                          c.sha256});
    }
    return t;
}

Table campaign_segments_table(const std::vector<CampaignSegmentRow>& segments) {
    Table t{{"segment",
             "class",
             "cluster",
             "points",
             "voxels",
             "outcome",
             "reference_segment",
             "reference_overlap",
             "pairs",
             "rank",
             "centroid_x_m",
             "centroid_y_m",
             "centroid_z_m",
             "tx_m",
             "ty_m",
             "tz_m",
             "sigma_tx_m",
             "sigma_ty_m",
             "sigma_tz_m",
             "rx_rad",
             "ry_rad",
             "rz_rad",
             "sigma_rx_rad",
             "sigma_ry_rad",
             "sigma_rz_rad",
             "cut_fraction",
             "cut_bias_m",
             "rmse_m",
             "iterations",
             "converged",
             "test_statistic",
             "test_dof",
             "test_p",
             "c2c_mean_m",
             "c2c_sigma_m",
             "c2c_median_m",
             "c2c_p95_m",
             "c2c_max_m"},
            {}};
    const auto o = [](const std::optional<double>& v) { return optional_cell(v); };
    for (const auto& s : segments) {
        const auto& p = s.parameters;
        const auto& sp = s.sigmas;
        t.rows.push_back({s.segment,
                          s.kind,
                          s.cluster,
                          s.points,
                          s.voxels,
                          s.outcome,
                          optional_cell(s.reference_segment),
                          o(s.reference_overlap),
                          s.pairs,
                          s.rank,
                          o(s.centroid[0]),
                          o(s.centroid[1]),
                          o(s.centroid[2]),
                          o(p[3]),
                          o(p[4]),
                          o(p[5]),
                          o(sp[3]),
                          o(sp[4]),
                          o(sp[5]),
                          o(p[0]),
                          o(p[1]),
                          o(p[2]),
                          o(sp[0]),
                          o(sp[1]),
                          o(sp[2]),
                          o(s.cut_fraction),
                          o(s.cut_bias),
                          o(s.rmse),
                          s.iterations,
                          s.converged,
                          o(s.test_statistic),
                          optional_cell(s.test_dof),
                          o(s.test_p),
                          o(s.c2c_mean),
                          o(s.c2c_sigma),
                          o(s.c2c_median),
                          o(s.c2c_p95),
                          o(s.c2c_max)});
    }
    return t;
}

int run_query_campaigns(const ReadOptions& options) {
    return run_reporting_errors("query campaigns", [&] {
        const auto range = time_range(options);
        const auto db = open_for_reading(options);
        print(std::cout, campaigns_table(db.campaigns().in_range(range)), options.format);
    });
}

namespace {

void require_campaign(const EpochDatabase& db, CampaignId id) {
    if (!db.campaigns().get(id))
        throw Error("no campaign " + std::to_string(id) + " (tlsmon query campaigns lists them)");
}

}  // namespace

int run_query_campaign_segments(const CampaignSegmentsOptions& options) {
    return run_reporting_errors("query campaign-segments", [&] {
        const auto db = open_for_reading(options.read);
        require_campaign(db, options.campaign);
        print(std::cout, campaign_segments_table(db.campaigns().segments(options.campaign)),
              options.read.format);
    });
}

int run_query_campaign_points(const CampaignSegmentsOptions& options) {
    return run_reporting_errors("query campaign-points", [&] {
        const auto db = open_for_reading(options.read);
        require_campaign(db, options.campaign);
        const auto points = db.campaigns().points(options.campaign);
        if (!points)
            throw Error("campaign " + std::to_string(options.campaign) +
                        " kept no points (stored before they were kept)");
        const auto a = points->columns();
        std::vector<std::string> columns(kCampaignPointArrays.begin(), kCampaignPointArrays.end());
        columns.push_back("c2c_m");
        RowPrinter out(std::cout, columns, {}, options.read.format);
        const auto& o = points->origin;
        for (std::size_t i = 0; i < points->size(); ++i) {
            const double dx = (*a[4])[i], dy = (*a[5])[i], dz = (*a[6])[i];
            const bool c2c = std::isfinite(dx);
            const auto component = [&](double v) { return c2c ? Cell(v) : Cell(); };
            const std::array<Cell, 8> row{o[0] + double((*a[0])[i]),
                                          o[1] + double((*a[1])[i]),
                                          o[2] + double((*a[2])[i]),
                                          std::int64_t((*a[3])[i]),
                                          component(dx),
                                          component(dy),
                                          component(dz),
                                          component(std::sqrt(dx * dx + dy * dy + dz * dz))};
            out.row(row);
        }
        out.finish();
    });
}

}  // namespace tlsmon
