#include "daemon/ingest_service.hpp"

#include <poll.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <iostream>
#include <thread>
#include <utility>

#include "config/config.hpp"
#include "config/reload.hpp"
#include "config/site_definition.hpp"
#include "daemon/alarm_actions.hpp"
#include "daemon/alarm_shelving.hpp"
#include "daemon/central_forwarder.hpp"
#include "daemon/http/http_service.hpp"
#include "daemon/ingest.hpp"
#include "daemon/ingest_campaign.hpp"
#include "daemon/ingest_files.hpp"
#include "daemon/ingest_meteo.hpp"
#include "daemon/logging.hpp"
#include "daemon/modbus/modbus_service.hpp"
#include "daemon/notify/notify_service.hpp"
#include "daemon/retention_service.hpp"
#include "daemon/shutdown.hpp"
#include "daemon/startup_checks.hpp"
#include "daemon/system_alarm_watch.hpp"
#include "daemon/systemd_notify.hpp"
#include "daemon/watcher.hpp"
#include "formats/meteo_csv.hpp"
#include "pipeline/epoch_pipeline.hpp"

namespace tlsmon {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::duration;
using std::chrono::duration_cast;

namespace {

Clock::duration seconds(double s) {
    return duration_cast<Clock::duration>(duration<double>(s));
}

// The pause after a database or disk failure: retry_initial, doubling up to retry_max.
double next_backoff(double current, const IngestConfig& c) {
    return current == 0 ? c.retry_initial : std::min(current * 2, c.retry_max);
}

// Sleeps `seconds` (less when a stop is asked), keeping systemd's watchdog fed.
void wait_alive(SystemdNotify& systemd, Shutdown& shutdown, double seconds) {
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(seconds));
    while (Clock::now() < until && !shutdown.wait_for(std::chrono::milliseconds(200))) {
        systemd.watchdog_if_due();
    }
}

// The Modbus server as `config` asks (nullptr when disabled); Error when it cannot listen.
std::unique_ptr<ModbusService> start_modbus_service(const Config& config) {
    if (!config.modbus.enabled) return nullptr;
    std::vector<std::string> zones;
    for (const auto& z : config.zones) zones.push_back(z.name);
    return std::make_unique<ModbusService>(
        config.modbus, config.paths.database, std::move(zones),
        [](EpochDatabase& db, const std::string& rule, const std::string& client, UtcSeconds now) {
            return acknowledge_alarm(db, rule, AlarmActor::scada, now, "modbus client " + client);
        });
}

// The dashboard's door to the alarm actions: the same functions as `tlsmon alarms` and the
// Modbus coils.
int carry_out_operator_action(EpochDatabase& db, const OperatorAction& a, UtcSeconds now) {
    const auto web = AlarmActor::web;
    if (a.action == "ack") return acknowledge_alarm(db, a.rule, web, now, a.who, a.comment);
    if (a.action == "shelve")
        return shelve_alarm(db, a.rule, a.until.value_or(now), web, now, a.who, a.comment);
    if (a.action == "unshelve") return unshelve_alarm(db, a.rule, web, now, a.who, a.comment);
    if (a.action == "out-of-service")
        return remove_alarm_from_service(db, a.rule, web, now, a.who, a.comment);
    if (a.action == "in-service")
        return return_alarm_to_service(db, a.rule, web, now, a.who, a.comment);
    throw Error("unknown alarm action '" + a.action + "'");
}

void log_config(const Config& config) {
    spdlog::info("configuration {}:", config.file.string());
    for (const auto& line : describe(config)) spdlog::info("  {}", line);
}

class Daemon {
  public:
    // `modbus`: a server already serving SCADA while the database could not be opened,
    // since `refused_since`; taken over once the database opens (left to the caller when
    // it does not), else started here.
    Daemon(Config config, bool once, Shutdown& shutdown, std::unique_ptr<ModbusService>& modbus,
           std::optional<UtcSeconds> refused_since)
        : config_(std::move(config)),
          once_(once),
          shutdown_(shutdown),
          db_(EpochDatabase::open(config_.paths.database, EpochDatabase::Mode::read_write)),
          watcher_(config_.paths.ingest, config_.ingest),
          pipeline_config_(pipeline_config(config_)) {
        modbus_ = std::move(modbus);
        if (refused_since) {    // the system alarm of that time, stored with the rows to come
            disk_full_ = true;  // as Modbus shows it, until a write goes through
            SystemObservation seen;
            seen.now = *refused_since;
            seen.database_error = true;
            unstored_.push_back(seen);
        }
    }

