// The keypoint method's own error on the `pier` faces, match by match: the epochs are
// registered by the exact map H₀⁻¹·H_e (no registration error), so each kept match's vector
// less the true change at its reference point is the method's alone. Per zone (the south
// face and its 10 m bands) and epoch: the matches' mean error along the wall (normal,
// horizontal, vertical) with its standard error, the true change at the matches, and the
// zone's figure (the stratified mean the stage stores) less the truth over the zone's area;
// the matches' mean error over its standard error with the matches in cells of side L as
// clusters; at the end those ratios' RMS over the zone epochs, and the stage's figures over
// the stage's own standard error. MATCHES.csv: each kept match's error along the wall.
//
// Between the reference and epochs 1–3 (3, 6 and 9 h: the thermal bending moves the face)
// CHANGES switches off:
//   d   the scanner's drift        a   the atmosphere        q   all noise
//   r   the range noise            g   the angular noise     i   the intensity noise
//   p   the refinement's prefilter (keypoints.prefilter_px = 0)
//   I   (on, not off) the intensity noise doubled
//   R   the reference epoch's noise (the later epochs keep theirs)
//   b   the thermal bending (the face stays where the reference saw it)
//   F   the outlier filters (keypoints.mad_k = 10⁹)
//
//   bench_keypoint_own_error [CHANGES] [NOISE_SEED] [REFERENCE_NOISE_SEED] [MATCHES.csv]
//   (default: everything on, the preset's seed, the reference's the epochs')
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "pipeline/keypoint_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "tests/pipeline/keypoint_series.hpp"
#include "tests/support/simulated_targets.hpp"

namespace {

using namespace tlsmon;

// The faces' window at the preset's step, as the keypoint tests render it.
std::vector<Scan> render_faces(const sim::Site& site, const sim::EpochConditions& c) {
    return {test::render_window(site, c, test::kFaceStepDeg)};
}

// The keypoint tests' zones on the south face: the face and its 10 m bands.
std::vector<ZoneShape> south_zones(const sim::Site& site) {
    std::vector<ZoneShape> zones = test::pier_zones(site);
    std::erase_if(zones, [](const ZoneShape& z) { return z.name == "west"; });
    return zones;
}

struct Mean {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum2 = Eigen::Vector3d::Zero();
    double n = 0;
    void add(const Eigen::Vector3d& x) { sum += x, sum2 += x.cwiseProduct(x), n += 1; }
    Eigen::Vector3d mean() const { return sum / n; }
    Eigen::Vector3d standard_error() const {
        const Eigen::Vector3d m = mean();
        return ((sum2 / n - m.cwiseProduct(m)) / (n - 1)).cwiseSqrt();
    }
};

}  // namespace

