// Patch-based M3C2 after registration on simulated series of the `pier` preset, beside M3C2
// on the same zones and epochs (tests/support/simulated_zones.hpp; each method's defaults,
// tuned on neither series): the zone medians against the truth, the patches' LoD95 against
// the core points', and the LoD's coverage of the true change patch by patch, with and without
// deformation. The faces are rendered at 0.05° (4–5 cm at 45–60 m;
// tests/pipeline/simulated_windows.hpp), the registration on the preset's targets with the
// truth's range scales.
//
// Truth: the pier's displacement u_i at the place c the distance is taken at (the centroid of
// the reference points it rests on, on their plane: PbM3c2Reference::measured_at) along the
// patch normal
// n, (u_i(c) − u_0(c))·n; a zone's true value is, for M3C2, the median over its measured core
// points (tests/pipeline/test_m3c2_simulated.cpp), for PB-M3C2 the median over its measured
// patches' footprint cells, the area its row's median is taken over
// (tests/support/pbm3c2_truth.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/statistics.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/pipeline/registered_outputs.hpp"
#include "tests/support/pbm3c2_truth.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

namespace tlsmon {
namespace {

// Per zone (the configuration's order) over the epochs: the zone medians' errors and the
// median per-point LoD95, for one method.
struct ZoneScore {
    std::vector<double> errors, point_lods;
    double rms() const {
        double s = 0;
        for (double e : errors) s += e * e;
        return std::sqrt(s / double(errors.size()));
    }
};

struct Series {
    std::vector<std::string> zones;
    std::vector<ZoneScore> m3c2, pbm3c2;
    std::size_t patches = 0, within = 0;  // measured patches, and those with |d − t| ≤ LoD95
    std::size_t south_patches = 0, south_within = 0;
    // The south face's patches with the epoch's realized registration error along the normal
    // taken out, within the fits' own LoD95 (1.96·σ_fits); and that error in units of σ_T at
    // the face's first patch, per epoch.
    std::size_t south_own_within = 0;
    std::vector<double> registration_z;
    double largest_truth = 0;
};

// Adds one method's epoch: `d`, `lod`, `truth` per place, `members` per zone.
void add_epoch(std::vector<ZoneScore>& scores, const std::vector<double>& d,
               const std::vector<double>& lod, const std::vector<double>& truth,
               const std::vector<std::vector<std::uint32_t>>& members) {
    scores.resize(members.size());
    for (std::size_t z = 0; z < members.size(); ++z) {
        std::vector<double> dz, tz, lz;
        for (auto k : members[z]) {
            if (!std::isfinite(d[k])) continue;
            dz.push_back(d[k]), tz.push_back(truth[k]), lz.push_back(lod[k]);
        }
        if (dz.empty()) continue;
        scores[z].errors.push_back(median(dz) - median(tz));
        scores[z].point_lods.push_back(median(lz));
    }
}

Series run_series(const sim::Site& site, const std::vector<double>& hours) {
    const RegistrationConfig targets = test::simulated_targets(site);
    M3c2Config m3c2;
    m3c2.core_spacing = 1.0;
    m3c2.max_depth = 0.5;
    m3c2.zones = test::simulated_pier_zones(site);
    PbM3c2Config pb;
    pb.zones = m3c2.zones;
    const auto e0 = test::render_windows(site, 0, hours[0], 0.05);
    const ReferenceTargets reference = measure_reference_targets(targets, e0.targets);
    const M3c2Reference m3c2_ref = prepare_m3c2_reference(m3c2, e0.pier);
    const PbM3c2Reference pb_ref =
        prepare_pbm3c2_reference(pb, build_supervoxels(pb.segmentation, e0.pier), e0.pier);
    // The product survives the reference cache's encoding.
    const PbM3c2Reference decoded = PbM3c2Reference::decode(pb_ref.encode());
    EXPECT_EQ(decoded.patches.size(), pb_ref.patches.size());
    EXPECT_EQ(decoded.zone_patches, pb_ref.zone_patches);
    EXPECT_EQ(decoded.encode(), pb_ref.encode());
    Series out;
    out.zones = pb_ref.zone_names;
    for (std::size_t i = 1; i < hours.size(); ++i) {
        const int epoch = static_cast<int>(i);
        const auto ei = test::render_windows(site, epoch, hours[i], 0.05);
        const auto o = test::registered_outputs(targets, reference, e0, ei, epoch);
        if (!o) continue;
        const auto truth_at = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& n) {
            const double t = (sim::pier_displacement(site, c, epoch, ei.conditions.bending) -
                              sim::pier_displacement(site, c, 0, e0.conditions.bending))
                                 .dot(n);
            out.largest_truth = std::max(out.largest_truth, std::abs(t));
            return t;
        };
        const M3c2Epoch m = measure_m3c2(m3c2, m3c2_ref, ei.pier, *o);
        std::vector<double> d, lod, truth;
        for (std::size_t k = 0; k < m.distances.size(); ++k) {
            const auto& n = m3c2_ref.reference.normals()[k];
            d.push_back(m.distances[k].distance);
            lod.push_back(m.distances[k].lod);
            truth.push_back(n.allFinite() ? truth_at(m3c2_ref.reference.core_points()[k], n)
                                          : std::nan(""));
        }
        add_epoch(out.m3c2, d, lod, truth, m3c2_ref.zone_cores);

        const PbM3c2Epoch p = measure_pbm3c2(pb, pb_ref, ei.pier, *o);
        d.clear(), lod.clear(), truth.clear();
        for (std::size_t k = 0; k < p.results.size(); ++k) {
            const auto& f = pb_ref.patches[k].frame;
            d.push_back(p.results[k].distance.distance);
            lod.push_back(p.results[k].distance.lod);
            truth.push_back(truth_at(pb_ref.measured_at(k, &p.results[k]), f.normal));
            if (!std::isfinite(d.back())) continue;
            const bool in = std::abs(d.back() - truth.back()) <= lod.back();
            ++out.patches, out.within += in;
        }
        bool first = true;
        for (auto k : pb_ref.zone_patches[0]) {
            if (!std::isfinite(d[k])) continue;
            ++out.south_patches, out.south_within += std::abs(d[k] - truth[k]) <= lod[k];
            const auto& f = pb_ref.patches[k].frame;
            const double e =
                test::registration_error_at(site, e0.conditions, ei.conditions, *o->to_reference,
                                            pb_ref.measured_at(k, &p.results[k]))
                    .dot(f.normal);
            const double own_lod = 1.96 * p.results[k].distance.sampling_sigma;
            out.south_own_within += std::abs(d[k] - truth[k] - e) <= own_lod;
            if (first) out.registration_z.push_back(e / p.registration_sigma[k]), first = false;
        }
        // The zone medians: the rows' values (over the zones' area) against the median of the
        // true change over the same area; the per-patch LoD95s as in add_epoch.
        const auto rows = pbm3c2_zone_results(pb_ref, p);
        out.pbm3c2.resize(pb_ref.zone_names.size());
        for (std::size_t z = 0; z < pb_ref.zone_names.size(); ++z) {
            std::vector<double> lz;
            for (auto k : pb_ref.zone_patches[z])
                if (std::isfinite(d[k])) lz.push_back(lod[k]);
            if (lz.empty()) continue;
            for (const auto& row : rows) {
                if (row.zone != pb_ref.zone_names[z] || row.quantity != "pbm3c2_median_m") continue;
                EXPECT_EQ(row.n, static_cast<std::int64_t>(lz.size()));
                out.pbm3c2[z].errors.push_back(
                    row.value -
                    test::areal_median_truth(
                        pb_ref, p, z, [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
                            return sim::pier_displacement(site, x, epoch, ei.conditions.bending) -
                                   sim::pier_displacement(site, x, 0, e0.conditions.bending);
                        }));
            }
            out.pbm3c2[z].point_lods.push_back(median(lz));
        }
    }
    for (std::size_t z = 0; z < out.zones.size(); ++z) {
        const auto& a = out.m3c2[z];
        const auto& b = out.pbm3c2[z];
        std::printf(
            "%-14s m3c2: median error RMS %.3f mm, point LoD95 %.3f mm | pbm3c2: %.3f mm, %.3f mm"
            " (%zu epochs)\n",
            out.zones[z].c_str(), 1e3 * a.rms(), 1e3 * median(a.point_lods),
            b.errors.empty() ? std::nan("") : 1e3 * b.rms(), 1e3 * median(b.point_lods),
            b.errors.size());
    }
    std::printf("patches within LoD95: %zu of %zu (%.1f %%); south face %zu of %zu (%.1f %%)\n",
                out.within, out.patches, 100.0 * double(out.within) / double(out.patches),
                out.south_within, out.south_patches,
                100.0 * double(out.south_within) / double(out.south_patches));
    std::printf(
        "south face, the registration's realized error taken out: %zu of %zu within the "
        "fits' own LoD95 (%.1f %%); that error in σ_T per epoch:",
        out.south_own_within, out.south_patches,
        100.0 * double(out.south_own_within) / double(out.south_patches));
    for (double z : out.registration_z) std::printf(" %+.2f", z);
    std::printf("\n");
    return out;
}

TEST(PbM3c2Simulated, ZoneMediansMatchTheTruthWithASmallerLodThanM3c2) {
    const sim::Site site = sim::preset_pier();
    const Series s = run_series(site, {0.0, 3.0, 6.0, 9.0});
    EXPECT_GT(s.largest_truth, 0.001);  // the pier bent by millimetres: something to measure
    for (std::size_t z = 0; z < s.zones.size(); ++z) {
        if (s.zones[z] == "west") {
            // Seen at 87°: no patch of the face is kept (docs/pbm3c2.md, max_incidence_deg),
            // and the deck's soffit inside its box is not the face.
            EXPECT_TRUE(s.pbm3c2[z].errors.empty());
            continue;
        }
        ASSERT_EQ(s.pbm3c2[z].errors.size(), 3u) << s.zones[z];
        EXPECT_LE(s.pbm3c2[z].rms(), 0.0003) << s.zones[z];
        // At least 20 % below M3C2's (29–30 % on this series, the registration's σ unpadded).
        EXPECT_LT(median(s.pbm3c2[z].point_lods), 0.80 * median(s.m3c2[z].point_lods))
            << s.zones[z];
    }
}

// Without deformation, on the south face. An epoch's patches all share its registration error,
// one draw of σ_T, so how many of them fall within their LoD95 depends on that draw (with
// σ_T at a third of the fits' σ, one draw at 1.9 σ_T moved a sixth of them out) and cannot
// judge it. The patches' own part is scored apart: their error less the realized
// registration error along the normal against the fits' LoD95, at 95 % within the
// two-sided 99 % binomial band (not padded either). σ_T itself is scored over independent
// series (bench/registration_coverage.cpp; docs/calibration.md); here its realized error only
// has to be a plausible draw of it.
TEST(PbM3c2Simulated, WithoutDeformationThePatchesOwnLodHoldsAt95Percent) {
    sim::Site site = sim::preset_pier();
    site.deformation.enabled = false;
    site.noise.seed = 5;
    const Series s = run_series(site, {0.0, 4.0, 8.0});
    ASSERT_GT(s.south_patches, 600u);
    const double n = double(s.south_patches), share = double(s.south_own_within) / n;
    const double band = 2.576 * std::sqrt(0.95 * 0.05 / n);
    EXPECT_GE(share, 0.95 - band);
    EXPECT_LE(share, 0.95 + band);
    ASSERT_EQ(s.registration_z.size(), 2u);
    for (double z : s.registration_z) EXPECT_LT(std::abs(z), 3.0);
}

}  // namespace
}  // namespace tlsmon
