#include "daemon/modbus/modbus_service.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include "daemon/modbus/modbus_server.hpp"
#include "daemon/modbus/modbus_snapshot.hpp"
#include "daemon/modbus/register_image.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

struct ModbusService::State {
    ModbusConfig config;
    std::filesystem::path database;
    std::vector<std::string> zones;
    Acknowledge acknowledge;
    std::mutex mutex;
    std::condition_variable wake;
    bool stop = false;
    bool dirty = true;
    std::deque<std::pair<std::string, std::string>> acks;  // rule, client
    bool disk_full = false;
    MapInputs last_inputs;
    std::unique_ptr<ModbusServer> server;
    std::thread thread;

    void run();
    void refresh(std::optional<EpochDatabase>& db);
};

ModbusService::ModbusService(const ModbusConfig& config, const std::filesystem::path& database,
                             std::vector<std::string> config_zones, Acknowledge acknowledge)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.config = config;
    s.database = database;
    s.zones = std::move(config_zones);
    s.acknowledge = std::move(acknowledge);
    s.last_inputs = modbus_map_inputs(nullptr, s.zones, config);
    s.server = std::make_unique<ModbusServer>(
        config, [&s](const std::string& rule, const std::string& client) {
            {
                std::lock_guard lock(s.mutex);
                s.acks.emplace_back(rule, client);
            }
            s.wake.notify_one();
        });
    s.thread = std::thread([&s] { s.run(); });
}

ModbusService::~ModbusService() {
    State& s = *state_;
    {
        std::lock_guard lock(s.mutex);
        s.stop = true;
    }
    s.wake.notify_one();
    if (s.thread.joinable()) s.thread.join();
    s.server.reset();
}

void ModbusService::epoch_committed() {
    {
        std::lock_guard lock(state_->mutex);
        state_->dirty = true;
    }
    state_->wake.notify_one();
}

void ModbusService::set_disk_full(bool full) {
    {
        std::lock_guard lock(state_->mutex);
        if (state_->disk_full == full) return;
        state_->disk_full = full;
        state_->dirty = true;
    }
    state_->wake.notify_one();
}

void ModbusService::State::refresh(std::optional<EpochDatabase>& db) {
    ModbusSnapshot snapshot;
    MapInputs inputs = last_inputs;
    bool full = false;
    {
        std::lock_guard lock(mutex);
        full = disk_full;
    }
    try {
        if (!db) db = EpochDatabase::open(database, EpochDatabase::Mode::read_write);
        inputs = modbus_map_inputs(&*db, zones, config);
        const RegisterMap map = build_register_map(inputs);
        snapshot = read_modbus_snapshot(*db, inputs, config, now_utc());
        snapshot.disk_full = full;
        server->publish(std::make_shared<const RegisterImage>(
            render_registers(map, inputs, snapshot, config.word_order)));
        last_inputs = std::move(inputs);
        return;
    } catch (const std::exception& e) {
        spdlog::warn("modbus: registers not refreshed: {}", e.what());
        db.reset();  // opened again next time
    }
    // The database cannot be read: the last map, with no values and the fault bit set.
    snapshot = ModbusSnapshot{};
    snapshot.database_ok = false;
    snapshot.disk_full = full;
    try {
        const RegisterMap map = build_register_map(last_inputs);
        server->publish(std::make_shared<const RegisterImage>(
            render_registers(map, last_inputs, snapshot, config.word_order)));
    } catch (const std::exception& e) {
        spdlog::error("modbus: {}", e.what());
    }
}

void ModbusService::State::run() {
    std::optional<EpochDatabase> db;
    const auto interval = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(config.snapshot_interval));
    while (true) {
        std::deque<std::pair<std::string, std::string>> todo;
        {
            std::unique_lock lock(mutex);
            wake.wait_for(lock, interval, [&] { return stop || dirty || !acks.empty(); });
            if (stop) return;
            todo.swap(acks);
            dirty = false;
        }
        for (const auto& [rule, client] : todo) {
            try {
                if (!db) db = EpochDatabase::open(database, EpochDatabase::Mode::read_write);
                const int n = acknowledge(*db, rule, client, now_utc());
                spdlog::info("modbus: acknowledgement by SCADA {} ({}): {} rule(s) changed", client,
                             rule == "*" ? std::string("all") : rule, n);
            } catch (const std::exception& e) {
                spdlog::error("modbus: acknowledging {} failed: {}", rule, e.what());
                db.reset();
            }
        }
        refresh(db);
    }
}

}  // namespace tlsmon
