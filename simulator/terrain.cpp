#include "simulator/terrain.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "simulator/geometry.hpp"
#include "simulator/random.hpp"
#include "simulator/texture.hpp"

namespace tlsmon::sim {

double terrain_height(const Terrain& t, double y) {
    const auto& ys = t.profile_y;
    const auto& zs = t.profile_z;
    if (y <= ys.front()) return zs.front();
    if (y >= ys.back()) return zs.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(ys.begin(), ys.end(), y) -
                                                   ys.begin());  // ys[k-1] <= y < ys[k]
    const double f = (y - ys[k - 1]) / (ys[k] - ys[k - 1]);
    return zs[k - 1] + f * (zs[k] - zs[k - 1]);
}

double support_height(const Terrain& t, double x, double y, int* block) {
    double z = terrain_height(t, y);
    if (block) *block = -1;
    for (std::size_t i = 0; i < t.blocks.size(); ++i) {
        const Block& b = t.blocks[i];
        // (x, y) in the block's own axes (its yaw undone; its motion is millimetres).
        const double yaw = b.yaw_deg * 3.141592653589793 / 180.0;
        const Eigen::Vector2d r(x - b.centre().x(), y - b.centre().y());
        const Eigen::Vector2d q(std::cos(yaw) * r.x() + std::sin(yaw) * r.y(),
                                -std::sin(yaw) * r.x() + std::cos(yaw) * r.y());
        const Eigen::Vector3d half = 0.5 * (b.hi - b.lo);
        if (std::abs(q.x()) > half.x() || std::abs(q.y()) > half.y()) continue;
        if (b.hi.z() > z) {
            z = b.hi.z();
            if (block) *block = static_cast<int>(i);
        }
    }
    return z;
}

namespace {

// The ground's roughness at (x, y): within ±roughness along its normal (Terrain).
double roughness_height(const Terrain& t, double x, double y) {
    const std::uint64_t seed = hash_combine(0x726f756768ULL, 1);
    const double w = t.roughness_wavelength;
    return t.roughness * (2.0 * value_noise(seed, x / w, y / w) - 1.0);
}

// The ray's first hit on the rough ground about its hit t0 on the smooth piece of normal n:
// the surface raised by r(x, y) along n. The ray's height over the smooth piece is
// (t − t0)·(n·d), so f(t) = (t − t0)·(n·d) − r(o + t·d) is ≥ 0 where the ray enters the band
// |height| ≤ roughness and ≤ 0 where it leaves it; the hit is f's first crossing, marched in
// steps of a sixty-fourth of the wavelength and then bisected. A bump in front hides the ground
// behind it (a shadow), as on real rough ground seen at a grazing angle.
double roughened(const Terrain& t, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t0,
                 const Eigen::Vector3d& n) {
    const double nd = n.dot(d);
    if (nd > -1e-3) return t0;
    const auto f = [&](double tt) {
        const Eigen::Vector3d p = o + tt * d;
        return (tt - t0) * nd - roughness_height(t, p.x(), p.y());
    };
    const double t_in = t0 + t.roughness / nd, t_out = t0 - t.roughness / nd;
    const double step = t.roughness_wavelength / 64.0;
    double lo = std::max(t_in, 0.0), hi = lo;
    while (hi < t_out) {
        const double next = std::min(hi + step, t_out);
        if (f(next) <= 0.0) {
            hi = next;
            break;
        }
        lo = hi = next;
    }
    for (int k = 0; k < 40 && hi - lo > 1e-7; ++k) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) > 0.0 ? lo : hi) = mid;
    }
    return hi;
}

double intersect_profile(const Terrain& t, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                         double t_max, Eigen::Vector3d& normal) {
    const auto& ys = t.profile_y;
    const auto& zs = t.profile_z;
    const std::size_t n = ys.size();
    double best = kNoHit;
    // Piece k spans [ys[k−1], ys[k]] with slope m; piece 0 and piece n are the level ends.
    // On a piece h(y) = z_a + m (y − y_a), and z(t) − h(y(t)) = c0 + c1 t vanishes at
    // t = −c0 / c1, a crossing from above when c1 < 0.
    for (std::size_t k = 0; k <= n; ++k) {
        double y_lo, y_hi, y_a, z_a, m;
        if (k == 0) {
            y_lo = -kNoHit, y_hi = ys[0], y_a = ys[0], z_a = zs[0], m = 0.0;
        } else if (k == n) {
            y_lo = ys[n - 1], y_hi = kNoHit, y_a = ys[n - 1], z_a = zs[n - 1], m = 0.0;
        } else {
            y_lo = ys[k - 1], y_hi = ys[k], y_a = y_lo, z_a = zs[k - 1];
            m = (zs[k] - zs[k - 1]) / (y_hi - y_lo);
        }
        const double c1 = d.z() - m * d.y();
        if (c1 >= -1e-15) continue;
        const double c0 = o.z() - z_a - m * (o.y() - y_a);
        const double tt = -c0 / c1;
        if (!(tt > 0.0 && tt < best && tt < t_max)) continue;
        const double y = o.y() + tt * d.y();
        if (y < y_lo || y > y_hi) continue;
        best = tt;
        normal = Eigen::Vector3d(0.0, -m, 1.0).normalized();
    }
    if (best < kNoHit && t.roughness > 0.0) best = roughened(t, o, d, best, normal);
    return best;
}

}  // namespace

