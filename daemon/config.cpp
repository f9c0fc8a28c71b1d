#include "daemon/config.hpp"

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kTimeSources = {"scan", "file_name", "mtime"};

fs::path resolve(const fs::path& p, const fs::path& base) {
    return (p.is_absolute() ? p : base / p).lexically_normal();
}

bool is_sha256(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](unsigned char c) {
               return std::isdigit(c) || (c >= 'a' && c <= 'f');
           });
}

void read_station(TomlFields& t, StationConfig& c) {
    t.get("name", c.name);
    if (c.name.empty() || c.name.find('/') != std::string::npos) {
        t.fail("name", "expected a non-empty station name without '/'");
    }
    t.reject_unknown_keys();
}

void read_paths(TomlFields& t, PathsConfig& c, const fs::path& base) {
    t.get("ingest", c.ingest);
    t.get("archive", c.archive);
    t.get("quarantine", c.quarantine);
    t.get("database", c.database);
    t.reject_unknown_keys();
    c.ingest = resolve(c.ingest, base);
    c.archive = resolve(c.archive, base);
    c.quarantine = resolve(c.quarantine, base);
    c.database = resolve(c.database, base);
    if (c.archive == c.ingest) t.fail("archive", "must differ from paths.ingest");
    if (c.quarantine == c.ingest) t.fail("quarantine", "must differ from paths.ingest");
    if (c.quarantine == c.archive) t.fail("quarantine", "must differ from paths.archive");
    if (c.database.parent_path() == c.ingest) {
        t.fail("database", "must not lie in the ingest folder");
    }
}

void read_ingest(TomlFields& t, IngestConfig& c) {
    t.get("extensions", c.extensions);
    if (c.extensions.empty()) t.fail("extensions", "expected at least one extension");
    std::set<std::string> seen;
    for (auto& e : c.extensions) {
        if (e.empty() || !std::all_of(e.begin(), e.end(),
                                      [](unsigned char ch) { return std::isalnum(ch) != 0; })) {
            t.fail("extensions", "'" + e + "' is not an extension (letters and digits, no dot)");
        }
        std::transform(e.begin(), e.end(), e.begin(),
                       [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
        if (!seen.insert(e).second) t.fail("extensions", "'" + e + "' is listed twice");
    }
    t.get_seconds("stable_seconds", c.stable_seconds, 0.0, 86400.0);
    t.get_seconds("rescan_interval", c.rescan_interval, 0.1, 86400.0);
    t.get_seconds("max_growing", c.max_growing, 1.0, 30.0 * 86400.0);
    if (c.max_growing <= c.stable_seconds) {
        t.fail("max_growing", "must be longer than ingest.stable_seconds");
    }
    t.get_choice("archive", c.archive, {"move", "keep"});
    t.get("reference_epoch", c.reference_epoch);
    if (!c.reference_epoch.empty() && !is_sha256(c.reference_epoch) &&
        c.reference_epoch.find('/') != std::string::npos) {
        t.fail("reference_epoch",
               "expected a file name (no folder) or a sha256 of 64 lower-case hex digits");
    }
    t.get("acquisition_time", c.acquisition_time);
    if (c.acquisition_time.empty()) t.fail("acquisition_time", "expected at least one source");
    std::set<std::string> sources;
    for (const auto& s : c.acquisition_time) {
        if (std::find(kTimeSources.begin(), kTimeSources.end(), s) == kTimeSources.end()) {
            t.fail("acquisition_time", "'" + s + "' is not one of: scan, file_name, mtime");
        }
        if (!sources.insert(s).second) t.fail("acquisition_time", "'" + s + "' is listed twice");
    }
    t.get_seconds("retry_initial", c.retry_initial, 0.1, 3600.0);
    t.get_seconds("retry_max", c.retry_max, 0.1, 86400.0);
    if (c.retry_max < c.retry_initial) t.fail("retry_max", "must be >= ingest.retry_initial");
    t.reject_unknown_keys();
}

void read_logging(TomlFields& t, LoggingConfig& c, const fs::path& base) {
    t.get_choice("level", c.level, {"trace", "debug", "info", "warn", "error", "critical", "off"});
    std::string file = c.file.string();  // "" is allowed here: no log file
    t.get("file", file);
    c.file = file.empty() ? std::filesystem::path() : resolve(file, base);
    t.get("max_size", c.max_size, 4096, std::int64_t{1} << 40);
    t.get("max_files", c.max_files, 1, 1000);
    t.get_choice("journald", c.journald, {"auto", "on", "off"});
    t.reject_unknown_keys();
}

void read_daemon(TomlFields& t, DaemonConfig& c) {
    t.get_seconds("status_interval", c.status_interval, 1.0, 86400.0);
    t.reject_unknown_keys();
}

ZoneConfig read_zone(TomlFields& t, const std::set<std::string>& taken) {
    ZoneConfig z;
    if (!t.has("name")) t.fail("name", "every [[zone]] needs a name");
    t.get("name", z.name);
    if (z.name.empty()) t.fail("name", "expected a non-empty zone name");
    if (taken.count(z.name)) t.fail("name", "zone '" + z.name + "' is defined twice");
    for (const char* key : {"min", "max"}) {
        if (!t.has(key)) t.fail(key, "every [[zone]] needs min = [x, y, z] and max = [x, y, z]");
        std::vector<double> v;
        t.get(key, v);
        if (v.size() != 3) t.fail(key, "expected three numbers [x, y, z] in metres");
        std::copy(v.begin(), v.end(), (std::string(key) == "min" ? z.min : z.max).begin());
    }
    for (int i = 0; i < 3; ++i) {
        if (!(z.min[i] < z.max[i])) t.fail("max", "each coordinate must exceed the one in min");
    }
    t.reject_unknown_keys();
    return z;
}

Config parse_table(const toml::table& root, const std::string& source, const fs::path& base) {
    Config c;
    c.file = source;
    // Defaults are relative too: they resolve against the configuration's folder.
    c.paths.ingest = resolve(c.paths.ingest, base);
    c.paths.archive = resolve(c.paths.archive, base);
    c.paths.quarantine = resolve(c.paths.quarantine, base);
    c.paths.database = resolve(c.paths.database, base);
    TomlFields top(root, source);
    if (auto t = top.table("station")) read_station(*t, c.station);
    if (auto t = top.table("paths")) read_paths(*t, c.paths, base);
    if (auto t = top.table("ingest")) read_ingest(*t, c.ingest);
    if (auto t = top.table("logging")) read_logging(*t, c.logging, base);
    if (auto t = top.table("daemon")) read_daemon(*t, c.daemon);
    std::set<std::string> zone_names;
    for (auto& t : top.array_of_tables("zone")) {
        c.zones.push_back(read_zone(t, zone_names));
        zone_names.insert(c.zones.back().name);
    }
    top.reject_unknown_keys();
    return c;
}

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\';
        out += ch;
    }
    return out + '"';
}

