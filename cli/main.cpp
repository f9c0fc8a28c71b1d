// tlsmon: unattended deformation monitoring with a terrestrial laser scanner.
// The whole command line is declared here, the only file that includes CLI11 (its header
// costs seconds to compile); each subcommand is a plain function in cli/<command>.cpp.
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <string_view>
#include <utility>

#include "cli/commands.hpp"
#include "cli/program_arguments.hpp"
#include "config/keys.hpp"
#include "pipeline/campaign_comparison.hpp"
#include "pipeline/keypoint_config.hpp"
#include "pipeline/m3c2_config.hpp"
#include "pipeline/pbm3c2_config.hpp"
#include "pipeline/primitive_config.hpp"
#include "simulator/pls.hpp"

namespace tlsmon {
namespace {

// --db, --config, --format (and --from/--to when `with_time_range`) of the reading
// commands. The format is checked by name here and handed on as an enum by `finish`.
struct ReadOptionsOnTheCommandLine {
    ReadOptions options;
    std::string format = "table";

    void add_to(CLI::App* cmd, bool with_time_range) {
        auto* db = cmd->add_option("--db", options.db, "Epoch database (SQLite file)");
        auto* config = cmd->add_option("--config", options.config,
                                       "Configuration file naming the database (paths.database)");
        db->excludes(config);
        cmd->add_option("--format", format, "Output format")
            ->check(CLI::IsMember({"table", "csv", "json"}));
        if (with_time_range) {
            cmd->add_option("--from", options.from,
                            "Start: ISO-8601 UTC (e.g. 2026-03-01T00:00Z), or before now "
                            "(e.g. -7d, -12h, -30min)");
            cmd->add_option("--to", options.to,
                            "End (inclusive): ISO-8601 UTC, now, or before now");
        }
    }
    const ReadOptions& finish() {
        static const std::map<std::string, OutputFormat> formats = {{"table", OutputFormat::table},
                                                                    {"csv", OutputFormat::csv},
                                                                    {"json", OutputFormat::json}};
        options.format = formats.at(format);
        return options;
    }
};

// Every subcommand's options, filled by the parser, and the exit code its callback sets.
struct CommandLine {
    int code = 0;
    CheckConfigOptions check_config;
    InfoOptions info;
    RunOptions run;
    std::string run_config;
    SimulateOptions simulate;
    ReadOptionsOnTheCommandLine status;
    ReadOptionsOnTheCommandLine epochs;
    ReadOptionsOnTheCommandLine meteo;
    ReadOptionsOnTheCommandLine registrations;
    RegisterOptions register_;
    std::string register_format = "table";
    ReadOptionsOnTheCommandLine series_read;
    SeriesOptions series;
    ReadOptionsOnTheCommandLine keypoint_models_read;
    KeypointModelsOptions keypoint_models;
    ReadOptionsOnTheCommandLine thermal_models_read;
    ThermalModelsOptions thermal_models;
    ReadOptionsOnTheCommandLine keypoints_read;
    KeypointsQueryOptions keypoints_query;
    ReadOptionsOnTheCommandLine corepoints_read;
    CorePointsOptions corepoints;
    ReadOptionsOnTheCommandLine planes_read;
    PlanesQueryOptions planes;
    ReadOptionsOnTheCommandLine stable_areas_read;
    StableAreasQueryOptions stable_areas;
    ReadOptionsOnTheCommandLine events_read;
    EventsOptions events;
    ReadOptionsOnTheCommandLine export_read;
    ExportOptions export_;
    ReadOptionsOnTheCommandLine backup_read;
    BackupOptions backup;
    std::map<std::string, EpochPinOptions> epoch_pins;
    std::map<std::string, RetentionOptions> retention;
    std::map<std::string, ReadOptionsOnTheCommandLine> retention_read;
    ReadOptionsOnTheCommandLine epochs_pinned;
    M3c2Options m3c2;
    PbM3c2Options pbm3c2;
    PrimitivesOptions primitives;
    VectorsOptions vectors;
    CampaignCompareOptions campaign_compare;
    CampaignAddOptions campaign_add;
    ReadOptionsOnTheCommandLine campaigns;
    ReadOptionsOnTheCommandLine campaign_segments_read;
    CampaignSegmentsOptions campaign_segments;
    ReadOptionsOnTheCommandLine campaign_points_read;
    CampaignSegmentsOptions campaign_points;
    KeypointsOptions keypoints;
    ModbusMapOptions modbus_map;
    ReadOptionsOnTheCommandLine alarms;
    ReadOptionsOnTheCommandLine alarm_history_read;
    AlarmHistoryOptions alarm_history;
    std::map<std::string, AlarmActionOptions> alarm_actions;
    ReportOptions report;
    ReadOptionsOnTheCommandLine calibration_read;
    CalibrationOptions calibration;
    DemoOptions demo;
    ReadOptionsOnTheCommandLine targets;
    TargetResurveyOptions resurvey;
    UsersOptions users;
    NotifyTestOptions notify_test;
    std::map<std::string, CentralAdminOptions> central_admin;
    ReadOptionsOnTheCommandLine central_status;
    std::map<std::string, FleetOptions> fleet;
    std::map<std::string, ReadOptionsOnTheCommandLine> fleet_read;
};

void add_check_config(CLI::App& app, CommandLine& c) {
    auto& o = c.check_config;
    auto* cmd = app.add_subcommand("check-config",
                                   "Validate a configuration file and print "
                                   "the effective values");
    cmd->add_option("FILE", o.file, "TOML configuration file")->required();
    cmd->callback([&] { c.code = run_check_config(o); });
}

void add_info(CLI::App& app, CommandLine& c) {
    auto& o = c.info;
    auto* cmd = app.add_subcommand(
        "info", "Describe scanner exports: format, scans, points, grid, intensity, pose");
    cmd->add_option("FILE", o.files, "Scan files (PTX, PTS, XYZ, PLY, PCD, LAS, E57)")->required();
    cmd->add_flag("--json", o.json, "Print a JSON array, one object per file");
    cmd->callback([&] { c.code = run_info(o); });
}

void add_run(CLI::App& app, CommandLine& c) {
    auto& o = c.run;
    auto* cmd = app.add_subcommand("run", "Run the ingest daemon on the configured folders");
    cmd->add_option("--config", c.run_config, "TOML configuration file")->required();
    cmd->add_flag("--once", o.once,
                  "Process the files present (once complete) and the backlog, then exit");
    cmd->callback([&] {
        o.config_file = c.run_config;
        c.code = run_ingest(o);
    });
}

void add_simulate(CLI::App& app, CommandLine& c) {
    auto& o = c.simulate;
    auto* cmd = app.add_subcommand(
        "simulate",
        "Write synthetic PTX scans of a bridge pier with known deformation, drift "
        "and targets, each with its truth (JSON) and the site's meteo file (CSV)");
    cmd->add_option("--config", o.config, "Scene file (TOML), see etc/simulator-small.toml")
        ->check(CLI::ExistingFile);
    cmd->add_option("--preset", o.preset, "Scene preset")
        ->check(CLI::IsMember({"small", "pier", "round", "hochmosel"}));
    cmd->add_option("--out", o.out, "Output folder (created if needed)")->required();
    cmd->add_option("--epochs", o.epochs, "Number of epochs")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    cmd->add_option("--cadence", o.cadence,
                    "Time between scans, e.g. 15min (default: the scene's, 15min)");
    cmd->add_option("--start", o.start, "Acquisition time of epoch 0 (UTC)")->capture_default_str();
    cmd->add_option("--seed", o.seed,
                    "Seed of the measurement noise and the drift jitter (default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--realtime", o.realtime,
                    "Write one scan every SECONDS (temporary name, then rename)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--slow-copy", o.slow_copy,
                    "Write each scan under its final name in chunks over SECONDS")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--threads", o.threads, "Render threads")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--campaign", o.campaign,
                    "Instead of the station's scans, a personal laser scanner's campaign walked "
                    "around the pier with this SLAM drift: campaign.ply, reference.ply and "
                    "campaign.truth.json (docs/campaigns.md)")
        ->check(CLI::IsMember({"none", "linear", "random-walk"}));
    cmd->add_option("--pulse-rate", o.pulse_rate,
                    "Campaign: pulses per second (default " +
                        toml_number(sim::PlsScanner{}.pulse_rate) + ")")
        ->check(CLI::PositiveNumber);
    cmd->add_option(
           "--range-sigma", o.range_sigma,
           "Campaign: range noise, m (default " + toml_number(sim::PlsScanner{}.range_sigma) + ")")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--slam-frame", o.slam_frame,
                  "Campaign: written in the SLAM's own frame (origin where the walk starts, a "
                  "heading drawn from the seed, levelled), as a handheld scanner delivers it; "
                  "the frame in campaign.truth.json");
    cmd->callback([&] { c.code = run_simulate(o); });
}

