#pragma once
// The subcommands of the `tlsmon` program as plain functions: each takes its options struct
// and returns the process exit code. The measuring ones (run, simulate, register, m3c2,
// keypoints, report, demo) are those of tlsmon-analysis; in `tlsmon` they hand the command
// line over to it (cli/analysis_handoff.cpp). Only cli/main.cpp knows the command line (CLI11,
// whose header costs seconds per file that includes it): it declares every option and
// help text and fills these structs.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cli/query_output.hpp"
#include "daemon/ingest_service.hpp"

namespace tlsmon {

// `tlsmon check-config FILE`
struct CheckConfigOptions {
    std::string file;
};
// 0: valid (effective values on stdout); 1: an error naming file, line and key.
int run_check_config(const CheckConfigOptions& options);

// `tlsmon info FILE...`
struct InfoOptions {
    std::vector<std::string> files;
    bool json = false;
};
// 0: every file read; 2: at least one could not be read (the others are still reported).
int run_info(const InfoOptions& options);

// `tlsmon status`: 0, or 1 with the error on stderr (as the other reading commands).
int run_status(const ReadOptions& options);

// `tlsmon query epochs`
int run_query_epochs(const ReadOptions& options);

// `tlsmon query meteo`: each epoch's meteo sidecar and the values used
int run_query_meteo(const ReadOptions& options);

// `tlsmon query registrations`: each epoch's registration, its parameters and targets
int run_query_registrations(const ReadOptions& options);

// `tlsmon register REFERENCE EPOCH --config SITE`: the registration of EPOCH onto
// REFERENCE through the site's targets, for an analyst checking a scan by hand.
struct RegisterOptions {
    std::string reference;
    std::string epoch;
    std::string config;
    std::string method;  // targets, planes, targets+planes; "" = the configuration's
    OutputFormat format = OutputFormat::table;
};
// 0: accepted; 3: registered but refused (the reason printed); 1: an error.
int run_register(const RegisterOptions& options);

// `tlsmon targets`: each reference target's status in the newest epoch, whether and since
// when it is excluded as moved, and why.
int run_targets(const ReadOptions& options);

// `tlsmon targets resurvey NAME [--by WHO]`: clears the target's exclusion and records who.
struct TargetResurveyOptions {
    std::string db;
    std::string config;
    std::string target;
    std::string by;  // empty: "cli:$USER"
};
// 0: cleared; 1: an error (the target is not excluded, no database, ...).
int run_target_resurvey(const TargetResurveyOptions& options);

// `tlsmon query series --zone Z --quantity Q`
struct SeriesOptions {
    ReadOptions read;
    std::string zone;
    std::string quantity;
};
int run_query_series(const SeriesOptions& options);

// `tlsmon query keypoint-models [--quantity Q] [--residuals]`: the keypoint displacement
// model of each epoch, or the residuals of its own segments
struct KeypointModelsOptions {
    ReadOptions read;
    std::string quantity;  // "" = every modelled quantity
    bool residuals = false;
};
int run_query_keypoint_models(const KeypointModelsOptions& options);

// `tlsmon query thermal-models [--zone Z] [--quantity Q] [--compensations]`: every version of
// the thermal models, or each epoch's compensation in the time range
struct ThermalModelsOptions {
    ReadOptions read;
    std::string zone;      // "" = every zone
    std::string quantity;  // "" = every modelled quantity
    bool compensations = false;
};
int run_query_thermal_models(const ThermalModelsOptions& options);

// `tlsmon query keypoints [--zone Z]`: the keypoint stage's figures per zone and epoch
struct KeypointsQueryOptions {
    ReadOptions read;
    std::string zone;  // "" = every zone with keypoint rows
};
int run_query_keypoints(const KeypointsQueryOptions& options);

// `tlsmon query corepoints --epoch N [--out FILE]`: one epoch's M3C2 at every core point
// (with --out: CSV, or JSON with --format json).
struct CorePointsOptions {
    ReadOptions read;
    std::int64_t epoch = 0;
    std::string out;
};
int run_query_corepoints(const CorePointsOptions& options);

// `tlsmon export (--epoch N [--map m3c2|pbm3c2|vectors|zones] | --campaign N) --out FILE`:
// one stored map's per-point results as LAS 1.4 with extra bytes, CSV or GeoJSON, or the
// epoch's zones with their values as GeoJSON or CSV (by FILE's extension).
struct ExportOptions {
    ReadOptions read;
    std::int64_t epoch = 0;
    std::int64_t campaign = 0;
    std::string map = "m3c2";  // or pbm3c2, vectors, zones
    std::string out;
    std::string crs;     // "" = the configuration's [station] crs, if any
    std::string bundle;  // `--bundle DIR`: the window of read.from/read.to as a folder
};
int run_export(const ExportOptions& options);
int run_export_bundle(const ExportOptions& options);

// `tlsmon backup DEST`: a consistent copy of the database while the daemon runs
// (docs/backup.md); DEST a new file, or a folder to put a time-stamped copy in.
struct BackupOptions {
    ReadOptions read;
    std::string destination;
};
int run_backup(const BackupOptions& options);

// `tlsmon epochs pin N [--note TEXT] [--by WHO]`, `unpin N`, `pinned`: epochs whose
// per-core-point maps the retention policy never thins (docs/retention.md); each pin and
// unpin is a system event naming who.
struct EpochPinOptions {
    std::string action;  // "pin", "unpin", "pinned"
    ReadOptions read;
    std::int64_t epoch = 0;
    std::string note;
    std::string by;  // empty: "cli:$USER"
};
int run_epoch_pins(const EpochPinOptions& options);

// `tlsmon retention plan|run`: what a pass of the site's [retention] policy (the defaults with
// --db) keeps and thins, or one pass now, as the daemon runs it (docs/retention.md).
struct RetentionOptions {
    std::string action;  // "plan", "run"
    ReadOptions read;
};
int run_retention(const RetentionOptions& options);
// `tlsmon archive plan|run --config FILE`: the same for the site's [archive] policy of the
// scans in paths.archive (docs/retention.md).
int run_archive(const RetentionOptions& options);

// `tlsmon query planes --epoch N`: the reference planes the registration on planes matched
// in one epoch, each with its role (datum, moved, monitored), tilt and shift with σ, and test.
struct PlanesQueryOptions {
    ReadOptions read;
    std::int64_t epoch = 0;
};
int run_query_planes(const PlanesQueryOptions& options);

// `tlsmon query stable-areas --epoch N [--state S | --as-zones]`
struct StableAreasQueryOptions {
    ReadOptions read;
    std::int64_t epoch = 0;
    std::string state;      // "" = every supervoxel; else stable, unstable, unknown, not_planar
    bool as_zones = false;  // the unstable areas as [[zone]] tables (needs read.config)
};
int run_query_stable_areas(const StableAreasQueryOptions& options);

// `tlsmon events [--kind K]`
struct EventsOptions {
    ReadOptions read;
    std::string kind;  // "" = every kind
};
int run_events(const EventsOptions& options);

// `tlsmon modbus-map --config FILE [--format markdown|csv]`: 0, or 1 with the error.
struct ModbusMapOptions {
    std::string config;
    std::string format = "markdown";
};
int run_modbus_map(const ModbusMapOptions& options);

// `tlsmon alarms`: the rules whose state is not normal.
int run_alarms(const ReadOptions& options);

// `tlsmon alarms history [--rule R]`: alarm events by time.
struct AlarmHistoryOptions {
    ReadOptions read;
    std::string rule;  // "" = every rule
};
int run_alarm_history(const AlarmHistoryOptions& options);

// `tlsmon alarms ack|shelve|unshelve|out-of-service|in-service RULE` ("*" = every rule): 0, or 1
// with the error.
struct AlarmActionOptions {
    std::string db;
    std::string config;
    std::string action;  // "ack", "shelve", "unshelve", "out-of-service", "in-service"
    std::string rule;
    std::string until;  // shelve: ISO-8601 UTC
};
int run_alarm_action(const AlarmActionOptions& options);

// `tlsmon simulate`
struct SimulateOptions {
    std::string config;
    std::string preset;
    std::string out;
    int epochs = 24;
    std::string cadence;
    std::string start = "2026-06-01T06:00:00Z";
    std::optional<std::int64_t> seed;
    double realtime = 0.0;
    double slow_copy = 0.0;
    unsigned threads = 2;
    // A personal laser scanner's campaign with this SLAM drift (none, linear, random-walk)
    // instead of the station's scans (cli/simulate_campaign.cpp).
    std::string campaign;
    std::optional<double> pulse_rate;   // Hz
    std::optional<double> range_sigma;  // m
    bool slam_frame = false;            // the campaign in the SLAM's own frame, not the scene's
};
// 0, or 1 with the error on stderr.
int run_simulate(const SimulateOptions& options);

// `tlsmon m3c2 REFERENCE COMPARED ...`: M3C2 between any two readable scan files, one CSV row
// per core point (docs/m3c2.md).
struct M3c2Options {
    std::string reference;
    std::string compared;
    std::string out;
    std::string config;     // a site's configuration: its [m3c2], zones and registration
    std::string core_file;  // core points from this file (else subsampled at core_spacing)
    // Each one given replaces the parameter (algorithms/m3c2/parameters.hpp).
    std::optional<double> core_spacing;
    std::vector<double> normal_radii;  // empty: not given
    std::optional<double> cylinder_radius;
    std::optional<double> max_depth;
    std::optional<std::string> orient;  // "scanner" or "X,Y,Z"
    std::optional<double> registration_error;
    bool median = false;
    std::optional<int> min_points;
    std::optional<double> max_roughness;
    std::optional<double> stray_distance;
    std::optional<int> threads;
};
// 0, or 1 with the error on stderr.
int run_m3c2(const M3c2Options& options);

// `tlsmon pbm3c2 REFERENCE COMPARED ... --out RESULT.csv`: patch-based M3C2 between two scan
// files (docs/pbm3c2.md): the site's [pbm3c2], zones, segmentation and registration with
// --config, else a fresh site's parameters on the whole of REFERENCE in the files' frame.
struct PbM3c2Options {
    std::string reference;
    std::string compared;
    std::string out;
    std::string config;
    // Each one given replaces the parameter (algorithms/patches/parameters.hpp; the
    // segmentation's: [registration] stable_voxel, stable_seed).
    std::optional<double> search_depth;
    std::optional<int> min_points;
    std::optional<double> max_roughness;
    std::optional<double> max_incidence_deg;
    std::optional<double> voxel;
    std::optional<double> seed;
    std::optional<int> threads;
};
// 0, or 1 with the error on stderr.
int run_pbm3c2(const PbM3c2Options& options);

// `tlsmon vectors REFERENCE COMPARED ... --out RESULT.csv`: 3-D vectors by local registration
// of quasi-rigid areas between two scan files (docs/vectors.md): the site's [vectors], zones,
// segmentation and registration with --config, else a fresh site's parameters on the whole of
// REFERENCE in the files' frame.
struct VectorsOptions {
    std::string reference;
    std::string compared;
    std::string out;
    std::string config;
    // Each one given replaces the parameter ([vectors]; the segmentation's: [registration]
    // stable_voxel, stable_seed).
    std::optional<double> window;
    std::optional<double> search_radius;
    std::optional<double> search_depth;
    std::optional<double> block;
    std::optional<double> max_incidence_deg;
    std::optional<double> voxel;
    std::optional<double> seed;
    std::optional<int> threads;
};
// 0, or 1 with the error on stderr.
int run_vectors(const VectorsOptions& options);

// `tlsmon campaign compare REFERENCE CAMPAIGN --out DIR`: a campaign cloud (a personal or
// mobile scanner's) against the TLS reference, segment by segment (docs/campaigns.md).
struct CampaignCompareOptions {
    std::string reference;
    std::string campaign;
    std::string out;                        // a folder, created
    std::string metric = "point-to-plane";  // of the segments' ICP, or point-to-point
    std::string c2c = "local-plane";        // or nearest-point
    std::optional<double> radius;           // the local planes' and verticality's
    std::optional<double> max_distance;     // of a pair
    std::optional<int> min_segment_points;
    std::optional<double> min_planar_share;        // of a segment's points on modelled surfaces
    std::optional<double> thinning;                // m, the classification's voxel
    std::optional<long long> registration_points;  // the most a registration uses
    bool keep_ground = false;                      // segment the ground like the rest
    std::optional<double> ground_threshold;        // cloth simulation filter's class threshold
    std::optional<double> cloth_resolution;
    std::optional<int> rigidness;
    std::optional<int> threads;
    std::string coarse = "auto";  // the campaign's frame: none, planes or auto
};
int run_campaign_compare(const CampaignCompareOptions& options);

// `tlsmon campaign add FILE --instrument NAME [--config SITE]`: a campaign cloud compared with
// the site's reference epoch and stored as a campaign epoch (docs/campaigns.md).
struct CampaignAddOptions {
    std::string file;
    std::string instrument;  // an [[instrument]] of the configuration
    std::string config;
    std::optional<std::string> acquired;  // ISO 8601 UTC; default as the ingest finds it
};
// 0: stored, or stored before; 1 with the error on stderr.
int run_campaign_add(const CampaignAddOptions& options);

// `tlsmon query campaigns`, `tlsmon query campaign-segments --campaign N`: the campaign epochs
// acquired in a range, or one campaign's segments.
int run_query_campaigns(const ReadOptions& options);
struct CampaignSegmentsOptions {
    ReadOptions read;
    std::int64_t campaign = 0;
};
int run_query_campaign_segments(const CampaignSegmentsOptions& options);
// `tlsmon query campaign-points --campaign N`: the points a campaign kept ([campaign]
// store_spacing) in the reference's frame, with their segment and C2C vector.
int run_query_campaign_points(const CampaignSegmentsOptions& options);

// `tlsmon primitives REFERENCE COMPARED --config SITE --out RESULT.csv`: the primitives the
// site's zones name, fitted in both files, their change tested (docs/primitives.md); without
// --config one zone --box holding one --kind, in the files' own frame.
struct PrimitivesOptions {
    std::string reference;
    std::string compared;
    std::string out;
    std::string config;
    std::string kind = "cylinder";
    std::vector<double> box;  // x_min y_min z_min x_max y_max z_max
    std::optional<double> band;
    std::optional<double> max_incidence_deg;
    std::optional<double> alpha;
    std::optional<int> threads;
};
// 0, or 1 with the error on stderr.
int run_primitives(const PrimitivesOptions& options);

// `tlsmon report --database DB [--truth DIR] --out DIR`: a run's report (Markdown, CSV, PNG
// plots), scored against the simulator's truth when given. 0, or 1 with the error on stderr.
struct ReportOptions {
    std::string database;
    std::string truth;  // "": no truth, nothing scored
    std::string out;
    std::string config;  // the daemon's configuration, named in the example commands
    int modbus_port = 1502;
    std::string from, to;  // the window, as ReadOptions; empty = open
};
int run_report(const ReportOptions& options);

// `tlsmon calibration --db DB --truth DIR`: each method's coverage of its true errors by its
// own σ / LoD95 (docs/calibration.md). 0, or 1 with the error on stderr.
struct CalibrationOptions {
    ReadOptions read;
    std::string truth;
};
int run_calibration(const CalibrationOptions& options);

// `tlsmon demo`: the daemon on a simulated day, one scan every few seconds, a line per epoch,
// then the report.
struct DemoOptions {
    std::string workdir = "tlsmon-demo";
    int epochs = 96;
    double interval = 2.0;
    std::string preset = "small";
    std::string start;  // ISO-8601 UTC; "" = 00:00 UTC today (the reference at night)
    int modbus_port = 1502;
    int http_port = 8080;  // the dashboard on 127.0.0.1; 0: none
    bool serve = false;    // after the report, keep the daemon (and dashboard) until Ctrl-C
    unsigned threads = 2;
};
// 0: the run finished and its report was written; 1: an error; 130: interrupted (Ctrl-C).
int run_demo(const DemoOptions& options);

// `tlsmon keypoints REFERENCE EPOCH ... --out VECTORS.csv`: keypoint displacement vectors
// between two structured scans already in one frame.
struct KeypointsOptions {
    std::string reference;
    std::string epoch;
    std::string out;
    std::string config;  // a site's configuration: its [keypoints], zones and registration
    // Each one given replaces the parameter (algorithms/keypoints/parameters.hpp).
    std::optional<std::string> detector;
    std::optional<std::string> descriptor;
    std::optional<double> detector_threshold;
    std::optional<double> window_deg;
    std::optional<double> window_m;
    std::optional<double> ratio;
    bool mutual = false;
    bool clahe = false;
    bool no_refine = false;
    std::optional<double> segments_deg;  // bands of the vertical angle this high
    std::string images;                  // folder for the pictures; "": none
    std::string summary;                 // CSV of the segments' figures; "": none
    double vector_scale = 20.0;
    std::optional<int> scan;  // only the k-th structured scan of each file, from 1
};
// 0, or 1 with the error on stderr.
int run_keypoints(const KeypointsOptions& options);

// `tlsmon run`: the ingest daemon (run_daemon, daemon/ingest_service.hpp).
int run_ingest(const RunOptions& options);

// `tlsmon users add NAME --role ROLE | remove NAME | list`: the dashboard's users file.
struct UsersOptions {
    std::string action;  // add, remove, list
    std::string name;
    std::string role = "viewer";
    std::string file;  // the users file; "" = the configuration's http.users_file
    std::string config;
    bool password_stdin = false;
};
int run_users(const UsersOptions& options);

// `tlsmon notify test` (docs/notifications.md); measuring program (libcurl, libmosquitto).
struct NotifyTestOptions {
    std::string config;
    std::string channel;  // "" = every channel
};
int run_notify_test(const NotifyTestOptions& options);

// `tlsmon central migrate|add-site|rotate-credential URL` (docs/central.md): the central
// database's schema and its sites, done as the database's owner.
struct CentralAdminOptions {
    std::string action;  // migrate, add-site, rotate-credential
    std::string url;
    std::string password_file;  // the owner's; "" = libpq's PGPASSFILE
    std::string name, location;
    std::string site_password_file;  // the site's (new) password
};
int run_central_admin(const CentralAdminOptions& options);
// `tlsmon central status --db|--config`: this site's forwarding: backlog, lag, last error.
int run_central_status(const ReadOptions& options);

// `tlsmon fleet sites|status|query series|query alarms --central URL`: the central
// database's view of every site, as the site's own `tlsmon query` prints its own.
struct FleetOptions {
    std::string action;  // sites, status, series, alarms, serve
    std::string central, password_file;
    ReadOptions read;  // format, from, to
    std::string site, zone, quantity;
    std::optional<double> min_abs;
    std::string address = "127.0.0.1";  // serve: where the fleet's page listens
    int port = 8090;
    std::filesystem::path web_root;  // "" = the installed dashboard files
};
int run_fleet(const FleetOptions& options);
// `fleet serve` (cli/fleet_serve.cpp).
int serve_fleet(const FleetOptions& options);

}  // namespace tlsmon
