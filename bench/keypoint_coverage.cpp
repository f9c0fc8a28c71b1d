// Does the keypoints' LoD95 (and M3C2's beside it) cover the error at the nominal rate on the
// `pier` and `hochmosel` presets, over independent series? The keypoint tests score one series
// each (tests/pipeline/test_keypoints_simulated.cpp), and within a series every epoch shares
// the reference epoch's errors — its noise, its targets' centres — so a day of epochs is one
// draw of them (docs/calibration.md, "One series is one draw"). Here SERIES series, each with
// its own noise and drift seed, its own start in the day and its own cadence, are rendered and
// processed as the tests do (tests/pipeline/keypoint_series.hpp: the targets' and the faces'
// windows, the registration on the targets, the keypoint stage, M3C2 in the same zones) and
// every zone figure is scored against the truth over the zone's area. Nothing is tuned: the
// defaults are scored.
//
//   bench_keypoint_coverage PRESET [SERIES=14] [FIRST_SEED=5000] [--epochs N=4] [--patches]
//                           [--scaling a_priori|larger_of|a_posteriori] [--stray-distance M]
//
// PRESET: `pier` (the south face and its four 10 m bands) or `hochmosel` (the detail strip's
// thirteen 10 m bands). Series k (seed FIRST_SEED + k) starts 24·frac(0.618·k) hours into the
// preset's day and takes an epoch every 1 + 5·frac(0.382·k) hours: the drift and the thermal
// bending sweep the day. Prints per method (keypoints along h and v, M3C2's zone median and
// mean; with --patches also PB-M3C2's, its defaults on the reference's supervoxels) pooled
// and per zone: n, bias, RMS, max, RMS of the σ (LoD95 / 1.96), RMS(error/σ), the
// coverage of the 68 % and 95 % intervals with their Wilson bands (report/calibration.hpp),
// and the bands and verdicts with the series as clusters (a series' figures share its
// reference's draw: they count as n_eff independent ones); then the wall and CPU seconds;
// last, the keypoints' own error over their standard error by the epoch's lattice phase.
// Each method's figures are also split in two: "reg", the epoch's realized registration
// error over the zone's area along the figure (test::registration_error_at) against the
// registration's σ along it; "own", the error less that, against the rest of the σ (the
// keypoints' standard error; the normal aggregates' sampling part, √(σ² − σ_reg²)): which of
// the two misses. --stray-distance: M3C2's `stray_distance` (100: the method as published).
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "report/calibration.hpp"
#include "tests/pipeline/keypoint_series.hpp"