    void run();

  private:
    IngestContext context() { return IngestContext{db_, config_, station_, events_}; }
    PipelineContext pipeline() {
        return PipelineContext{db_, pipeline_config_, events_, reference_cache_};
    }
    bool start();         // false: stopped before the database took the start's rows
    void store_site();    // station, zones, rules, the start event, the reference epoch
    void note_disk();     // disk_full_ from the last write, shown on Modbus at once
    void start_modbus();  // (again) as config_.modbus says; the old server stops first
    void start_http();    // likewise for config_.http
    // Likewise for config_.notify; when it is off, the notifier's cursor passes over the
    // alarm events (turning it on later must not send the history).
    void start_notify();
    void start_retention();
    void switch_central_outbox();
    void start_central();
    // After a reload: `start` (again), each outcome an event ("Modbus server restarted on
    // ADDRESS:PORT", or why it could not be and what is `without` it meanwhile).
    void restart_server(const std::string& name, const std::string& section,
                        const std::function<void()>& start, bool enabled,
                        const std::string& address, int port, const std::string& without);
    void reload();
    void ingest_complete_files(Clock::time_point now);
    // Copies of epochs that were not processed yet, once those epochs are.
    void ingest_waiting_copies();
    void ingest(const fs::path& file);
    // Processes pending epochs until none is left, a retry is due later, or stop.
    void process_backlog();
    // The campaign files taken, after the backlog (a campaign needs the reference epoch).
    void process_campaigns();
    // Feeds the system alarms (daemon/system_alarm_watch.hpp); a failure is logged only.
    void observe(SystemObservation seen);
    void report_status();
    std::string since_start() const {
        return std::to_string(done_) + " epoch(s) done, " + std::to_string(rejected_) +
               " rejected, " + std::to_string(failed_) + " failed since start";
    }
    Clock::duration next_wait(Clock::time_point now) const;

