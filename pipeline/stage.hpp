#pragma once
// The stage contract (docs/pipeline.md, "Stages"). Every analysis of an epoch is a Stage with
// one signature, run(StageContext&), and two halves:
//   prepare the reference — what the stage derives once from the reference epoch (core
//     points, normals, keypoints, target centres), cached in the ReferenceCache keyed by the
//     reference's sha256 and the parameters it depends on;
//   measure an epoch — against that product, writing the stage's own rows into the results.
// A stage that cannot analyse this epoch (no reference yet, a scan that does not cover the
// site, a registration that fails its quality gate) says why in its verdict; the epoch is
// then stored `rejected` with that reason — the file was fine (`failed` means the file was
// not), but nothing of it may feed an analysis or an alarm.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "algorithms/registration/rigid_transform.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/scan.hpp"
#include "pipeline/reference_cache.hpp"
#include "storage/epoch_database.hpp"
#include "storage/epoch_results.hpp"

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

// What the registration hands to the later stages: the map of the epoch's points into the
// reference frame.
struct StageOutputs {
    // Maps the epoch's points into the reference frame; absent without registration.
    std::optional<registration::RigidTransform> to_reference;
    // The epoch's ranges are to be scaled by 1/range_scale about `scanner` before
    // `to_reference` applies (1: no atmospheric correction).
    double range_scale = 1.0;
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();
    // The reference epoch's scale when the epoch's was applied (the registration corrects
    // both or neither): `to_reference` maps into the reference's corrected ranges.
    double reference_range_scale = 1.0;
};

// What a stage may read of the epochs before this one. The daemon reads it from the epoch
// database; a one-shot command comparing two files has none of it.
struct StageHistory {
    std::set<std::string> excluded_targets;  // moved; excluded until re-surveyed
    // Per target, in how many consecutive registered epochs just before this one it failed
    // its outlier test (RegistrationStore::outlier_runs).
    std::map<std::string, int> outlier_runs;
    // The reference epoch's own air (its stored meteo; this epoch's when it is the reference).
    std::optional<MeteoSidecar> reference_meteo;
    const SeriesReader* series = nullptr;  // the stored time series; none: this epoch alone
    // The newest accepted registration before this epoch (rotation and translation only): a
    // fixed station's approximate transformation for the next.
    std::optional<registration::RigidTransform> last_transform;
    // The state bytes of the newest `count` stable-area masks before this epoch, newest first,
    // of this reference and a segmentation; unset: this epoch alone.
    std::function<std::vector<std::vector<std::uint8_t>>(const std::string& segmentation,
                                                         int count)>
        stable_area_states;
    // The thermal compensation's models, compensations and stored air; none: this epoch alone.
    const ThermalStore* thermal = nullptr;
};

// Everything one stage sees of one epoch.
struct StageContext {
    const EpochInput& input;
    ReferenceEpoch& reference;
    ReferenceCache& cache;
    const StageHistory& history;
    const std::vector<ZoneShape>& zones;  // the site's zones, in the configuration's order
    StageOutputs& outputs;                // written by the registration, read by the rest
    EpochResults& results;                // each stage adds its own rows
    bool is_reference() const { return reference.epoch().id == input.epoch.id; }
};

class Stage {
  public:
    virtual ~Stage() = default;
    // The stage's name in the epoch's stage list and in its rejection reasons.
    virtual const char* name() const = 0;
    // Prepare the reference (cached), measure the epoch, add the rows to ctx.results.
    virtual StageVerdict run(StageContext& ctx) const = 0;
};

using StageList = std::vector<std::shared_ptr<const Stage>>;

// A stage with one reference product: `Product` provides encode/decode (reference_cache.hpp)
// and `kStage`, `kFormatVersion`, its cache entry's name and payload layout.
template <class Product>
class ReferenceStage : public Stage {
  public:
    StageVerdict run(StageContext& ctx) const final {
        if (std::string why = not_measured(ctx); !why.empty()) return StageVerdict{"", why};
        const auto product = ctx.cache.get<Product>(
            ctx.reference,
            ProductKey{Product::kStage, reference_parameters(), Product::kFormatVersion},
            [this](const std::vector<Scan>& scans) { return prepare_reference(scans); });
        return measure(ctx, *product);
    }

    // The canonical text of every parameter the product depends on (its cache key).
    virtual std::string reference_parameters() const = 0;
    virtual Product prepare_reference(const std::vector<Scan>& reference_scans) const = 0;
    virtual StageVerdict measure(StageContext& ctx, const Product& reference) const = 0;
    // Why this epoch is not measured at all (the stage does not apply to it, which rejects
    // nothing: e.g. no structured scan for the keypoints); "" measures it.
    virtual std::string not_measured(const StageContext&) const { return {}; }
};

}  // namespace tlsmon