void add_status(CLI::App& app, CommandLine& c) {
    auto& o = c.status;
    auto* cmd =
        app.add_subcommand("status", "Last epoch, backlog, failures, alarms, database size");
    o.add_to(cmd, false);
    cmd->callback([&] { c.code = run_status(o.finish()); });
}

void add_query(CLI::App& app, CommandLine& c) {
    auto* query = app.add_subcommand("query", "Query the epoch database");
    query->require_subcommand(1);

    auto& epochs_options = c.epochs;
    auto* epochs = query->add_subcommand("epochs", "Epochs acquired in a time range");
    epochs_options.add_to(epochs, true);
    epochs->callback([&] { c.code = run_query_epochs(epochs_options.finish()); });

    auto& meteo_options = c.meteo;
    auto* meteo = query->add_subcommand(
        "meteo", "Epochs in a time range with their meteo sidecar and the values used");
    meteo_options.add_to(meteo, true);
    meteo->callback([&] { c.code = run_query_meteo(meteo_options.finish()); });

    auto& registrations_options = c.registrations;
    auto* registrations = query->add_subcommand(
        "registrations",
        "Epochs in a time range with their registration: parameters, σ, targets, zone σ");
    registrations_options.add_to(registrations, true);
    registrations->callback(
        [&] { c.code = run_query_registrations(registrations_options.finish()); });

    auto& models_read = c.keypoint_models_read;
    auto& models_options = c.keypoint_models;
    auto* models = query->add_subcommand(
        "keypoint-models",
        "Epochs in a time range with their keypoint displacement model d(t, z): coefficients, "
        "convergence, residual scale (docs/keypoints.md)");
    models->add_option("--quantity", models_options.quantity,
                       "Only the model of this quantity (e.g. keypoint_along_surface_h_m)");
    models->add_flag("--residuals", models_options.residuals,
                     "One row per residual of each fitting epoch's own segments");
    models_read.add_to(models, true);
    models->callback([&] {
        models_options.read = models_read.finish();
        c.code = run_query_keypoint_models(models_options);
    });

    auto& thermal_read = c.thermal_models_read;
    auto& thermal_options = c.thermal_models;
    auto* thermal = query->add_subcommand(
        "thermal-models",
        "The thermal compensation's models, every version: lags, coefficients, σ, training "
        "window (docs/thermal.md); with --compensations each epoch's compensation quality");
    thermal->add_option("--zone", thermal_options.zone, "Only this zone's");
    thermal->add_option("--quantity", thermal_options.quantity,
                        "Only the model of this quantity (e.g. m3c2_median_m)");
    thermal->add_flag("--compensations", thermal_options.compensations,
                      "One row per epoch in the time range and zone quantity: compensated, "
                      "extrapolated, no_meteo or no_model, with the model health");
    thermal_read.add_to(thermal, true);
    thermal->callback([&] {
        thermal_options.read = thermal_read.finish();
        c.code = run_query_thermal_models(thermal_options);
    });

    auto& keypoints_read = c.keypoints_read;
    auto& keypoints_options = c.keypoints_query;
    auto* keypoints = query->add_subcommand(
        "keypoints",
        "Epochs in a time range with the keypoint displacement of each zone: matches kept, "
        "mean vector, components along the wall, LoD95 (docs/keypoints.md)");
    keypoints->add_option("--zone", keypoints_options.zone, "Only this zone");
    keypoints_read.add_to(keypoints, true);
    keypoints->callback([&] {
        keypoints_options.read = keypoints_read.finish();
        c.code = run_query_keypoints(keypoints_options);
    });

    auto& campaigns_options = c.campaigns;
    auto* campaigns = query->add_subcommand(
        "campaigns",
        "Campaign epochs acquired in a time range: instrument, global registration, whether the "
        "segments moved as one, C2C (docs/campaigns.md)");
    campaigns_options.add_to(campaigns, true);
    campaigns->callback([&] { c.code = run_query_campaigns(campaigns_options.finish()); });

    auto& segments_read = c.campaign_segments_read;
    auto& segments_options = c.campaign_segments;
    auto* segments = query->add_subcommand(
        "campaign-segments",
        "One campaign's segments: class, outcome, parameters with their σ where observed, the "
        "test against the others, C2C (docs/campaigns.md)");
    segments->add_option("--campaign", segments_options.campaign, "The campaign's id")->required();
    segments_read.add_to(segments, false);
    segments->callback([&] {
        segments_options.read = segments_read.finish();
        c.code = run_query_campaign_segments(segments_options);
    });

    auto& points_read = c.campaign_points_read;
    auto& points_options = c.campaign_points;
    auto* points = query->add_subcommand(
        "campaign-points",
        "The points one campaign kept ([campaign] store_spacing) in the reference's frame after "
        "their segment's registration, with their segment and C2C vector (docs/campaigns.md)");
    points->add_option("--campaign", points_options.campaign, "The campaign's id")->required();
    points_read.add_to(points, false);
    points->callback([&] {
        points_options.read = points_read.finish();
        c.code = run_query_campaign_points(points_options);
    });

    auto& series_read = c.series_read;
    auto& series_options = c.series;
    auto* series = query->add_subcommand("series", "Time series of one zone and quantity");
    series->add_option("--zone", series_options.zone, "Zone name")->required();
    series->add_option("--quantity", series_options.quantity, "Quantity (e.g. m3c2_mean_m)")
        ->required();
    series_read.add_to(series, true);
    series->callback([&] {
        series_options.read = series_read.finish();
        c.code = run_query_series(series_options);
    });

    auto& corepoints_read = c.corepoints_read;
    auto& corepoints_options = c.corepoints;
    auto* corepoints = query->add_subcommand(
        "corepoints", "One epoch's M3C2 map: every core point, its normal, distance and LoD");
    corepoints->add_option("--epoch", corepoints_options.epoch, "Epoch id")->required();
    corepoints->add_option("--out", corepoints_options.out,
                           "Write to this file (CSV; JSON with --format json)");
    corepoints_read.add_to(corepoints, false);
    corepoints->callback([&] {
        corepoints_options.read = corepoints_read.finish();
        c.code = run_query_corepoints(corepoints_options);
    });

    auto& planes_read = c.planes_read;
    auto& planes_options = c.planes;
    auto* planes = query->add_subcommand(
        "planes",
        "One epoch's planes from the registration on planes: role (datum, moved, monitored), "
        "tilt and shift with σ, test statistic (docs/registration.md)");
    planes->add_option("--epoch", planes_options.epoch, "Epoch id")->required();
    planes_read.add_to(planes, false);
    planes->callback([&] {
        planes_options.read = planes_read.finish();
        c.code = run_query_planes(planes_options);
    });

    auto& stable_read = c.stable_areas_read;
    auto& stable_options = c.stable_areas;
    auto* stable = query->add_subcommand(
        "stable-areas",
        "One epoch's stable-area mask from the registration on stable areas: each supervoxel of "
        "the reference with its state (stable, unstable, unknown, not_planar), change along its "
        "normal and LoD95 (docs/registration.md)");
    stable->add_option("--epoch", stable_options.epoch, "Epoch id")->required();
    stable->add_option("--state", stable_options.state, "Only the supervoxels in this state")
        ->check(CLI::IsMember({"stable", "unstable", "unknown", "not_planar"}));
    stable
        ->add_flag("--as-zones", stable_options.as_zones,
                   "Instead: the areas outside the zones unstable for stable_persistent_epochs "
                   "epochs up to this one, as [[zone]] tables to add to the configuration (TOML; "
                   "needs --config)")
        ->excludes("--state");
    stable_read.add_to(stable, false);
    stable->callback([&] {
        stable_options.read = stable_read.finish();
        c.code = run_query_stable_areas(stable_options);
    });
}

