#pragma once
// Reading a TOML table into a plain config struct, key by key, with every mistake reported
// as "FILE:LINE:COLUMN: key 'a.b': what is wrong". Keys that are read are remembered, so
// that after the struct is filled every key nobody asked for is reported as unknown
// (a misspelt key must not silently fall back to its default).
#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tlsmon {

class ConfigError : public Error {
  public:
    using Error::Error;
};

// Parses a TOML file; a syntax error becomes a ConfigError naming file, line and column.
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
    // One of `allowed` (an enumeration given by name in the file).
    void get_choice(const std::string& key, std::string& value,
                    const std::vector<std::string>& allowed);
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

    // Throws for the first key of this table that no getter asked for.
    void reject_unknown_keys() const;

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

}  // namespace tlsmon