int main(int argc, char** argv) {
    const std::string changes = argc > 1 ? argv[1] : "";
    const auto off = [&](char c) { return changes.find(c) != std::string::npos; };
    sim::Site site = sim::preset_pier();
    if (off('d')) site.drift.enabled = false;
    if (off('a')) site.atmosphere.enabled = false;
    if (argc > 2) site.noise.seed = std::strtoull(argv[2], nullptr, 10);
    if (off('q')) site.noise.enabled = false;
    if (off('r')) site.noise.signal_a = site.noise.signal_b_ppm = 0.0;
    if (off('g')) site.noise.angular_arcsec = 0.0;
    if (off('i')) site.noise.intensity_sigma = 0.0;
    KeypointConfig config;
    config.zones = south_zones(site);
    if (off('p')) config.prefilter_px = 0.0;
    if (off('F')) config.mad_k = 1e9;
    if (off('I')) site.noise.intensity_sigma *= 2.0;

    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    sim::Site reference_site = site;
    if (argc > 3) reference_site.noise.seed = std::strtoull(argv[3], nullptr, 10);
    if (off('R')) reference_site.noise.enabled = false;
    const std::vector<Scan> s0 = render_faces(reference_site, c0);
    const KeypointReference ref = prepare_keypoint_reference(config, s0);
    const std::vector<std::vector<Eigen::Vector3d>> cells = test::zone_cells(config, ref, s0);
    FILE* csv = argc > 4 ? std::fopen(argv[4], "w") : nullptr;
    if (csv) std::fprintf(csv, "epoch,zone,reference_row,reference_column,error_h_m,error_v_m\n");
    std::printf("switched off: '%s'; reference: %zu keypoints\n", changes.c_str(), ref.keypoints());
    std::printf(
        "epoch zone     kept | matches' mean error n, h, v (± SE)      | truth at them n, h, v "
        "| figure − area truth n, h, v (mm)\n");
    constexpr std::array<double, 6> kSides{0.0, 0.05, 0.25, 1.0, 2.0, 4.0};
    std::array<Eigen::Vector2d, kSides.size()> z2;
    z2.fill(Eigen::Vector2d::Zero());
    int figures = 0;
    // The zone's figure (the stratified mean the stage stores) less the area's truth, over
    // the stage's own standard error: (n, Σ z_h², Σ z_v², within 1.96 SE h, v).
    std::array<double, 5> stage_z{};
    for (int i = 1; i <= 3; ++i) {
        sim::EpochConditions ci = sim::epoch_conditions(site, i, 3.0 * i);
        if (off('b')) ci.bending = c0.bending;
        const std::vector<Scan> si = render_faces(site, ci);
        const StageOutputs o = test::exact_outputs(site, c0, ci, si[0]);
        KeypointEpoch measured = measure_keypoints(config, ref, si, o);
        const KeypointSegmentsResult segments =
            keypoint_segments(config, ref, std::move(measured.matches), o);
        const auto true_change = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
            return sim::pier_displacement(site, p, i, ci.bending) -
                   sim::pier_displacement(site, p, 0, c0.bending);
        };
        for (std::size_t z = 0; z < segments.segments.size(); ++z) {
            const auto& s = segments.segments[z];
            const auto& w = s.displacement.wall;
            if (!s.displacement.defined() || !w.defined()) {
                std::printf("%d  %-8s undefined: %s\n", i, s.zone.c_str(),
                            s.displacement.undefined_reason.c_str());
                continue;
            }
            Mean error, truth;
            std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> placed;  // (h, v), error
            for (std::size_t k = 0; k < s.matches.size(); ++k) {
                if (s.removed_by[k] != keypoints::OutlierFilter::none) continue;
                const auto& m = s.matches[k];
                const Eigen::Vector3d u = test::in_wall(w, true_change(m.reference_point));
                const Eigen::Vector3d e = test::in_wall(w, m.displacement()) - u;
                error.add(e), truth.add(u);
                if (csv)
                    std::fprintf(csv, "%d,%s,%.0f,%.0f,%.6e,%.6e\n", i, s.zone.c_str(),
                                 m.reference_row, m.reference_column, e[1], e[2]);
                const Eigen::Vector3d at = m.reference_point - w.centroid;
                placed.push_back({{at.dot(w.horizontal), at.dot(w.vertical)}, e.tail<2>()});
            }
            const Eigen::Vector3d area = test::zone_truth(cells[z], w, true_change);
            const Eigen::Vector3d me = 1e3 * error.mean(), se = 1e3 * error.standard_error();
            const Eigen::Vector3d mt = 1e3 * truth.mean();
            const Eigen::Vector3d fe = 1e3 * (s.displacement.along - area);
            std::printf(
                "%d  %-8s %5.0f | %+.3f±%.3f %+.3f±%.3f %+.3f±%.3f | %+6.2f %+6.2f %+6.2f | "
                "%+.3f %+.3f %+.3f\n",
                i, s.zone.c_str(), error.n, me[0], se[0], me[1], se[1], me[2], se[2], mt[0], mt[1],
                mt[2], fe[0], fe[1], fe[2]);
            // The mean error against its standard error with cells of side L as clusters (each
            // cell's summed deviations, squared; L = 0: every match its own cluster).
            std::printf("   mean error / SE (h, v) with clusters of side L:");
            for (std::size_t l = 0; l < kSides.size(); ++l) {
                const double L = kSides[l];
                std::map<std::pair<long, long>, Eigen::Vector2d> cells_sum;
                const Eigen::Vector2d mean_e = error.mean().tail<2>();
                long next = 0;
                for (const auto& [x, e] : placed) {
                    const std::pair key = L > 0 ? std::pair{std::lround(std::floor(x[0] / L)),
                                                            std::lround(std::floor(x[1] / L))}
                                                : std::pair{next++, 0L};
                    cells_sum.try_emplace(key, Eigen::Vector2d::Zero()).first->second += e - mean_e;
                }
                Eigen::Vector2d variance = Eigen::Vector2d::Zero();
                for (const auto& [key, sum] : cells_sum) variance += sum.cwiseProduct(sum);
                variance /= error.n * error.n;
                const Eigen::Vector2d z = mean_e.cwiseQuotient(variance.cwiseSqrt());
                z2[l] += z.cwiseProduct(z);
                std::printf("  %.2f m: %+.1f %+.1f", L, z[0], z[1]);
            }
            std::printf("\n");
            ++figures;
            for (int k = 1; k < 3; ++k) {
                const double zk =
                    (s.displacement.along[k] - area[k]) / s.displacement.along_standard_error[k];
                stage_z[k] += zk * zk;
                stage_z[k + 2] += std::abs(zk) <= 1.96;
            }
            stage_z[0] += 1;
        }
    }
    std::printf("over %d zone epochs, RMS(mean error / SE) in h and v, clusters of side L:\n",
                figures);
    for (std::size_t l = 0; l < kSides.size(); ++l)
        std::printf("  %.2f m: %.2f %.2f\n", kSides[l], std::sqrt(z2[l][0] / figures),
                    std::sqrt(z2[l][1] / figures));
    std::printf(
        "the stage's figures against the area's truth: RMS(error / SE) h %.2f, v %.2f; within "
        "1.96 SE %.0f and %.0f of %.0f\n",
        std::sqrt(stage_z[1] / stage_z[0]), std::sqrt(stage_z[2] / stage_z[0]), stage_z[3],
        stage_z[4], stage_z[0]);
    if (csv) std::fclose(csv);
    return 0;
}
