#pragma once
// Processing one pending epoch: claim -> read the file once and check its sha256 -> parse ->
// the stages in order against the reference epoch (run_stages in epoch_pipeline.cpp) ->
// the alarm rules on its rows, inside the commit of everything in one transaction ->
// archive the file.
// An unreadable file goes to quarantine and the epoch is `failed` with the reason; an epoch
// a stage cannot analyse is `rejected` with the stage's reason; a disk or database failure
// puts the epoch back to `pending` for a later retry.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "alarms/alarm_rule.hpp"
#include "pipeline/coverage_stage.hpp"
#include "pipeline/epoch_meteo.hpp"
#include "pipeline/keypoint_stage.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_config.hpp"
#include "pipeline/primitive_config.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/sha256.hpp"
#include "pipeline/system_event_log.hpp"
#include "pipeline/thermal_config.hpp"
#include "pipeline/vector_config.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

enum class ArchiveMode { move, keep };

// What the pipeline needs of the daemon's configuration (config/config.hpp fills it).
struct PipelineConfig {
    std::filesystem::path archive;     // processed files go here (ArchiveMode::move)
    std::filesystem::path quarantine;  // unreadable files + <name>.reason.txt
    ArchiveMode archive_mode = ArchiveMode::move;
    std::string reference_epoch;  // "" = first accepted epoch; else file name or sha256
    CoverageConfig coverage;
    RegistrationConfig registration;  // no targets: no registration
    MeteoConfig meteo;
    M3c2Config m3c2;               // with the zones; none: the stage does not run
    PbM3c2Config pbm3c2;           // with the zones and the segmentation; likewise
    PrimitivesConfig primitives;   // with the zones naming a primitive; likewise
    VectorConfig vectors;          // with the zones and the segmentation; likewise
    KeypointConfig keypoints;      // with the zones (segments = zones; none: it does not run)
    ThermalConfig thermal;         // the compensation of the zone quantities it names
    std::vector<ZoneShape> zones;  // the site's zones, in the configuration's order
    // The stages in order; empty: the site's (site_stages, pipeline/site_stages.hpp).
    StageList stages;
    // Evaluated in each epoch's commit (pipeline/alarm_evaluation.hpp).
    std::vector<AlarmRuleSpec> alarm_rules;
};

struct PipelineContext {
    EpochDatabase& db;
    const PipelineConfig& config;
    SystemEventLog& events;
    ReferenceCache& cache;  // lives as long as the daemon: products stay in memory
};

enum class EpochOutcome { done, rejected, failed, retry_later, skipped };

// `preloaded`: the file's bytes as ingest read and hashed them, if at hand; used (moved
// from) when they are this epoch's content and the file is unchanged since.
// `sidecar`: the scan's complete meteo sidecar, if the ingest found one (it decides how long
// to wait for it). Used: archived with the scan; rejected: quarantined with its reason; both
// recorded in the epoch's commit. Not touched when the epoch fails or is retried.
EpochOutcome process_epoch(PipelineContext& ctx, const Epoch& epoch,
                           HashedBytes* preloaded = nullptr,
                           const std::optional<std::filesystem::path>& sidecar = std::nullopt);

// The reference epoch (epoch 0 of the analyses), set once: the epoch named by
// `reference_epoch` (file name or sha256), else the first accepted one (earliest
// acquisition among the done epochs). Called after each commit and at start, so a stop
// or a database error between a commit and this call is repaired later.
void ensure_reference(PipelineContext& ctx);

}  // namespace tlsmon
