// Does each method's own σ / LoD95 cover its error at the nominal rate over independent
// series? `tlsmon calibration --truth` scores one series, and within a series every epoch
// shares the reference epoch's errors (the registration's reference centres above all), so a
// day of epochs is one draw of them (docs/calibration.md, "One series is one draw"). Here
// SERIES series of the demo's scene (the `small` preset at 0.05°, five spheres, the abutment's
// check zone), each with its own noise and drift seed, its own start in the day and its own
// cadence, are each rendered by `tlsmon simulate`, processed by `tlsmon run --once` with the
// demo's configuration and scored by `tlsmon calibration --truth --format json`; its rows are
// pooled over the series (counts, covered shares, bias, RMS), with the Wilson bands and the
// verdicts of report/calibration.hpp. Nothing is tuned here: it is the defaults that are scored.
//
//   bench_method_coverage [SERIES=40] [FIRST_SEED=3000] [--epochs N=3] [--keep DIR]
//                         [--set SECTION.KEY=VALUE]...
//
// `--set` puts `KEY = VALUE` (TOML) into the daemon's configuration's [SECTION], to score a
// setting other than the default (e.g. --set registration.covariance_scaling='"a_priori"').
// The environment's TLSMON_BENCH_BINARY, when set, is the tlsmon that runs instead of the
// build's, to score two builds on the same seeds.
//
// Series k (seed FIRST_SEED + k) starts frac(0.618·k) of a day after midnight, k + 2 days
// before today (the daemon refuses scans dated ahead of its clock), every 1 + 5·frac(0.382·k)
// hours: the scanner's drift and the thermal bending sweep the day. The scene's knocked target
// and step lie beyond the N epochs: nothing but the thermal bending moves.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/daemon_bench.hpp"
#include "core/utc_time.hpp"
#include "report/calibration.hpp"
#include "tests/support/daemon_harness.hpp"

using namespace tlsmon;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Runs `command`, throwing with its output when it fails.
void run(const std::string& command) {
    const auto r = test::shell(command);
    if (r.status != 0) throw std::runtime_error("failed: " + command + "\n" + r.output);
}

// One (method, part) pooled over the series.
struct Pool {
    std::string unit;
    std::size_t n = 0, within68 = 0, within95 = 0;
    double sum = 0, sum2 = 0, sigma2 = 0, worst = 0;
    bool numbers = true;  // false for χ² shares and a registration's mixed "all"
    int series = 0;

    void add(const json& row) {
        const auto k = row.at("n").get<std::size_t>();
        n += k;
        within68 +=
            std::size_t(std::llround(row.at("cover68_pct").get<double>() * double(k) / 100));
        within95 +=
            std::size_t(std::llround(row.at("cover95_pct").get<double>() * double(k) / 100));
        ++series;
        if (!row.contains("bias") || row.at("bias").is_null()) {
            numbers = false;
            return;
        }
        unit = row.value("unit", "");
        const double bias = row.at("bias"), rms = row.at("rms"), s = row.at("rms_sigma");
        sum += bias * double(k);
        sum2 += rms * rms * double(k);
        sigma2 += s * s * double(k);
        worst = std::max(worst, row.at("max_abs").get<double>());
    }
};

void print(const std::map<std::pair<std::string, std::string>, Pool>& pools) {
    std::printf("%-34s %-16s %5s %4s %8s %8s %8s %9s | %6s %-11s %-16s | %6s %-11s %s\n", "method",
                "part", "n", "unit", "bias", "rms", "max", "rms_sigma", "cov68", "band", "verdict",
                "cov95", "band", "verdict");
    for (const auto& [key, p] : pools) {
        const auto b68 = report::wilson_interval(p.within68, p.n);
        const auto b95 = report::wilson_interval(p.within95, p.n);
        std::printf("%-34s %-16s %5zu %4s ", key.first.c_str(), key.second.c_str(), p.n,
                    p.unit.c_str());
        if (p.numbers && p.n > 0) {
            const double nn = double(p.n);
            std::printf("%+8.3f %8.3f %8.3f %9.3f", p.sum / nn, std::sqrt(p.sum2 / nn), p.worst,
                        std::sqrt(p.sigma2 / nn));
        } else {
            std::printf("%8s %8s %8s %9s", "", "", "", "");
        }
        std::printf(" | %5.1f%% %4.1f-%5.1f%% %-16s | %5.1f%% %4.1f-%5.1f%% %s\n",
                    100.0 * double(p.within68) / double(std::max<std::size_t>(p.n, 1)),
                    100 * b68.lower, 100 * b68.upper,
                    report::to_string(report::sigma_verdict(p.within68, p.n, report::kNominal68)),
                    100.0 * double(p.within95) / double(std::max<std::size_t>(p.n, 1)),
                    100 * b95.lower, 100 * b95.upper,
                    report::to_string(report::sigma_verdict(p.within95, p.n, report::kNominal95)));
    }
}

// One `--set SECTION.KEY=VALUE`: the line `KEY = VALUE` for the section's header.
struct Setting {
    std::string header, line;
};

