#include "config/modbus_config.hpp"

#include <array>

namespace tlsmon {

namespace {

constexpr std::array<Named<WordOrder>, 2> kWordOrders{{
    {WordOrder::abcd, "ABCD"},
    {WordOrder::cdab, "CDAB"},
}};

constexpr std::array<Named<ModbusValueType>, 2> kValueTypes{{
    {ModbusValueType::float32, "float32"},
    {ModbusValueType::int32, "int32"},
}};

}  // namespace

std::vector<SectionKey<ModbusConfig>> modbus_keys() {
    using K = Keys<ModbusConfig>;
    constexpr double day = 86400.0;
    return {
        K::flag(&ModbusConfig::enabled, "enabled",
                "Run the Modbus TCP server for SCADA (docs/modbus.md)."),
        K::text(&ModbusConfig::address, "address", "an IPv4 address",
                "Address the server listens on; `0.0.0.0`: every interface."),
        K::integer(&ModbusConfig::port, "port", 1, 65535, "",
                   "TCP port (Modbus: 502, which needs privileges; the demo uses 1502)."),
        K::integer(&ModbusConfig::unit_id, "unit_id", 0, 255, "",
                   "Unit identifier answered; requests for another unit are dropped."),
        K::choice(&ModbusConfig::word_order, "word_order", kWordOrders,
                  "Order of the two registers of a 32-bit value (float32, uint32): `ABCD` = high "
                  "word first, `CDAB` = low word first. Bytes within a register are always "
                  "big-endian."),
        K::choice(&ModbusConfig::value_type, "value_type", kValueTypes,
                  "Type of each zone quantity's value, LoD and rate registers: `float32` (NaN: "
                  "none), or `int32` for PLCs without floating point: lengths in micrometres, "
                  "counts as they are, other quantities in thousandths, -2147483648 "
                  "(0x80000000) for none or out of range (docs/modbus.md)."),
        K::integer(&ModbusConfig::max_clients, "max_clients", 1, 256, "",
                   "Connections served at once; a further one is closed at once."),
        K::seconds(&ModbusConfig::idle_timeout, "idle_timeout", 1, day, "",
                   "A client that sends no complete request for this long is disconnected."),
        K::names(&ModbusConfig::allowlist, "allowlist", "IPv4 addresses",
                 "Client addresses allowed to connect; empty: any client."),
        K::flag(&ModbusConfig::writable_coils, "writable_coils",
                "Whether SCADA may acknowledge alarms by writing the acknowledge coils; `false`: "
                "every write is answered with an exception."),
        K::names(&ModbusConfig::quantities, "quantities",
                 "1 to 8 quantity names a stage writes, no repeats; append only",
                 "The quantities of each zone shown in the input registers; the position in this "
                 "list is the quantity's slot in the zone's block, so add new ones at the end."),
        K::seconds(&ModbusConfig::stale_seconds, "stale_seconds", 1, 30 * day, "",
                   "A zone value whose epoch was acquired longer ago than this is flagged stale in "
                   "its quality word."),
        K::seconds(&ModbusConfig::snapshot_interval, "snapshot_interval", 0.1, 3600, "",
                   "The registers are rebuilt from the database after each epoch and at least "
                   "this often."),
    };
}

}  // namespace tlsmon
