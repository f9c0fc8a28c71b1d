#include "pipeline/epoch_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

fs::path free_name(const fs::path& folder, const std::string& name, const std::string& tag) {
    fs::path candidate = folder / name;
    if (!fs::exists(candidate)) return candidate;
    const fs::path n(name);
    const std::string stem = n.stem().string();
    const std::string ext = n.extension().string();
    for (int i = 1;; ++i) {
        std::string free = stem + "." + tag;
        if (i > 1) free.append("-").append(std::to_string(i));
        candidate = folder / (free + ext);
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
    const fs::path tmp = to.parent_path() / ("." + to.filename().native() + ".part");
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
