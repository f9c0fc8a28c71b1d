#include "pipeline/pbm3c2_reference.hpp"

#include "algorithms/patches/patch_plane.hpp"
#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

Eigen::Vector3d PbM3c2Reference::measured_in_frame(std::size_t k,
                                                   const patches::PatchResult* result) const {
    const auto over_centroid = [](const patches::PlaneFit& fit) {
        return Eigen::Vector3d(fit.centroid.x(), fit.centroid.y(), fit.height);
    };
    if (result && result->reference.valid) return over_centroid(result->reference);
    const auto whole = patches::fit_plane(moments[k]);
    return whole.valid ? over_centroid(whole) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d PbM3c2Reference::measured_at(std::size_t k,
                                             const patches::PatchResult* result) const {
    return from_frame(k, measured_in_frame(k, result));
}

Eigen::Vector3d PbM3c2Reference::from_frame(std::size_t k, const Eigen::Vector3d& uvw) const {
    const auto& frame = patches[k].frame;
    return frame.origin + uvw.x() * frame.u + uvw.y() * frame.v + uvw.z() * frame.normal;
}

namespace {

constexpr std::size_t kFrameValues = 12;   // origin, normal, u, v
constexpr std::size_t kMomentValues = 10;  // PlaneMoments' sums, per block

}  // namespace

std::string PbM3c2Reference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    std::vector<double> frames, moment_values;
    std::vector<std::int32_t> cells;  // per patch: u0, v0, width, height
    std::vector<double> cell_size;
    std::vector<std::uint8_t> occupied;
    for (const auto& p : patches) {
        for (const auto* a : {&p.frame.origin, &p.frame.normal, &p.frame.u, &p.frame.v})
            for (int k = 0; k < 3; ++k) frames.push_back((*a)(k));
        const auto& f = p.footprint;
        cells.insert(cells.end(), {f.u0, f.v0, f.width, f.height});
        cell_size.push_back(f.cell);
        occupied.insert(occupied.end(), f.occupied.begin(), f.occupied.end());
    }
    std::vector<std::uint32_t> block_counts;
    std::vector<std::int32_t> block_places;  // i, j
    for (const auto& patch_blocks : blocks) {
        block_counts.push_back(static_cast<std::uint32_t>(patch_blocks.size()));
        for (const auto& b : patch_blocks) {
            const auto& m = b.moments;
            block_places.insert(block_places.end(), {b.i, b.j});
            moment_values.insert(moment_values.end(),
                                 {m.m, m.su, m.sv, m.sw, m.suu, m.suv, m.svv, m.suw, m.svw, m.sww});
        }
    }
    w.put_array(frames);
    w.put_array(cells);
    w.put_array(cell_size);
    w.put_array(occupied);
    w.put_array(supervoxel);
    w.put_array(block_side);
    w.put_array(block_counts);
    w.put_array(block_places);
    w.put_array(moment_values);
    for (int k = 0; k < 3; ++k) w.put<double>(scanner(k));
    w.put<std::uint64_t>(zone_names.size());
    for (std::size_t z = 0; z < zone_names.size(); ++z) {
        w.put_array(std::vector<char>(zone_names[z].begin(), zone_names[z].end()));
        w.put_array(zone_patches[z]);
    }
    return w.take();
}

PbM3c2Reference PbM3c2Reference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("pbm3c2 stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    PbM3c2Reference r;
    const auto frames = in.get_array<double>();
    const auto cells = in.get_array<std::int32_t>();
    const auto cell_size = in.get_array<double>();
    const auto occupied = in.get_array<std::uint8_t>();
    r.supervoxel = in.get_array<std::uint32_t>();
    r.block_side = in.get_array<double>();
    const auto block_counts = in.get_array<std::uint32_t>();
    const auto block_places = in.get_array<std::int32_t>();
    const auto moment_values = in.get_array<double>();
    const std::size_t n = cell_size.size();
    std::size_t all_blocks = 0;
    for (const auto c : block_counts) all_blocks += c;
    if (frames.size() != kFrameValues * n || cells.size() != 4 * n || r.supervoxel.size() != n ||
        r.block_side.size() != n || block_counts.size() != n ||
        block_places.size() != 2 * all_blocks ||
        moment_values.size() != kMomentValues * all_blocks) {
        throw Error("pbm3c2 stage payload: patches of inconsistent sizes");
    }
    std::size_t at = 0, block = 0;
    for (std::size_t k = 0; k < n; ++k) {
        patches::Patch p;
        const double* f = &frames[kFrameValues * k];
        p.frame.origin = {f[0], f[1], f[2]};
        p.frame.normal = {f[3], f[4], f[5]};
        p.frame.u = {f[6], f[7], f[8]};
        p.frame.v = {f[9], f[10], f[11]};
        auto& fp = p.footprint;
        fp.u0 = cells[4 * k], fp.v0 = cells[4 * k + 1];
        fp.width = cells[4 * k + 2], fp.height = cells[4 * k + 3];
        fp.cell = cell_size[k];
        if (fp.width < 0 || fp.height < 0 || !(fp.cell > 0))
            throw Error("pbm3c2 stage payload: a malformed footprint");
        const std::size_t size = std::size_t(fp.width) * std::size_t(fp.height);
        if (at + size > occupied.size()) throw Error("pbm3c2 stage payload: footprints cut short");
        if (!(r.block_side[k] > 0)) throw Error("pbm3c2 stage payload: a malformed block side");
        fp.occupied.assign(occupied.begin() + long(at), occupied.begin() + long(at + size));
        at += size;
        r.patches.push_back(std::move(p));
        auto& patch_blocks = r.blocks.emplace_back();
        for (std::uint32_t b = 0; b < block_counts[k]; ++b, ++block) {
            const double* m = &moment_values[kMomentValues * block];
            patch_blocks.push_back({block_places[2 * block],
                                    block_places[2 * block + 1],
                                    {m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9]}});
            // In (j, i) order, as seen_alike reads them.
            if (b > 0) {
                const auto& p = patch_blocks[b - 1];
                const auto& q = patch_blocks[b];
                if (p.j > q.j || (p.j == q.j && p.i >= q.i))
                    throw Error("pbm3c2 stage payload: blocks out of order");
            }
        }
        r.moments.push_back(patches::total(patch_blocks));
    }
    if (at != occupied.size()) throw Error("pbm3c2 stage payload: footprints of another size");
    for (int k = 0; k < 3; ++k) r.scanner(k) = in.get<double>();
    const auto zones = in.get<std::uint64_t>();
    if (zones > payload.size()) throw Error("pbm3c2 stage payload: too many zones");
    for (std::uint64_t z = 0; z < zones; ++z) {
        const auto name = in.get_array<char>();
        r.zone_names.emplace_back(name.begin(), name.end());
        r.zone_patches.push_back(in.get_array<std::uint32_t>());
        for (auto k : r.zone_patches.back())
            if (k >= n) throw Error("pbm3c2 stage payload: patch out of range");
    }
    in.finish();
    return r;
}

}  // namespace tlsmon