Eigen::Vector3d Creep::displacement(int epoch) const {
    if (from_epoch < 0 || epoch < from_epoch) return Eigen::Vector3d::Zero();
    return static_cast<double>(epoch - from_epoch + 1) * rate;
}

double intersect_terrain(const Terrain& t, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                         double t_max, Eigen::Vector3d& normal, const Eigen::Vector3d& creep,
                         Eigen::Vector3d* material) {
    double best = intersect_profile(t, o, d, t_max, normal);
    const bool creeping = t.creep.from_epoch >= 0 && creep != Eigen::Vector3d::Zero();
    if (creeping && best < kNoHit) {
        const Eigen::Vector3d p = o + best * d;
        if (t.creep.holds(p.x(), p.y())) best = kNoHit;  // that ground has moved away
    }
    if (material && best < kNoHit) *material = o + best * d;
    if (!creeping) return best;
    // The moved slab: the ray, moved back by the displacement, against the unmoved profile;
    // a hit whose unmoved point lies inside the circle.
    Eigen::Vector3d n;
    const double tc = intersect_profile(t, o - creep, d, std::min(best, t_max), n);
    if (tc < best) {
        const Eigen::Vector3d q = o - creep + tc * d;
        if (t.creep.holds(q.x(), q.y())) {
            best = tc;
            normal = n;
            if (material) *material = q;
        }
    }
    return best;
}

double terrain_albedo(const Texture& tex, const Terrain& t, double x, double y) {
    // Patches of grass (darker at 1.5 µm: leaf water absorbs), soil and gravel (brighter)
    // over metres, and clods and stones over decimetres.
    const std::uint64_t seed = hash_combine(tex.seed, 0x7465727261696eULL);
    const double patch = value_noise(seed, x / 6.0, y / 6.0) - 0.5;
    const double fine = value_noise(hash_combine(seed, 3), x / 0.25, y / 0.25) - 0.5;
    const double a = t.albedo * (1.0 + 0.9 * patch + 0.5 * fine);
    return std::clamp(a, 0.03, 1.0);
}

const char* kind_name(Block::Kind kind) {
    switch (kind) {
        case Block::Kind::foundation:
            return "foundation";
        case Block::Kind::abutment:
            return "abutment";
        case Block::Kind::wall:
            return "wall";
    }
    return "foundation";
}

Eigen::Isometry3d Block::displacement(int epoch) const {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    if (motion.from_epoch < 0 || epoch < motion.from_epoch) return m;
    constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);
    const Eigen::Vector3d r = kArcsec * motion.rotation_arcsec;
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const Eigen::Vector3d c = centre();
    m.linear() = R;
    m.translation() = c - R * c + motion.translation;  // about the centre, then shifted
    return m;
}

Eigen::Isometry3d Block::pose(int epoch) const {
    Eigen::Isometry3d own = Eigen::Isometry3d::Identity();
    own.linear() = Eigen::AngleAxisd(yaw_deg * 3.141592653589793 / 180.0, Eigen::Vector3d::UnitZ())
                       .toRotationMatrix();
    own.translation() = centre();
    return displacement(epoch) * own;
}

void validate_terrain(const Terrain& t) {
    if (t.profile_y.empty() || t.profile_y.size() != t.profile_z.size()) {
        throw Error("terrain: profile_y and profile_z need the same number (≥ 1) of values");
    }
    for (std::size_t k = 1; k < t.profile_y.size(); ++k) {
        if (!(t.profile_y[k] > t.profile_y[k - 1])) {
            throw Error("terrain: profile_y must increase");
        }
    }
    if (!(t.roughness >= 0.0) || !(t.roughness_wavelength > 0.0)) {
        throw Error("terrain: roughness must be >= 0 m and its wavelength > 0 m");
    }
    if (t.creep.from_epoch >= 0 && !(t.creep.radius > 0)) {
        throw Error("terrain: the creeping patch needs a radius > 0");
    }
    for (const Block& b : t.blocks) {
        if (!(b.hi.array() > b.lo.array()).all()) {
            throw Error("terrain: block '" + b.name + "' needs hi > lo on every axis");
        }
    }
}

}  // namespace tlsmon::sim