    Config config_;
    bool once_;
    Shutdown& shutdown_;
    EpochDatabase db_;
    FolderWatcher watcher_;
    PipelineConfig pipeline_config_;
    std::optional<std::pair<EpochId, HashedBytes>> latest_bytes_;  // see ingest()
    ReferenceCache reference_cache_{db_};
    SystemdNotify systemd_;
    SystemEventLog events_;
    std::optional<StationId> station_;
    Clock::time_point next_rescan_{};
    Clock::time_point retry_at_{};  // processing / ingest paused until then (disk full)
    double backoff_ = 0;
    std::vector<fs::path> retry_files_;
    struct WaitingCopy {
        fs::path file;
        EpochId epoch = 0;
    };
    std::vector<WaitingCopy> waiting_copies_;
    MeteoSidecars meteo_;
    CampaignIngest campaigns_;
    // The next epoch in acquisition order waits for its meteo sidecar until then.
    std::optional<Clock::time_point> meteo_wait_;
    Clock::time_point next_status_{};
    std::int64_t done_ = 0, rejected_ = 0, failed_ = 0;
    bool disk_full_ = false;  // the last write failed for lack of space
    static constexpr std::size_t kMaxUnstored = 64;
    std::vector<SystemObservation> unstored_;  // system alarm observations not stored yet
    UtcSeconds started_ = now_utc();
    std::optional<double> disk_free_share_;  // as last observed
    // Last members: stopped first, before the database they read is closed.
    std::unique_ptr<HttpService> http_;
    std::unique_ptr<ModbusService> modbus_;
    std::unique_ptr<NotifyService> notify_;
    std::unique_ptr<RetentionService> retention_;
    std::unique_ptr<CentralForwarder> central_;
};

// Modbus first: SCADA sees the daemon (and a full disk) while the database refuses writes;
// the rows a start writes are retried with the back-off until the database takes them.
bool Daemon::start() {
    if (!modbus_) start_modbus();
    start_http();
    start_notify();
    systemd_.ready();
    while (!shutdown_.stop_requested()) {
        try {
            store_site();
            break;
        } catch (const StorageError& e) {
            events_.write_failed(e);
            note_disk();
            backoff_ = next_backoff(backoff_, config_.ingest);
            spdlog::error("cannot start processing: {}; retry in {:.1f} s", e.what(), backoff_);
            SystemObservation seen;
            seen.database_error = true;
            observe(seen);
            wait_alive(systemd_, shutdown_, backoff_);
        }
    }
    if (shutdown_.stop_requested()) return false;
    start_retention();  // after the site is stored: its first pass runs now
    start_central();
    backoff_ = 0;
    watcher_.rescan(Clock::now());
    next_rescan_ = Clock::now() + seconds(config_.ingest.rescan_interval);
    return true;
}

void Daemon::store_site() {
    station_ = db_.site().upsert_station(config_.station.name, {0.0, 0.0, 0.0});
    // The rules' definitions; their states (and memories) stay as stored.
    store_zones_and_rules(db_, config_);
    store_system_alarm_rules(db_);
    const std::int64_t recovered = db_.epochs().recover_interrupted();
    events_.record(db_, "info", "start",
                   "tlsmon started (" + config_.file.string() + "); " + std::to_string(recovered) +
                       " interrupted epoch(s) back to pending");
    if (!can_register(pipeline_config_.registration)) {
        events_.record(db_, "warning", "no_registration", kNoRegistrationWarning);
    }
    if (stable_areas_alone(pipeline_config_.registration)) {
        events_.record(db_, "warning", "stable_areas_alone", kStableAreasAloneWarning);
    }
    switch_central_outbox();
    auto ctx = pipeline();
    ensure_reference(ctx);
    events_.wrote();
    note_disk();
}

// The outbox's triggers on or off as [central] enabled and forward_arrays say; switched on for
// the first time, the site's history is queued (docs/central.md).
void Daemon::switch_central_outbox() {
    db_.central_outbox().set_forward_arrays(config_.central.forward_arrays);
    const std::int64_t queued = db_.central_outbox().set_enabled(config_.central.enabled);
    if (queued > 0) {
        events_.record(db_, "info", "central_forward",
                       std::to_string(queued) +
                           " entries of the site's history queued for the central database");
    }
}

void Daemon::start_central() {
    central_.reset();
    if (config_.central.enabled)
        central_ = std::make_unique<CentralForwarder>(config_.central, config_.paths.database,
                                                      config_.station.name);
}

void Daemon::note_disk() {
    const bool full = events_.disk_full();
    if (full == disk_full_) return;
    disk_full_ = full;
    if (full) {
        spdlog::error("the database's disk is full: nothing is stored until space returns");
    } else {
        spdlog::info("the database takes writes again");
    }
    if (modbus_) modbus_->set_disk_full(full);
}

void Daemon::start_http() {
    http_.reset();
    if (!config_.http.enabled) return;
    DashboardSite site;
    site.station = config_.station.name;
    for (const auto& z : config_.zones) site.zones.push_back(z.name);
    site.started = started_;
    site.disk_free_share = disk_free_share_;
    http_ = std::make_unique<HttpService>(config_.http, config_.paths.database, std::move(site),
                                          carry_out_operator_action);
}

void Daemon::start_notify() {
    notify_.reset();
    if (!config_.notify.enabled) {
        try {
            pass_over_alarm_events(db_);
        } catch (const StorageError& e) {
            spdlog::warn("notifications are off; their cursor stays behind: {}", e.what());
        }
        return;
    }
    for (const auto& problem : notify_file_problems(config_.notify))
        events_.record(db_, "warning", "notify_config", problem + "; its sends fail until it can");
    DashboardSite site;
    site.station = config_.station.name;
    for (const auto& z : config_.zones) site.zones.push_back(z.name);
    site.started = started_;
    site.disk_free_share = disk_free_share_;
    notify_ =
        std::make_unique<NotifyService>(config_.notify, config_.paths.database, std::move(site));
}

void Daemon::start_retention() {
    retention_.reset();
    if (config_.retention.enabled || config_.archive.enabled) {
        retention_ = std::make_unique<RetentionService>(
            config_.retention, config_.archive, config_.paths.archive, config_.paths.database);
    }
}

void Daemon::restart_server(const std::string& name, const std::string& section,
                            const std::function<void()>& start, bool enabled,
                            const std::string& address, int port, const std::string& without) {
    try {
        start();
        events_.record(db_, "info", "config_reload",
                       enabled
                           ? name + " server restarted on " + address + ":" + std::to_string(port)
                           : name + " server stopped (" + section + ".enabled = false)");
    } catch (const Error& e) {
        events_.record(db_, "error", "config_reload",
                       "the " + name + " server could not be restarted: " + e.what() + "; " +
                           without + " until the next reload");
    }
}

void Daemon::start_modbus() {
    modbus_.reset();
    modbus_ = start_modbus_service(config_);
    if (modbus_) modbus_->set_disk_full(disk_full_);
}

void Daemon::reload() {
    try {
        Config fresh = load_config(config_.file);
        if (fresh.paths.ingest != config_.paths.ingest ||
            fresh.paths.database != config_.paths.database) {
            events_.record(db_, "warning", "config_reload",
                           "paths.ingest and paths.database change only on restart: kept " +
                               config_.paths.ingest.string() + " and " +
                               config_.paths.database.string());
            fresh.paths.ingest = config_.paths.ingest;
            fresh.paths.database = config_.paths.database;
        }
        create_missing_folders(check_startup(fresh));  // a new archive or quarantine folder
        const ReloadChanges changes = compare_for_reload(config_, fresh);
        if (!changes.refused.empty()) {
            events_.record(db_, "error", "config_reload",
                           "reload refused, the previous configuration stays: " + changes.refused +
                               "; restart tlsmon to apply such a configuration on purpose");
            return;
        }
        setup_logging(fresh.logging);
        const bool restart_modbus = changes.modbus;
        const bool restart_http = changes.http;
        const bool restart_retention =
            !(fresh.retention == config_.retention) || !(fresh.archive == config_.archive);
        const bool restart_central = !(fresh.central == config_.central);
        config_ = std::move(fresh);
        pipeline_config_ = pipeline_config(config_);
        watcher_.set_config(config_.ingest);
        station_ = db_.site().upsert_station(config_.station.name, {0.0, 0.0, 0.0});
        store_zones_and_rules(db_, config_);
        log_config(config_);
        for (const auto& removed : changes.removed) {
            events_.record(db_, "warning", "config_reload", "reload removes " + removed);
        }
        if (restart_modbus) {
            restart_server(
                "Modbus", "modbus", [this] { start_modbus(); }, config_.modbus.enabled,
                config_.modbus.address, config_.modbus.port, "SCADA has no server");
        }
        if (restart_http) {
            restart_server(
                "HTTP", "http", [this] { start_http(); }, config_.http.enabled,
                config_.http.address, config_.http.port, "no dashboard");
        }
        if (changes.notify) {
            try {
                start_notify();
                events_.record(db_, "info", "config_reload",
                               config_.notify.enabled
                                   ? "notifications restarted: " +
                                         std::to_string(config_.notify.channels.size()) +
                                         " channel(s), " +
                                         std::to_string(config_.notify.routes.size()) + " route(s)"
                                   : std::string("notifications stopped (notify.enabled = false)"));
            } catch (const Error& e) {
                events_.record(db_, "error", "config_reload",
                               std::string("notifications could not be restarted: ") + e.what() +
                                   "; none are sent until the next reload");
            }
        }
        if (restart_retention) {
            start_retention();
            events_.record(
                db_, "info", "config_reload",
                std::string(config_.retention.enabled
                                ? "retention policy restarted"
                                : "retention stopped (retention.enabled = false): every map is "
                                  "kept") +
                    (config_.archive.enabled ? "; archive policy on"
                                             : "; archive policy off: every scan is kept"));
        }
        if (restart_central) {
            switch_central_outbox();
            start_central();
            events_.record(db_, "info", "config_reload",
                           config_.central.enabled
                               ? "central forwarding restarted"
                               : "central forwarding stopped (central.enabled = false); the "
                                 "outbox keeps what is not yet sent");
        }
        events_.record(db_, "info", "config_reload", "configuration reloaded");
    } catch (const Error& e) {
        events_.record(db_, "error", "config_reload",
                       std::string("reload failed, the previous configuration stays: ") + e.what());
    }
}

void Daemon::ingest_complete_files(Clock::time_point now) {
    std::vector<GrowingFile> growing;
    std::vector<fs::path> files = watcher_.take_complete(now, growing);
    for (const auto& g : growing) {
        events_.record(db_, "warning", "file_growing",
                       g.path.string() + " is still growing after " +
                           std::to_string(static_cast<long>(g.seconds)) + " s (" +
                           std::to_string(g.size) + " bytes); not processed while it grows");
    }
    for (const auto& entry : watcher_.take_not_files()) {
        if (entry.kind == "symbolic link") {
            std::error_code ec;
            const fs::path target = fs::read_symlink(entry.path, ec);
            events_.record(db_, "warning", "symlink",
                           entry.path.string() + " is a symbolic link" +
                               (ec ? std::string() : " to " + target.string()) +
                               "; links in the ingest folder are never followed: left in place, "
                               "not ingested (copy or move the scan itself into the folder)");
        } else {
            events_.record(db_, "warning", "not_a_file",
                           entry.path.string() + " is a " + entry.kind +
                               ", not a regular file: left in place, not ingested");
        }
    }
    if (now >= retry_at_) {
        files.insert(files.begin(), retry_files_.begin(), retry_files_.end());
        retry_files_.clear();
    } else {
        retry_files_.insert(retry_files_.end(), files.begin(), files.end());
        return;
    }
    // Copies of one scan arriving together: the one whose name carries a time stamp comes
    // first and becomes the epoch (with the acquisition time of its name); the others are
    // its duplicates.
    std::stable_partition(files.begin(), files.end(), [](const fs::path& f) {
        return time_from_file_name(f.filename().string()).has_value();
    });
    for (const auto& f : files) ingest(f);
    if (!retry_files_.empty() && retry_at_ <= now) {
        backoff_ = next_backoff(backoff_, config_.ingest);
        retry_at_ = now + seconds(backoff_);
    }
}

void Daemon::ingest(const fs::path& file) {
    auto ctx = context();
    if (is_meteo_sidecar_name(file.filename().string())) {
        meteo_.take(ctx, file, Clock::now());
        return;
    }
    if (const auto* instrument = instrument_for(config_.instruments, file.filename().string())) {
        campaigns_.take(file, *instrument);
        return;
    }
    HashedBytes bytes;
    ctx.new_epoch_bytes = &bytes;
    EpochId epoch = 0;
    const IngestOutcome outcome = ingest_file(ctx, file, &epoch);
    // The newest epoch's bytes stay at hand (one file's worth of memory): at the usual
    // cadence it is the next epoch processed, which then reads nothing again.
    if (outcome == IngestOutcome::new_epoch) latest_bytes_ = {epoch, std::move(bytes)};
    if (outcome == IngestOutcome::retry_later) {
        retry_files_.push_back(file);
        note_disk();
    }
    if (outcome == IngestOutcome::wait_for_epoch) waiting_copies_.push_back({file, epoch});
}

void Daemon::ingest_waiting_copies() {
    if (waiting_copies_.empty() || Clock::now() < retry_at_) return;
    std::vector<WaitingCopy> waiting = std::exchange(waiting_copies_, {});
    for (std::size_t i = 0; i < waiting.size(); ++i) {
        try {
            const auto epoch = db_.epochs().find(waiting[i].epoch);
            if (epoch && (epoch->status == EpochStatus::pending ||
                          epoch->status == EpochStatus::processing)) {
                waiting_copies_.push_back(waiting[i]);  // not yet: hashed again only then
                continue;
            }
        } catch (const StorageError& e) {
            spdlog::warn("{}", e.what());
            waiting_copies_.insert(waiting_copies_.end(), waiting.begin() + i, waiting.end());
            return;
        }
        ingest(waiting[i].file);
    }
}

void Daemon::process_backlog() {
    meteo_wait_.reset();
    if (Clock::now() < retry_at_) return;
    auto ctx = pipeline();
    try {
        events_.flush(db_);
        if (backoff_ > 0) db_.epochs().recover_interrupted();
        for (const Epoch& epoch : db_.epochs().pending()) {
            if (shutdown_.stop_requested()) return;
            systemd_.watchdog();  // one epoch may take the whole WatchdogSec
            // In acquisition order: an epoch waiting for its meteo sidecar holds back the
            // later ones (the reference epoch and the alarms' time order depend on it).
            const auto meteo = meteo_.pair(epoch, config_.meteo, watcher_, Clock::now());
            if (!meteo.ready) {
                meteo_wait_ = meteo.wake;
                return;
            }
            HashedBytes* preloaded = nullptr;
            if (latest_bytes_ && latest_bytes_->first == epoch.id)
                preloaded = &latest_bytes_->second;
            const EpochOutcome outcome = process_epoch(ctx, epoch, preloaded, meteo.sidecar);
            if (preloaded) latest_bytes_.reset();
            if (meteo.sidecar) {
                auto ingest_ctx = context();
                meteo_.after_processing(ingest_ctx, *meteo.sidecar, Clock::now());
            }
            if (outcome == EpochOutcome::retry_later) {
                backoff_ = next_backoff(backoff_, config_.ingest);
                retry_at_ = Clock::now() + seconds(backoff_);
                spdlog::warn("processing paused for {:.1f} s", backoff_);
                SystemObservation seen;
                seen.database_error = true;
                observe(seen);
                return;
            }
            events_.wrote();  // the commit went through
            note_disk();
            if (modbus_) modbus_->epoch_committed();
            if (http_) http_->epoch_committed(epoch.id);
            if (notify_) notify_->wake();  // the epoch's alarm events
            if (central_) central_->wake();
            if (outcome == EpochOutcome::done) ++done_;
            if (outcome == EpochOutcome::rejected) ++rejected_;
            if (outcome == EpochOutcome::failed) ++failed_;
            if (outcome != EpochOutcome::skipped) {
                SystemObservation seen;
                seen.last_epoch_rejected = outcome == EpochOutcome::rejected;
                seen.last_epoch_failed = outcome == EpochOutcome::failed;
                seen.database_error = false;
                observe(seen);
            }
            backoff_ = 0;
            systemd_.watchdog_if_due();
            // New files keep arriving during a long backlog: take them in between.
            watcher_.read_events(Clock::now());
            if (shutdown_.take_reload()) reload();
        }
    } catch (const std::exception& e) {  // the database, or the file system under it
        if (const auto* storage = dynamic_cast<const StorageError*>(&e)) {
            events_.write_failed(*storage);
        }
        backoff_ = next_backoff(backoff_, config_.ingest);
        retry_at_ = Clock::now() + seconds(backoff_);
        spdlog::error("{}; retry in {:.1f} s", e.what(), backoff_);
        SystemObservation seen;
        seen.database_error = true;
        observe(seen);
    }
}

void Daemon::process_campaigns() {
    if (!campaigns_.waiting() || Clock::now() < retry_at_) return;
    systemd_.watchdog();  // a campaign of 20 M points takes about a minute and a half
    auto ctx = context();
    if (!campaigns_.process(ctx)) note_disk();
}

void Daemon::observe(SystemObservation seen) {
    const SystemAlarmConfig config{.cadence_seconds = config_.alarm.cadence,
                                   .stale_factor = config_.alarm.stale_factor,
                                   .disk_free_min = config_.alarm.disk_free_min};
    seen.now = now_utc();
    try {
        if (!seen.last_epoch_acquired) seen.last_epoch_acquired = newest_epoch_acquired(db_);
    } catch (const std::exception& e) {
        spdlog::warn("system.stale not observed: {}", e.what());
    }
    if (!seen.disk_free_fraction) {
        seen.disk_free_fraction = disk_free_share(config_.paths.database.parent_path());
    }
    disk_free_share_ = seen.disk_free_fraction;
    // Kept in memory, in order, until the database takes them: an alarm raised while the
    // disk is full is stored with the time it was raised (the first kept is never dropped).
    unstored_.push_back(seen);
    if (unstored_.size() > kMaxUnstored) unstored_.erase(unstored_.begin() + 1);
    try {
        while (!unstored_.empty()) {
            observe_system_alarms(db_, config, unstored_.front());
            unstored_.erase(unstored_.begin());
        }
        events_.wrote();
        // A shelve ends at its expiry, not at its rule's next epoch (docs/alarms.md).
        if (const int n = expire_due_shelves(db_, seen.now))
            spdlog::info("{} shelve(s) expired", n);
    } catch (const StorageError& e) {
        events_.write_failed(e);
        spdlog::error("system alarms kept in memory ({}) until the database takes them: {}",
                      unstored_.size(), e.what());
    } catch (const std::exception& e) {
        spdlog::error("system alarms not updated: {}", e.what());
    }
    note_disk();
}

void Daemon::report_status() {
    const auto now = Clock::now();
    if (now < next_status_) return;
    next_status_ = now + seconds(config_.daemon.status_interval);
    observe({});  // system.stale and system.disk_nearly_full
    if (notify_) {
        notify_->set_disk_free_share(disk_free_share_);
        notify_->wake();
    } else {
        try {
            pass_over_alarm_events(db_);
        } catch (const StorageError&) {
            // the next status tick tries again
        }
    }
    std::string text = since_start();
    if (now < retry_at_) text += "; waiting to retry after a disk/database error";
    systemd_.status(text);
}

Clock::duration Daemon::next_wait(Clock::time_point now) const {
    Clock::duration wait = next_rescan_ > now ? next_rescan_ - now : Clock::duration::zero();
    wait = std::min(wait, watcher_.until_next_check(now));
    if (retry_at_ > now) wait = std::min(wait, retry_at_ - now);
    if (meteo_wait_)
        wait = std::min(wait, *meteo_wait_ > now ? *meteo_wait_ - now : Clock::duration::zero());
    if (auto orphan = meteo_.next_orphan_check()) {
        wait = std::min(wait, *orphan > now ? *orphan - now : Clock::duration::zero());
    }
    if (auto w = systemd_.until_watchdog()) wait = std::min(wait, *w);
    return std::max(wait, Clock::duration(std::chrono::milliseconds(10)));
}

void Daemon::run() {
    if (!start()) {
        systemd_.stopping();
        return;
    }
    spdlog::info("watching {}", config_.paths.ingest.string());
    while (!shutdown_.stop_requested()) {
        const auto now = Clock::now();
        watcher_.read_events(now);
        if (now >= next_rescan_) {
            watcher_.rescan(now);
            next_rescan_ = now + seconds(config_.ingest.rescan_interval);
        }
        ingest_complete_files(now);
        {
            auto ctx = context();
            meteo_.quarantine_orphans(ctx, now);
        }
        process_backlog();
        process_campaigns();
        ingest_waiting_copies();
        if (shutdown_.take_reload()) reload();
        systemd_.watchdog_if_due();
        report_status();
        if (http_) http_->heartbeat(now_utc(), disk_free_share_);
        if (once_ && !watcher_.has_candidates_in_time() && retry_files_.empty() &&
            waiting_copies_.empty() && !meteo_wait_ && Clock::now() >= retry_at_) {
            break;
        }
        const auto wait = next_wait(Clock::now());
        pollfd fds[2] = {{watcher_.fd(), POLLIN, 0}, {shutdown_.fd(), POLLIN, 0}};
        const int ms =
            static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(wait).count());
        ::poll(fds, 2, ms);
        if (fds[1].revents & POLLIN) shutdown_.clear_wakeup();
    }
    systemd_.stopping();
    events_.record(db_, "info", "stop", "tlsmon stopped; " + since_start());
}

}  // namespace

