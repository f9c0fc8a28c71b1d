#pragma once
// What the report reads from an epoch database (read only): the epochs, their
// registrations and targets, the zones with their time series, the alarm rules and events.
// Plain structs, so the comparison with the truth (report/analysis.hpp) is pure.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "report/truth.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon::report {

struct RunEpoch {
    Epoch epoch;
    std::optional<RegistrationRow> registration;
    std::vector<TargetObservation> targets;
    std::vector<RegistrationZoneSigma> zone_sigmas;
};

struct RunZone {
    ZoneId id = 0;  // its Modbus slot is id − 1 (docs/modbus.md)
    std::string name;
    std::optional<ZoneBox> box;  // absent for a zone that is not a box
    bool no_change = false;      // a check zone on ground known not to move ([[zone]])
    // quantity -> its time series, by acquisition time
    std::map<std::string, std::vector<SeriesPoint>> series;
};

struct RunData {
    std::filesystem::path database;
    std::optional<EpochId> reference;
    std::vector<RunEpoch> epochs;  // by acquisition time
    std::vector<RunZone> zones;    // by id
    std::vector<AlarmRule> rules;  // configured rules (system.* left out)
    std::vector<AlarmEvent> alarm_events;
    std::vector<CampaignRow> campaigns;  // acquired in the window (docs/campaigns.md)
};

// Reads everything the report needs of the epochs acquired in `window` (open: all of them);
// the reference epoch is read too when it lies outside, since every comparison is a
// difference to it. Throws StorageError (naming the file) when the database cannot be opened.
// `series`: every zone's time series, or only the check zones' (all that is scored without
// a truth: a year of a large site's series is gigabytes of copies for nothing).
enum class ZoneSeries { all, check_zones };
RunData read_run(const std::filesystem::path& database, const TimeRange& window = {},
                 ZoneSeries series = ZoneSeries::all);
RunData read_run(const EpochDatabase& db, const TimeRange& window = {},
                 ZoneSeries series = ZoneSeries::all);

// A zone definition as stored ({"type":"box","min":[..],"max":[..]}); nullopt otherwise.
std::optional<ZoneBox> parse_zone_box(const std::string& definition_json);
// Whether a stored zone definition marks a no-change check zone ("no_change": true).
bool parse_zone_no_change(const std::string& definition_json);

}  // namespace tlsmon::report
