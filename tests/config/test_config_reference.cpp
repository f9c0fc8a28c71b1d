// The key declarations (config/keys.cpp) against what users read: the reference
// tables of docs/configuration.md and the shipped etc/tlsmon.toml.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "config/keys.hpp"

namespace tlsmon {
namespace {

const std::filesystem::path kSource = TLSMON_SOURCE_DIR;

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The text between "<!-- BEGIN keys SECTION -->\n" and "<!-- END keys SECTION -->".
std::string docs_table(const std::string& docs, const std::string& section) {
    const std::string begin = "<!-- BEGIN keys " + section + " -->\n";
    const std::string end = "<!-- END keys " + section + " -->";
    const auto from = docs.find(begin);
    const auto to = docs.find(end);
    if (from == std::string::npos || to == std::string::npos || to < from) return "(no markers)";
    return docs.substr(from + begin.size(), to - from - begin.size());
}

TEST(ConfigReference, DocsTablesAreTheDeclarations) {
    const std::string docs = read_text(kSource / "docs/configuration.md");
    const auto sections = config_sections();
    EXPECT_EQ(sections,
              (std::vector<std::string>{
                  "station",   "paths",        "ingest",  "meteo",  "logging",    "daemon",
                  "coverage",  "registration", "m3c2",    "pbm3c2", "primitives", "vectors",
                  "keypoints", "campaign",     "thermal", "modbus", "http",       "alarm",
                  "notify",    "retention",    "archive", "central"}));
    for (const auto& section : sections) {
        EXPECT_EQ(docs_table(docs, section), reference_table(section))
            << "docs/configuration.md, section [" << section
            << "]: replace the table between its markers with the expected text above";
    }
}

TEST(ConfigReference, ReferenceRowShowsDefaultAndRangeFromTheDeclaration) {
    const std::string table = reference_table("ingest");
    EXPECT_NE(table.find("| `max_growing` | duration | `3600` | 1 s .. 30 d, > `stable_seconds` |"),
              std::string::npos)
        << table;
    EXPECT_NE(table.find("| `archive` | string | `\"move\"` | `move`, `keep` |"), std::string::npos)
        << table;
}

TEST(ConfigReference, ShippedFileSetsEveryKeyToItsDefault) {
    const std::filesystem::path file = kSource / "etc/tlsmon.toml";
    const Config shipped = load_config(file);
    // The shipped paths point into the checkout's var/ folder (deploy/install.sh rewrites
    // them): the defaults resolved against var/ are what the file must say.
    const Config defaults = parse_config("", "defaults", kSource / "var");
    const toml::table raw = parse_toml_file(file);
    for (const ConfigKey& k : config_keys()) {
        const std::string key = k.section + "." + k.name;
        // An optional key without a default is shown commented out.
        if (k.value(defaults) == kNoValue)
            EXPECT_FALSE(raw.at_path(key)) << key << " has no default to set";
        else
            EXPECT_TRUE(raw.at_path(key)) << key << " is missing from etc/tlsmon.toml";
        EXPECT_EQ(k.value(shipped), k.value(defaults)) << key;
    }
}

}  // namespace
}  // namespace tlsmon
