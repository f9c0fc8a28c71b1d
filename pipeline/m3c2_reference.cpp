#include "pipeline/m3c2_reference.hpp"

#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

std::string M3c2Reference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    const std::string inner = reference.encode();
    w.put_array(std::vector<char>(inner.begin(), inner.end()));
    w.put<double>(scanner.x());
    w.put<double>(scanner.y());
    w.put<double>(scanner.z());
    w.put<std::uint64_t>(zone_names.size());
    for (std::size_t z = 0; z < zone_names.size(); ++z) {
        w.put_array(std::vector<char>(zone_names[z].begin(), zone_names[z].end()));
        w.put_array(zone_cores[z]);
    }
    return w.take();
}

M3c2Reference M3c2Reference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("m3c2 stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    M3c2Reference r;
    const auto inner = in.get_array<char>();
    r.reference = m3c2::Reference::decode(std::string_view(inner.data(), inner.size()));
    r.scanner.x() = in.get<double>();
    r.scanner.y() = in.get<double>();
    r.scanner.z() = in.get<double>();
    const auto zones = in.get<std::uint64_t>();
    if (zones > payload.size()) throw Error("m3c2 stage payload: too many zones");
    for (std::uint64_t z = 0; z < zones; ++z) {
        const auto name = in.get_array<char>();
        r.zone_names.emplace_back(name.begin(), name.end());
        r.zone_cores.push_back(in.get_array<std::uint32_t>());
        for (auto k : r.zone_cores.back()) {
            if (k >= r.reference.size()) throw Error("m3c2 stage payload: core point out of range");
        }
    }
    in.finish();
    return r;
}

}  // namespace tlsmon