void add_register(CLI::App& app, CommandLine& c) {
    auto& o = c.register_;
    auto* cmd = app.add_subcommand(
        "register",
        "Register a scan onto a reference scan through the site's targets or the scene's "
        "planes and print the transformation, its σ, each target's residual and each plane's "
        "change");
    cmd->add_option("REFERENCE", o.reference, "Reference scan (epoch 0)")->required();
    cmd->add_option("EPOCH", o.epoch, "Scan to register")->required();
    cmd->add_option("--config", o.config, "Site configuration ([[target]] tables)")->required();
    cmd->add_option("--method", o.method,
                    "What the datum rests on, in place of the configuration's "
                    "registration.method")
        ->check(CLI::IsMember({"targets", "planes", "targets+planes", "stable_areas",
                               "targets+stable_areas", "planes+stable_areas",
                               "targets+planes+stable_areas"}));
    cmd->add_option("--format", c.register_format, "Output format")
        ->check(CLI::IsMember({"table", "json"}));
    cmd->callback([&] {
        o.format = c.register_format == "json" ? OutputFormat::json : OutputFormat::table;
        c.code = run_register(o);
    });
}

void add_events(CLI::App& app, CommandLine& c) {
    auto& read = c.events_read;
    auto& o = c.events;
    auto* cmd = app.add_subcommand("events", "List system and alarm events");
    read.add_to(cmd, true);
    cmd->add_option("--kind", o.kind, "Only events of this kind (e.g. disk_full, raise, ack)");
    cmd->callback([&] {
        o.read = read.finish();
        c.code = run_events(o);
    });
}

void add_export(CLI::App& app, CommandLine& c) {
    auto& read = c.export_read;
    auto& o = c.export_;
    auto* cmd = app.add_subcommand(
        "export",
        "One stored map's per-point results as LAS 1.4 (every attribute as extra bytes), CSV "
        "or GeoJSON, or an epoch's zones and their values as GeoJSON or CSV, by the file's "
        "extension (docs/export.md)");
    auto* epoch = cmd->add_option("--epoch", o.epoch, "Epoch id");
    auto* bundle = cmd->add_option(
        "--bundle", o.bundle,
        "A new folder for the window's (--from/--to) database extract, maps as LAS, series "
        "CSV, manifest and SHA256SUMS");
    cmd->add_option("--map", o.map,
                    "Which of the epoch's maps; zones: every zone's footprint and values")
        ->check(CLI::IsMember({"m3c2", "pbm3c2", "vectors", "zones"}))
        ->capture_default_str()
        ->needs(epoch);
    auto* campaign = cmd->add_option("--campaign", o.campaign, "A campaign's id: its kept points");
    epoch->excludes(campaign);
    auto* out = cmd->add_option("--out", o.out, "The file to write: .las, .csv or .geojson");
    bundle->excludes(epoch)->excludes(campaign)->excludes(out);
    cmd->add_option("--crs", o.crs,
                    "The coordinate system the LAS or GeoJSON file names (e.g. EPSG:25832); "
                    "default: the configuration's [station] crs");
    read.add_to(cmd, true);
    cmd->callback([&] {
        o.read = read.finish();
        if (!o.bundle.empty()) {
            c.code = run_export_bundle(o);
            return;
        }
        if (o.epoch <= 0 && o.campaign <= 0)
            throw CLI::ValidationError("give --epoch or --campaign (or --bundle)");
        if (o.out.empty()) throw CLI::ValidationError("give --out FILE");
        if (!o.read.from.empty() || !o.read.to.empty())
            throw CLI::ValidationError("--from/--to choose the epochs of a --bundle");
        c.code = run_export(o);
    });
}

void add_backup(CLI::App& app, CommandLine& c) {
    auto& read = c.backup_read;
    auto& o = c.backup;
    auto* cmd = app.add_subcommand(
        "backup",
        "A consistent copy of the epoch database, also while the daemon runs (docs/backup.md)");
    cmd->add_option("DEST", o.destination,
                    "The copy: a new file, or a folder for <database>-<UTC time>.sqlite")
        ->required();
    read.add_to(cmd, false);
    cmd->callback([&] {
        o.read = read.finish();
        c.code = run_backup(o);
    });
}

