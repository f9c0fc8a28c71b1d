// M3C2 and PB-M3C2 on the rough valley slope (tests/support/rough_slope.hpp) where the
// relief shadows, seen from one station and from a station set up anew: the reference from
// the preset's station, epochs 1–3 (the slab settled 0.94, 1.9 and 2.8 mm along its normal)
// from the same station or from one moved by SHIFT (m, the scanner's frame, not turned), each
// epoch put into the reference's frame by the exact map. From one station the shadows fall
// alike in every epoch; from another the epochs see other parts of the relief — the case of
// the thesis on rigid patches (§5.1), where cylinders are said to bias the distance and
// planes fitted to patches not to.
//
// Per relief and station: each method's bias, RMS and mean LoD95 (mm) over every core point's
// or patch's figure and SEEDS noise draws (one draw of the relief), the bias's standard error
// with the draws as clusters, and the share within the LoD95.
//
//   bench_rough_slope [SEEDS] [FIRST_SEED]     (default: 5 draws from seed 1)
#include "tests/support/rough_slope.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

using namespace tlsmon;

struct Setup {
    const char* name;
    bool moved;
    Eigen::Vector3d shift;
};

struct Pooled {
    test::SlopeScore all;
    std::vector<double> draw_bias;
    void add(const test::SlopeScore& s) { all.add(s), draw_bias.push_back(s.bias()); }
    // The bias's standard error with the draws as clusters: their biases' spread / √draws.
    double bias_se() const {
        const double k = double(draw_bias.size());
        if (k < 2) return std::nan("");
        double mean = 0, ss = 0;
        for (double b : draw_bias) mean += b / k;
        for (double b : draw_bias) ss += (b - mean) * (b - mean);
        return std::sqrt(ss / (k - 1) / k);
    }
    void print(const char* method) const {
        std::printf(
            "    %-7s %5zu figures: bias %+.3f ± %.3f, RMS %.3f, mean LoD95 %.3f mm, "
            "%5.1f %% within\n",
            method, all.n, 1e3 * all.bias(), 1e3 * bias_se(), 1e3 * all.rms(), 1e3 * all.mean_lod(),
            100 * all.share_within());
    }
};

}  // namespace

int main(int argc, char** argv) {
    const int draws = argc > 1 ? std::atoi(argv[1]) : 5;
    const int first = argc > 2 ? std::atoi(argv[2]) : 1;
    const struct { double roughness, wavelength; } reliefs[] = {{0.02, 0.1}, {0.03, 0.1}};
    const Setup setups[] = {
        {"the same station", false, {0, 0, 0}}, {"1 m higher", true, {0, 0, 1.0}},
        {"1 m lower", true, {0, 0, -1.0}},      {"3 m along x", true, {3.0, 0, 0}},
        {"3 m along y", true, {0, 3.0, 0}},     {"3 m along -y", true, {0, -3.0, 0}}};
    for (const auto& r : reliefs) {
        for (const auto& st : setups) {
            Pooled m3c2, pb;
            for (int seed = first; seed < first + draws; ++seed) {
                sim::Site site = test::rough_slope(r.roughness, r.wavelength);
                site.noise.seed = static_cast<std::uint64_t>(seed);
                if (st.moved) {
                    site.events.station_change_epoch = 1;
                    site.events.station_shift = st.shift;
                    site.events.station_turn_deg = 0.0;
                }
                // ±6°: the zone seen whole from every station.
                const auto [m, p] = test::score_slope(site, 3, 6.0);
                m3c2.add(m), pb.add(p);
            }
            std::printf("±%.0f cm at %.2f m, epochs from %s (%d draws from seed %d):\n",
                        1e2 * r.roughness, r.wavelength, st.name, draws, first);
            m3c2.print("M3C2");
            pb.print("PB-M3C2");
            std::fflush(stdout);
        }
    }
}
