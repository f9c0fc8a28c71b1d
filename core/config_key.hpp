#pragma once
// A configuration key declared beside the struct it sets (PDAL's `addArgs` is the model):
// its name, type, allowed range, meaning, how it is read from its TOML section into a member
// and how that member is written back as TOML text — in one statement, e.g.
//
//   number(&M3c2Config::cylinder_radius, "cylinder_radius", 0.001, 100, "m",
//          "Radius of the projection cylinder (d/2 of Lague 2013).")
//
// The default is the member's initialiser. Each section's list is collected, with the name
// of its TOML table, into the configuration's keys (config/keys.hpp), from which the
// reader, the effective configuration logged at start, the one-shot commands' parameter
// lines and the reference tables of docs/configuration.md all come.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/toml_fields.hpp"

namespace tlsmon {

template <class S>
struct SectionKey {
    std::string name;   // "stable_seconds"
    std::string type;   // as documented: "duration", "integer", "string", "path", ...
    std::string range;  // the allowed values in words, from the same limits the reader uses
    std::string help;   // what the key means
    // Reads the key from its section (absent: the value in `s` stands). Rules that involve
    // other keys are checked once the section is read.
    std::function<void(TomlFields& section, S& s)> read;
    // The value as TOML text ("10", "\"move\"", "[\"ptx\"]").
    std::function<std::string(const S& s)> value;
};

// The value of an optional key that was not given (shown, never written to a file).
inline constexpr const char* kNoValue = "(none)";

// A string and a number as TOML writes them: "a \"b\"", 0.1.
std::string toml_string(const std::string& s);
std::string toml_number(double v);
// 86400 -> "1 d", 3600 -> "1 h", 0.1 -> "0.1 s": a duration as the docs write it.
std::string duration_text(double seconds);
// "a" and "b" -> "a, b"; an empty part is left out.
std::string joined_rules(std::initializer_list<std::string> parts);

template <class Names>
std::string names_in_backticks(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "`" : ", `") + std::string(n.name) + "`";
    return out;
}

namespace config_key_detail {

// `field` may be a member of a base of S (the kernel's Parameters a section embeds).
template <class S, class B, class T>
T& at(S& s, T B::*field) {
    static_assert(std::is_base_of_v<B, S>);
    return s.*field;
}
template <class S, class B, class T>
const T& at(const S& s, T B::*field) {
    static_assert(std::is_base_of_v<B, S>);
    return s.*field;
}

template <class S>
SectionKey<S> key(std::string name, std::string type, std::string range, std::string help) {
    return SectionKey<S>{
        std::move(name), std::move(type), std::move(range), std::move(help), {}, {}};
}

}  // namespace config_key_detail