std::optional<Setting> parse_setting(const std::string& assignment) {
    const auto dot = assignment.find('.'), eq = assignment.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot) return std::nullopt;
    return Setting{
        "[" + assignment.substr(0, dot) + "]\n",
        assignment.substr(dot + 1, eq - dot - 1) + " = " + assignment.substr(eq + 1) + "\n"};
}

// The setting's line under its section's header, or in a new section at the end.
void apply(std::string& config, const Setting& s) {
    const auto at = config.find("\n" + s.header);
    if (at == std::string::npos)
        config += "\n" + s.header + s.line;
    else
        config.insert(at + 1 + s.header.size(), s.line);
}

double frac(double x) {
    return x - std::floor(x);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args;
    int epochs = 3;
    fs::path keep;
    std::vector<Setting> settings;
    bool bad_setting = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--epochs" && i + 1 < argc) {
            epochs = std::atoi(argv[++i]);
        } else if (a == "--keep" && i + 1 < argc) {
            keep = argv[++i];
        } else if (a == "--set" && i + 1 < argc) {
            const std::string assignment = argv[++i];
            if (const auto setting = parse_setting(assignment)) {
                settings.push_back(*setting);
            } else {
                std::fprintf(stderr, "--set wants SECTION.KEY=VALUE, not %s\n", assignment.c_str());
                bad_setting = true;
            }
        } else {
            args.push_back(a);
        }
    }
    const int series = args.size() > 0 ? std::atoi(args[0].c_str()) : 40;
    const int first_seed = args.size() > 1 ? std::atoi(args[1].c_str()) : 3000;
    if (series < 1 || epochs < 2 || bad_setting) {
        std::fprintf(stderr,
                     "usage: bench_method_coverage [SERIES] [FIRST_SEED] [--epochs N>=2] "
                     "[--keep DIR] [--set SECTION.KEY=VALUE]...\n");
        return 2;
    }
    bench::BenchDir tmp;
    const char* other = std::getenv("TLSMON_BENCH_BINARY");
    const std::string tlsmon = other ? other : TLSMON_BINARY;
    // The demo's scene with its events beyond the series: 96 epochs put them at 24 and 48.
    const std::string scene_text = scene_file_text(demo_scene("small", 96));
    const sim::Site site = parse_scene_file(scene_text, "demo", std::nullopt);
    const std::int64_t today = now_utc() / 86400 * 86400;
    std::map<std::pair<std::string, std::string>, Pool> pools;
    const auto t0 = std::chrono::steady_clock::now();
    int failed = 0;
    for (int k = 0; k < series; ++k) {
        const int seed = first_seed + k;
        const fs::path dir = (keep.empty() ? tmp / "series" : keep) / std::to_string(seed);
        fs::remove_all(dir);
        const fs::path config = bench::write_daemon_folder(dir, scene_text, site);
        if (!settings.empty()) {
            std::string text = bench::read_text(config);
            for (const auto& setting : settings) apply(text, setting);
            bench::write_text(config, text);
        }
        const std::int64_t start =
            today - (k + 2) * 86400 + std::llround(86400 * frac(0.6180339887 * k));
        const double cadence_h = 1.0 + 5.0 * frac(0.3819660113 * k);
        try {
            run(tlsmon + " simulate --config " + (dir / "scene.toml").string() + " --out " +
                (dir / "scans").string() + " --epochs " + std::to_string(epochs) + " --seed " +
                std::to_string(seed) + " --start " + format_utc(start) + " --cadence " +
                std::to_string(std::lround(cadence_h * 60)) + "min");
            for (const auto& f : fs::directory_iterator(dir / "scans")) {
                const auto ext = f.path().extension();
                if (ext == ".ptx" || ext == ".csv") bench::place(f.path(), dir / "ingest");
            }
            run(tlsmon + " run --once --config " + config.string() + " > " +
                (dir / "daemon.out").string());
            run(tlsmon + " calibration --config " + config.string() + " --truth " +
                (dir / "scans").string() + " --format json > " +
                (dir / "calibration.json").string());
            const json rows = json::parse(bench::read_text(dir / "calibration.json"));
            for (const auto& row : rows)
                pools[{row.at("method").get<std::string>(), row.at("part").get<std::string>()}].add(
                    row);
        } catch (const std::exception& e) {
            ++failed;
            std::fprintf(stderr, "series %d (seed %d): %s\n", k, seed, e.what());
        }
        if (keep.empty()) fs::remove_all(dir);
        std::fprintf(stderr, "series %d of %d done, %.0f s\n", k + 1, series,
                     bench::seconds_since(t0));
    }
    std::printf(
        "demo scene: %d series of %d epochs from seed %d (%d failed), %.0f s wall, %.0f s CPU "
        "of this process's children\n",
        series, epochs, first_seed, failed, bench::seconds_since(t0),
        bench::children_cpu_seconds());
    print(pools);
    return failed ? 1 : 0;
}
