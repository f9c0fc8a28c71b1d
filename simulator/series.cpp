#include "simulator/series.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "core/error.hpp"
#include "simulator/meteo_station.hpp"
#include "simulator/render.hpp"
#include "simulator/truth.hpp"

namespace tlsmon::sim {

std::int64_t parse_utc(const std::string& iso) {
    int y, mo, d, h, mi, s;
    char z = 0;
    if (std::sscanf(iso.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c", &y, &mo, &d, &h, &mi, &s, &z) != 7 ||
        z != 'Z' || iso.size() != 20) {
        throw Error("time '" + iso + "': expected UTC as YYYY-MM-DDTHH:MM:SSZ");
    }
    using namespace std::chrono;
    const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                             day{static_cast<unsigned>(d)}};
    if (!ymd.ok() || h > 23 || mi > 59 || s > 59 || h < 0 || mi < 0 || s < 0) {
        throw Error("time '" + iso + "': not a valid date and time");
    }
    return sys_days(ymd).time_since_epoch().count() * 86400LL + h * 3600LL + mi * 60LL + s;
}

std::string format_utc(std::int64_t t) {
    using namespace std::chrono;
    const sys_seconds tp{seconds{t}};
    const auto days = floor<std::chrono::days>(tp);
    const year_month_day ymd{days};
    const hh_mm_ss hms{tp - days};
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02d:%02d:%02dZ", static_cast<int>(ymd.year()),
                  static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                  static_cast<int>(hms.hours().count()), static_cast<int>(hms.minutes().count()),
                  static_cast<int>(hms.seconds().count()));
    return buf;
}

std::string scan_file_stem(const std::string& station, std::int64_t t) {
    std::string iso = format_utc(t);  // 2026-06-01T06:00:00Z -> 20260601T060000Z
    iso.erase(std::remove_if(iso.begin(), iso.end(), [](char c) { return c == '-' || c == ':'; }),
              iso.end());
    return station + "_" + iso;
}

EpochFiles simulate_epoch(const Site& site, int epoch, std::int64_t start_utc, unsigned threads,
                          const PtxWriteOptions& ptx) {
    EpochFiles f;
    f.epoch = epoch;
    const double seconds = epoch * site.cadence_seconds;
    f.acquired_utc = start_utc + static_cast<std::int64_t>(std::llround(seconds));
    f.stem = scan_file_stem(site.scanner.station, f.acquired_utc);
    const auto& missing = site.events.missing_epochs;
    f.missing = std::find(missing.begin(), missing.end(), epoch) != missing.end();
    const double hours = seconds / 3600.0;
    // The weather station logs whether or not the scanner delivers.
    if (site.meteo.enabled) f.meteo = meteo_csv(site, f.acquired_utc);
    const auto meteo_truth = [&](nlohmann::json& truth) {
        truth["meteo_station"] = {
            {"enabled", site.meteo.enabled},
            {"file", site.meteo.enabled ? nlohmann::json(f.stem + ".meteo.csv") : nlohmann::json()},
            {"span_minutes", site.meteo.span_minutes},
            {"temperature_sigma_c", site.meteo.temperature_sigma_c},
            {"pressure_sigma_hpa", site.meteo.pressure_sigma_hpa},
            {"humidity_sigma_pct", site.meteo.humidity_sigma_pct},
            {"resolution", 0.1}};
    };
    if (f.missing) {
        f.truth = truth_json(site, epoch, hours, f.acquired_utc, nullptr);
        f.truth["scan"]["missing"] = true;
        meteo_truth(f.truth);
        return f;
    }
    const EpochConditions rendered_conditions =
        epoch_conditions(site, epoch, hours, f.acquired_utc);
    RenderedScan rendered = render_epoch(site, rendered_conditions, threads);
    rendered.scan.source = f.stem + ".ptx";
    rendered.scan.acquired_utc = static_cast<double>(f.acquired_utc);
    f.ptx = ptx_text(rendered.scan, ptx);
    // Detail scans follow the overview in the same file, as further PTX scans.
    nlohmann::json details = nlohmann::json::array();
    for (std::size_t d = 0; d < site.scanner.details.size(); ++d) {
        const RenderedScan detail = render_detail(site, d, rendered_conditions, threads);
        f.ptx += ptx_text(detail.scan, ptx);
        details.push_back(detail_truth(site.scanner.details[d], detail));
    }
    f.cut_short = site.events.cut_short_epoch == epoch;
    if (f.cut_short) {
        // The export stops part-way (scanner or copy interrupted), at a line boundary.
        const std::size_t keep =
            static_cast<std::size_t>(std::clamp(site.events.cut_short_fraction, 0.0, 1.0) *
                                     static_cast<double>(f.ptx.size()));
        const std::size_t nl = f.ptx.rfind('\n', keep);
        f.ptx.resize(nl == std::string::npos ? 0 : nl + 1);
    }
    f.truth = truth_json(site, epoch, hours, f.acquired_utc, &rendered);
    f.truth["scan"]["file"] = f.stem + ".ptx";
    f.truth["scan"]["cut_short"] = f.cut_short;
    f.truth["scan"]["bytes"] = f.ptx.size();
    f.truth["scan"]["details"] = std::move(details);
    meteo_truth(f.truth);
    return f;
}

}  // namespace tlsmon::sim
