#include "config/folder_overlap.hpp"

#include <algorithm>
#include <functional>
#include <system_error>

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// Whether `inner` is `outer` or lies below it, component by component.
bool lexically_within(const fs::path& inner, const fs::path& outer) {
    auto i = inner.begin();
    for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
        if (o->empty()) continue;  // a trailing separator
        if (i == inner.end() || *i != *o) return false;
    }
    return true;
}

// `inner` is `outer` or lies below it on disk: the symbolic links of both resolved, and
// each existing folder from `inner` up compared with `outer` by identity (device, inode).
bool within_on_disk(const fs::path& inner, const fs::path& outer) {
    std::error_code ec;
    const fs::path a = fs::weakly_canonical(inner, ec);
    if (ec) return lexically_within(inner, outer);
    const fs::path b = fs::weakly_canonical(outer, ec);
    if (ec) return lexically_within(inner, outer);
    if (lexically_within(a, b)) return true;
    if (!fs::exists(b, ec)) return false;
    for (fs::path p = a; !p.empty(); p = p.parent_path()) {
        if (fs::exists(p, ec) && fs::equivalent(p, b, ec)) return true;
        if (p == p.root_path()) break;
    }
    return false;
}

using Within = std::function<bool(const fs::path&, const fs::path&)>;

std::optional<FolderOverlap> overlap(const PathsConfig& c, const Within& within) {
    struct Folder {
        const char* key;
        const fs::path& path;
    };
    const Folder folders[] = {
        {"ingest", c.ingest}, {"archive", c.archive}, {"quarantine", c.quarantine}};
    const auto named = [](const Folder& f) {
        return "paths." + std::string(f.key) + " (" + f.path.string() + ")";
    };
    // Reported against the later key of each pair: the ingest folder is the one to keep.
    for (std::size_t j = 1; j < 3; ++j) {
        for (std::size_t i = 0; i < j; ++i) {
            const Folder& a = folders[j];
            const Folder& b = folders[i];
            const std::string path = a.path.string();
            if (within(a.path, b.path) && within(b.path, a.path)) {
                return FolderOverlap{
                    a.key, path + " is the folder of " + named(b) + "; the folders must be apart"};
            }
            if (within(a.path, b.path)) {
                return FolderOverlap{
                    a.key, path + " lies inside " + named(b) + "; the folders must be apart"};
            }
            if (within(b.path, a.path)) {
                return FolderOverlap{a.key,
                                     path + " holds " + named(b) + "; the folders must be apart"};
            }
        }
    }
    const fs::path db_folder = c.database.parent_path();
    for (const Folder& f : folders) {
        if (within(db_folder, f.path)) {
            return FolderOverlap{"database", c.database.string() + " lies in " + named(f) +
                                                 ", whose files are moved or removed"};
        }
    }
    return std::nullopt;
}

}  // namespace

std::optional<FolderOverlap> folders_overlap(const PathsConfig& paths) {
    return overlap(paths, lexically_within);
}

std::optional<FolderOverlap> folders_overlap_on_disk(const PathsConfig& paths) {
    return overlap(paths, within_on_disk);
}

}  // namespace tlsmon
