#pragma once
// A LAS file as an independent reader sees it: copc.js from the npm registry
// (tests/export/read_las_with_copc.js, installed by deploy/install-deps.sh --tests) run by
// Node.js; its header, VLRs, Extra Bytes descriptors, WKT and every point's values by name.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "tests/support/run_tlsmon.hpp"

namespace tlsmon::test {

inline nlohmann::json read_las_independently(const std::filesystem::path& file) {
    const CommandRun r =
        run_tlsmon_at("node",
                      std::string(TLSMON_SOURCE_DIR) + "/tests/export/read_las_with_copc.js '" +
                          file.string() + "'",
                      false);
    if (r.status != 0) {
        throw std::runtime_error("copc.js could not read " + file.string() + " (exit " +
                                 std::to_string(r.status) + ")");
    }
    return nlohmann::json::parse(r.out);
}

// A value the reader printed: numbers as they are, non-finite ones as their text.
inline double las_number(const nlohmann::json& v) {
    return v.is_string() ? std::stod(v.get<std::string>()) : v.get<double>();
}

}  // namespace tlsmon::test
