#include "demo/site_config_writer.hpp"

#include <fmt/format.h>

#include <cmath>

#include "config/keys.hpp"
#include "simulator/stable_ground.hpp"

namespace tlsmon {

namespace {

// Rounded to the centimetre: what a site sketch or a hand-held GNSS gives.
std::string approximate(const Eigen::Vector3d& p) {
    const auto cm = [](double v) { return std::round(100.0 * v) / 100.0; };
    return fmt::format("[{:.2f}, {:.2f}, {:.2f}]", cm(p.x()), cm(p.y()), cm(p.z()));
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
        } else {
            out += fmt::format("kind = \"checkerboard\"\nsize = {}\n", toml_number(t.size));
        }
        out += "approximate = " + approximate(t.centre) + "\n";
    }
    // The pier's south face (seen head-on) and west face (grazing), 0.5 m either side, with
    // their design normals. The west face's box starts 0.5 m behind the corner, so that the
    // boxes meet without overlapping (zones with different normals may not).
    const auto& p = site.pier;
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
    // Stable ground for the ICP (registration.icp): the foundation and the ground around the
    // pier's foot, the abutments; never the pier.
    const auto vec = [](const Eigen::Vector3d& v) {
        return fmt::format("[{}, {}, {}]", toml_number(v.x()), toml_number(v.y()),
                           toml_number(v.z()));
    };
    for (const auto& b : sim::stable_ground(site)) {
        out += "\n[[stable_region]]\nname = " + toml_string(b.name) + "\nmin = " + vec(b.min) +
               "\nmax = " + vec(b.max) + "\n";
    }
    return out;
}

}  // namespace tlsmon