std::string names(const std::vector<std::string>& v) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + quoted(v[i]);
    return out + "]";
}

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string triple(const std::array<double, 3>& v) {
    std::string s = "[";
    s += number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
    return s;
}

}  // namespace

Config load_config(const fs::path& path) {
    const toml::table root = parse_toml_file(path);
    const fs::path base = fs::absolute(path).parent_path();
    return parse_table(root, path.string(), base);
}

Config parse_config(std::string_view text, const std::string& source_name,
                    const fs::path& base_dir) {
    const toml::table root = parse_toml_string(text, source_name);
    return parse_table(root, source_name, base_dir);
}

std::vector<std::string> describe(const Config& c) {
    std::vector<std::string> l;
    l.push_back("station.name = " + quoted(c.station.name));
    l.push_back("paths.ingest = " + quoted(c.paths.ingest.string()));
    l.push_back("paths.archive = " + quoted(c.paths.archive.string()));
    l.push_back("paths.quarantine = " + quoted(c.paths.quarantine.string()));
    l.push_back("paths.database = " + quoted(c.paths.database.string()));
    l.push_back("ingest.extensions = " + names(c.ingest.extensions));
    l.push_back("ingest.stable_seconds = " + number(c.ingest.stable_seconds));
    l.push_back("ingest.rescan_interval = " + number(c.ingest.rescan_interval));
    l.push_back("ingest.max_growing = " + number(c.ingest.max_growing));
    l.push_back("ingest.archive = " + quoted(c.ingest.archive));
    l.push_back("ingest.reference_epoch = " + quoted(c.ingest.reference_epoch));
    l.push_back("ingest.acquisition_time = " + names(c.ingest.acquisition_time));
    l.push_back("ingest.retry_initial = " + number(c.ingest.retry_initial));
    l.push_back("ingest.retry_max = " + number(c.ingest.retry_max));
    l.push_back("logging.level = " + quoted(c.logging.level));
    l.push_back("logging.file = " + quoted(c.logging.file.string()));
    l.push_back("logging.max_size = " + std::to_string(c.logging.max_size));
    l.push_back("logging.max_files = " + std::to_string(c.logging.max_files));
    l.push_back("logging.journald = " + quoted(c.logging.journald));
    l.push_back("daemon.status_interval = " + number(c.daemon.status_interval));
    for (const auto& z : c.zones) {
        l.push_back("zone " + quoted(z.name) + ": min = " + triple(z.min) +
                    ", max = " + triple(z.max));
    }
    return l;
}

PipelineConfig pipeline_config(const Config& config) {
    PipelineConfig p;
    p.archive = config.paths.archive;
    p.quarantine = config.paths.quarantine;
    p.archive_mode = config.ingest.archive == "keep" ? ArchiveMode::keep : ArchiveMode::move;
    p.reference_epoch = config.ingest.reference_epoch;
    return p;
}

}  // namespace tlsmon