void add_epochs(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "epochs",
        "Pin epochs whose per-core-point maps the retention policy keeps (docs/retention.md)");
    cmd->require_subcommand(1);
    const std::pair<const char*, const char*> actions[] = {
        {"pin", "Keep epoch N's maps whatever its age (recorded as an event naming who)"},
        {"unpin", "Let epoch N's maps follow the retention policy again"}};
    for (const auto& [name, help] : actions) {
        auto& o = c.epoch_pins[name];
        o.action = name;
        auto* sub = cmd->add_subcommand(name, help);
        auto* db = sub->add_option("--db", o.read.db, "Epoch database (SQLite file)");
        sub->add_option("--config", o.read.config, "Configuration file naming the database")
            ->excludes(db);
        sub->add_option("N", o.epoch, "Epoch id (tlsmon query epochs)")->required();
        sub->add_option("--by", o.by, "Who acts (default: cli:$USER)");
        if (std::string(name) == "pin") {
            sub->add_option("--note", o.note, "Why it is kept (shown by `epochs pinned`)");
        }
        sub->callback([&] { c.code = run_epoch_pins(o); });
    }
    auto& o = c.epoch_pins["pinned"];
    o.action = "pinned";
    auto* pinned = cmd->add_subcommand("pinned", "List the pinned epochs");
    c.epochs_pinned.add_to(pinned, false);
    pinned->callback([&] {
        o.read = c.epochs_pinned.finish();
        c.code = run_epoch_pins(o);
    });
}

// `tlsmon retention plan|run` and `tlsmon archive plan|run`: a policy's plan, or one pass.
void add_policy_passes(CLI::App& app, CommandLine& c, const std::string& command,
                       const std::string& description, const char* plan_help, const char* run_help,
                       int (*run)(const RetentionOptions&)) {
    auto* cmd = app.add_subcommand(command, description);
    cmd->require_subcommand(1);
    const std::pair<const char*, const char*> actions[] = {{"plan", plan_help}, {"run", run_help}};
    for (const auto& [name, help] : actions) {
        auto& o = c.retention[command + " " + name];
        o.action = name;
        auto* sub = cmd->add_subcommand(name, help);
        auto& read = c.retention_read[command + " " + name];
        read.add_to(sub, false);
        sub->callback([&o, &read, &c, run] {
            o.read = read.finish();
            c.code = run(o);
        });
    }
}

void add_retention(CLI::App& app, CommandLine& c) {
    add_policy_passes(
        app, c, "retention",
        "The retention policy of per-core-point maps: `plan` (what a pass would keep and thin), "
        "`run` (one pass now, as the daemon does) (docs/retention.md)",
        "What a pass of the policy (the site's with --config) would keep and thin",
        "One pass now: thin, then give the freed space back to the file system", run_retention);
}

void add_archive(CLI::App& app, CommandLine& c) {
    add_policy_passes(
        app, c, "archive",
        "The archive policy of raw scans (needs --config): `plan` (the archive's size, what a "
        "pass would remove, re-encode and free), `run` (one pass now, as the daemon does) "
        "(docs/retention.md)",
        "The archive now and what a pass of the site's [archive] policy would do",
        "One pass now: remove the scans the policy thins, re-encode those it keeps", run_archive);
}

void add_alarms(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "alarms",
        "Alarms standing now (not normal); history; "
        "acknowledge, shelve, unshelve, out-of-service, in-service (docs/alarms.md)");
    c.alarms.add_to(cmd, false);
    auto* history = cmd->add_subcommand("history", "Alarm events by time");
    c.alarm_history_read.add_to(history, true);
    history->add_option("--rule", c.alarm_history.rule, "Only this rule's events");
    history->callback([&] {
        c.alarm_history.read = c.alarm_history_read.finish();
        c.code = run_alarm_history(c.alarm_history);
    });
    const std::pair<const char*, const char*> actions[] = {
        {"ack", "Acknowledge the alarm of RULE (\"*\": every rule)"},
        {"shelve", "Shelve the alarm of RULE until --until"},
        {"unshelve", "End the shelve of RULE"},
        {"out-of-service", "Remove RULE from service (maintenance) until in-service"},
        {"in-service", "Return RULE to service"}};
    for (const auto& [name, help] : actions) {
        auto& o = c.alarm_actions[name];
        o.action = name;
        auto* sub = cmd->add_subcommand(name, help);
        auto* db = sub->add_option("--db", o.db, "Epoch database (SQLite file)");
        sub->add_option("--config", o.config, "Configuration file naming the database")
            ->excludes(db);
        sub->add_option("RULE", o.rule, "Alarm rule name")->required();
        if (std::string(name) == "shelve") {
            sub->add_option("--until", o.until, "End of the shelve, ISO-8601 UTC")->required();
        }
        sub->callback([&] { c.code = run_alarm_action(o); });
    }
    cmd->callback([cmd, &c] {
        if (cmd->get_subcommands().empty()) c.code = run_alarms(c.alarms.finish());
    });
}

// A one-shot command's parameter option: its default, the site's with --config, else a fresh
// site's.
std::string fallback(const std::string& key, const std::string& value) {
    return " (default: the site's " + key + ", else " + value + ")";
}

void add_m3c2(CLI::App& app, CommandLine& c) {
    auto& o = c.m3c2;
    auto* cmd = app.add_subcommand(
        "m3c2",
        "M3C2 distances (Lague 2013) from REFERENCE to COMPARED at core points, with LoD95; "
        "one CSV row per core point (docs/m3c2.md). Parameters: a fresh site's defaults, or "
        "the site's with --config (its zones and registration too: the numbers the daemon "
        "stores); each option replaces one. Radii and half-lengths in metres");
    const M3c2Config defaults;
    const auto listed = [](const std::vector<double>& values) {
        std::string out;
        for (double v : values) out += (out.empty() ? "" : ",") + toml_number(v);
        return out;
    };
    cmd->add_option("REFERENCE", o.reference, "Reference scan file (normals, core points)")
        ->required();
    cmd->add_option("COMPARED", o.compared, "Compared scan file")->required();
    cmd->add_option("--config", o.config,
                    "A site's configuration: its [m3c2] parameters, [[zone]] core points and "
                    "registration of COMPARED onto REFERENCE");
    auto* core = cmd->add_option("--core", o.core_file, "Core points: every point of this file");
    cmd->add_option("--core-spacing", o.core_spacing,
                    "Core points: REFERENCE subsampled at this spacing" +
                        fallback("m3c2.core_spacing", toml_number(defaults.core_spacing)))
        ->excludes(core);
    cmd->add_option("--normal-radii", o.normal_radii,
                    "Normal radii R1,R2,...: the most planar scale is used" +
                        fallback("m3c2.normal_radii", listed(defaults.normal_radii)))
        ->delimiter(',');
    cmd->add_option("--cylinder-radius", o.cylinder_radius,
                    "Cylinder radius (projection scale)" +
                        fallback("m3c2.cylinder_radius", toml_number(defaults.cylinder_radius)));
    cmd->add_option("--max-depth", o.max_depth,
                    "Cylinder half-length along the normal" +
                        fallback("m3c2.max_depth", toml_number(defaults.max_depth)));
    cmd->add_option("--orient", o.orient,
                    "Normal orientation: scanner (towards REFERENCE's scanner) or X,Y,Z" +
                        fallback("m3c2.orientation", "scanner"));
    cmd->add_option(
        "--reg-error", o.registration_error,
        "Registration error added to the LoD without a registration (Lague 2013, "
        "eq. 1)" +
            fallback("m3c2.registration_error", toml_number(defaults.registration_error)));
    cmd->add_flag("--median", o.median, "Median and interquartile range instead of mean and std");
    cmd->add_option("--min-points", o.min_points,
                    "Fewer points in either cylinder: no distance (NaN)" +
                        fallback("m3c2.min_points", std::to_string(defaults.min_points)));
    cmd->add_option("--max-roughness", o.max_roughness,
                    "A reference cylinder spreading more than this (m) holds an edge: no "
                    "distance" +
                        fallback("m3c2.max_roughness", toml_number(defaults.max_roughness)));
    cmd->add_option("--stray-distance", o.stray_distance,
                    "Leave out a cylinder's points farther than this (m) and 3.5 robust σ from "
                    "its median projection (twice --max-depth or more: as published)" +
                        fallback("m3c2.stray_distance", toml_number(defaults.stray_distance)));
    cmd->add_option("--threads", o.threads, "Threads (0: every core)");
    cmd->add_option("--out", o.out, "Result CSV file")->required();
    cmd->callback([&] { c.code = run_m3c2(o); });
}

