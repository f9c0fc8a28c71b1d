#pragma once
// The dashboard's JSON API (docs/http.md): each resource as a function from the epoch
// database (a read-only connection) and the request's parameters to JSON. No sockets here:
// daemon/http/http_service.cpp maps URLs to these.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/series_reader.hpp"

namespace tlsmon {

class EpochDatabase;

using Json = nlohmann::ordered_json;

// A time as ISO 8601 UTC text, null when absent (an open end of a window).
Json time_or_null(const std::optional<UtcSeconds>& t);

// What the daemon knows of itself and the site that the database does not say.
struct DashboardSite {
    std::string station;
    std::vector<std::string> zones;  // as configured, in file order
    UtcSeconds started = 0;          // the daemon's start
    std::optional<double> disk_free_share;
};

// `/api/v1/site`: station, daemon, epochs and backlog, the last epoch with its registration,
// the active alarms, and `zones` as zone_overview made them.
Json site_overview(const EpochDatabase& db, const DashboardSite& site, UtcSeconds now,
                   UtcSeconds heartbeat, Json zones);
// Every zone quantity's latest value with a day's sparkline: it changes only when an epoch
// commits, so the server keeps it from one commit to the next.
Json zone_overview(const EpochDatabase& db, const DashboardSite& site);

// `/api/v1/zones`: every zone with its stored quantities.
Json zone_list(const EpochDatabase& db, const DashboardSite& site);

// `/api/v1/series?zone=Z&quantity=Q&from=T&to=T&width=W`.
struct SeriesRequest {
    std::string zone;
    std::string quantity;
    TimeRange range;
    std::size_t width = 0;  // the chart's pixels: at most 2 points per pixel; 0 = every point
};

struct SeriesView {
    SeriesRequest request;
    std::size_t total = 0;            // points in the window before decimation
    std::vector<SeriesPoint> points;  // what is shown
};

SeriesView series_view(const EpochDatabase& db, const SeriesRequest& request);
// With the alarm rules watching the quantity (levels), their raises and acknowledgements,
// the rejected epochs inside the window, and the keypoint model d(t, z) at the zone's height
// where the quantity has one.
Json series_json(const EpochDatabase& db, const SeriesView& view);
// `/api/v1/meteo?from&to&width`: the air temperature and pressure each epoch of the window
// was processed with, each decimated to `width` like a series (0: every epoch).
Json meteo_json(const EpochDatabase& db, const TimeRange& range, std::size_t width);
// Exactly the points of the view, one per line (docs/http.md).
std::string series_csv(const SeriesView& view);

// `/api/v1/events?from&to&kind`, `/api/v1/alarms`, `/api/v1/epochs?from&to`,
// `/api/v1/epochs/N`.
Json events_json(const EpochDatabase& db, const TimeRange& range,
                 const std::optional<std::string>& kind);
Json alarms_json(const EpochDatabase& db, const TimeRange& history);
Json epochs_json(const EpochDatabase& db, const TimeRange& range);
std::optional<Json> epoch_json(const EpochDatabase& db, EpochId id);

// `/api/v1/epochs/N/corepoints`: the epoch's M3C2 map per zone in the zone's wall frame
// (u along the wall, horizontal; v up), one entry per core point with a distance. An Error
// when there is none (`absent`: no such epoch, no M3C2 result in it; the text in the
// Error) or when the stored map cannot be put together (`absent` false: the server's
// fault).
Json core_point_map_json(const EpochDatabase& db, EpochId id, bool& absent);

}  // namespace tlsmon
