#include "core/toml_fields.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

namespace tlsmon {

namespace {

std::string position(const std::string& source, const toml::source_region& region) {
    std::ostringstream s;
    s << source << ':' << region.begin.line << ':' << region.begin.column;
    return s.str();
}

}  // namespace

toml::table parse_toml_file(const std::filesystem::path& path) {
    // Read here rather than by toml::parse_file, whose "File could not be opened" drops
    // the system's reason (missing file? permission?).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw ConfigError("cannot open " + path.string() + ": " + std::strerror(errno));
    std::string text;
    char buffer[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            ::close(fd);
            throw ConfigError("cannot read " + path.string() + ": " + std::strerror(error));
        }
        text.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(fd);
    return parse_toml_string(text, path.string());
}

toml::table parse_toml_string(std::string_view text, const std::string& source_name) {
    try {
        return toml::parse(text, source_name);
    } catch (const toml::parse_error& e) {
        throw ConfigError(position(source_name, e.source()) + ": " + std::string(e.description()));
    }
}

TomlFields::TomlFields(const toml::table& table, std::string source_name, std::string prefix)
    : table_(&table), source_(std::move(source_name)), prefix_(std::move(prefix)) {}

std::string TomlFields::where(const std::string& key) const {
    const toml::node* node = table_->get(key);
    const toml::source_region& region = node ? node->source() : table_->source();
    const std::string dotted = prefix_.empty() ? key : prefix_ + "." + key;
    return position(source_, region) + ": key '" + dotted + "'";
}

void TomlFields::fail(const std::string& key, const std::string& what) const {
    throw ConfigError(where(key) + ": " + what);
}

const toml::node* TomlFields::find(const std::string& key) {
    read_.insert(key);
    return table_->get(key);
}

bool TomlFields::has(const std::string& key) const {
    return table_->contains(key);
}

bool TomlFields::is_array(const std::string& key) const {
    const toml::node* n = table_->get(key);
    return n && n->is_array();
}

void TomlFields::get(const std::string& key, std::vector<std::vector<double>>& values) {
    const toml::node* n = find(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "expected an array of arrays of numbers");
    std::vector<std::vector<double>> out;
    for (const auto& row : *a) {
        const toml::array* r = row.as_array();
        if (!r) fail(key, "expected an array of arrays of numbers");
        auto& v = out.emplace_back();
        for (const auto& e : *r) {
            if (!e.is_number()) fail(key, "expected an array of arrays of numbers");
            const double x = *e.value<double>();
            if (!std::isfinite(x)) fail(key, "array holds a non-finite number");
            v.push_back(x);
        }
    }
    values = std::move(out);
}

void TomlFields::get(const std::string& key, bool& value) {
    const toml::node* n = find(key);
    if (!n) return;
    if (auto v = n->value<bool>(); v && n->is_boolean()) {
        value = *v;
        return;
    }
    fail(key, "expected true or false");
}

void TomlFields::get(const std::string& key, std::string& value) {
    const toml::node* n = find(key);
    if (!n) return;
    if (!n->is_string()) fail(key, "expected a string");
    value = *n->value<std::string>();
}

void TomlFields::get(const std::string& key, std::filesystem::path& value) {
    std::string s = value.string();
    get(key, s);
    if (has(key) && s.empty()) fail(key, "expected a non-empty path");
    value = s;
}

void TomlFields::get(const std::string& key, double& value, double min, double max) {
    const toml::node* n = find(key);
    if (!n) return;
    if (!n->is_number()) fail(key, "expected a number");
    const double v = *n->value<double>();
    if (!std::isfinite(v) || v < min || v > max) {
        std::ostringstream s;
        s << "value " << v << " is outside " << min << " .. " << max;
        fail(key, s.str());
    }
    value = v;
}

void TomlFields::get(const std::string& key, std::int64_t& value, std::int64_t min,
                     std::int64_t max) {
    const toml::node* n = find(key);
    if (!n) return;
    if (!n->is_integer()) fail(key, "expected a whole number");
    const std::int64_t v = *n->value<std::int64_t>();
    if (v < min || v > max) {
        fail(key, "value " + std::to_string(v) + " is outside " + std::to_string(min) + " .. " +
                      std::to_string(max));
    }
    value = v;
}

void TomlFields::get(const std::string& key, int& value, int min, int max) {
    std::int64_t v = value;
    get(key, v, min, max);
    value = static_cast<int>(v);
}

void TomlFields::get_choice(const std::string& key, std::string& value,
                            const std::vector<std::string>& allowed) {
    std::string v = value;
    get(key, v);
    for (const auto& a : allowed) {
        if (a == v) {
            value = v;
            return;
        }
    }
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "'" + v + "' is not one of: " + list);
}

