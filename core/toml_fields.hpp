#pragma once
// Reading a TOML table into a plain config struct, key by key, with every mistake reported
// as "FILE:LINE:COLUMN: key 'a.b': what is wrong". Keys that are read are remembered, so
// that after the struct is filled every key nobody asked for is reported as unknown
// (a misspelt key must not silently fall back to its default).
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace tlsmon {

class ConfigError : public Error {
  public:
    using Error::Error;
};

// A value chosen by name in the file: one per enumerator, e.g. {ArchiveMode::keep, "keep"}.
template <class E>
struct Named {
    E value;
    std::string_view name;
};

// The name of `value` in `names` (an array of Named<E>).
template <class E, class Names>
std::string_view name_of(E value, const Names& names) {
    for (const auto& n : names) {
        if (n.value == value) return n.name;
    }
    return "?";
}

// "a, b, c": the names of `names`, as an error message lists them.
template <class Names>
std::string list_of_names(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + std::string(n.name);
    return out;
}

// Parses a TOML file; a syntax error becomes a ConfigError naming file, line and column,
// a file that cannot be read one with the system's reason ("cannot open F: No such file
// or directory").
toml::table parse_toml_file(const std::filesystem::path& path);
toml::table parse_toml_string(std::string_view text, const std::string& source_name);

class TomlFields {
  public:
    // `prefix` is the dotted path of `table` inside the document ("" for the root).
    TomlFields(const toml::table& table, std::string source_name, std::string prefix = "");

    // Each getter leaves `value` unchanged when the key is absent, so the struct's default
    // stands; a present key of the wrong type or out of range is a ConfigError.
    void get(const std::string& key, bool& value);
    void get(const std::string& key, std::string& value);
    void get(const std::string& key, std::filesystem::path& value);
    void get(const std::string& key, double& value, double min, double max);
    void get(const std::string& key, std::int64_t& value, std::int64_t min, std::int64_t max);
    void get(const std::string& key, int& value, int min, int max);
    // One of `allowed`, kept as text (a list known only at run time, e.g. preset names).
    void get_choice(const std::string& key, std::string& value,
                    const std::vector<std::string>& allowed);
    // One of `names` (an array of Named<E>), stored as its enumerator.
    template <class E, class Names>
    void get_choice(const std::string& key, E& value, const Names& names);
    // An array of distinct names from `names`, at least one.
    template <class E, class Names>
    void get_choices(const std::string& key, std::vector<E>& values, const Names& names);
    // A duration written as "15min", "30s", "2h", "500ms" or a bare number of seconds.
    void get_seconds(const std::string& key, double& seconds, double min, double max);

    bool has(const std::string& key) const;
    // A sub-table (absent -> nullopt); its keys are checked by its own TomlFields.
    std::optional<TomlFields> table(const std::string& key);
    // An array of tables ([[zone]] ...), each with its own TomlFields.
    std::vector<TomlFields> array_of_tables(const std::string& key);
    // An array of numbers.
    void get(const std::string& key, std::vector<double>& values);
    // An array of strings.
    void get(const std::string& key, std::vector<std::string>& values);
    // An array of arrays of numbers ([[x1, y1], [x2, y2], ...]).
    void get(const std::string& key, std::vector<std::vector<double>>& values);
    // Whether the key is present and holds an array.
    bool is_array(const std::string& key) const;

    // Throws for the first key of this table that no getter asked for.
    void reject_unknown_keys() const;
    // Keys that moved elsewhere (old name -> "section.key"): the error names the new place.
    void reject_unknown_keys(const std::map<std::string, std::string>& moved) const;

    [[noreturn]] void fail(const std::string& key, const std::string& what) const;
    std::string where(const std::string& key) const;  // "file:line:col: key 'a.b'"

  private:
    const toml::node* find(const std::string& key);

    const toml::table* table_;
    std::string source_;
    std::string prefix_;
    std::set<std::string> read_;
};

// Parses "15min", "30s", "2h", "1d", "500ms" or "900" (seconds). Throws ConfigError.
double parse_duration_seconds(const std::string& text);

template <class E, class Names>
void TomlFields::get_choice(const std::string& key, E& value, const Names& names) {
    if (!has(key)) {
        find(key);  // absent: the default stands, and the key counts as known
        return;
    }
    std::string text;
    get(key, text);
    for (const auto& n : names) {
        if (n.name == text) {
            value = n.value;
            return;
        }
    }
    fail(key, "'" + text + "' is not one of: " + list_of_names(names));
}

template <class E, class Names>
void TomlFields::get_choices(const std::string& key, std::vector<E>& values, const Names& names) {
    if (!has(key)) {
        find(key);
        return;
    }
    std::vector<std::string> texts;
    get(key, texts);
    if (texts.empty()) fail(key, "expected at least one of: " + list_of_names(names));
    std::vector<E> out;
    for (const auto& text : texts) {
        const auto* named = [&]() -> const Named<E>* {
            for (const auto& n : names) {
                if (n.name == text) return &n;
            }
            return nullptr;
        }();
        if (!named) fail(key, "'" + text + "' is not one of: " + list_of_names(names));
        if (std::find(out.begin(), out.end(), named->value) != out.end()) {
            fail(key, "'" + text + "' is listed twice");
        }
        out.push_back(named->value);
    }
    values = std::move(out);
}

}  // namespace tlsmon