int run_daemon(const RunOptions& options) {
    SignalThread::block_signals();
    Config config;
    try {
        config = load_config(options.config_file);
        const auto missing = check_startup(config);  // the same checks as `check-config`
        setup_logging(config.logging);  // (makes the log file's folder, among `missing`)
        create_missing_folders(missing);
    } catch (const Error& e) {
        std::cerr << "tlsmon run: " << e.what() << '\n';
        return 1;
    }
    log_config(config);
    // Services start in this order and stop in the reverse one: signals, then the daemon
    // (watcher, database) which is destroyed before the signal thread is joined.
    Shutdown shutdown;
    SignalThread signals(shutdown);
    try {
        // A database that cannot be opened for lack of space (a restart while the disk is
        // full): Modbus serves SCADA meanwhile, with the disk-full bit, and the opening is
        // retried with the back-off until space returns.
        std::unique_ptr<ModbusService> modbus;
        SystemdNotify systemd;
        std::optional<UtcSeconds> refused_since;
        double backoff = 0;
        while (!shutdown.stop_requested()) {
            try {
                Daemon daemon(config, options.once, shutdown, modbus, refused_since);
                daemon.run();
                break;
            } catch (const StorageError& e) {
                if (!e.disk_full()) throw;
                if (!refused_since) refused_since = now_utc();
                backoff = next_backoff(backoff, config.ingest);
                spdlog::error("{}; the disk is full: retry in {:.1f} s", e.what(), backoff);
                if (!modbus && config.modbus.enabled) modbus = start_modbus_service(config);
                if (modbus) modbus->set_disk_full(true);
                systemd.ready();
                systemd.status("the epoch database cannot be opened: the disk is full");
                wait_alive(systemd, shutdown, backoff);
            }
        }
    } catch (const std::exception& e) {
        spdlog::critical("tlsmon run: {}", e.what());
        return 1;
    }
    spdlog::info("stopped");
    return 0;
}

}  // namespace tlsmon
