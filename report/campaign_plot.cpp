#include "report/campaign_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "report/gnuplot.hpp"

namespace tlsmon::report {

namespace fs = std::filesystem;

namespace {

// One view's rows: "a b da_mm db_mm" of the segments whose arrow is drawn, and "a b" of those
// observing neither direction.
struct View {
    std::string moved = "# a_m b_m da_mm db_mm\n", apart = moved, unobserved = "# a_m b_m\n";
    std::vector<double> lengths;
};

void add(View& view, const campaign::SegmentTransform& t, int a, int b, bool set_apart) {
    const bool ha = t.translation_observed(a), hb = t.translation_observed(b);
    if (!ha && !hb) {
        view.unobserved += fmt::format("{:.3f} {:.3f}\n", t.centroid(a), t.centroid(b));
        return;
    }
    const double da = ha ? 1e3 * t.parameters(3 + a) : 0, db = hb ? 1e3 * t.parameters(3 + b) : 0;
    (set_apart ? view.apart : view.moved) +=
        fmt::format("{:.3f} {:.3f} {:.4f} {:.4f}\n", t.centroid(a), t.centroid(b), da, db);
    view.lengths.push_back(std::hypot(da, db));
}

}  // namespace

std::optional<std::string> draw_segment_parameters(const CampaignComparison& c, double alpha,
                                                   const fs::path& work, const fs::path& png) {
    fs::create_directories(work);
    View plan, elevation;
    for (std::size_t s = 0; s < c.segments.size(); ++s) {
        const auto& t = c.segments[s].transform;
        if (!t.registered()) continue;
        const double p = c.consistency.segment_p_value[s];
        const bool set_apart = std::isfinite(p) && p < alpha;
        add(plan, t, 0, 1, set_apart);
        add(elevation, t, 0, 2, set_apart);
    }
    // The points, thinned to about 20 000, for orientation.
    std::string points = "# x_m y_m z_m\n";
    const std::size_t step = std::max<std::size_t>(1, c.registered.size() / 20000);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (std::size_t i = 0; i < c.registered.size(); i += step) {
        const auto& x = c.registered[i];
        points += fmt::format("{:.3f} {:.3f} {:.3f}\n", x.x(), x.y(), x.z());
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    write_text(work / "points.dat", points);
    write_text(work / "plan_moved.dat", plan.moved);
    write_text(work / "plan_apart.dat", plan.apart);
    write_text(work / "plan_unobserved.dat", plan.unobserved);
    write_text(work / "elevation_moved.dat", elevation.moved);
    write_text(work / "elevation_apart.dat", elevation.apart);
    write_text(work / "elevation_unobserved.dat", elevation.unobserved);

    // Metres drawn per millimetre: the largest arrow as 12 % of the scene's extent.
    std::vector<double> lengths = plan.lengths;
    lengths.insert(lengths.end(), elevation.lengths.begin(), elevation.lengths.end());
    const double largest =
        lengths.empty() ? 1.0 : *std::max_element(lengths.begin(), lengths.end());
    const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), 0.5});
    const double k = 0.12 * extent / std::max(largest, 0.1);
    const auto view = [&](const std::string& name, int a_column, int b_column,
                          const std::string& xlabel, const std::string& ylabel,
                          const std::string& title) {
        const auto arrows = [&](const std::string& file, const char* colour,
                                const std::string& label) {
            return fmt::format(
                "'{}_{}.dat' using 1:2:($3*{:.6g}):($4*{:.6g}) with vectors head filled size "
                "screen 0.008,25 lw 2 lc rgb '{}' title {}",
                name, file, k, k, colour, gnuplot_quoted(label));
        };
        return fmt::format(
            "set xlabel {}\nset ylabel {}\nset title {}\n"
            "plot 'points.dat' using {}:{} with dots lc rgb '#c8c8c8' notitle, {}, {}, "
            "'{}_unobserved.dat' using 1:2 with points pt 2 ps 1.5 lc rgb '#555555' "
            "title 'neither direction observed'\n",
            gnuplot_quoted(xlabel), gnuplot_quoted(ylabel), gnuplot_quoted(title), a_column,
            b_column, arrows("moved", "#0b3d91", "segment's translation"),
            arrows("apart", "#c0392b", fmt::format("differs from the others (p < {:g})", alpha)),
            name);
    };
    const std::string scale = fmt::format("1 mm drawn as {:.2g} m", k);
    const std::string gp =
        "set terminal pngcairo size 1000,1100 font 'DejaVu Sans,10' noenhanced\n" +
        fmt::format("set output '{}'\n", fs::absolute(png).string()) +
        "set grid lc rgb '#e4e4e4'\nset key below\nset size ratio -1\n"
        "set multiplot layout 2,1\n" +
        view("plan", 1, 2, "x (m); " + scale, "y (m)",
             fmt::format("plan: {} segments registered, segments moved as one: {}",
                         c.consistency.segments,
                         c.consistency.dof == 0 ? "not testable"
                         : c.consistency.differ ? "no"
                                                : "yes")) +
        view("elevation", 1, 3, "x (m); " + scale, "z (m)", "elevation") + "unset multiplot\n";
    const fs::path script = work / "segments.gp";
    write_text(script, gp);
    if (!run_gnuplot(script, png, work / "segments.log"))
        return "not drawn: see " + (work / "segments.log").string();
    return std::nullopt;
}

}  // namespace tlsmon::report