void add_pbm3c2(CLI::App& app, CommandLine& c) {
    auto& o = c.pbm3c2;
    auto* cmd = app.add_subcommand(
        "pbm3c2",
        "Patch-based M3C2 from REFERENCE to COMPARED: the distance between the two planes of "
        "each patch of REFERENCE (its supervoxels) with its LoD95; one CSV row per patch "
        "(docs/pbm3c2.md). Parameters: a fresh site's defaults on the whole of REFERENCE, or the "
        "site's with --config (its zones, segmentation and registration too: the numbers the "
        "daemon stores); each option replaces one. Lengths in metres");
    const PbM3c2Config defaults;
    cmd->add_option("REFERENCE", o.reference, "Reference scan file (the patches)")->required();
    cmd->add_option("COMPARED", o.compared, "Compared scan file")->required();
    cmd->add_option("--config", o.config,
                    "A site's configuration: its [pbm3c2] parameters, [[zone]] patches, "
                    "segmentation and registration of COMPARED onto REFERENCE");
    cmd->add_option("--search-depth", o.search_depth,
                    "A point belongs to a patch within this of its plane" +
                        fallback("pbm3c2.search_depth", toml_number(defaults.search_depth)));
    cmd->add_option("--min-points", o.min_points,
                    "Fewer points on a patch in either scan: no distance (NaN)" +
                        fallback("pbm3c2.min_points", std::to_string(defaults.min_points)));
    cmd->add_option("--max-roughness", o.max_roughness,
                    "A reference patch farther than this (RMS) from its plane: no distance" +
                        fallback("pbm3c2.max_roughness", toml_number(defaults.max_roughness)));
    cmd->add_option(
        "--voxel", o.voxel,
        "The segmentation's voxel" +
            fallback("registration.stable_voxel", toml_number(defaults.segmentation.voxel)));
    cmd->add_option("--seed", o.seed,
                    "The supervoxels' size" + fallback("registration.stable_seed",
                                                       toml_number(defaults.segmentation.seed)));
    cmd->add_option("--threads", o.threads, "Threads (0: every core)");
    cmd->add_option("--out", o.out, "Result CSV file")->required();
    cmd->callback([&] { c.code = run_pbm3c2(o); });
}

void add_primitives(CLI::App& app, CommandLine& c) {
    auto& o = c.primitives;
    auto* cmd = app.add_subcommand(
        "primitives",
        "Geometric primitives (cylinder, plane, sphere) fitted in REFERENCE and COMPARED and the "
        "change of their parameters tested: a round pier's tilt, top displacement and radius "
        "(docs/primitives.md). With --config the site's zones naming a primitive, its "
        "registration and [primitives] parameters (the numbers the daemon stores); else one "
        "--box holding one --kind in the files' own frame. Lengths in metres");
    const PrimitivesConfig defaults;
    cmd->add_option("REFERENCE", o.reference, "Reference scan file")->required();
    cmd->add_option("COMPARED", o.compared, "Compared scan file")->required();
    cmd->add_option("--config", o.config,
                    "A site's configuration: its [[zone]] tables with `primitive`, [primitives] "
                    "and the registration of COMPARED onto REFERENCE");
    cmd->add_option("--kind", o.kind, "The primitive in --box")
        ->check(CLI::IsMember({"cylinder", "plane", "sphere"}))
        ->capture_default_str();
    cmd->add_option("--box", o.box, "Zone without --config: x_min y_min z_min x_max y_max z_max")
        ->expected(6);
    cmd->add_option("--band", o.band,
                    "Points within this of the starting primitive" +
                        fallback("primitives.band", toml_number(defaults.band)));
    cmd->add_option(
        "--max-incidence-deg", o.max_incidence_deg,
        "Points seen more obliquely are left out" +
            fallback("primitives.max_incidence_deg", toml_number(defaults.max_incidence_deg)));
    cmd->add_option("--alpha", o.alpha,
                    "Test level" + fallback("primitives.alpha", toml_number(defaults.alpha)));
    cmd->add_option("--threads", o.threads, "Threads (0: every core)");
    cmd->add_option("--out", o.out, "Result CSV file (zone, quantity, value, lod, n, significant)")
        ->required();
    cmd->callback([&] { c.code = run_primitives(o); });
}

void add_vectors(CLI::App& app, CommandLine& c) {
    auto& o = c.vectors;
    auto* cmd = app.add_subcommand(
        "vectors",
        "3-D displacement vectors from REFERENCE to COMPARED: each patch of REFERENCE (its "
        "supervoxels) registered on its own by matching its heights and intensities, a vector "
        "with its covariance per area; one CSV row per area (docs/vectors.md). Parameters: a "
        "fresh site's defaults on the whole of REFERENCE, or the site's with --config (its "
        "zones, segmentation and registration too: the numbers the daemon stores); each option "
        "replaces one. Lengths in metres");
    const VectorConfig defaults;
    cmd->add_option("REFERENCE", o.reference, "Reference scan file (the areas)")->required();
    cmd->add_option("COMPARED", o.compared, "Compared scan file")->required();
    cmd->add_option("--config", o.config,
                    "A site's configuration: its [vectors] parameters, [[zone]] areas, "
                    "segmentation and registration of COMPARED onto REFERENCE");
    cmd->add_option("--window", o.window,
                    "The side of the square measured about each patch's centroid" +
                        fallback("vectors.window", toml_number(defaults.window)));
    cmd->add_option("--search-radius", o.search_radius,
                    "The largest movement along the surface looked for" +
                        fallback("vectors.search_radius", toml_number(defaults.search_radius)));
    cmd->add_option("--search-depth", o.search_depth,
                    "A point belongs to an area within this of its plane" +
                        fallback("vectors.search_depth", toml_number(defaults.search_depth)));
    cmd->add_option(
        "--block", o.block,
        "The covariance's blocks" + fallback("vectors.block", toml_number(defaults.block)));
    cmd->add_option(
        "--max-incidence-deg", o.max_incidence_deg,
        "Patches seen more obliquely are left out" +
            fallback("vectors.max_incidence_deg", toml_number(defaults.max_incidence_deg)));
    cmd->add_option(
        "--voxel", o.voxel,
        "The segmentation's voxel" +
            fallback("registration.stable_voxel", toml_number(defaults.segmentation.voxel)));
    cmd->add_option("--seed", o.seed,
                    "The supervoxels' size" + fallback("registration.stable_seed",
                                                       toml_number(defaults.segmentation.seed)));
    cmd->add_option("--threads", o.threads, "Threads (0: every core)");
    cmd->add_option("--out", o.out, "Result CSV file")->required();
    cmd->callback([&] { c.code = run_vectors(o); });
}

