#pragma once
// Pairing each scan with its meteo sidecar `<scan stem>.meteo.csv` (docs/formats.md) in the
// ingest folder. The sidecar may come before or after its scan:
//   - a complete sidecar whose scan is not there yet, or whose epoch is pending, is kept
//     ready; the epoch is processed with it;
//   - a pending epoch without its sidecar waits for it up to meteo.wait_seconds from when the
//     scan was recorded (epochs.discovered, so a restart does not start the wait again), and
//     longer only while the sidecar is there and still being written; then it goes without;
//   - a sidecar that comes after its epoch was processed (or whose scan failed) is not used:
//     it is recorded as `unused` and archived beside its scan (or where the scan went);
//   - a sidecar whose scan has not come after meteo.orphan_seconds is recorded as `orphan`
//     and quarantined with its reason.
// A sidecar is known by its sha256 and name once recorded: seen again after a stop it is
// moved where its record says, or left alone when it stays in place (archive = "keep").
// Nothing here reads the sidecar's values: the pipeline does (pipeline/epoch_meteo.hpp).
#include <filesystem>
#include <map>
#include <optional>

#include "daemon/ingest.hpp"
#include "daemon/watcher.hpp"

namespace tlsmon {

class MeteoSidecars {
  public:
    // A complete sidecar handed out by the watcher.
    void take(IngestContext& ctx, const std::filesystem::path& sidecar, SteadyTime now);

    struct Pairing {
        bool ready = false;                            // the epoch may be processed now ...
        std::optional<std::filesystem::path> sidecar;  // ... with this sidecar, or without
        std::optional<SteadyTime> wake;                // not ready: when to ask again
    };
    // Whether `epoch` may be processed now, and with which sidecar.
    Pairing pair(const Epoch& epoch, const MeteoConfig& config, const FolderWatcher& watcher,
                 SteadyTime now) const;

    // After process_epoch was given `sidecar`: forgotten if the pipeline moved it; taken
    // again if it is still there (the epoch failed, or it stays in place).
    void after_processing(IngestContext& ctx, const std::filesystem::path& sidecar, SteadyTime now);

    // Sidecars kept ready longer than meteo.orphan_seconds without their scan: quarantined.
    void quarantine_orphans(IngestContext& ctx, SteadyTime now);
    // When the next sidecar may become an orphan.
    std::optional<SteadyTime> next_orphan_check() const;

  private:
    // Known by its record: finished or left alone; its epoch processed: unused; no epoch
    // and `may_be_orphan`: orphan; else kept ready for its epoch. A database error keeps it
    // ready (looked at again as a possible orphan later).
    void settle(IngestContext& ctx, const std::filesystem::path& sidecar, SteadyTime now,
                bool may_be_orphan);

    // Complete sidecars waiting for their epoch to be processed, and when to look at each
    // again as a possible orphan.
    std::map<std::filesystem::path, SteadyTime> ready_;
};

}  // namespace tlsmon
