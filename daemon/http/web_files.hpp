#pragma once
// The dashboard's static files, read into memory once at start: a request names a file by
// its path relative to the web root and is answered only when that exact name was found
// there, so no part of a URL ever reaches the file system (path traversal has nothing to
// act on).
#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace tlsmon {

struct WebFile {
    std::string content_type;
    std::string body;
};

class WebFiles {
  public:
    // Every regular file under `root` (symbolic links not followed out of it); Error when
    // `root` holds no index.html.
    static WebFiles load(const std::filesystem::path& root);

    // "index.html", "vendor/dygraph.min.js"; none for anything else.
    const WebFile* find(const std::string& name) const;
    const std::filesystem::path& root() const { return root_; }
    std::size_t size() const { return files_.size(); }

  private:
    std::filesystem::path root_;
    std::map<std::string, WebFile> files_;
};

// The web root: `configured` when set; else the files installed with the program
// (`../share/tlsmon/web` beside its bin/, or `web/` beside it in a build tree).
std::filesystem::path find_web_root(const std::filesystem::path& configured);

}  // namespace tlsmon
