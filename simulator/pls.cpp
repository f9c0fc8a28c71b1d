#include "simulator/pls.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "simulator/random.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon::sim {

namespace {

constexpr std::size_t kBlock = 4096;  // pulses per generator: fixed, so threads do not matter
constexpr std::uint64_t kPulseStream = 0x706c73ULL;
constexpr std::uint64_t kDriftStream = 0x736c616dULL;

Eigen::Matrix3d rotation_matrix(const Eigen::Vector3d& w) {
    const double angle = w.norm();
    if (angle == 0) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

}  // namespace

const char* drift_model_name(SlamDriftModel model) {
    switch (model) {
        case SlamDriftModel::none:
            return "none";
        case SlamDriftModel::linear:
            return "linear";
        case SlamDriftModel::random_walk:
            return "random-walk";
    }
    return "?";
}

SlamDriftModel drift_model(const std::string& name) {
    for (const auto m : {SlamDriftModel::none, SlamDriftModel::linear, SlamDriftModel::random_walk})
        if (name == drift_model_name(m)) return m;
    throw Error("unknown SLAM drift model '" + name + "' (none, linear, random-walk)");
}

Eigen::Vector3d SlamPoseError::apply(const Eigen::Vector3d& sensor,
                                     const Eigen::Vector3d& p) const {
    return sensor + translation + rotation_matrix(rotation) * (p - sensor);
}

SlamDriftPath::SlamDriftPath(const SlamDrift& drift, double duration)
    : drift_(drift), duration_(duration) {
    if (drift.model != SlamDriftModel::random_walk) return;
    const auto n = static_cast<std::size_t>(std::ceil(duration / drift.knot_seconds)) + 1;
    Rng rng(hash_combine(drift.seed, kDriftStream));
    const double st = drift.translation_density * std::sqrt(drift.knot_seconds);
    const double sr = drift.rotation_density_mrad * 1e-3 * std::sqrt(drift.knot_seconds);
    knots_.resize(n);  // the walk starts with no error: the SLAM's origin
    for (std::size_t k = 1; k < n; ++k) {
        knots_[k] = knots_[k - 1];
        for (int a = 0; a < 3; ++a) {
            knots_[k].translation[a] += st * rng.normal();
            knots_[k].rotation[a] += sr * rng.normal();
        }
    }
}

SlamPoseError SlamDriftPath::at(double t) const {
    t = std::clamp(t, 0.0, duration_);
    switch (drift_.model) {
        case SlamDriftModel::none:
            return {};
        case SlamDriftModel::linear: {
            const double f = duration_ > 0 ? t / duration_ : 0.0;
            return {f * 1e-3 * drift_.end_rotation_mrad, f * drift_.end_translation};
        }
        case SlamDriftModel::random_walk: {
            const double u = t / drift_.knot_seconds;
            const auto k = std::min(static_cast<std::size_t>(u), knots_.size() - 2);
            const double f = u - double(k);
            return {(1 - f) * knots_[k].rotation + f * knots_[k + 1].rotation,
                    (1 - f) * knots_[k].translation + f * knots_[k + 1].translation};
        }
    }
    return {};
}

double walk_duration(const PlsTrajectory& trajectory) {
    double length = 0;
    for (std::size_t i = 1; i < trajectory.waypoints.size(); ++i)
        length += (trajectory.waypoints[i] - trajectory.waypoints[i - 1]).norm();
    return length / trajectory.speed;
}

Eigen::Vector3d sensor_position(const PlsTrajectory& trajectory, double t) {
    const auto& w = trajectory.waypoints;
    double remaining = std::max(0.0, t) * trajectory.speed;
    for (std::size_t i = 1; i < w.size(); ++i) {
        const double leg = (w[i] - w[i - 1]).norm();
        if (remaining <= leg && leg > 0) return w[i - 1] + (remaining / leg) * (w[i] - w[i - 1]);
        remaining -= leg;
    }
    return w.back();
}

std::vector<Eigen::Vector3d> noise_free_points(const PlsCampaign& c, const PlsCloud& cloud) {
    const SlamDriftPath drift(c.drift, cloud.duration);
    std::vector<Eigen::Vector3d> out(cloud.truth.size());
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = drift.at(cloud.time[i])
                     .apply(sensor_position(c.trajectory, cloud.time[i]), cloud.truth[i]);
    return out;
}

Eigen::Matrix4d slam_frame(const PlsTrajectory& trajectory, double heading) {
    const auto& w = trajectory.waypoints;
    double leg_heading = 0;
    for (std::size_t i = 1; i < w.size(); ++i) {
        const Eigen::Vector3d leg = w[i] - w[0];
        if (leg.head<2>().norm() > 1e-6) {
            leg_heading = std::atan2(leg.y(), leg.x());
            break;
        }
    }
    const Eigen::Vector2d x(std::cos(leg_heading + heading), std::sin(leg_heading + heading));
    Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
    F.block<3, 1>(0, 0) << x.x(), x.y(), 0;
    F.block<3, 1>(0, 1) << -x.y(), x.x(), 0;
    if (!w.empty()) F.block<3, 1>(0, 3) = w.front();
    return F;
}

PlsTrajectory walk_around_pier(const Site& site) {
    const Pier& p = site.pier;
    const double x0 = p.x0 - 8.0, x1 = p.x1 + 4.0, y0 = p.y0 - 6.0, y1 = p.y1 + 6.0;
    PlsTrajectory t;
    for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}})
        t.waypoints.emplace_back(x, y, terrain_height(site.terrain, y) + 1.5);
    return t;
}