namespace {

using namespace tlsmon;

double frac(double x) {
    return x - std::floor(x);
}

// One method and zone's figures, each with the series it came from.
struct Scored {
    std::vector<report::ScoredFigure> figures;
    std::vector<int> series;
};

// RMS(error/σ): 1 for an honest σ, whatever the coverage's sampling noise.
double rms_z(const std::vector<report::ScoredFigure>& figures) {
    double sum = 0;
    for (const auto& f : figures) sum += (f.error / f.sigma) * (f.error / f.sigma);
    return figures.empty() ? NAN : std::sqrt(sum / double(figures.size()));
}

// A coverage whose figures come in clusters (the series: their epochs share the reference's
// draw, an epoch's zones its registration) as that many independent figures: n / deff, deff =
// V_cluster / V_binomial ≥ 1 (Kish 1965's design effect), V_cluster = G/(G − 1) ·
// Σ_g (hits_g − p̂·n_g)² / n² over the G series (the cluster-robust variance of the share);
// the hits scaled with it. Its Wilson band and verdict are report/calibration.hpp's.
struct EffectiveCount {
    std::size_t hits = 0, n = 0;
};

EffectiveCount clustered(const Scored& s, double multiple) {
    std::map<int, std::pair<double, double>> by_series;  // series -> (hits, n)
    for (std::size_t i = 0; i < s.figures.size(); ++i) {
        const auto& f = s.figures[i];
        auto& [hits, n] = by_series[s.series[i]];
        hits += std::abs(f.error) <= multiple * f.sigma;
        n += 1;
    }
    const double n = double(s.figures.size());
    double hits = 0;
    for (const auto& [g, hn] : by_series) hits += hn.first;
    const double p = hits / n, groups = double(by_series.size());
    double v = 0;
    for (const auto& [g, hn] : by_series)
        v += (hn.first - p * hn.second) * (hn.first - p * hn.second);
    v *= groups > 1 ? groups / (groups - 1) / (n * n) : 0;
    const double binomial = p * (1 - p) / n;
    const double deff = binomial > 0 ? std::max(1.0, v / binomial) : 1.0;
    const auto k = std::size_t(std::llround(n / deff));
    return {std::size_t(std::llround(p * double(k))), k};
}

void print(const std::map<std::pair<std::string, std::string>, Scored>& scored) {
    std::printf(
        "%-20s %-14s %4s %7s %6s %6s %6s %5s | %6s %-11s | %6s %-11s | %5s %-11s %-15s | "
        "%-11s %s\n",
        "method", "zone", "n", "bias", "rms", "max", "σ", "e/σ", "cov68", "Wilson band", "cov95",
        "Wilson band", "n_eff", "band68", "verdict68", "band95", "verdict95");
    for (const auto& [key, s] : scored) {
        const report::CoverageRow r = report::coverage_of(key.first, key.second, s.figures);
        const EffectiveCount c68 = clustered(s, 1.0), c95 = clustered(s, report::kLod95Factor);
        const auto b68 = report::wilson_interval(c68.hits, c68.n);
        const auto b95 = report::wilson_interval(c95.hits, c95.n);
        std::printf(
            "%-20s %-14s %4zu %+7.3f %6.3f %6.3f %6.3f %5.2f | %5.1f%% %4.1f-%5.1f%% | "
            "%5.1f%% %4.1f-%5.1f%% | %5zu %4.1f-%5.1f%% %-15s | %4.1f-%5.1f%% %s\n",
            r.method.c_str(), r.part.c_str(), r.n, 1e3 * r.error.bias, 1e3 * r.error.rms,
            1e3 * r.error.max_abs, 1e3 * r.rms_sigma, rms_z(s.figures), 100 * r.coverage68(),
            100 * r.band68.lower, 100 * r.band68.upper, 100 * r.coverage95(), 100 * r.band95.lower,
            100 * r.band95.upper, std::min(c68.n, c95.n), 100 * b68.lower, 100 * b68.upper,
            report::to_string(report::sigma_verdict(c68.hits, c68.n, report::kNominal68)),
            100 * b95.lower, 100 * b95.upper,
            report::to_string(report::sigma_verdict(c95.hits, c95.n, report::kNominal95)));
    }
}

// The keypoints' own error by the fraction of a pixel φ = frac(−shift) the epoch's image lies
// off the reference's lattice (docs/keypoints.md, "The lattice's phase"): an error common to
// a zone's matches that depends on φ shows as a mean of error/SE away from 0 in some bins.
void print_by_phase(const std::array<std::vector<std::pair<double, double>>, 2>& by_phase) {
    constexpr int kBins = 8;
    std::printf(
        "\nthe keypoints' own error / SE by the lattice phase φ (h: azimuth, v: elevation)\n");
    std::printf("φ bin        |  n  h mean  h RMS |  n  v mean  v RMS\n");
    for (int b = 0; b < kBins; ++b) {
        std::printf("%.3f-%.3f ", double(b) / kBins, double(b + 1) / kBins);
        for (const auto& figures : by_phase) {
            double n = 0, sum = 0, sum2 = 0;
            for (const auto& [phase, z] : figures)
                if (int(phase * kBins) == b) n += 1, sum += z, sum2 += z * z;
            std::printf(" | %3.0f %+6.2f %6.2f", n, n > 0 ? sum / n : NAN,
                        n > 0 ? std::sqrt(sum2 / n) : NAN);
        }
        std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args;
    int epochs = 4;
    bool patches = false;
    std::string scaling_name = to_string(RegistrationConfig{}.covariance_scaling);
    double stray_distance = M3c2Config{}.stray_distance;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--epochs" && i + 1 < argc)
            epochs = std::atoi(argv[++i]);
        else if (a == "--patches")
            patches = true;
        else if (a == "--scaling" && i + 1 < argc)
            scaling_name = argv[++i];
        else if (a == "--stray-distance" && i + 1 < argc)
            stray_distance = std::atof(argv[++i]);
        else
            args.push_back(a);
    }
    const std::string preset = args.empty() ? "" : args[0];
    const int series = args.size() > 1 ? std::atoi(args[1].c_str()) : 14;
    const int first_seed = args.size() > 2 ? std::atoi(args[2].c_str()) : 5000;
    const auto scaling = covariance_scaling_named(scaling_name);
    if ((preset != "pier" && preset != "hochmosel") || series < 1 || epochs < 2 || !scaling) {
        std::fprintf(stderr,
                     "usage: bench_keypoint_coverage pier|hochmosel [SERIES] [FIRST_SEED] "
                     "[--epochs N>=2] [--patches] [--scaling a_priori|larger_of|a_posteriori] "
                     "[--stray-distance M]\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::map<std::pair<std::string, std::string>, Scored> scored;
    int k = 0;  // the series
    const auto score = [&](const std::string& method, const std::string& zone, double error,
                           double lod95) {
        if (!std::isfinite(error) || !std::isfinite(lod95) || lod95 <= 0) return;
        const report::ScoredFigure f{error, lod95 / report::kLod95Factor};
        for (const auto& part : {std::string("all"), zone}) {
            scored[{method, part}].figures.push_back(f);
            scored[{method, part}].series.push_back(k);
        }
    };
    // An aggregate along the normals whole, its registration part and the rest: the
    // aggregate's σ is the quadratic sum of the two (algorithms/m3c2/zone_uncertainty.hpp).
    const auto score_normal = [&](const std::string& method, const std::string& zone,
                                  const test::NormalFigure& f) {
        const double error = f.value - f.truth, sigma = f.lod / report::kLod95Factor;
        score(method, zone, error, f.lod);
        score(method + " reg", zone, f.registration_error,
              report::kLod95Factor * f.registration_sigma);
        score(method + " own", zone, error - f.registration_error,
              report::kLod95Factor *
                  std::sqrt(sigma * sigma - f.registration_sigma * f.registration_sigma));
    };
    // The keypoints' own error over their standard error, h and v, with the epoch's lattice
    // phase along azimuth and elevation: (φ, z).
    std::array<std::vector<std::pair<double, double>>, 2> by_phase;
    int refused = 0, undefined = 0;
    for (; k < series; ++k) {
        test::Scenario scenario =
            preset == "pier" ? test::pier_scenario() : test::hochmosel_scenario();
        scenario.site.noise.seed = static_cast<std::uint64_t>(first_seed + k);
        scenario.covariance_scaling = *scaling;
        scenario.m3c2_stray_distance = stray_distance;
        const double start = 24.0 * frac(0.6180339887 * k);
        const double cadence = 1.0 + 5.0 * frac(0.3819660113 * k);
        std::vector<double> hours;
        for (int e = 0; e < epochs; ++e) hours.push_back(start + e * cadence);
        const test::Series s = test::run_series(scenario, hours, patches);
        for (const auto& why : s.refused)
            std::fprintf(stderr, "series %d: refused %s\n", k, why.c_str());
        refused += int(s.refused.size());
        for (const auto& f : s.figures) {
            if (f.zone == "west") continue;  // grazing: undefined by design
            if (!f.d.defined() || !f.truth.allFinite()) {
                ++undefined;
                continue;
            }
            // Each figure whole, then split: its realized registration error against the
            // registration's σ along it, and the rest against the method's own σ.
            const auto& w = f.d.wall;
            for (int k = 1; k < 3; ++k) {
                const std::string method = k == 1 ? "keypoints h" : "keypoints v";
                const Eigen::Vector3d u = k == 1 ? w.horizontal : w.vertical;
                const double error = f.d.along[k] - f.truth[k];
                score(method, f.zone, error,
                      test::lod_of(f.zone, f.d, f.registration,
                                   k == 1 ? kKeypointAlongSurfaceH : kKeypointAlongSurfaceV));
                score(method + " reg", f.zone, f.registration_error[k],
                      report::kLod95Factor * std::sqrt(u.dot(f.registration * u)));
                score(method + " own", f.zone, error - f.registration_error[k],
                      report::kLod95Factor * f.d.along_standard_error[k]);
                const double phase = -f.lattice_shift[k - 1] - std::floor(-f.lattice_shift[k - 1]);
                by_phase[k - 1].push_back(
                    {phase, (error - f.registration_error[k]) / f.d.along_standard_error[k]});
            }
            score_normal("m3c2 median", f.zone, f.m3c2_median);
            score_normal("m3c2 mean", f.zone, f.m3c2_mean);
            score_normal("pbm3c2 median", f.zone, f.pbm3c2_median);
            score_normal("pbm3c2 mean", f.zone, f.pbm3c2_mean);
        }
        std::fprintf(stderr, "series %d of %d (seed %d, %.1f h + %.1f h steps) done, %.0f s\n",
                     k + 1, series, first_seed + k, start, cadence, bench::seconds_since(t0));
    }
    std::printf(
        "%s: %d series of %d epochs from seed %d, covariance_scaling %s; %d epochs refused, %d "
        "zone figures undefined; %.0f s wall, %.0f s CPU\n",
        preset.c_str(), series, epochs, first_seed, scaling_name.c_str(), refused, undefined,
        bench::seconds_since(t0), bench::process_cpu_seconds());
    print(scored);
    print_by_phase(by_phase);
    return 0;
}
