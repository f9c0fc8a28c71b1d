#include "pipeline/vector_reference.hpp"

#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

namespace {

constexpr std::size_t kFrameValues = 12;  // origin, normal, u, v

}  // namespace

std::string VectorReference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    std::vector<double> frame_values;
    for (const auto& f : frames)
        for (const auto* a : {&f.origin, &f.normal, &f.u, &f.v})
            for (int k = 0; k < 3; ++k) frame_values.push_back((*a)(k));
    std::vector<float> sample_values;
    sample_values.reserve(4 * samples.size());
    for (const auto& s : samples)
        sample_values.insert(sample_values.end(), {s.u, s.v, s.w, s.intensity});
    w.put_array(frame_values);
    w.put_array(supervoxel);
    w.put_array(offsets);
    w.put_array(sample_values);
    for (int k = 0; k < 3; ++k) w.put<double>(scanner(k));
    w.put<std::uint64_t>(zone_names.size());
    for (std::size_t z = 0; z < zone_names.size(); ++z) {
        w.put_array(std::vector<char>(zone_names[z].begin(), zone_names[z].end()));
        w.put_array(zone_areas[z]);
    }
    return w.take();
}

VectorReference VectorReference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("vectors stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    VectorReference r;
    const auto frame_values = in.get_array<double>();
    r.supervoxel = in.get_array<std::uint32_t>();
    r.offsets = in.get_array<std::uint64_t>();
    const auto sample_values = in.get_array<float>();
    const std::size_t n = r.supervoxel.size();
    if (frame_values.size() != kFrameValues * n || r.offsets.size() != n + 1 ||
        sample_values.size() % 4 != 0 || r.offsets.front() != 0 ||
        r.offsets.back() != sample_values.size() / 4)
        throw Error("vectors stage payload: areas of inconsistent sizes");
    for (std::size_t k = 0; k < n; ++k) {
        if (r.offsets[k] > r.offsets[k + 1])
            throw Error("vectors stage payload: offsets out of order");
        const double* f = &frame_values[kFrameValues * k];
        patches::PatchFrame frame;
        frame.origin = {f[0], f[1], f[2]};
        frame.normal = {f[3], f[4], f[5]};
        frame.u = {f[6], f[7], f[8]};
        frame.v = {f[9], f[10], f[11]};
        r.frames.push_back(frame);
    }
    r.samples.resize(sample_values.size() / 4);
    for (std::size_t i = 0; i < r.samples.size(); ++i)
        r.samples[i] = {sample_values[4 * i], sample_values[4 * i + 1], sample_values[4 * i + 2],
                        sample_values[4 * i + 3]};
    for (int k = 0; k < 3; ++k) r.scanner(k) = in.get<double>();
    const auto zones = in.get<std::uint64_t>();
    if (zones > payload.size()) throw Error("vectors stage payload: too many zones");
    for (std::uint64_t z = 0; z < zones; ++z) {
        const auto name = in.get_array<char>();
        r.zone_names.emplace_back(name.begin(), name.end());
        r.zone_areas.push_back(in.get_array<std::uint32_t>());
        for (auto k : r.zone_areas.back())
            if (k >= n) throw Error("vectors stage payload: area out of range");
    }
    in.finish();
    return r;
}

}  // namespace tlsmon
