// Patch-based M3C2's own σ on full `pier` epochs, one change between epochs at a time: the
// registration is the exact map H₀⁻¹·H_e (no σ_T, no registration error), so each patch's
// error d − truth is the fits' alone and is scored against their own σ,
// √(σ₁²/m₁ + σ_h₂²): RMS(error/σ) and the share within 1.96σ, per band of the south face and
// for the patches in its outermost metre on either side (the face's vertical edges).
// Between the reference and epochs 1 and 2 the noise is always drawn anew; CHANGES adds:
//   d   the scanner's drift (the grid's phase on the surface moves)
//   b   the thermal bending (the face moves along its normal by up to millimetres)
//   a   the atmosphere (range scales, corrected as from a weather station)
//   s   the whole pier shifted along y by SHIFT_MM from epoch 1 on (a step event)
//
//   bench_pbm3c2_own_sigma [CHANGES] [SHIFT_MM]     (default: none, 5 mm)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pipeline/pbm3c2_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

namespace {

using namespace tlsmon;

struct Tally {
    double z2 = 0, n = 0, within = 0;
    void add(double z) { z2 += z * z, n += 1, within += std::abs(z) <= 1.96; }
    void print(const char* name) const {
        std::printf("  %-14s %4.0f patches, RMS(error/σ) %.2f, %5.1f %% within 1.96σ\n", name, n,
                    std::sqrt(z2 / n), 100 * within / n);
    }
};

}  // namespace

int main(int argc, char** argv) {
    const std::string changes = argc > 1 ? argv[1] : "";
    const double shift_mm = argc > 2 ? std::atof(argv[2]) : 5.0;
    const auto has = [&](char c) { return changes.find(c) != std::string::npos; };
    sim::Site site = sim::preset_pier();
    site.drift.enabled = has('d');
    if (has('s')) {
        site.events.step_epoch = 1;
        site.events.step_z_min = -1.0;
        site.events.step_z_max = site.pier.height + 1.0;
        site.events.step_displacement = Eigen::Vector3d(0, 1e-3 * shift_mm, 0);
    }
    PbM3c2Config pb;
    pb.threads = 2;
    pb.zones = test::simulated_pier_zones(site);
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    const std::vector<Scan> s0{sim::render_epoch(site, c0, 2).scan};
    const PbM3c2Reference ref =
        prepare_pbm3c2_reference(pb, build_supervoxels(pb.segmentation, s0), s0);
    std::printf("changes '%s'%s\n", changes.c_str(),
                has('s') ? (" (shift " + std::to_string(shift_mm) + " mm)").c_str() : "");
    for (int i = 1; i <= 2; ++i) {
        sim::EpochConditions ci = sim::epoch_conditions(site, i, 3.0 * i);
        if (!has('b')) ci.bending = c0.bending;
        if (!has('a')) ci.atmosphere = c0.atmosphere;
        const std::vector<Scan> si{sim::render_epoch(site, ci, 2).scan};
        const StageOutputs o = test::exact_outputs(site, c0, ci, si[0]);
        const PbM3c2Epoch p = measure_pbm3c2(pb, ref, si, o);
        std::vector<Tally> bands(ref.zone_names.size());
        Tally edges, all;
        for (std::size_t z = 0; z < ref.zone_names.size(); ++z) {
            for (const auto k : ref.zone_patches[z]) {
                const auto& r = p.results[k].distance;
                if (!std::isfinite(r.distance)) continue;
                const Eigen::Vector3d c = ref.measured_at(k, &p.results[k]);
                const double truth = (sim::pier_displacement(site, c, i, ci.bending) -
                                      sim::pier_displacement(site, c, 0, c0.bending))
                                         .dot(ref.patches[k].frame.normal);
                const double e = (r.distance - truth) / r.sampling_sigma;
                bands[z].add(e);
                if (ref.zone_names[z] != "south") continue;
                all.add(e);
                if (c.x() < site.pier.x0 + 1.0 || c.x() > site.pier.x1 - 1.0) edges.add(e);
            }
        }
        std::printf("epoch %d:\n", i);
        for (std::size_t z = 0; z < bands.size(); ++z)
            if (bands[z].n > 0) bands[z].print(ref.zone_names[z].c_str());
        edges.print("south, edges");
    }
    return 0;
}
