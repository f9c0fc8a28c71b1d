#include "demo/site_config_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "config/keys.hpp"
#include "simulator/stable_ground.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon {

namespace {

// Rounded to the centimetre: what a site sketch or a hand-held GNSS gives.
std::string approximate(const Eigen::Vector3d& p) {
    const auto cm = [](double v) { return std::round(100.0 * v) / 100.0; };
    return fmt::format("[{:.2f}, {:.2f}, {:.2f}]", cm(p.x()), cm(p.y()), cm(p.z()));
}

// [x, y, z] as TOML numbers.
std::string vec(const Eigen::Vector3d& v) {
    return fmt::format("[{}, {}, {}]", toml_number(v.x()), toml_number(v.y()), toml_number(v.z()));
}

}  // namespace

std::string site_configuration(const sim::Site& site) {
    const auto& s = site.scanner;
    std::string out = fmt::format(
        "# Site configuration written by `tlsmon simulate` for station '{}'.\n"
        "# Scanner at [{:.3f}, {:.3f}, {:.3f}] (project frame), heading {}°.\n"
        "# Targets: approximate positions (cm); their centres are measured in the reference "
        "epoch.\n\n[station]\nname = {}\n",
        s.station, s.position.x(), s.position.y(), s.position.z(), s.heading_deg,
        toml_string(s.station));
    for (const auto& t : site.targets) {
        out += "\n[[target]]\nname = " + toml_string(t.name) + "\n";
        if (t.kind == sim::Target::Kind::sphere) {
            out += fmt::format("kind = \"sphere\"\nradius = {}\n", toml_number(t.radius));
            // Masts, stands and the short masts on blocks all hold it from below.
            if (t.mount == sim::Target::Mount::none) out += "mount = \"none\"\n";
        } else {
            out += fmt::format("kind = \"checkerboard\"\nsize = {}\n", toml_number(t.size));
        }
        out += "approximate = " + approximate(t.centre) + "\n";
    }
    const auto& p = site.pier;
    if (p.round()) {
        // A round pier: one zone around the column from above its foundation to below the
        // deck, 0.3 m beyond its surface, holding a cylinder (docs/primitives.md).
        const double half = 0.5 * p.diameter + 0.3;
        const Eigen::Vector2d c = p.centre();
        out += fmt::format(
            "\n[[zone]]\nname = \"pier_column\"\nmin = [{}, {}, 1]\nmax = [{}, {}, {}]\n"
            "primitive = \"cylinder\"\n",
            toml_number(c.x() - half), toml_number(c.y() - half), toml_number(c.x() + half),
            toml_number(c.y() + half), toml_number(p.height - 0.5));
    } else {
        // The pier's south face (seen head-on) and west face (grazing), 0.5 m either side,
        // with their design normals. The west face's box starts 0.5 m behind the corner, so
        // that the boxes meet without overlapping (zones with different normals may not).
        out += fmt::format(
            "\n[[zone]]\nname = \"pier_south_face\"\nmin = [{}, {}, 0]\nmax = [{}, {}, {}]\n"
            "normal = [0, -1, 0]\n",
            toml_number(p.x0), toml_number(p.y0 - 0.5), toml_number(p.x1), toml_number(p.y0 + 0.5),
            toml_number(p.height));
        out += fmt::format(
            "\n[[zone]]\nname = \"pier_west_face\"\nmin = [{}, {}, 0]\nmax = [{}, {}, {}]\n"
            "normal = [-1, 0, 0]\n",
            toml_number(p.x0 - 0.5), toml_number(p.y0 + 0.5), toml_number(p.x0 + 0.5),
            toml_number(p.y1), toml_number(p.height));
    }
    // Patch-based M3C2 beside M3C2 on the same zones (docs/pbm3c2.md).
    out += "\n[pbm3c2]\nenabled = true\n";
    // Stable ground for the ICP (registration.icp): the foundation and the ground around the
    // pier's foot, the abutments; never the pier.
    for (const auto& b : sim::stable_ground(site)) {
        out += "\n[[stable_region]]\nname = " + toml_string(b.name) + "\nmin = " + vec(b.min) +
               "\nmax = " + vec(b.max) + "\n";
    }
    return out;
}

std::string abutment_check_zone(const sim::Site& site) {
    constexpr double inset = 0.6, half_depth = 0.3;
    for (const sim::Block& b : site.terrain.blocks) {
        if (b.kind != sim::Block::Kind::abutment || b.yaw_deg != 0.0 || b.motion.from_epoch >= 0)
            continue;
        // Its four vertical faces (axis k, side ±1); the one whose outward normal points most
        // towards the scanner.
        int axis = 0;
        double side = -1, best = -2;
        for (int k = 0; k < 2; ++k) {
            for (const double s : {-1.0, 1.0}) {
                Eigen::Vector3d centre = b.centre();
                centre(k) = s < 0 ? b.lo(k) : b.hi(k);
                const double facing = s * (site.scanner.position - centre).normalized()(k);
                if (facing > best) std::tie(axis, side, best) = std::tuple(k, s, facing);
            }
        }
        const int along = 1 - axis;
        const double plane = side < 0 ? b.lo(axis) : b.hi(axis);
        const double foot = std::max(b.lo.z(), sim::terrain_height(site.terrain, b.centre().y()));
        Eigen::Vector3d lo, hi, normal = Eigen::Vector3d::Zero();
        lo(axis) = plane - half_depth;
        hi(axis) = plane + half_depth;
        lo(along) = b.lo(along) + inset;
        hi(along) = b.hi(along) - inset;
        lo.z() = foot + inset;
        hi.z() = b.hi.z() - inset;
        normal(axis) = side;
        if (!(lo.array() < hi.array()).all()) continue;
        return "\n# A check zone: the face of the abutment " + toml_string(b.name) +
               ", which does not move; its values are scored against zero.\n[[zone]]\nname = " +
               toml_string("check_" + b.name) + "\nmin = " + vec(lo) + "\nmax = " + vec(hi) +
               "\nnormal = " + vec(normal) + "\nno_change = true\n";
    }
    return "";
}

}  // namespace tlsmon
