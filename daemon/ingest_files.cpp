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

#include "algorithms/error.hpp"
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

std::int64_t acquisition_time(const fs::path& path, const std::vector<std::string>& precedence,
                              std::string& used) {
    for (const auto& source : precedence) {
        if (source == "scan" && detect_format(path) == ScanFormat::e57) {
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
        } else if (source == "file_name") {
            if (auto t = time_from_file_name(path.filename().string())) {
                used = "file_name";
                return *t;
            }
        } else if (source == "mtime") {
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

fs::path free_name(const fs::path& folder, const std::string& name, const std::string& tag) {
    fs::path candidate = folder / name;
    if (!fs::exists(candidate)) return candidate;
    const fs::path n(name);
    const std::string stem = n.stem().string();
    const std::string ext = n.extension().string();
    for (int i = 1;; ++i) {
        candidate = folder / (stem + "." + tag + (i > 1 ? "-" + std::to_string(i) : "") + ext);
        if (!fs::exists(candidate)) return candidate;
    }
}

namespace {

void sync_folder(const fs::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

}  // namespace

void move_file(const fs::path& from, const fs::path& to) {
    if (::rename(from.c_str(), to.c_str()) == 0) {
        sync_folder(to.parent_path());
        return;
    }
    if (errno != EXDEV) {
        throw Error("cannot move " + from.string() + " to " + to.string() + ": " +
                    std::strerror(errno));
    }
    // Another file system: copy to a temporary name, sync, rename, then remove the source.
    const fs::path tmp = to.parent_path() / ("." + to.filename().string() + ".part");
    std::error_code ec;
    fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
    if (!ec) {
        // The source is removed below: the copy must be on disk first.
        const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0 || ::fsync(fd) != 0) ec.assign(errno, std::generic_category());
        if (fd >= 0) ::close(fd);
    }
    if (!ec) fs::rename(tmp, to, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw Error("cannot copy " + from.string() + " to " + to.string() + ": " + ec.message());
    }
    sync_folder(to.parent_path());
    fs::remove(from, ec);
}

bool write_reason_file(const fs::path& file, const std::string& original,
                       const std::string& reason) {
    std::ofstream out(file.string() + ".reason.txt");
    out << "file: " << original << "\nreason: " << reason << '\n';
    return static_cast<bool>(out.flush());
}

}  // namespace tlsmon
