#pragma once
// The [modbus] section of the configuration: the Modbus TCP server for SCADA
// (docs/modbus.md). Plain data; the keys are declared in config/keys.cpp.
#include <string>
#include <vector>

#include "core/config_key.hpp"

namespace tlsmon {

// The order of the two 16-bit words of a 32-bit value: ABCD = high word first (Modbus
// big-endian, the default), CDAB = low word first (many PLCs).
enum class WordOrder { abcd, cdab };

// How a zone quantity's value, LoD and rate are written: IEEE 754 float32 (NaN: none), or
// for PLCs without floating point, a signed 32-bit integer in fixed units (lengths in µm,
// counts as they are, other quantities in thousandths; docs/modbus.md).
enum class ModbusValueType { float32, int32 };

struct ModbusConfig {
    bool enabled = false;
    std::string address = "127.0.0.1";  // IPv4 address the server listens on
    int port = 1502;
    int unit_id = 1;
    WordOrder word_order = WordOrder::abcd;
    ModbusValueType value_type = ModbusValueType::float32;
    int max_clients = 32;
    double idle_timeout = 60.0;          // seconds without a request before a client is dropped
    std::vector<std::string> allowlist;  // IPv4 client addresses; empty = any client
    bool writable_coils = true;          // acknowledge coils; false = every write refused
    // The quantities of each zone shown in the registers, slot = position (append only).
    std::vector<std::string> quantities = {"m3c2_median_m", "m3c2_mean_m", "keypoint_dz_m"};
    double stale_seconds = 2700.0;   // a zone value older than this is flagged stale
    double snapshot_interval = 5.0;  // registers refreshed from the database this often
};

// The keys of [modbus] (core/config_key.hpp).
std::vector<SectionKey<ModbusConfig>> modbus_keys();

}  // namespace tlsmon