void add_campaign(CLI::App& app, CommandLine& c) {
    auto& o = c.campaign_compare;
    auto* cmd = app.add_subcommand(
        "campaign", "Campaign clouds of a personal or mobile scanner (docs/campaigns.md)");
    cmd->require_subcommand(1);
    auto* compare = cmd->add_subcommand(
        "compare",
        "CAMPAIGN against the TLS REFERENCE segment by segment: the whole cloud registered, "
        "the ground removed, segmented by verticality, each segment registered on its own with its "
        "parameters' "
        "covariance, the test of whether the segments moved as one, C2C distances. Writes "
        "segments.csv and segments.ply (every point with its segment and C2C vector) into "
        "--out, and segments.png (their translations drawn). Both files in one frame; lengths in "
        "metres");
    const CampaignParameters defaults;
    compare->add_option("REFERENCE", o.reference, "The TLS reference scan file")->required();
    compare->add_option("CAMPAIGN", o.campaign, "The campaign's scan file")->required();
    compare->add_option("--out", o.out, "Result folder (created)")->required();
    compare->add_option("--metric", o.metric, "The segments' ICP (default point-to-plane)")
        ->check(CLI::IsMember({"point-to-plane", "point-to-point"}));
    compare
        ->add_option("--c2c", o.c2c,
                     "C2C to the local plane or the nearest point (default "
                     "local-plane)")
        ->check(CLI::IsMember({"local-plane", "nearest-point"}));
    compare->add_option("--radius", o.radius,
                        "Local planes' and verticality's neighbourhood (default " +
                            toml_number(defaults.verticality.radius) + ")");
    compare->add_option(
        "--max-distance", o.max_distance,
        "The farthest pair (default " + toml_number(defaults.surface.max_distance) + ")");
    compare->add_option("--min-segment-points", o.min_segment_points,
                        "Smaller segments are not registered (default " +
                            std::to_string(defaults.min_segment_points) + ")");
    compare->add_option("--min-planar-share", o.min_planar_share,
                        "A segment with fewer pairs on surfaces a local plane models than this "
                        "share of its points is unobserved (default " +
                            toml_number(defaults.min_planar_share) + ")");
    compare->add_option("--thinning", o.thinning,
                        "Voxel (m) the cloud is thinned to for verticality and segmentation, 0: "
                        "every point (default " +
                            toml_number(defaults.thinning) + ")");
    compare->add_option("--registration-points", o.registration_points,
                        "The most points a registration uses, every k-th in the file's order "
                        "(default " +
                            std::to_string(defaults.registration_points) + ")");
    compare->add_flag("--keep-ground", o.keep_ground,
                      "Segment the ground too (default: the cloth simulation filter's ground is "
                      "left out of the segments, kept for the registration)");
    compare->add_option("--ground-threshold", o.ground_threshold,
                        "A point this close to the cloth is ground (default " +
                            toml_number(defaults.ground.class_threshold) + ")");
    compare->add_option("--cloth-resolution", o.cloth_resolution,
                        "The cloth's particle spacing (default " +
                            toml_number(defaults.ground.cloth_resolution) + ")");
    compare->add_option("--rigidness", o.rigidness,
                        "The cloth's rigidness: 1 steep slopes, 2 relief, 3 flat (default " +
                            std::to_string(defaults.ground.rigidness) + ")");
    compare->add_option("--threads", o.threads, "Threads (0: every core)");
    compare
        ->add_option("--coarse", o.coarse,
                     "The campaign's own frame brought near the reference's by both clouds' "
                     "planes (planes), not at all (none: the files are in one frame), or planes "
                     "when they match unambiguously (auto, the default)")
        ->check(CLI::IsMember({"auto", "planes", "none"}));
    compare->callback([&] { c.code = run_campaign_compare(o); });

    auto& a = c.campaign_add;
    auto* add = cmd->add_subcommand(
        "add",
        "FILE of an [[instrument]] compared with the site's reference epoch as `compare` does, "
        "and stored as a campaign epoch (its segments with it), apart from the station's series "
        "and alarms; the same file again is known by its sha256 and not compared twice");
    add->add_option("FILE", a.file, "The campaign's scan file, in the reference's frame")
        ->required();
    add->add_option("--instrument", a.instrument, "An [[instrument]] of the configuration")
        ->required();
    add->add_option("--config", a.config, "Site configuration (its database and instruments)")
        ->required();
    add->add_option("--acquired", a.acquired,
                    "Acquisition time, ISO 8601 UTC (default: as the daemon takes it, "
                    "ingest.acquisition_time)");
    add->callback([&] { c.code = run_campaign_add(a); });
}

void add_keypoints(CLI::App& app, CommandLine& c) {
    auto& o = c.keypoints;
    auto* cmd = app.add_subcommand(
        "keypoints",
        "Keypoint displacement vectors between two structured scans, measured by the keypoint "
        "stage (docs/keypoints.md): a fresh site's parameters with bands of the vertical angle, "
        "or the site's with --config (its zones and registration too: the numbers the daemon "
        "stores); each option replaces one. One CSV row per match, a summary per segment");
    const KeypointConfig defaults;
    cmd->add_option("REFERENCE", o.reference, "Reference scan file (PTX or gridded E57)")
        ->required();
    cmd->add_option("EPOCH", o.epoch, "Compared scan file")->required();
    cmd->add_option("--config", o.config,
                    "A site's configuration: its [keypoints] parameters, [[zone]] segments and "
                    "registration of EPOCH onto REFERENCE");
    cmd->add_option(
        "--detector", o.detector,
        "kaze, akaze, sift, brisk or orb" + fallback("keypoints.detector", defaults.detector));
    cmd->add_option("--descriptor", o.descriptor,
                    "brisk, sift, orb, kaze or akaze (the last two on their own detector only)" +
                        fallback("keypoints.descriptor", defaults.descriptor));
    cmd->add_option(
           "--detector-threshold", o.detector_threshold,
           "KAZE/AKAZE response threshold" +
               fallback("keypoints.detector_threshold", toml_number(defaults.detector_threshold)))
        ->check(CLI::Range(1e-6, 1.0));
    cmd->add_option("--window-deg", o.window_deg,
                    "Angular radius of the matching window, degrees" +
                        fallback("keypoints.window_deg", toml_number(defaults.window_deg)))
        ->check(CLI::PositiveNumber);
    cmd->add_option("--window-m", o.window_m,
                    "Largest displacement expected at the object, m: the window is at least "
                    "this over each keypoint's range (0: the angle alone)" +
                        fallback("keypoints.window_m", toml_number(defaults.window_m)))
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option(
           "--ratio", o.ratio,
           "Lowe's ratio test (0: off)" + fallback("keypoints.ratio", toml_number(defaults.ratio)))
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--mutual", o.mutual, "Keep only mutually nearest matches");
    cmd->add_flag("--clahe", o.clahe, "Equalise the intensity images (CLAHE) before detection");
    cmd->add_flag("--no-refine", o.no_refine,
                  "No least-squares refinement of the matches on their intensity patches");
    cmd->add_option("--segments", o.segments_deg,
                    "Segments: bands of the reference's vertical angle this many degrees high" +
                        fallback("keypoints.band_width_deg", toml_number(defaults.band_width_deg)))
        ->check(CLI::PositiveNumber);
    cmd->add_option("--out", o.out, "Result CSV file, one row per match")->required();
    cmd->add_option("--summary", o.summary,
                    "CSV file, one row per segment: its figures at full precision, as the "
                    "daemon stores them (metres)");
    cmd->add_option("--images", o.images,
                    "Folder for reference.png and epoch.png: the intensity images with the "
                    "matches drawn");
    cmd->add_option("--vector-scale", o.vector_scale, "Vectors drawn this many times their length")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--scan", o.scan,
                    "Only this structured scan of each file, 1 = the first (a file may hold an "
                    "overview and its detail scans; `tlsmon info` lists them); default: every "
                    "scan, paired by their order, as the daemon")
        ->check(CLI::PositiveNumber);
    cmd->callback([&] { c.code = run_keypoints(o); });
}

