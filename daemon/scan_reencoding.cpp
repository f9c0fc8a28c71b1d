#include "daemon/scan_reencoding.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "formats/e57_writer.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"

namespace fs = std::filesystem;

namespace tlsmon {

namespace {

// The writer stores intensity in 12 bits (formats/e57_writer.cpp).
constexpr double kIntensityStep = 1.0 / 4095.0;

void sync(const fs::path& path, int flags) {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
        const int e = errno;
        if (fd >= 0) ::close(fd);
        throw Error(path.string() + ": making the re-encoded scan durable: " + std::strerror(e));
    }
    ::close(fd);
}

// "" when `b` (read back) holds `a` (read from the original) within the encoding's steps:
// half a count per axis in the scanner frame, rotated into the project frame (≤ √3/2 counts),
// half an intensity step; colour, grid, pose and time exactly (the time to a microsecond:
// it goes through GPS seconds).
std::string difference(const Scan& a, const Scan& b, double resolution) {
    if (a.size() != b.size()) {
        return std::to_string(b.size()) + " points instead of " + std::to_string(a.size());
    }
    const double max_xyz = 0.5 * std::sqrt(3.0) * resolution * (1 + 1e-6) + 1e-9;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if ((a.xyz[i] - b.xyz[i]).norm() > max_xyz) {
            return "point " + std::to_string(i) + " moved by " +
                   std::to_string((a.xyz[i] - b.xyz[i]).norm()) + " m";
        }
    }
    if (a.intensity.size() != b.intensity.size()) return "intensity lost";
    for (std::size_t i = 0; i < a.intensity.size(); ++i) {
        if (std::fabs(a.intensity[i] - b.intensity[i]) > 0.5 * kIntensityStep + 1e-6) {
            return "intensity of point " + std::to_string(i) + " changed";
        }
    }
    if (a.rgb != b.rgb) return "colour changed";
    if (a.grid.has_value() != b.grid.has_value()) return "grid lost";
    if (a.grid && (a.grid->rows != b.grid->rows || a.grid->columns != b.grid->columns ||
                   a.grid->row != b.grid->row || a.grid->column != b.grid->column)) {
        return "grid changed";
    }
    if ((a.pose.matrix() - b.pose.matrix()).cwiseAbs().maxCoeff() > 1e-9) {
        return "pose changed";
    }
    if (a.acquired_utc.has_value() != b.acquired_utc.has_value() ||
        (a.acquired_utc && std::fabs(*a.acquired_utc - *b.acquired_utc) > 1e-6)) {
        return "acquisition time changed";
    }
    return "";
}

}  // namespace

ReencodedScan reencode_as_e57(const fs::path& source, const std::string& sha256,
                              double resolution) {
    const HashedBytes content = read_file_hashed(source);
    if (content.sha256 != sha256) {
        throw Error(source.string() + " no longer holds the epoch's scan (sha256 " +
                    content.sha256.substr(0, 12) + " instead of " + sha256.substr(0, 12) +
                    "): not re-encoded");
    }
    const std::vector<Scan> scans = parse_scans(content.bytes, source);
    const fs::path target =
        free_name(source.parent_path(), source.stem().string() + ".e57", sha256.substr(0, 12));
    const fs::path part = target.string() + ".part";
    try {
        write_e57(part, scans, {.coordinate_scale = resolution});
        sync(part, O_RDONLY);
        const std::vector<Scan> back = read_scans(part);
        if (back.size() != scans.size()) {
            throw Error(std::to_string(back.size()) + " scans read back instead of " +
                        std::to_string(scans.size()));
        }
        for (std::size_t k = 0; k < scans.size(); ++k) {
            if (const auto why = difference(scans[k], back[k], resolution); !why.empty()) {
                throw Error("scan " + std::to_string(k) + ": " + why);
            }
        }
        fs::rename(part, target);
        sync(target.parent_path(), O_RDONLY | O_DIRECTORY);
    } catch (const std::exception& e) {
        std::error_code ignored;
        fs::remove(part, ignored);
        throw Error(source.string() +
                    ": re-encoding as E57 failed, the scan is kept as it is: " + e.what());
    }
    return {target, static_cast<std::int64_t>(fs::file_size(target)), sha256_file(target)};
}

}  // namespace tlsmon
