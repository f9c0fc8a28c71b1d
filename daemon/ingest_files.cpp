#include "daemon/ingest_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <regex>

#include "core/error.hpp"
#include "formats/e57_reader.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

std::optional<std::int64_t> time_from_file_name(const std::string& name) {
    static const std::regex stamp(R"((\d{4})(\d{2})(\d{2})T(\d{2})(\d{2})(\d{2})Z)");
    std::smatch m;
    if (!std::regex_search(name, m, stamp)) return std::nullopt;
    std::tm tm{};
    tm.tm_year = std::stoi(m[1]) - 1900;
    tm.tm_mon = std::stoi(m[2]) - 1;
    tm.tm_mday = std::stoi(m[3]);
    tm.tm_hour = std::stoi(m[4]);
    tm.tm_min = std::stoi(m[5]);
    tm.tm_sec = std::stoi(m[6]);
    if (tm.tm_mon > 11 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 || tm.tm_min > 59 ||
        tm.tm_sec > 60) {
        return std::nullopt;
    }
    std::tm check = tm;
    const std::time_t t = ::timegm(&check);
    if (check.tm_mday != tm.tm_mday) return std::nullopt;  // e.g. 31 February
    return static_cast<std::int64_t>(t);
}

std::optional<std::int64_t> file_mtime(const fs::path& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return std::nullopt;
    return static_cast<std::int64_t>(st.st_mtim.tv_sec);
}

std::int64_t acquisition_time(const fs::path& path, const std::vector<TimeSource>& precedence,
                              std::string& used) {
    for (const auto& source : precedence) {
        if (source == TimeSource::scan && detect_format(path) == ScanFormat::e57) {
            // Only E57 carries an acquisition time in its header (acquisitionStart, read
            // from the XML section without the points).
            try {
                if (auto t = read_e57_acquired_utc(path)) {
                    used = "scan";
                    return static_cast<std::int64_t>(std::floor(*t));
                }
            } catch (const Error&) {
                // Unreadable: the pipeline reports it; the time comes from elsewhere.
            }
        } else if (source == TimeSource::file_name) {
            if (auto t = time_from_file_name(path.filename().string())) {
                used = "file_name";
                return *t;
            }
        } else if (source == TimeSource::mtime) {
            if (auto t = file_mtime(path)) {
                used = "mtime";
                return *t;
            }
        }
    }
    if (auto t = file_mtime(path)) {
        used = "mtime (fallback)";
        return *t;
    }
    used = "now (fallback)";
    return std::chrono::duration_cast<std::chrono::seconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace tlsmon