// The key builders of one section S, e.g. `using K = Keys<M3c2Config>;` then
// `K::number(&M3c2Config::cylinder_radius, ...)`.
template <class S>
struct Keys {
    template <class B>
    static SectionKey<S> text(std::string B::*field, std::string name, std::string rule,
                              std::string help) {
        auto k =
            config_key_detail::key<S>(std::move(name), "string", std::move(rule), std::move(help));
        k.read = [field, n = k.name](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field));
        };
        k.value = [field](const S& s) { return toml_string(config_key_detail::at(s, field)); };
        return k;
    }

    // A path; relative ones are resolved once the section is read.
    template <class B>
    static SectionKey<S> path(std::filesystem::path B::*field, std::string name, std::string rule,
                              std::string help) {
        auto k =
            config_key_detail::key<S>(std::move(name), "path", std::move(rule), std::move(help));
        k.read = [field, n = k.name](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field));
        };
        k.value = [field](const S& s) {
            return toml_string(config_key_detail::at(s, field).string());
        };
        return k;
    }

    // A path that may be "" (none).
    template <class B>
    static SectionKey<S> optional_path(std::filesystem::path B::*field, std::string name,
                                       std::string help) {
        auto k = config_key_detail::key<S>(std::move(name), "path", "", std::move(help));
        k.read = [field, n = k.name](TomlFields& t, S& s) {
            std::string text = config_key_detail::at(s, field).string();
            t.get(n, text);
            config_key_detail::at(s, field) = text;
        };
        k.value = [field](const S& s) {
            return toml_string(config_key_detail::at(s, field).string());
        };
        return k;
    }

    template <class B>
    static SectionKey<S> flag(bool B::*field, std::string name, std::string help) {
        auto k = config_key_detail::key<S>(std::move(name), "boolean", "`true`, `false`",
                                           std::move(help));
        k.read = [field, n = k.name](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field));
        };
        k.value = [field](const S& s) {
            return std::string(config_key_detail::at(s, field) ? "true" : "false");
        };
        return k;
    }

    template <class B>
    static SectionKey<S> names(std::vector<std::string> B::*field, std::string name,
                               std::string rule, std::string help) {
        auto k = config_key_detail::key<S>(std::move(name), "array of strings", std::move(rule),
                                           std::move(help));
        k.read = [field, n = k.name](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field));
        };
        k.value = [field](const S& s) {
            std::string out = "[";
            for (const auto& v : config_key_detail::at(s, field))
                out += (out.size() > 1 ? ", " : "") + toml_string(v);
            return out + "]";
        };
        return k;
    }

    template <class B>
    static SectionKey<S> seconds(double B::*field, std::string name, double min, double max,
                                 std::string rule, std::string help) {
        auto k = config_key_detail::key<S>(
            std::move(name), "duration",
            joined_rules({duration_text(min) + " .. " + duration_text(max), std::move(rule)}),
            std::move(help));
        k.read = [field, n = k.name, min, max](TomlFields& t, S& s) {
            t.get_seconds(n, config_key_detail::at(s, field), min, max);
        };
        k.value = [field](const S& s) { return toml_number(config_key_detail::at(s, field)); };
        return k;
    }

    // A real number in [min, max] with its unit.
    template <class B>
    static SectionKey<S> number(double B::*field, std::string name, double min, double max,
                                std::string unit, std::string help) {
        std::string range = toml_number(min) + " .. " + toml_number(max);
        if (!unit.empty()) range += " " + unit;
        auto k =
            config_key_detail::key<S>(std::move(name), "number", std::move(range), std::move(help));
        k.read = [field, n = k.name, min, max](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field), min, max);
        };
        k.value = [field](const S& s) { return toml_number(config_key_detail::at(s, field)); };
        return k;
    }

    // A real number in [min, max] that may be left out: "(none)" until given.
    template <class B>
    static SectionKey<S> optional_number(std::optional<double> B::*field, std::string name,
                                         double min, double max, std::string unit,
                                         std::string help) {
        std::string range = toml_number(min) + " .. " + toml_number(max);
        if (!unit.empty()) range += " " + unit;
        auto k =
            config_key_detail::key<S>(std::move(name), "number", std::move(range), std::move(help));
        k.read = [field, n = k.name, min, max](TomlFields& t, S& s) {
            if (!t.has(n)) return;
            double v = 0;
            t.get(n, v, min, max);
            config_key_detail::at(s, field) = v;
        };
        k.value = [field](const S& s) {
            const auto& v = config_key_detail::at(s, field);
            return v ? toml_number(*v) : std::string(kNoValue);
        };
        return k;
    }

    template <class B, class T>
    static SectionKey<S> integer(T B::*field, std::string name, std::int64_t min, std::int64_t max,
                                 std::string unit, std::string help) {
        std::string range = std::to_string(min) + " .. " + std::to_string(max);
        if (!unit.empty()) range += " " + unit;
        auto k = config_key_detail::key<S>(std::move(name), "integer", std::move(range),
                                           std::move(help));
        k.read = [field, n = k.name, min, max](TomlFields& t, S& s) {
            t.get(n, config_key_detail::at(s, field), static_cast<T>(min), static_cast<T>(max));
        };
        k.value = [field](const S& s) { return std::to_string(config_key_detail::at(s, field)); };
        return k;
    }

    template <class B, class E, std::size_t N>
    static SectionKey<S> choice(E B::*field, std::string name,
                                const std::array<Named<E>, N>& options, std::string help) {
        auto k = config_key_detail::key<S>(std::move(name), "string", names_in_backticks(options),
                                           std::move(help));
        k.read = [field, n = k.name, &options](TomlFields& t, S& s) {
            t.get_choice(n, config_key_detail::at(s, field), options);
        };
        k.value = [field, &options](const S& s) {
            return toml_string(std::string(name_of(config_key_detail::at(s, field), options)));
        };
        return k;
    }

    template <class B, class E, std::size_t N>
    static SectionKey<S> choices(std::vector<E> B::*field, std::string name,
                                 const std::array<Named<E>, N>& options, std::string help) {
        auto k = config_key_detail::key<S>(
            std::move(name), "array of strings",
            "each of " + names_in_backticks(options) + ", no repeats", std::move(help));
        k.read = [field, n = k.name, &options](TomlFields& t, S& s) {
            t.get_choices(n, config_key_detail::at(s, field), options);
        };
        k.value = [field, &options](const S& s) {
            std::string out = "[";
            for (const E v : config_key_detail::at(s, field)) {
                out += (out.size() > 1 ? ", " : "") + toml_string(std::string(name_of(v, options)));
            }
            return out + "]";
        };
        return k;
    }
};

}  // namespace tlsmon
