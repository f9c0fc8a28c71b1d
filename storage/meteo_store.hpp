#pragma once
// The meteo sidecars recorded outside an epoch commit (one that came after its epoch was
// processed, an orphan), and the lookups the ingest and `tlsmon query meteo` need. The
// sidecar an epoch was processed with is written by its commit (ResultsWriter).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "storage/epochs.hpp"
#include "storage/ids.hpp"
#include "storage/meteo_sidecar.hpp"

namespace tlsmon {

struct TimeRange;

// The weather an epoch was processed with.
struct EpochMeteo {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;  // the epoch's acquisition time
    double air_temperature_c = 0, pressure_hpa = 0, relative_humidity_pct = 0;
};

class MeteoStore {
  public:
    explicit MeteoStore(Connection& connection) : c_(&connection) {}

    // The latest record of a sidecar with these bytes under this name, if any.
    std::optional<MeteoSidecar> find(const std::string& sha256, const std::string& file_name) const;
    // Every sidecar recorded for the epoch, in the order recorded.
    std::vector<MeteoSidecar> of_epoch(EpochId id) const;
    // The epochs acquired in the range that were processed with a sidecar's row, by
    // acquisition time.
    std::vector<EpochMeteo> used_in_range(const TimeRange& range) const;
    // The latest epoch whose scan was found in `folder` with this stem (the scan of the
    // sidecar `<folder>/<stem>.meteo.csv`), if any.
    std::optional<Epoch> scan_epoch(const std::filesystem::path& folder,
                                    const std::string& stem) const;
    // An unused or orphan sidecar (its own transaction).
    void record(const MeteoSidecar& sidecar);

  private:
    Connection* c_;
};

}  // namespace tlsmon