void add_modbus_map(CLI::App& app, CommandLine& c) {
    auto& o = c.modbus_map;
    auto* cmd = app.add_subcommand(
        "modbus-map", "Print the Modbus register map of a configuration (docs/modbus.md)");
    cmd->add_option("--config", o.config, "TOML configuration file")->required();
    cmd->add_option("--format", o.format, "Output format")
        ->check(CLI::IsMember({"markdown", "csv"}))
        ->capture_default_str();
    cmd->callback([&] { c.code = run_modbus_map(o); });
}

void add_report(CLI::App& app, CommandLine& c) {
    auto& o = c.report;
    auto* cmd = app.add_subcommand(
        "report",
        "A run's report: registration, zones, alarms (Markdown, CSV, PNG plots by gnuplot); "
        "with --truth scored against the simulator's truth files");
    cmd->add_option("--database", o.database, "Epoch database (SQLite file)")->required();
    cmd->add_option("--truth", o.truth,
                    "Folder of the simulator's *.truth.json files (a simulated series)");
    cmd->add_option("--out", o.out, "Output folder (created if needed)")->required();
    cmd->add_option("--config", o.config,
                    "The daemon's configuration, named in the report's example commands");
    cmd->add_option("--modbus-port", o.modbus_port, "Modbus port named in the examples")
        ->check(CLI::Range(1, 65535))
        ->capture_default_str();
    cmd->add_option("--from", o.from,
                    "Only epochs acquired from: ISO-8601 UTC, now, or before now (e.g. -7d)");
    cmd->add_option("--to", o.to, "Only epochs acquired until (inclusive)");
    cmd->callback([&] { c.code = run_report(o); });
}

void add_calibration(CLI::App& app, CommandLine& c) {
    auto& read = c.calibration_read;
    auto& o = c.calibration;
    auto* cmd = app.add_subcommand(
        "calibration",
        "Whether each method's own sigma / LoD95 covers its true error at the nominal 68 % and "
        "95 % rates, against the simulator's truth files; with or without them, the no-change "
        "checks (check zones against zero, each target against the others) and the agreement "
        "tests of joined estimates");
    read.add_to(cmd, true);
    cmd->add_option("--truth", o.truth,
                    "Folder of the simulator's *.truth.json files (without: the no-change "
                    "checks and the agreement tests only)");
    cmd->callback([&] {
        o.read = read.finish();
        c.code = run_calibration(o);
    });
}

void add_demo(CLI::App& app, CommandLine& c) {
    auto& o = c.demo;
    auto* cmd = app.add_subcommand(
        "demo",
        "Run the daemon on a simulated day (thermal bending, scanner drift, a knocked target, "
        "a step in one zone), one scan every few seconds, then report against the truth");
    cmd->add_option("--workdir", o.workdir,
                    "Working folder (created; a previous demo's folder is cleared)")
        ->capture_default_str();
    cmd->add_option("--epochs", o.epochs, "Number of 15-minute epochs")
        ->check(CLI::Range(4, 100000))
        ->capture_default_str();
    cmd->add_option("--interval", o.interval, "Seconds between scans (wall clock)")
        ->check(CLI::Range(0.0, 3600.0))
        ->capture_default_str();
    cmd->add_option("--preset", o.preset,
                    "Scene: small (0.05° grid, five spheres), pier or hochmosel (slow)")
        ->check(CLI::IsMember({"small", "pier", "hochmosel"}))
        ->capture_default_str();
    cmd->add_option("--start", o.start,
                    "Acquisition time of epoch 0, UTC (default: 00:00 UTC today)");
    cmd->add_option("--modbus-port", o.modbus_port, "Modbus TCP port on 127.0.0.1")
        ->check(CLI::Range(1, 65535))
        ->capture_default_str();
    cmd->add_option("--http-port", o.http_port, "Dashboard's port on 127.0.0.1 (0: none)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    cmd->add_flag("--serve", o.serve,
                  "After the report, keep the daemon and its dashboard running until Ctrl-C");
    cmd->add_option("--threads", o.threads, "Render threads of the simulator")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->callback([&] { c.code = run_demo(o); });
}

void add_targets(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "targets",
        "Reference targets: status in the newest epoch, excluded as moved since when and why; "
        "`resurvey NAME` clears an exclusion (docs/registration.md)");
    c.targets.add_to(cmd, false);
    auto& o = c.resurvey;
    auto* sub = cmd->add_subcommand(
        "resurvey",
        "Mark target NAME re-surveyed: its exclusion is cleared and an event records who");
    auto* db = sub->add_option("--db", o.db, "Epoch database (SQLite file)");
    sub->add_option("--config", o.config, "Configuration file naming the database")->excludes(db);
    sub->add_option("NAME", o.target, "Target name")->required();
    sub->add_option("--by", o.by, "Who re-surveyed it (default: cli:$USER)");
    sub->callback([&] { c.code = run_target_resurvey(o); });
    cmd->callback([cmd, &c] {
        if (cmd->get_subcommands().empty()) c.code = run_targets(c.targets.finish());
    });
}

void add_users(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "users", "The dashboard's users: add NAME --role ROLE, remove NAME, list (docs/http.md)");
    cmd->require_subcommand(1);
    auto& o = c.users;
    const auto common = [&](CLI::App* sub) {
        auto* file = sub->add_option("--file", o.file, "The users file");
        sub->add_option("--config", o.config, "Configuration naming it (http.users_file)")
            ->excludes(file);
    };
    auto* add = cmd->add_subcommand("add", "Add a user, or give one a new password or role");
    add->add_option("NAME", o.name, "User name")->required();
    add->add_option("--role", o.role, "viewer (reads), operator (acts on alarms) or admin")
        ->check(CLI::IsMember({"viewer", "operator", "admin"}))
        ->capture_default_str();
    add->add_flag("--password-stdin", o.password_stdin,
                  "Read the password from standard input (one line) instead of the terminal");
    common(add);
    add->callback([&] {
        o.action = "add";
        c.code = run_users(o);
    });
    auto* remove = cmd->add_subcommand("remove", "Remove a user");
    remove->add_option("NAME", o.name, "User name")->required();
    common(remove);
    remove->callback([&] {
        o.action = "remove";
        c.code = run_users(o);
    });
    auto* list = cmd->add_subcommand("list", "List the users and their roles");
    common(list);
    list->callback([&] {
        o.action = "list";
        c.code = run_users(o);
    });
}

