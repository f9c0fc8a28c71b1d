#include "daemon/http/calibration_api.hpp"

#include "report/calibration.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

Json band_json(const report::ShareInterval& b) {
    return Json::array({b.lower, b.upper});
}

Json number_or_null(bool blank, double v) {
    return blank ? Json(nullptr) : Json(v);
}

// One row in SI units (m, rad) with its unit named; the page shows mm and µrad.
Json row_json(const report::CoverageRow& r) {
    const bool blank = r.blank_numbers();
    return Json{{"method", r.method},
                {"part", r.part},
                {"n", r.n},
                {"unit", blank ? Json(nullptr) : Json(r.angle() ? "rad" : "m")},
                {"bias", number_or_null(blank, r.error.bias)},
                {"rms", number_or_null(blank, r.error.rms)},
                {"max_abs", number_or_null(blank, r.error.max_abs)},
                {"rms_sigma", number_or_null(blank, r.rms_sigma)},
                {"within68", r.within68},
                {"within95", r.within95},
                {"band68", band_json(r.band68)},
                {"band95", band_json(r.band95)},
                {"verdict68", report::to_string(r.verdict68)},
                {"verdict95", report::to_string(r.verdict95)}};
}

}  // namespace

Json calibration_json(const EpochDatabase& db, const TimeRange& window) {
    const report::RunData run = report::read_run(db, window, report::ZoneSeries::check_zones);
    const report::RunReport scored = report::analyse(run, {}, {});
    std::size_t epochs = 0;
    for (const auto& e : run.epochs) {
        if (e.epoch.acquired >= window.lower() && e.epoch.acquired <= window.upper()) ++epochs;
    }
    Json rows = Json::array();
    for (const auto& r : report::calibration(scored)) rows.push_back(row_json(r));
    return Json{{"from", time_or_null(window.from)},
                {"to", time_or_null(window.to)},
                {"epochs", epochs},
                {"rows", std::move(rows)}};
}

}  // namespace tlsmon
