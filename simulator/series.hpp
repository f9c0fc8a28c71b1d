#pragma once
// A series of epochs: acquisition times, file names, and one epoch's files as text.
//
// File names carry the acquisition time, since PTX headers have none:
//   <station>_YYYYMMDDTHHMMSSZ.ptx  and  <station>_YYYYMMDDTHHMMSSZ.truth.json   (UTC)
// and the weather station's <station>_YYYYMMDDTHHMMSSZ.meteo.csv (meteo_station.hpp).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "formats/ptx_writer.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// "2026-06-01T06:00:00Z" -> seconds since 1970-01-01T00:00:00Z. Throws tlsmon::Error.
std::int64_t parse_utc(const std::string& iso);
// Seconds since the epoch -> "2026-06-01T06:00:00Z".
std::string format_utc(std::int64_t unix_seconds);
// "<station>_20260601T060000Z"
std::string scan_file_stem(const std::string& station, std::int64_t unix_seconds);

struct EpochFiles {
    int epoch = 0;
    std::int64_t acquired_utc = 0;
    std::string stem;
    bool missing = false;    // the scanner exported nothing at this epoch (no files)
    bool cut_short = false;  // the PTX text stops before the declared cells
    std::string ptx;         // empty when missing
    std::string meteo;       // the station's file; written even for a missing scan; empty
                             // when the station is off (site.meteo.enabled)
    nlohmann::json truth;
};

// Renders epoch `epoch` of the series starting at `start_utc` every site.cadence_seconds.
EpochFiles simulate_epoch(const Site& site, int epoch, std::int64_t start_utc, unsigned threads = 2,
                          const PtxWriteOptions& ptx = {});

}  // namespace tlsmon::sim