double parse_duration_seconds(const std::string& text) {
    double number = 0;
    const char* begin = text.data();
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(begin, end, number);
    if (ec != std::errc{} || !std::isfinite(number) || number < 0) {
        throw ConfigError("'" + text + "' is not a duration (e.g. 15min, 30s, 2h)");
    }
    const std::string unit(ptr, end);
    if (unit.empty() || unit == "s") return number;
    if (unit == "ms") return number / 1000.0;
    if (unit == "min" || unit == "m") return number * 60.0;
    if (unit == "h") return number * 3600.0;
    if (unit == "d") return number * 86400.0;
    throw ConfigError("'" + text + "' has an unknown unit '" + unit + "' (ms, s, min, h, d)");
}

void TomlFields::get_seconds(const std::string& key, double& seconds, double min, double max) {
    const toml::node* n = find(key);
    if (!n) return;
    double v = 0;
    if (n->is_number()) {
        v = *n->value<double>();
    } else if (n->is_string()) {
        try {
            v = parse_duration_seconds(*n->value<std::string>());
        } catch (const ConfigError& e) {
            fail(key, e.what());
        }
    } else {
        fail(key, "expected a duration such as \"15min\" or a number of seconds");
    }
    if (!std::isfinite(v) || v < min || v > max) {
        std::ostringstream s;
        s << "duration " << v << " s is outside " << min << " .. " << max << " s";
        fail(key, s.str());
    }
    seconds = v;
}

std::optional<TomlFields> TomlFields::table(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    if (!n->is_table()) fail(key, "expected a table [" + key + "]");
    return TomlFields(*n->as_table(), source_, prefix_.empty() ? key : prefix_ + "." + key);
}

std::vector<TomlFields> TomlFields::array_of_tables(const std::string& key) {
    std::vector<TomlFields> out;
    const toml::node* n = find(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "expected an array of tables [[" + key + "]]");
    for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::table* t = (*a)[i].as_table();
        if (!t) fail(key, "element " + std::to_string(i) + " is not a table");
        out.emplace_back(
            *t, source_,
            (prefix_.empty() ? key : prefix_ + "." + key) + "[" + std::to_string(i) + "]");
    }
    return out;
}

void TomlFields::get(const std::string& key, std::vector<double>& values) {
    const toml::node* n = find(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "expected an array of numbers");
    std::vector<double> out;
    for (const auto& e : *a) {
        if (!e.is_number()) fail(key, "expected an array of numbers");
        const double v = *e.value<double>();
        if (!std::isfinite(v)) fail(key, "array holds a non-finite number");
        out.push_back(v);
    }
    values = std::move(out);
}

void TomlFields::get(const std::string& key, std::vector<std::string>& values) {
    const toml::node* n = find(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "expected an array of strings");
    std::vector<std::string> out;
    for (const auto& e : *a) {
        if (!e.is_string()) fail(key, "expected an array of strings");
        out.push_back(*e.value<std::string>());
    }
    values = std::move(out);
}

void TomlFields::reject_unknown_keys() const {
    reject_unknown_keys({});
}

void TomlFields::reject_unknown_keys(const std::map<std::string, std::string>& moved) const {
    for (const auto& [k, node] : *table_) {
        const std::string key(k.str());
        if (read_.count(key)) continue;
        const auto to = moved.find(key);
        if (to != moved.end()) fail(key, "moved to " + to->second + " (one model for the site)");
        fail(key, "unknown key");
    }
}

}  // namespace tlsmon
