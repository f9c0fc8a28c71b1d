// The report's figure of the 3-D vectors (docs/vectors.md): for the newest epoch that has
// them, per zone, every measured area's vector along the wall as an arrow from the area's
// centre (dark blue beyond its LoD95 along the wall, grey within), and in a scored run the
// truth's change since the reference at the same centre as a thin orange arrow. Wall frame
// as on the dashboard's map: u = up × n horizontal along the wall, v up, n the zone's pier
// face's outward normal (scored) or else the box's thinner horizontal side. Drawn by gnuplot
// like the other plots (report/plots.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/utc_time.hpp"
#include "pipeline/stored_area_vectors.hpp"
#include "report/data.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon::report {

namespace {

namespace fs = std::filesystem;

const TruthEpoch* truth_epoch(const std::vector<TruthEpoch>& truth, std::optional<int> epoch) {
    for (const auto& t : truth)
        if (epoch && t.epoch == *epoch && !t.missing) return &t;
    return nullptr;
}

// The 95th percentile of the lengths (for the arrows' scale).
double percentile95(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(0.95 * double(v.size() - 1))];
}

}  // namespace

void draw_area_vectors(const RunReport& r, const fs::path& dir, ReportFiles& files) {
    const auto db = EpochDatabase::open(r.database, EpochDatabase::Mode::read_only);
    // The newest registered epoch with vectors.
    const RegistrationCheck* epoch = nullptr;
    std::vector<StoredAreaVector> areas;
    for (auto it = r.registration.rbegin(); it != r.registration.rend() && areas.empty(); ++it) {
        if (it->is_reference || !it->registered) continue;
        areas = read_area_vectors(db, it->id);
        epoch = &*it;
    }
    if (areas.empty()) return;
    std::vector<TruthEpoch> truth;
    if (r.scored && !r.truth_folder.empty()) truth = read_truth_folder(r.truth_folder);
    const TruthEpoch* now = truth_epoch(truth, epoch->truth_epoch);
    const TruthEpoch* reference = truth_epoch(truth, r.reference_truth_epoch);
    std::map<std::string, std::optional<ZoneBox>> boxes;
    for (const auto& [name, definition] : db.site().zones())
        boxes[name] = parse_zone_box(definition);

    for (const ZoneCheck& z : r.zones) {
        const auto& box = boxes[z.zone];
        if (!box) continue;
        Eigen::Vector3d n = z.face ? z.face->normal : Eigen::Vector3d::Zero();
        if (!z.face) {
            const Eigen::Vector3d size = box->max - box->min;
            n = size.x() < size.y() ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
        }
        const Eigen::Vector3d v = Eigen::Vector3d::UnitZ(), u = v.cross(n).normalized();
        const bool with_truth = now && reference && z.face;
        std::string beyond = "# u_m v_m du_mm dv_mm\n", within = beyond, truth_rows = beyond;
        std::vector<double> lengths;
        double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
        int count = 0, significant = 0;
        for (const StoredAreaVector& a : areas) {
            if (!box->contains(a.centre)) continue;
            const Eigen::Vector3d &p = a.centre, &d = a.displacement;
            const double lod_u = a.lod95_along(u), lod_v = a.lod95_along(v);
            const bool beyond_lod = std::abs(u.dot(d)) > lod_u || std::abs(v.dot(d)) > lod_v;
            const std::string row = fmt::format("{:.4f} {:.4f} {:.5f} {:.5f}\n", u.dot(p), v.dot(p),
                                                1e3 * u.dot(d), 1e3 * v.dot(d));
            (beyond_lod ? beyond : within) += row;
            significant += beyond_lod;
            ++count;
            lengths.push_back(1e3 * std::hypot(u.dot(d), v.dot(d)));
            if (with_truth) {
                const Eigen::Vector3d t =
                    true_displacement(*now, p) - true_displacement(*reference, p);
                truth_rows += fmt::format("{:.4f} {:.4f} {:.5f} {:.5f}\n", u.dot(p), v.dot(p),
                                          1e3 * u.dot(t), 1e3 * v.dot(t));
                lengths.push_back(1e3 * std::hypot(u.dot(t), v.dot(t)));
            }
            u0 = std::min(u0, u.dot(p)), u1 = std::max(u1, u.dot(p));
            v0 = std::min(v0, v.dot(p)), v1 = std::max(v1, v.dot(p));
        }
        if (count == 0) continue;
        // Metres drawn per millimetre: the 95th percentile of the lengths as 6 % of the extent.
        const double extent = std::max({u1 - u0, v1 - v0, 0.5});
        const double k = 0.06 * extent / std::max(percentile95(lengths), 1e-3);
        const std::string base = "vectors_" + safe_name(z.zone);
        write_text(dir / (base + "_beyond.dat"), beyond);
        write_text(dir / (base + "_within.dat"), within);
        write_text(dir / (base + "_truth.dat"), truth_rows);
        const fs::path png = dir.parent_path() / (base + ".png");
        const auto arrows = [&](const std::string& file, const char* colour, double width,
                                const std::string& title) {
            return fmt::format(
                "'{}' using 1:2:($3*{:.6g}):($4*{:.6g}) with vectors head filled size "
                "screen 0.006,25 lw {} lc rgb '{}' title {}",
                file, k, k, width, colour, gnuplot_quoted(title));
        };
        const std::string scale = fmt::format("1 mm drawn as {:.2g} m", k);
        std::string plot =
            arrows(base + "_beyond.dat", "#0b3d91", 1.6, "measured, beyond its LoD95") + ", " +
            arrows(base + "_within.dat", "#8a8a8a", 1.2, "measured, within its LoD95");
        if (with_truth) plot += ", " + arrows(base + "_truth.dat", "#e07b00", 0.8, "truth");
        // Whole-metre tics along a narrow wall, so their labels do not run into each other.
        const double tic = std::max(1.0, std::round((u1 - u0) / 4.0));
        const double height = std::clamp((v1 - v0) / std::max(u1 - u0, 0.5), 0.6, 2.2);
        const std::string gp = fmt::format(
            "set terminal pngcairo size 900,{} font 'DejaVu Sans,10' noenhanced\n"
            "set output '{}'\nset grid lc rgb '#dddddd'\nset size ratio -1\n"
            "set key below\nset xtics {:g}\n"
            "set offsets graph 0.08, graph 0.08, graph 0.05, graph 0.05\n"
            "set xlabel {}\nset ylabel 'up, v (m)'\nset title {}\nplot {}\n",
            static_cast<int>(300 + 520 * height), fs::absolute(png).string(), tic,
            gnuplot_quoted("along the wall, u (m); each area's vector along the wall from its "
                           "centre, " +
                           scale),
            gnuplot_quoted(fmt::format("{}, epoch {}: {} areas, {} beyond their LoD95", z.zone,
                                       epoch->id, count, significant)),
            plot);
        const fs::path script = dir / (base + ".gp");
        write_text(script, gp);
        if (!run_gnuplot(script, png, dir / (base + ".log"))) {
            files.notes.push_back(png.filename().string() + " not drawn: see " +
                                  (dir / (base + ".log")).string());
            continue;
        }
        files.plots.push_back(png);
    }
}

}  // namespace tlsmon::report
