// `tlsmon modbus-map`: before the table, what an integrator sets up in the PLC — the server's
// address and port, the unit id, the addressing, and the word order with a known value.
#include <gtest/gtest.h>

#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon {
namespace {

TEST(ModbusMapCommand, SaysUnitIdAndWordOrderBeforeTheTable) {
    test::TempDir dir;
    const auto config = dir / "site.toml";
    test::write_text(config, R"([station]
name = "p3"
[paths]
ingest = "ingest"
archive = "archive"
quarantine = "quarantine"
database = "tlsmon.sqlite"
[modbus]
port = 1502
unit_id = 7
word_order = "CDAB"
)");
    const auto r = test::run_tlsmon("modbus-map --config " + config.string());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("Modbus TCP server 127.0.0.1:1502, unit id 7"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("word order CDAB (low word first)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("123456.0 reads 0x2000 0x47F1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("| table | address | count |"), std::string::npos) << r.out;
    // The CSV stays a table only.
    const auto csv = test::run_tlsmon("modbus-map --format csv --config " + config.string());
    ASSERT_EQ(csv.status, 0) << csv.out;
    EXPECT_EQ(csv.out.find("Modbus TCP server"), std::string::npos);
}

}  // namespace
}  // namespace tlsmon
