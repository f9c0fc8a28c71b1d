#pragma once
// What the stages of the epoch pipeline share: the epoch being processed, and a stage's
// verdict. A stage that cannot run for this epoch (no reference yet, a scan that does not
// cover the site, later: a registration that fails its quality gate) says why; the epoch is
// then stored `rejected` with that reason — the file was fine (`failed` means the file was
// not), but nothing of it may feed an analysis or an alarm.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/scan.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

struct EpochInput {
    const Epoch& epoch;
    std::shared_ptr<const std::vector<Scan>> scans;
    // The weather station's row nearest the acquisition time, from the scan's meteo sidecar
    // (outcome `used`, `values` set; docs/pipeline.md, "Meteo"). Absent when the scan came
    // without a sidecar or its sidecar was rejected: a stage that needs it says so.
    std::optional<MeteoSidecar> meteo = std::nullopt;
};

struct StageVerdict {
    std::string rejected;  // why the epoch cannot be analysed; empty when the stage ran
    std::string note;      // what the stage measured, in a few words (stored per epoch)
    bool ran() const { return rejected.empty(); }
};

}  // namespace tlsmon
