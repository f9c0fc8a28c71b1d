#pragma once
// The dashboard in a real browser: tests/web/dashboard_browser.py (Debian's chromium, headless,
// through chromium-driver and python3-selenium) in one of its modes, its JSON report parsed;
// its screenshots and log in `artifacts`. Throws with the log when the script fails.
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "tests/support/daemon_harness.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon::test {

inline nlohmann::json dashboard_browser(const std::string& arguments,
                                        const std::filesystem::path& artifacts) {
    const std::string log = (artifacts / "browser.log").string();
    const auto r = shell("(timeout 240 /usr/bin/python3 '" + std::string(TLSMON_SOURCE_DIR) +
                         "/tests/web/dashboard_browser.py' " + arguments + " 2>'" + log + "')");
    if (r.status != 0) {
        throw std::runtime_error("dashboard_browser.py " + arguments + " exit " +
                                 std::to_string(r.status) + ": " + r.output + "\n" +
                                 read_text(artifacts / "browser.log"));
    }
    return nlohmann::json::parse(r.output);
}

// The browsers' screenshots of one test, under the build folder's test-artifacts/NAME.
inline std::filesystem::path browser_artifacts(const std::string& name) {
    const auto dir = std::filesystem::path(TLSMON_BINARY).parent_path() / "test-artifacts" / name;
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace tlsmon::test
