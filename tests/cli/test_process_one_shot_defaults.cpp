// A parameter has one default: `tlsmon m3c2` and `tlsmon keypoints` without --config or
// options print the parameters they measured with, and every key of their configuration
// sections has the value a fresh site's configuration gives it (config/keys.hpp) —
// but for keypoints.segments: without a site there are no zones, the segments are bands.
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "config/keys.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

const std::string data = TLSMON_DATA_DIR;

// The `section.key = value` lines of a command's output.
std::map<std::string, std::string> printed_parameters(const std::string& out,
                                                      const std::string& section) {
    std::map<std::string, std::string> values;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) {
        const auto eq = line.find(" = ");
        if (line.rfind(section + ".", 0) != 0 || eq == std::string::npos) continue;
        values[line.substr(section.size() + 1, eq - section.size() - 1)] = line.substr(eq + 3);
    }
    return values;
}

void expect_fresh_site_defaults(const std::string& out, const std::string& section,
                                const std::map<std::string, std::string>& except) {
    const auto printed = printed_parameters(out, section);
    const Config fresh;
    int keys = 0;
    for (const auto& k : config_keys()) {
        if (k.section != section) continue;
        ++keys;
        const auto it = printed.find(k.name);
        ASSERT_NE(it, printed.end()) << section << "." << k.name << " not printed:\n" << out;
        const auto other = except.find(k.name);
        EXPECT_EQ(it->second, other == except.end() ? k.value(fresh) : other->second)
            << section << "." << k.name;
    }
    EXPECT_EQ(printed.size(), static_cast<std::size_t>(keys));
    EXPECT_GT(keys, 8);
}

TEST(OneShotDefaults, M3c2MeasuresWithAFreshSitesParameters) {
    test::TempDir dir;
    const auto r =
        test::run_tlsmon("m3c2 " + data + "/xyz/plane_horizontal_t1.xyz " + data +
                         "/xyz/plane_horizontal_t2.xyz --out " + (dir / "m.csv").string());
    ASSERT_EQ(r.status, 0) << r.out;
    expect_fresh_site_defaults(r.out, "m3c2", {});
}

TEST(OneShotDefaults, KeypointsMeasuresWithAFreshSitesParameters) {
    test::TempDir dir;
    const auto r = test::run_tlsmon("keypoints " + data + "/ptx/pumpA_from_e57.ptx " + data +
                                    "/ptx/pumpA_from_e57.ptx --out " + (dir / "k.csv").string());
    ASSERT_EQ(r.status, 0) << r.out;
    expect_fresh_site_defaults(r.out, "keypoints", {{"segments", "\"bands\""}});
}

}  // namespace
}  // namespace tlsmon
