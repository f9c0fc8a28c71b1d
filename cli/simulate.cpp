// `tlsmon simulate`: a series of synthetic scans (PTX) with their truth (JSON) and the site
// weather station's meteo file (CSV), all at once or in real time into an ingest folder, as
// a scanner and a weather station on site would deliver them.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "cli/commands.hpp"
#include "demo/site_config_writer.hpp"
#include "simulator/scene_file.hpp"
#include "simulator/series.hpp"

namespace tlsmon {

void simulate_campaign(const sim::Site& site, const SimulateOptions& options);

namespace {

void write_all(const std::filesystem::path& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    f.close();
    if (!f) throw Error("cannot write " + path.string());
}

// Written under a hidden temporary name, then renamed: the file appears complete at once,
// as scanner software and copy tools do.
void write_then_rename(const std::filesystem::path& path, const std::string& text) {
    const std::filesystem::path part =
        path.parent_path() / ("." + path.filename().string() + ".part");
    write_all(part, text);
    std::filesystem::rename(part, path);
}

// Written directly under its final name in chunks spread over `seconds`, so the file
// grows visibly (a slow network copy) and a watcher must wait until it is complete.
void write_slowly(const std::filesystem::path& path, const std::string& text, double seconds) {
    constexpr int chunks = 20;
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    const std::size_t step = (text.size() + chunks - 1) / chunks;
    const auto pause = std::chrono::duration<double>(seconds / chunks);
    for (std::size_t at = 0; at < text.size(); at += step) {
        const std::size_t n = std::min(step, text.size() - at);
        f.write(text.data() + at, static_cast<std::streamsize>(n));
        f.flush();
        if (!f) throw Error("cannot write " + path.string());
        std::this_thread::sleep_for(pause);
    }
    f.close();
    if (!f) throw Error("cannot write " + path.string());
}

void simulate(const SimulateOptions& o) {
    const std::optional<std::string> preset =
        o.preset.empty() ? std::nullopt : std::optional<std::string>(o.preset);
    sim::Site site = o.config.empty() ? sim::preset(preset.value_or("small"))
                                      : load_scene_file(o.config, preset);
    if (!o.cadence.empty()) site.cadence_seconds = parse_duration_seconds(o.cadence);
    if (site.cadence_seconds <= 0) throw ConfigError("--cadence must be positive");
    if (!o.campaign.empty()) return simulate_campaign(site, o);
    if (o.seed) site.noise.seed = static_cast<std::uint64_t>(*o.seed);
    const std::int64_t start = sim::parse_utc(o.start);
    const std::filesystem::path out(o.out);
    std::filesystem::create_directories(out);
    // The site's configuration (targets, station, zones) before any scan.
    write_then_rename(out / "site.toml", site_configuration(site));

    const auto wall_start = std::chrono::steady_clock::now();
    for (int epoch = 0; epoch < o.epochs; ++epoch) {
        if (o.realtime > 0.0 && epoch > 0) {
            std::this_thread::sleep_until(
                wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(o.realtime * epoch)));
        }
        const auto t0 = std::chrono::steady_clock::now();
        const sim::EpochFiles f = sim::simulate_epoch(site, epoch, start, o.threads);
        // The weather station logs whether or not the scanner delivers, and its file is in
        // place before the scan, like the truth.
        if (!f.meteo.empty()) write_then_rename(out / (f.stem + ".meteo.csv"), f.meteo);
        if (f.missing) {
            std::cout << "epoch " << epoch << " " << sim::format_utc(f.acquired_utc)
                      << ": missing scan (" << (f.meteo.empty() ? "nothing written" : "meteo only")
                      << ")" << std::endl;
            continue;
        }
        // The truth first, so it is in place when a watcher sees the scan.
        write_then_rename(out / (f.stem + ".truth.json"), f.truth.dump(2) + "\n");
        const std::filesystem::path ptx = out / (f.stem + ".ptx");
        if (o.slow_copy > 0.0) {
            write_slowly(ptx, f.ptx, o.slow_copy);
        } else {
            write_then_rename(ptx, f.ptx);
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::cout << "epoch " << epoch << " " << sim::format_utc(f.acquired_utc) << ": "
                  << ptx.string() << " " << f.truth["scan"]["rows"] << " rows x "
                  << f.truth["scan"]["columns"] << " columns, " << f.truth["scan"]["points"]
                  << " points" << (f.cut_short ? " (cut short)" : "") << ", " << seconds << " s"
                  << std::endl;
    }
}

}  // namespace

int run_simulate(const SimulateOptions& options) {
    try {
        simulate(options);
    } catch (const std::exception& e) {
        std::cerr << "tlsmon simulate: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