void add_notify(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand("notify", "Notifications (docs/notifications.md)");
    cmd->require_subcommand(1);
    auto* test = cmd->add_subcommand(
        "test", "Send a test notification through every channel (or --channel) now");
    test->add_option("--config", c.notify_test.config, "Site configuration")->required();
    test->add_option("--channel", c.notify_test.channel, "Only this [[notify.channel]]");
    test->callback([&] { c.code = run_notify_test(c.notify_test); });
}

void add_central(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "central",
        "The central PostgreSQL of many sites: its schema and sites, as its owner; "
        "this site's forwarding (docs/central.md)");
    cmd->require_subcommand(1);
    const std::pair<const char*, const char*> actions[] = {
        {"migrate", "Create or update the central database's schema"},
        {"add-site",
         "Register a site and create its role (its password from --site-password-file)"},
        {"rotate-credential", "Replace a site's password"}};
    for (const auto& [name, help] : actions) {
        auto& o = c.central_admin[name];
        o.action = name;
        auto* sub = cmd->add_subcommand(name, help);
        sub->add_option("URL", o.url, "The central database (libpq URI), as its owner")->required();
        sub->add_option("--password-file", o.password_file,
                        "The owner's password (first line); default: PGPASSFILE");
        if (o.action != "migrate") {
            sub->add_option("--name", o.name, "The site's name (a-z, 0-9, _ and -)")->required();
            sub->add_option("--site-password-file", o.site_password_file,
                            "The site's password (first line)")
                ->required();
        }
        if (o.action == "add-site")
            sub->add_option("--location", o.location, "Where the structure is");
        sub->callback([&] { c.code = run_central_admin(o); });
    }
    auto* status = cmd->add_subcommand(
        "status", "This site's forwarding: entries not yet sent, lag, last error");
    c.central_status.add_to(status, false);
    status->callback([&] { c.code = run_central_status(c.central_status.finish()); });
}

void add_fleet(CLI::App& app, CommandLine& c) {
    auto* cmd = app.add_subcommand(
        "fleet", "Every site's results in the central database (docs/central.md)");
    cmd->require_subcommand(1);
    auto add = [&](CLI::App* parent, const std::string& action, const char* help) {
        auto& o = c.fleet[action];
        auto& read = c.fleet_read[action];
        o.action = action;
        auto* sub = parent->add_subcommand(action, help);
        sub->add_option("--central", o.central, "The central database (libpq URI)")->required();
        sub->add_option("--password-file", o.password_file,
                        "The password (first line); default: PGPASSFILE");
        sub->add_option("--format", read.format, "Output format")
            ->check(CLI::IsMember({"table", "csv", "json"}));
        sub->callback([&] {
            o.read = read.finish();
            c.code = run_fleet(o);
        });
        return std::pair{sub, &o};
    };
    add(cmd, "sites", "The sites: epochs, newest epoch, last forward");
    auto [status, so] = add(cmd, "status", "Every zone quantity's newest value of every site");
    status->add_option("--min-abs", so->min_abs, "Only values with |value| at least this");
    status->add_option("--site", so->site, "Only this site");
    status->add_option("--quantity", so->quantity, "Only this quantity");
    auto [serve, sv] = add(cmd, "serve", "The fleet's page in a browser (read only)");
    serve->add_option("--address", sv->address, "Listen address (default 127.0.0.1)");
    serve->add_option("--port", sv->port, "Listen port (default 8090)")
        ->check(CLI::Range(1, 65535));
    serve->add_option("--web-root", sv->web_root, "The dashboard's files (default: installed)");
    auto* query = cmd->add_subcommand("query", "A series or the alarm events");
    query->require_subcommand(1);
    auto [series, se] = add(query, "series", "One zone quantity of one site over time");
    series->add_option("--site", se->site, "Site")->required();
    series->add_option("--zone", se->zone, "Zone")->required();
    series->add_option("--quantity", se->quantity, "Quantity, e.g. m3c2_median_m")->required();
    auto [alarms, ae] = add(query, "alarms", "Alarm events of every site (or --site)");
    alarms->add_option("--site", ae->site, "Only this site");
    for (auto* sub : {series, alarms}) {
        auto& read = c.fleet_read[sub->get_name()];
        sub->add_option("--from", read.options.from, "Start: ISO-8601 UTC, or before now (-7d)");
        sub->add_option("--to", read.options.to,
                        "End (inclusive): ISO-8601 UTC, now, or before now");
    }
}

}  // namespace
}  // namespace tlsmon

int main(int argc, char** argv) {
    CLI::App app{"tlsmon: unattended deformation monitoring with a terrestrial laser scanner"};
    app.set_version_flag("--version", std::string("tlsmon ") + TLSMON_VERSION);
    app.require_subcommand(1);
    tlsmon::CommandLine c;
    // Every command, by the name it is called with.
    using Add = void (*)(CLI::App&, tlsmon::CommandLine&);
    static constexpr std::pair<std::string_view, Add> commands[] = {
        {"check-config", tlsmon::add_check_config},
        {"info", tlsmon::add_info},
        {"run", tlsmon::add_run},
        {"simulate", tlsmon::add_simulate},
        {"status", tlsmon::add_status},
        {"query", tlsmon::add_query},
        {"events", tlsmon::add_events},
        {"export", tlsmon::add_export},
        {"backup", tlsmon::add_backup},
        {"epochs", tlsmon::add_epochs},
        {"retention", tlsmon::add_retention},
        {"archive", tlsmon::add_archive},
        {"m3c2", tlsmon::add_m3c2},
        {"pbm3c2", tlsmon::add_pbm3c2},
        {"primitives", tlsmon::add_primitives},
        {"vectors", tlsmon::add_vectors},
        {"campaign", tlsmon::add_campaign},
        {"keypoints", tlsmon::add_keypoints},
        {"modbus-map", tlsmon::add_modbus_map},
        {"register", tlsmon::add_register},
        {"alarms", tlsmon::add_alarms},
        {"report", tlsmon::add_report},
        {"calibration", tlsmon::add_calibration},
        {"demo", tlsmon::add_demo},
        {"targets", tlsmon::add_targets},
        {"users", tlsmon::add_users},
        {"notify", tlsmon::add_notify},
        {"central", tlsmon::add_central},
        {"fleet", tlsmon::add_fleet},
    };
    // A command named first is the only one declared: the whole tree of options (hundreds,
    // with their defaults' text) costs a millisecond of every `tlsmon status`. Anything else
    // (--help, --version, a misspelt command) sees them all.
    const std::string_view first = argc > 1 ? argv[1] : "";
    bool one = false;
    for (const auto& [name, add] : commands)
        if (name == first) add(app, c), one = true;
    if (!one)
        for (const auto& [name, add] : commands) add(app, c);

    tlsmon::remember_program_arguments(argc, argv);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return c.code;
}
