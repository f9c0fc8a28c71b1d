#pragma once
// The line per epoch `tlsmon demo` prints while the daemon works: read from the epoch
// database (read only) as each epoch is committed — its registration, the zone values with
// their level of detection, and the alarm changes it caused.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "storage/epoch_database.hpp"

namespace tlsmon {

class DemoProgress {
  public:
    // `start` and `cadence` (s) number the epochs as the simulator did; `zones` are shown in
    // this order when they have values.
    DemoProgress(std::filesystem::path database, int total, std::int64_t start, double cadence,
                 std::vector<std::string> zones, std::ostream& out);
    ~DemoProgress();

    // Prints the epochs committed since the last call; returns how many are processed
    // (done, rejected or failed). A database not there yet counts as none.
    int poll();

  private:
    std::string line(const EpochDatabase& db, const Epoch& e);

    std::filesystem::path database_;
    int total_;
    std::int64_t start_;
    double cadence_;
    std::vector<std::string> zones_;
    std::ostream& out_;
    std::unique_ptr<EpochDatabase> db_;
    std::set<EpochId> printed_;
    bool zone_values_seen_ = false;
    bool told_no_zone_values_ = false;
};

}  // namespace tlsmon
