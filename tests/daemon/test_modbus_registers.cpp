// The Modbus register words, map and image against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config.hpp"
#include "daemon/modbus/modbus_snapshot.hpp"
#include "daemon/modbus/register_image.hpp"
#include "daemon/modbus/register_map.hpp"
#include "daemon/modbus/register_words.hpp"

namespace tlsmon {
namespace {

TEST(ModbusWords, TestFloatIsIeee754HighWordFirstInAbcd) {
    // 123456 = 1.8837890625 * 2^16: sign 0, exponent 127 + 16 = 0x8F, mantissa 0x712000
    // -> 0x47F12000.
    EXPECT_EQ(float_words(123456.0f, WordOrder::abcd),
              (std::array<std::uint16_t, 2>{0x47F1, 0x2000}));
    EXPECT_EQ(float_words(123456.0f, WordOrder::cdab),
              (std::array<std::uint16_t, 2>{0x2000, 0x47F1}));
    EXPECT_EQ(float_words(-2.0f, WordOrder::abcd), (std::array<std::uint16_t, 2>{0xC000, 0x0000}));
    EXPECT_EQ(u32_words(0x12345678u, WordOrder::abcd),
              (std::array<std::uint16_t, 2>{0x1234, 0x5678}));
    EXPECT_EQ(u32_words(0x12345678u, WordOrder::cdab),
              (std::array<std::uint16_t, 2>{0x5678, 0x1234}));
    EXPECT_EQ(float_from_words({0x2000, 0x47F1}, WordOrder::cdab), 123456.0f);
}

MapInputs two_zones() {
    MapInputs in;
    in.zones = {{0, "pier top"}, {1, "pier foot"}};
    in.quantities = {"m3c2_median_m", "keypoint_dz_m"};
    in.rules = {{0, "top settles"}};
    return in;
}

const MapEntry* find(const RegisterMap& m, const std::string& name) {
    for (const auto& e : m.entries) {
        if (e.name == name) return &e;
    }
    return nullptr;
}

TEST(ModbusMap, AddressesFollowTheSlots) {
    const RegisterMap m = build_register_map(two_zones());
    ASSERT_TRUE(find(m, "test_float"));
    EXPECT_EQ(find(m, "test_float")->address, 7);
    // zone slot 1, quantity slot 1: 100 + 1 * 80 + 1 * 10 = 190.
    ASSERT_TRUE(find(m, "pier foot/keypoint_dz_m.value"));
    EXPECT_EQ(find(m, "pier foot/keypoint_dz_m.value")->address, 190);
    EXPECT_EQ(find(m, "pier foot/keypoint_dz_m.quality")->address, 196);
    EXPECT_EQ(find(m, "top settles.alarm")->table, ModbusTable::discrete_input);
    EXPECT_EQ(find(m, "top settles.alarm")->address, 18);  // 16 + 0 * 4 + 2
    EXPECT_EQ(find(m, "top settles.acknowledge")->address, 16);
    EXPECT_EQ(m.input_registers, 199);  // the last block ends at 190 + 9
    EXPECT_EQ(m.coils, 17);
}

TEST(ModbusMap, AddingAZoneRuleOrQuantityMovesNoAddress) {
    const RegisterMap before = build_register_map(two_zones());
    MapInputs more = two_zones();
    more.zones.insert(more.zones.begin(), MapSlot{2, "abutment"});  // sorts first by name
    more.quantities.push_back("m3c2_mean_m");
    more.rules.push_back({1, "foot tilts"});
    const RegisterMap after = build_register_map(more);
    for (const auto& e : before.entries) {
        const MapEntry* a = find(after, e.name);
        ASSERT_TRUE(a) << e.name;
        EXPECT_EQ(a->address, e.address) << e.name;
        EXPECT_EQ(a->table, e.table) << e.name;
    }
    EXPECT_GT(after.entries.size(), before.entries.size());
}

TEST(ModbusImage, MissingValuesAreNanWithQualityCleared) {
    const MapInputs in = two_zones();
    const RegisterMap m = build_register_map(in);
    ModbusSnapshot s;
    s.database_ok = true;
    s.values.push_back({0, 1, 0.004, 0.002, 0.5, false, true, false});
    s.rules.push_back(
        {0, "top settles", "pier top", "keypoint_dz_m", AlarmLevel::alert, IsaState::unack});
    const RegisterImage img = render_registers(m, in, s, WordOrder::abcd);
    const auto& r = img.input_registers;
    EXPECT_TRUE(std::isnan(float_from_words({r[100], r[101]}, WordOrder::abcd)));
    EXPECT_EQ(r[106], 0);
    EXPECT_EQ(float_from_words({r[110], r[111]}, WordOrder::abcd), 0.004f);
    EXPECT_EQ(float_from_words({r[114], r[115]}, WordOrder::abcd), 0.5f);
    EXPECT_EQ(r[116], kQualityValid);       // significant, fresh, registration fine
    EXPECT_EQ(r[117], 2);                   // alert
    EXPECT_EQ(r[118], 1);                   // unacknowledged
    EXPECT_EQ(img.discrete_inputs[16], 1);  // warning or above
    EXPECT_EQ(img.discrete_inputs[17], 1);  // alert or above
    EXPECT_EQ(img.discrete_inputs[18], 0);  // not alarm
    EXPECT_EQ(img.discrete_inputs[19], 1);  // unacknowledged
    EXPECT_EQ(img.discrete_inputs[kBitAnyUnacknowledged], 1);
    EXPECT_EQ(img.discrete_inputs[kBitSystemFault], 0);
    EXPECT_EQ(r[kRegStatus], kStatusRunning | kStatusDatabaseOk | kStatusAnyAlarm);
    EXPECT_EQ(img.coil_rules[16], "top settles");
    EXPECT_EQ(img.coil_rules[0], "*");
    EXPECT_EQ(img.coil_rules[1], "");
}

// value_type = int32: the same block as int32 in the quantity's fixed unit (metres as µm,
// counts as they are, shares in thousandths); none or beyond the range: INT32_MIN, invalid.
TEST(ModbusImage, Int32ValuesInFixedUnitsForPlcsWithoutFloats) {
    MapInputs in = two_zones();
    in.quantities = {"m3c2_median_m", "m3c2_valid_count", "m3c2_significant_share"};
    in.value_type = ModbusValueType::int32;
    const RegisterMap m = build_register_map(in);
    const MapEntry* value = find(m, "pier top/m3c2_median_m.value");
    ASSERT_TRUE(value);
    EXPECT_EQ(value->type, ModbusType::int32);
    EXPECT_EQ(value->unit, "µm");
    EXPECT_EQ(find(m, "pier top/m3c2_median_m.rate")->unit, "µm/d");
    EXPECT_EQ(find(m, "pier top/m3c2_valid_count.value")->unit, "count");
    EXPECT_EQ(find(m, "pier top/m3c2_significant_share.value")->unit, "1e-3 share");
    EXPECT_EQ(value->address, 100);  // the addresses do not depend on the type

    ModbusSnapshot s;
    s.database_ok = true;
    s.values.push_back({0, 0, -0.0041234, 0.0006, 0.0000126, false, true, false});
    s.values.push_back({0, 1, 1234.0, std::nullopt, std::nullopt, false, true, false});
    s.values.push_back({0, 2, 0.8765, std::nullopt, std::nullopt, false, true, false});
    s.values.push_back({1, 0, 3000.0, std::nullopt, std::nullopt, false, true, false});
    const RegisterImage img = render_registers(m, in, s, WordOrder::abcd);
    const auto& r = img.input_registers;
    const auto i32 = [&](int a) {
        return static_cast<std::int32_t>((std::uint32_t{r[a]} << 16) | r[a + 1]);
    };
    EXPECT_EQ(i32(100), -4123);  // −4.1234 mm in µm, rounded
    EXPECT_EQ(i32(102), 600);
    EXPECT_EQ(i32(104), 13);  // 12.6 µm/d
    EXPECT_EQ(r[106] & kQualityValid, kQualityValid);
    EXPECT_EQ(i32(110), 1234);
    EXPECT_EQ(i32(112), INT32_MIN);  // no LoD
    EXPECT_EQ(i32(120), 877);
    // 3000 m is 3·10⁹ µm, beyond int32: none, and the value is not valid.
    EXPECT_EQ(i32(180), INT32_MIN);
    EXPECT_EQ(r[186] & kQualityValid, 0);
    // A zone quantity without a value at all.
    EXPECT_EQ(i32(190), INT32_MIN);
    // 0x80000000 in CDAB is the low word first.
    EXPECT_EQ(u32_words(0x80000000u, WordOrder::cdab), (std::array<std::uint16_t, 2>{0, 0x8000}));
}

TEST(ModbusSnapshot, RateWindowIsTheRateRulesElseADay) {
    const auto rule = [](std::string name, std::string zone, std::string definition, bool enabled) {
        return AlarmRule{
            0, std::move(name), std::move(zone), "m3c2_median_m", std::move(definition), enabled};
    };
    const std::vector<AlarmRule> rules{
        rule("level", "top", R"({"rate_window_seconds":null})", true),
        rule("off", "top", R"({"rate_window_seconds":600})", false),
        rule("rate", "top", R"({"rate_window_seconds":7200})", true),
        rule("other", "foot", R"({"rate_window_seconds":3600})", true)};
    EXPECT_EQ(rate_window(rules, "top", "m3c2_median_m"), 7200.0);
    EXPECT_EQ(rate_window(rules, "foot", "m3c2_median_m"), 3600.0);
    EXPECT_EQ(rate_window(rules, "foot", "m3c2_mean_m"), 86400.0);
    EXPECT_EQ(rate_window(rules, "side", "m3c2_median_m"), 86400.0);
}

TEST(ModbusSnapshot, ConfiguredZonesUnknownToTheDatabaseTakeTheNextSlots) {
    ModbusConfig c;
    const MapInputs in = modbus_map_inputs(nullptr, {"b", "a"}, c);
    ASSERT_EQ(in.zones.size(), 2u);
    EXPECT_EQ(in.zones[0].name, "b");
    EXPECT_EQ(in.zones[0].slot, 0);
    EXPECT_EQ(in.zones[1].slot, 1);
}

TEST(ModbusConfigSection, ReadsAndChecksTheKeys) {
    const Config c = parse_config(
        "[modbus]\nenabled = true\nport = 1503\nword_order = \"CDAB\"\nallowlist = "
        "[\"10.0.0.7\"]\n",
        "site.toml", "/tmp");
    EXPECT_TRUE(c.modbus.enabled);
    EXPECT_EQ(c.modbus.port, 1503);
    EXPECT_EQ(c.modbus.word_order, WordOrder::cdab);
    EXPECT_EQ(c.modbus.allowlist, std::vector<std::string>{"10.0.0.7"});
    try {
        parse_config("[modbus]\nallowlist = [\"10.0.0\"]\n", "site.toml", "/tmp");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("site.toml"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("allowlist"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parse_config("[modbus]\nword_order = \"BADC\"\n", "site.toml", "/tmp"), Error);
    EXPECT_THROW(parse_config("[modbus]\nport = 70000\n", "site.toml", "/tmp"), Error);
}

}  // namespace
}  // namespace tlsmon
