#include "algorithms/m3c2/reference.hpp"

#include <cstdint>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon::m3c2 {

Reference prepare_reference(const std::vector<Eigen::Vector3d>& reference,
                            std::vector<Eigen::Vector3d> core_points,
                            const NormalParameters& normals, const CylinderParameters& cylinders,
                            unsigned threads, std::span<const Eigen::Vector3d> given_normals,
                            std::span<const std::uint8_t> left_out) {
    validate(normals);
    validate(cylinders);
    const std::size_t n = core_points.size();
    if (!given_normals.empty() && given_normals.size() != n)
        throw Error("m3c2: " + std::to_string(given_normals.size()) + " given normals for " +
                    std::to_string(n) + " core points");
    const auto given = [&](std::size_t k) {
        return !given_normals.empty() && given_normals[k].allFinite() &&
               given_normals[k].norm() > 0.0;
    };
    // Estimated only where no normal is given.
    std::vector<std::size_t> estimated;
    std::vector<Eigen::Vector3d> estimated_at;
    for (std::size_t k = 0; k < n; ++k) {
        if (given(k)) continue;
        estimated.push_back(k);
        estimated_at.push_back(core_points[k]);
    }
    const std::vector<CoreNormal> found =
        estimated_at.empty()
            ? std::vector<CoreNormal>{}
            : estimate_normals(reference, estimated_at, normals, threads, left_out);
    std::vector<Eigen::Vector3d> axes(n);
    Reference r;
    r.normal_radius.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        if (given(k)) {
            axes[k] = oriented(given_normals[k].normalized(), core_points[k], normals.orientation);
            r.normal_radius[k] = 0.0;
        }
    }
    for (std::size_t j = 0; j < estimated.size(); ++j) {
        axes[estimated[j]] = found[j].normal;
        r.normal_radius[estimated[j]] = found[j].radius;
    }
    r.cylinders = make_cylinders(std::move(core_points), std::move(axes), cylinders, threads);
    r.reference_side = cylinder_sides(r.cylinders, reference, threads, left_out);
    return r;
}

std::vector<Distance> distances(const Reference& reference,
                                const std::vector<CylinderSide>& compared_side,
                                const DistanceParameters& parameters) {
    validate(parameters);
    if (compared_side.size() != reference.size())
        throw Error("m3c2: " + std::to_string(compared_side.size()) + " compared cylinders for " +
                    std::to_string(reference.size()) + " core points");
    std::vector<Distance> out(reference.size());
    for (std::size_t k = 0; k < out.size(); ++k)
        out[k] = distance_between(reference.reference_side[k], compared_side[k], parameters);
    return out;
}

namespace {

std::vector<double> flatten(const std::vector<Eigen::Vector3d>& v) {
    std::vector<double> out;
    out.reserve(3 * v.size());
    for (const auto& p : v) out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
}

std::vector<Eigen::Vector3d> unflatten(const std::vector<double>& v, std::size_t n) {
    if (v.size() != 3 * n) throw Error("m3c2 reference payload: arrays of different lengths");
    std::vector<Eigen::Vector3d> out(n);
    for (std::size_t k = 0; k < n; ++k) out[k] = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
    return out;
}

}  // namespace

std::string Reference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    w.put<double>(cylinders.parameters.radius);
    w.put<double>(cylinders.parameters.max_depth);
    w.put<std::uint32_t>(cylinders.parameters.statistic == CylinderStatistic::median ? 1 : 0);
    w.put<double>(cylinders.parameters.stray_distance);
    w.put<std::uint64_t>(size());
    w.put_array(flatten(cylinders.centres));
    w.put_array(flatten(cylinders.axes));
    w.put_array(normal_radius);
    std::vector<double> centre, spread, roughness, lateral, lateral_spread;
    std::vector<std::uint32_t> count;
    for (const auto& s : reference_side) {
        centre.push_back(s.centre);
        spread.push_back(s.spread);
        count.push_back(s.count);
        roughness.push_back(s.roughness);
        lateral.insert(lateral.end(), {s.lateral.x(), s.lateral.y(), s.lateral.z()});
        lateral_spread.push_back(s.lateral_spread);
    }
    w.put_array(centre);
    w.put_array(spread);
    w.put_array(count);
    w.put_array(roughness);
    w.put_array(lateral);
    w.put_array(lateral_spread);
    return w.take();
}

Reference Reference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion)
        throw Error("m3c2 reference payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    CylinderParameters parameters;
    parameters.radius = in.get<double>();
    parameters.max_depth = in.get<double>();
    const auto statistic = in.get<std::uint32_t>();
    if (statistic > 1) throw Error("m3c2 reference payload: unknown statistic");
    parameters.statistic = statistic == 1 ? CylinderStatistic::median : CylinderStatistic::mean;
    parameters.stray_distance = in.get<double>();
    const auto n = in.get<std::uint64_t>();
    auto centres = unflatten(in.get_array<double>(), n);
    auto axes = unflatten(in.get_array<double>(), n);
    Reference r;
    r.normal_radius = in.get_array<double>();
    const auto centre = in.get_array<double>();
    const auto spread = in.get_array<double>();
    const auto count = in.get_array<std::uint32_t>();
    const auto roughness = in.get_array<double>();
    const auto lateral = in.get_array<double>();
    const auto lateral_spread = in.get_array<double>();
    in.finish();
    if (r.normal_radius.size() != n || centre.size() != n || spread.size() != n ||
        count.size() != n || roughness.size() != n || lateral.size() != 3 * n ||
        lateral_spread.size() != n)
        throw Error("m3c2 reference payload: arrays of different lengths");
    r.reference_side.resize(n);
    for (std::size_t k = 0; k < n; ++k)
        r.reference_side[k] = {centre[k],
                               spread[k],
                               count[k],
                               roughness[k],
                               {lateral[3 * k], lateral[3 * k + 1], lateral[3 * k + 2]},
                               lateral_spread[k]};
    try {
        validate(parameters);
    } catch (const Error& e) {
        throw Error(std::string("m3c2 reference payload: ") + e.what());
    }
    r.cylinders = make_cylinders(std::move(centres), std::move(axes), parameters);
    return r;
}

}  // namespace tlsmon::m3c2
