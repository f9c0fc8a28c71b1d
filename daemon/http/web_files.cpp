#include "daemon/http/web_files.hpp"

#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

std::string content_type(const fs::path& file) {
    static const std::map<std::string, std::string> types{
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".svg", "image/svg+xml"},
        {".png", "image/png"},
        {".json", "application/json"},
        {".ico", "image/x-icon"},
        {".txt", "text/plain; charset=utf-8"}};
    const auto it = types.find(file.extension().string());
    return it == types.end() ? "application/octet-stream" : it->second;
}

std::string read_bytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error("cannot read the dashboard file " + file.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

WebFiles WebFiles::load(const fs::path& root) {
    WebFiles w;
    w.root_ = root;
    std::error_code ec;
    if (!fs::is_regular_file(root / "index.html", ec)) {
        throw Error("the dashboard's files are not in " + root.string() +
                    " (no index.html): set http.web_root to the folder installed with tlsmon");
    }
    for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::end(it);
         it.increment(ec)) {
        if (!it->is_regular_file()) continue;
        const std::string name = fs::relative(it->path(), root).generic_string();
        w.files_[name] = WebFile{content_type(it->path()), read_bytes(it->path())};
    }
    if (ec) throw Error("reading the dashboard's files in " + root.string() + ": " + ec.message());
    return w;
}

const WebFile* WebFiles::find(const std::string& name) const {
    const auto it = files_.find(name);
    return it == files_.end() ? nullptr : &it->second;
}

fs::path find_web_root(const fs::path& configured) {
    if (!configured.empty()) return configured;
    std::error_code ec;
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "web";
    const fs::path bin = program.parent_path();
    for (const fs::path& candidate : {bin / "web", bin.parent_path() / "share/tlsmon/web"}) {
        if (fs::is_regular_file(candidate / "index.html", ec)) return candidate;
    }
    return bin.parent_path() / "share/tlsmon/web";
}

}  // namespace tlsmon
