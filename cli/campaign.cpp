// `tlsmon campaign compare REFERENCE CAMPAIGN --out DIR`: a campaign cloud against the TLS
// reference segment by segment (pipeline/campaign_comparison.hpp, docs/campaigns.md). Writes
// DIR/segments.csv (one row per segment: its parameters with their σ where the segment's
// surfaces observe them, the test against the others, C2C statistics) and DIR/segments.ply
// (every campaign point after its registration, its segment, class, ground flag and C2C
// vector), and prints the global registration, the ground, the consistency test and the C2C
// summary.
// `tlsmon campaign add FILE --instrument NAME --config SITE`: the same comparison against the
// site's reference epoch, stored as a campaign epoch (pipeline/campaign_epoch.hpp).
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli/campaign_tables.hpp"
#include "cli/commands.hpp"
#include "cli/result_file.hpp"
#include "config/config.hpp"
#include "config/site_definition.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/fixed_decimals.hpp"
#include "daemon/ingest_files.hpp"
#include "formats/ply_writer.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/campaign_comparison.hpp"
#include "pipeline/campaign_config.hpp"
#include "pipeline/campaign_epoch.hpp"
#include "report/campaign_plot.hpp"

namespace tlsmon {

namespace {

namespace fs = std::filesystem;

CampaignParameters parameters_of(const CampaignCompareOptions& o) {
    CampaignParameters p;
    p.icp.metric = o.metric == "point-to-point" ? campaign::IcpMetric::point_to_point
                                                : campaign::IcpMetric::point_to_plane;
    p.c2c = o.c2c == "nearest-point" ? campaign::C2cModel::nearest_point
                                     : campaign::C2cModel::local_plane;
    if (o.radius) p.verticality.radius = p.surface.plane_radius = *o.radius;
    if (o.max_distance) p.surface.max_distance = *o.max_distance;
    if (o.min_segment_points) p.min_segment_points = *o.min_segment_points;
    if (o.min_planar_share) p.min_planar_share = *o.min_planar_share;
    if (o.thinning) p.thinning = *o.thinning;
    if (o.registration_points) {
        if (*o.registration_points < 1) throw Error("--registration-points must be positive");
        p.registration_points = std::size_t(*o.registration_points);
    }
    p.remove_ground = !o.keep_ground;
    if (o.ground_threshold) p.ground.class_threshold = *o.ground_threshold;
    if (o.cloth_resolution) p.ground.cloth_resolution = *o.cloth_resolution;
    if (o.rigidness) p.ground.rigidness = *o.rigidness;
    if (o.threads) {
        if (*o.threads < 0) throw Error("--threads must not be negative");
        p.threads = unsigned(*o.threads);
    }
    p.coarse = o.coarse == "planes" ? CoarseRegistration::planes
               : o.coarse == "none" ? CoarseRegistration::none
                                    : CoarseRegistration::automatic;
    return p;
}

void write_segments(const std::filesystem::path& path, const CampaignComparison& c) {
    std::ostringstream text;
    print(text, campaign_segments_table(segment_rows(c)), OutputFormat::csv);
    ResultFile f(path.string());
    f.write(text.str());
    f.close();
}

void write_points(const std::filesystem::path& path, const CampaignComparison& c) {
    const std::size_t n = c.registered.size();
    std::vector<std::int32_t> segment(c.segmentation.segment.begin(), c.segmentation.segment.end());
    std::vector<std::uint8_t> kind(n, std::uint8_t(campaign::VerticalityClass::undefined));
    std::vector<std::uint8_t> ground(n, 0);
    if (!c.ground.ground.empty()) ground = c.ground.ground;
    std::vector<float> distance(n), dx(n), dy(n), dz(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (segment[i] >= 0)
            kind[i] = std::uint8_t(c.segmentation.segments[std::size_t(segment[i])].kind);
        distance[i] = c.c2c[i].norm();
        dx[i] = c.c2c[i].x();
        dy[i] = c.c2c[i].y();
        dz[i] = c.c2c[i].z();
    }
    const PlyAttribute attributes[] = {{"segment", std::span<const std::int32_t>(segment)},
                                       {"class", std::span<const std::uint8_t>(kind)},
                                       {"ground", std::span<const std::uint8_t>(ground)},
                                       {"c2c", std::span<const float>(distance)},
                                       {"c2c_x", std::span<const float>(dx)},
                                       {"c2c_y", std::span<const float>(dy)},
                                       {"c2c_z", std::span<const float>(dz)}};
    write_ply(path, c.registered, attributes);
}

std::string mm(double metres) {
    return fixed_decimals(1e3 * metres, 2);
}

// The campaign's frame onto the reference as four rows of four numbers (CloudCompare's and
// PDAL's matrix text): x_ref = M·x.
void write_frame(const fs::path& path, const Eigen::Matrix4d& M) {
    std::ostringstream text;
    text.precision(12);
    for (int r = 0; r < 4; ++r)
        text << M(r, 0) << " " << M(r, 1) << " " << M(r, 2) << " " << M(r, 3) << "\n";
    ResultFile f(path.string());
    f.write(text.str());
    f.close();
}

// The comparison's lines: the frame found, the global registration, the ground, the segments,
// their test and the C2C summary.
void print_summary(const CampaignComparison& c, const CampaignParameters& p) {
    const auto& f = c.coarse;
    if (f.used == CoarseRegistration::planes) {
        const Eigen::Matrix4d& M = f.matrix;
        std::cout << "frame (coarse, planes): " << f.support << " of " << f.campaign_planes
                  << " planes on the reference's " << f.reference_planes << " (next heading "
                  << f.runner_up << "), heading "
                  << fixed_decimals(std::atan2(M(1, 0), M(0, 0)) * 180.0 / std::numbers::pi, 2)
                  << "°, shift (" << fixed_decimals(M(0, 3), 3) << ", "
                  << fixed_decimals(M(1, 3), 3) << ", " << fixed_decimals(M(2, 3), 3) << ") m\n";
    } else if (!f.note.empty()) {
        std::cout << "frame (coarse): none, " << f.note << "\n";
    }
    const auto& g = c.global;
    std::cout << "global registration (point-to-plane): " << g.pairs << " pairs, rank " << g.rank()
              << ", centroid shift (" << mm(g.parameters(3)) << ", " << mm(g.parameters(4)) << ", "
              << mm(g.parameters(5)) << ") mm, RMSE " << mm(g.rmse) << " mm\n";
    if (p.remove_ground)
        std::cout << "ground (cloth simulation filter): " << c.ground.ground_points
                  << " points, left out of the segments\n";
    std::size_t registered = 0;
    for (const auto& s : c.segments) registered += s.transform.registered();
    std::cout << c.segmentation.segments.size() << " segments (of " << c.thinned << " voxels at "
              << csv_number(p.thinning) << " m, spacing " << mm(c.segmentation.spacing) << " mm), "
              << registered << " registered (" << campaign::metric_name(p.icp.metric) << ")\n";
    const auto& t = c.consistency;
    if (t.dof > 0)
        std::cout << "segments moved as one: T = " << fixed_decimals(t.statistic, 1) << ", dof "
                  << t.dof << ", p "
                  << (t.p_value < 1e-4 ? "< 0.0001" : "= " + fixed_decimals(t.p_value, 4)) << " -> "
                  << (t.differ ? "no, they differ" : "yes") << " (α " << csv_number(p.alpha)
                  << ")\n";
    else
        std::cout << "segments moved as one: not testable (" << t.segments
                  << " registered segments do not hold every direction together)\n";
    std::cout << "C2C ("
              << (p.c2c == campaign::C2cModel::local_plane ? "local plane" : "nearest point")
              << "): mean " << mm(c.c2c_all.mean) << " mm, σ " << mm(c.c2c_all.sigma)
              << " mm, 95 % " << mm(c.c2c_all.p95) << " mm, " << c.c2c_all.missing
              << " points without\n";
}

}  // namespace

int run_campaign_compare(const CampaignCompareOptions& o) {
    try {
        const CampaignParameters p = parameters_of(o);
        validate(p);
        const std::vector<Eigen::Vector3d> reference =
            all_points(read_scans(o.reference), o.reference);
        const std::vector<Eigen::Vector3d> cloud = all_points(read_scans(o.campaign), o.campaign);
        std::cout << "reference: " << reference.size() << " points; campaign: " << cloud.size()
                  << " points\n";
        const CampaignComparison c = compare_campaign(reference, cloud, p);
        print_summary(c, p);
        std::filesystem::create_directories(o.out);
        write_segments(std::filesystem::path(o.out) / "segments.csv", c);
        write_points(std::filesystem::path(o.out) / "segments.ply", c);
        const fs::path out(o.out);
        write_frame(out / "frame.txt", c.frame());
        const auto not_drawn = report::draw_segment_parameters(c, p.alpha, out / "segments.plot",
                                                               out / "segments.png");
        std::cout << "-> " << o.out << "/frame.txt, " << o.out << "/segments.csv, " << o.out
                  << "/segments.ply";
        if (not_drawn)
            std::cout << "; segments.png " << *not_drawn;
        else
            std::cout << ", " << o.out << "/segments.png";
        std::cout << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon campaign compare: " << e.what() << "\n";
        return 1;
    }
}

int run_campaign_add(const CampaignAddOptions& o) {
    try {
        const Config config = load_config(o.config);
        const InstrumentConfig& instrument =
            instrument_named(config.instruments, o.instrument, config.file.string());
        CampaignSource source;
        source.file = fs::absolute(o.file);
        source.instrument = instrument.name;
        source.kind = kind_name(instrument.kind);
        if (o.acquired) {
            source.acquired = parse_utc(*o.acquired);
        } else {
            std::string used;
            source.acquired = acquisition_time(source.file, config.ingest.acquisition_time, used);
        }
        const CampaignParameters p = campaign_parameters(config.campaign, instrument.range_sigma);
        EpochDatabase db =
            EpochDatabase::open(config.paths.database, EpochDatabase::Mode::read_write);
        // Its zone rows need the configured zones and rules stored, as the daemon does.
        const std::optional<CampaignFeed> feed = campaign_feed(config);
        if (feed) store_zones_and_rules(db, config);
        CampaignReferences references;
        const StoredCampaign stored =
            add_campaign(db, source, read_file_hashed(source.file), p,
                         config.campaign.store_spacing, references, feed ? &*feed : nullptr);
        if (stored.known) {
            std::cout << o.file << " is campaign " << stored.row.id << " already ("
                      << stored.row.instrument << ", acquired " << format_utc(stored.row.acquired)
                      << "): not compared again\n";
            return 0;
        }
        std::cout << "campaign: " << stored.row.points << " points; reference epoch "
                  << stored.row.reference_epoch << "\n";
        print_summary(*stored.comparison, p);
        for (const auto& z : db.campaigns().zone_results(stored.row.id)) {
            std::cout << fmt::format("zone {}: {} {:+.1f} mm, LoD95 {:.1f} mm, {} points{}\n",
                                     z.zone, z.quantity, z.value * 1e3,
                                     z.uncertainty.value_or(0) * 1e3, z.n,
                                     z.significant ? ", significant" : "");
        }
        db.events().record({now_utc(), "info", "campaign",
                            "campaign " + std::to_string(stored.row.id) + " of instrument '" +
                                instrument.name + "' added from " + source.file.string(),
                            std::nullopt});
        std::cout << "-> campaign " << stored.row.id
                  << " (tlsmon query campaign-segments --campaign " << stored.row.id << ")\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon campaign add: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