void validate(const PlsCampaign& c) {
    if (c.trajectory.waypoints.size() < 2) throw Error("PLS: the walk needs two waypoints");
    if (!(c.trajectory.speed > 0)) throw Error("PLS: the walking speed must be positive");
    if (!(walk_duration(c.trajectory) > 0)) throw Error("PLS: the walk has no length");
    const PlsScanner& s = c.scanner;
    if (!(s.pulse_rate > 0)) throw Error("PLS: the pulse rate must be positive");
    if (!(s.min_range >= 0 && s.max_range > s.min_range))
        throw Error("PLS: max_range must exceed min_range >= 0");
    if (!(s.range_sigma >= 0)) throw Error("PLS: range_sigma must not be negative");
    if (!(s.blind_cone_deg >= 0 && s.blind_cone_deg < 90))
        throw Error("PLS: blind_cone_deg must lie in [0, 90)");
    if (c.drift.model == SlamDriftModel::random_walk && !(c.drift.knot_seconds > 0))
        throw Error("PLS: the drift's knot_seconds must be positive");
}

PlsCloud render_pls(const Site& site, int epoch, const PlsCampaign& c, unsigned threads) {
    validate(c);
    const SceneAtEpoch scene(site, epoch, 0.0);
    const double duration = walk_duration(c.trajectory);
    const SlamDriftPath drift(c.drift, duration);
    const PlsScanner& sc = c.scanner;
    const auto pulses = static_cast<std::size_t>(std::ceil(duration * sc.pulse_rate));
    const std::size_t blocks = (pulses + kBlock - 1) / kBlock;
    const double down = -std::cos(sc.blind_cone_deg * std::numbers::pi / 180.0);
    std::vector<PlsCloud> parts(blocks);
    parallel_for(
        blocks,
        [&](std::size_t b) {
            Rng rng(hash_combine(hash_combine(sc.seed, kPulseStream), b));
            PlsCloud& out = parts[b];
            for (std::size_t k = b * kBlock; k < std::min(pulses, (b + 1) * kBlock); ++k) {
                const double t = (double(k) + 0.5) / sc.pulse_rate;
                const double z = 2.0 * rng.uniform() - 1.0,
                             phi = 2.0 * std::numbers::pi * rng.uniform();
                const double e_r = rng.normal();
                if (z < down) continue;
                const double h = std::sqrt(1.0 - z * z);
                const Eigen::Vector3d d(h * std::cos(phi), h * std::sin(phi), z);
                const Eigen::Vector3d s = sensor_position(c.trajectory, t);
                const Hit hit = cast_ray(scene, s, d, sc.max_range);
                if (hit.surface == Surface::none || hit.range < sc.min_range) continue;
                const double signal = hit.albedo * std::abs(d.dot(hit.normal));
                if (signal < sc.min_return) continue;
                const double measured = hit.range + sc.range_sigma * e_r;
                out.points.push_back(drift.at(t).apply(s, s + measured * d));
                out.truth.push_back(s + hit.range * d);
                out.normal.push_back(hit.normal.cast<float>());
                out.time.push_back(static_cast<float>(t));
                out.intensity.push_back(static_cast<float>(std::clamp(
                    signal * std::exp(-hit.range / site.texture.range_attenuation), 0.0, 1.0)));
                out.surface.push_back(static_cast<std::uint8_t>(hit.surface));
            }
        },
        threads);
    PlsCloud cloud;
    cloud.duration = duration;
    std::size_t total = 0;
    for (const auto& p : parts) total += p.points.size();
    cloud.points.reserve(total);
    cloud.truth.reserve(total);
    cloud.normal.reserve(total);
    cloud.time.reserve(total);
    cloud.intensity.reserve(total);
    cloud.surface.reserve(total);
    for (auto& p : parts) {
        cloud.points.insert(cloud.points.end(), p.points.begin(), p.points.end());
        cloud.truth.insert(cloud.truth.end(), p.truth.begin(), p.truth.end());
        cloud.normal.insert(cloud.normal.end(), p.normal.begin(), p.normal.end());
        cloud.time.insert(cloud.time.end(), p.time.begin(), p.time.end());
        cloud.intensity.insert(cloud.intensity.end(), p.intensity.begin(), p.intensity.end());
        cloud.surface.insert(cloud.surface.end(), p.surface.begin(), p.surface.end());
        p = {};
    }
    return cloud;
}

}  // namespace tlsmon::sim
