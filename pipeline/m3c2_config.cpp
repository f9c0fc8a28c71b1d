#include "pipeline/m3c2_config.hpp"

#include <array>

namespace tlsmon {

namespace {

constexpr std::array<Named<m3c2::CylinderStatistic>, 2> kM3c2Statistics{{
    {m3c2::CylinderStatistic::mean, "mean"},
    {m3c2::CylinderStatistic::median, "median"},
}};

// [m3c2] normal_radii: lengths in metres, at least one.
SectionKey<M3c2Config> m3c2_radii() {
    SectionKey<M3c2Config> k{
        "normal_radii",
        "array of numbers",
        "1 to 10 radii, each 0.001 .. 100 m",
        "The normal scales D/2 of Lague 2013, as radii: at each core point the "
        "normal is taken at the radius where the reference is most planar "
        "(docs/m3c2.md).",
        {},
        {}};
    k.read = [](TomlFields& t, M3c2Config& c) {
        std::vector<double> v = c.normal_radii;
        t.get("normal_radii", v);
        if (v.empty() || v.size() > 10) t.fail("normal_radii", "expected 1 to 10 radii");
        for (double r : v) {
            if (!(r >= 0.001 && r <= 100)) {
                t.fail("normal_radii", "radius " + toml_number(r) + " is outside 0.001 .. 100 m");
            }
        }
        c.normal_radii = v;
    };
    k.value = [](const M3c2Config& c) {
        std::string out = "[";
        for (double r : c.normal_radii) out += (out.size() > 1 ? ", " : "") + toml_number(r);
        return out + "]";
    };
    return k;
}

// [m3c2] orientation: "scanner" or [x, y, z].
SectionKey<M3c2Config> m3c2_orientation() {
    SectionKey<M3c2Config> k{
        "orientation",
        "string or array of 3 numbers",
        "`\"scanner\"` or a non-zero `[x, y, z]`",
        "Which way the normals point, and so the sign of a distance: `scanner` = "
        "towards the reference scan's position (positive = towards the scanner); "
        "a vector v = the side with n · v ≥ 0 (e.g. `[0, 0, 1]`: up).",
        {},
        {}};
    k.read = [](TomlFields& t, M3c2Config& c) {
        if (!t.has("orientation")) {
            std::string ignored;
            t.get("orientation", ignored);  // absent: the default stands, the key is known
            return;
        }
        if (t.is_array("orientation")) {
            std::vector<double> v;
            t.get("orientation", v);
            if (v.size() != 3) t.fail("orientation", "expected \"scanner\" or [x, y, z]");
            c.orient_to_scanner = false;
            c.orientation = Eigen::Vector3d(v[0], v[1], v[2]);
            return;
        }
        std::string text;
        t.get("orientation", text);
        if (text != "scanner") t.fail("orientation", "expected \"scanner\" or [x, y, z]");
        c.orient_to_scanner = true;
    };
    k.value = [](const M3c2Config& c) {
        if (c.orient_to_scanner) return std::string("\"scanner\"");
        const auto& v = c.orientation;
        return "[" + toml_number(v.x()) + ", " + toml_number(v.y()) + ", " + toml_number(v.z()) +
               "]";
    };
    return k;
}

}  // namespace

std::vector<SectionKey<M3c2Config>> m3c2_keys() {
    using K = Keys<M3c2Config>;
    return {
        K::flag(&M3c2Config::enabled, "enabled",
                "Run M3C2 (docs/m3c2.md) for every epoch against the reference epoch, at core "
                "points inside the zones; without any `[[zone]]` it does not run."),
        K::number(&M3c2Config::core_spacing, "core_spacing", 0.001, 100, "m",
                  "Core points: the reference's points inside the zones, one per cube of this edge "
                  "(the one nearest the cube's centre; none within half of it of another). Taken "
                  "once, with the reference epoch."),
        m3c2_radii(),
        K::number(&M3c2Config::cylinder_radius, "cylinder_radius", 0.001, 100, "m",
                  "Radius of the projection cylinder (d/2 of Lague 2013)."),
        K::number(&M3c2Config::max_depth, "max_depth", 0.001, 100, "m",
                  "Half-length of the cylinder along the normal: the largest change measured."),
        K::integer(&M3c2Config::min_points, "min_points", 2, 1000000, "",
                   "Points each cloud needs in a cylinder; fewer: no distance at that core point "
                   "(NaN, not counted in the zone's values)."),
        m3c2_orientation(),
        K::choice(&M3c2Config::statistic, "statistic", kM3c2Statistics,
                  "Per cylinder: `mean` with the standard deviation, or `median` with the "
                  "interquartile range as the spread (robust to stray points)."),
        K::number(&M3c2Config::max_roughness, "max_roughness", 0.0001, 100, "m",
                  "A core point whose reference cylinder spreads more than this along the normal "
                  "(the roughness σ1 of Lague 2013, of all its points, strays included; the IQR "
                  "with `median`) holds an edge or a corner: no distance there (NaN, not "
                  "counted in the zone's values)."),
        K::number(&M3c2Config::stray_distance, "stray_distance", 0.0001, 100, "m",
                  "With `mean`: a cylinder's points farther than this from the median of its "
                  "projections, and than 3.5 robust σ (1.4826·MAD) of them, are strays — the "
                  "next face round a corner, mixed returns behind an edge — and are left out of "
                  "the mean and its spread. Twice `max_depth` or more keeps the method as "
                  "published (CloudCompare, py4dgeo)."),
        K::number(&M3c2Config::registration_error, "registration_error", 0, 1, "m",
                  "The LoD's registration term (reg of Lague 2013, eq. 1) when there is no "
                  "registration (no `[[target]]`). With a registration it is not used: each core "
                  "point gets the registration's σ along its normal."),
        K::integer(&M3c2Config::threads, "threads", 0, 256, "",
                   "Threads of the stage; 0: every core."),
    };
}

}  // namespace tlsmon
