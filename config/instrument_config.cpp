#include "config/instrument_config.hpp"

#include <fnmatch.h>

#include <array>

#include "core/config_key.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace {

constexpr std::array<Named<InstrumentKind>, 3> kKinds{{
    {InstrumentKind::tls, "tls"},
    {InstrumentKind::pls, "pls"},
    {InstrumentKind::mls, "mls"},
}};

}  // namespace

const char* kind_name(InstrumentKind kind) {
    return name_of(kind, kKinds).data();
}

bool InstrumentConfig::matches(const std::string& file_name) const {
    return !pattern.empty() && ::fnmatch(pattern.c_str(), file_name.c_str(), 0) == 0;
}

const InstrumentConfig* instrument_for(const std::vector<InstrumentConfig>& instruments,
                                       const std::string& file_name) {
    for (const auto& i : instruments)
        if (i.matches(file_name)) return &i;
    return nullptr;
}

const InstrumentConfig* find_instrument(const std::vector<InstrumentConfig>& instruments,
                                        const std::string& name) {
    for (const auto& i : instruments)
        if (i.name == name) return &i;
    return nullptr;
}

const InstrumentConfig& instrument_named(const std::vector<InstrumentConfig>& instruments,
                                         const std::string& name, const std::string& file) {
    if (const auto* i = find_instrument(instruments, name)) return *i;
    std::string names;
    for (const auto& i : instruments) names += (names.empty() ? "" : ", ") + i.name;
    throw Error("no [[instrument]] named '" + name + "' in " + file +
                (names.empty() ? " (it has none)" : " (it has " + names + ")"));
}

InstrumentConfig read_instrument(TomlFields& t, const std::vector<InstrumentConfig>& taken) {
    InstrumentConfig i;
    if (!t.has("name")) t.fail("name", "every [[instrument]] needs a name");
    t.get("name", i.name);
    if (i.name.empty() || i.name.find('/') != std::string::npos)
        t.fail("name", "expected a non-empty instrument name without '/'");
    for (const auto& other : taken)
        if (other.name == i.name) t.fail("name", "instrument '" + i.name + "' is defined twice");
    t.get_choice("kind", i.kind, kKinds);
    t.get("range_sigma", i.range_sigma, 0.0, 1.0);
    t.get("pattern", i.pattern);
    if (i.pattern.find('/') != std::string::npos)
        t.fail("pattern", "a pattern matches file names in the ingest folder: no '/'");
    for (const auto& other : taken)
        if (!i.pattern.empty() && other.pattern == i.pattern)
            t.fail("pattern", "instrument '" + other.name + "' has the same pattern");
    t.reject_unknown_keys();
    return i;
}

std::string describe(const InstrumentConfig& i) {
    return "instrument " + toml_string(i.name) + ": kind = " + kind_name(i.kind) +
           ", range_sigma = " + toml_number(i.range_sigma) +
           (i.pattern.empty() ? "" : ", pattern = " + toml_string(i.pattern));
}

}  // namespace tlsmon
