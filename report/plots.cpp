// The report's plots, drawn by gnuplot (Debian `gnuplot-nox`, pngcairo terminal): the data
// and the script of each plot are written under plots/ so that anyone can redraw or change
// them, then `gnuplot` renders the PNG.
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "core/error.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"

namespace tlsmon::report {

namespace {

namespace fs = std::filesystem;

// Vertical dashed lines at the truth's events, at the database's epoch the truth's epoch is.
std::string event_marks(const RunReport& r) {
    std::string s;
    const auto at = [&](int truth_epoch) -> std::optional<EpochId> {
        const auto id = r.epoch_id.find(truth_epoch);
        return id == r.epoch_id.end() ? std::nullopt : std::optional<EpochId>(id->second);
    };
    if (r.knocked) {
        if (const auto x = at(r.knocked->since_epoch)) {
            s += fmt::format(
                "set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lc rgb '#aa5500'\n"
                "set label 'target {1} knocked' at {0},graph 0.95 offset 0.5,0 textcolor rgb "
                "'#aa5500' font ',9'\n",
                *x, r.knocked->target);
        }
    }
    if (r.step) {
        if (const auto x = at(r.step->since_epoch)) {
            s += fmt::format(
                "set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lc rgb '#cc0000'\n"
                "set label 'step z {1:g}-{2:g} m' at {0},graph 0.88 offset 0.5,0 textcolor rgb "
                "'#cc0000' font ',9'\n",
                *x, r.step->z_min, r.step->z_max);
        }
    }
    return s;
}

// The epochs of the run on the x axis of every plot, by the database's epoch id (the number
// `tlsmon query epochs` shows).
std::string epoch_range(const RunReport& r) {
    if (r.registration.empty()) return "";
    const EpochId lo = r.registration.front().id, hi = r.registration.back().id;
    return hi > lo ? fmt::format("set xrange [{}:{}]\n", lo, hi) : std::string();
}

const char* kHeader =
    "set terminal pngcairo size 1100,{} font 'DejaVu Sans,10' noenhanced\n"
    "set output {}\n"
    "set grid lc rgb '#dddddd'\n"
    "set key outside right top\n"
    "set xlabel 'epoch (database id)'\n";

bool plot_registration(const RunReport& r, const fs::path& dir, ReportFiles& files) {
    // Residual length per target (one data block each), the registration's own σ and
    // targets' RMS, and with a truth the errors against it.
    std::map<std::string, std::string> per_target;
    std::string errors =
        "# epoch top_error_mm pier_max_error_mm registration_sigma_3d_mm target_rms_mm\n";
    std::string rejected = "# epoch (rejected or not registered)\n";
    const auto mm_or_nan = [](const std::optional<double>& v) {
        return v ? fmt::format("{:.5f}", 1e3 * *v) : std::string("NaN");
    };
    for (const RegistrationCheck& c : r.registration) {
        // The reference's residuals are zero by construction; a target excluded in an
        // earlier epoch is not measured (stored as zero): neither is drawn.
        for (const auto& [name, len] : c.target_residuals) {
            if (c.is_reference || len <= 0.0) continue;
            per_target[name] += fmt::format("{} {:.5f}\n", c.id, 1e3 * len);
        }
        if (c.accepted && !c.is_reference) {
            errors += fmt::format(
                "{} {} {} {} {:.5f}\n", c.id,
                mm_or_nan(c.top_error ? std::optional<double>(c.top_error->norm()) : std::nullopt),
                mm_or_nan(c.max_error), mm_or_nan(c.zone_sigma_m), 1e3 * c.target_rms_m);
        } else if (!c.is_reference) {
            rejected += fmt::format("{}\n", c.id);
        }
    }
    std::string targets_dat;
    std::string target_plot;
    int index = 0;
    for (const auto& [name, rows] : per_target) {
        targets_dat += "# " + name + "\n" + rows + "\n\n";
        target_plot += fmt::format(
            "{}'registration_targets.dat' index {} with linespoints pt 7 "
            "ps 0.5 title {}",
            index ? ", " : "", index, gnuplot_quoted("target " + name));
        ++index;
    }
    write_text(dir / "registration_targets.dat", targets_dat);
    write_text(dir / "registration_errors.dat", errors);
    write_text(dir / "registration_rejected.dat", rejected);
    const fs::path png = dir.parent_path() / "registration.png";
    std::string gp =
        fmt::format(fmt::runtime(kHeader), 900, gnuplot_quoted(fs::absolute(png).string()));
    // The same plot area in both panels, so the epochs line up.
    gp += "set lmargin at screen 0.07\nset rmargin at screen 0.76\n";
    gp += fmt::format(
        "set multiplot layout 2,1 title 'Registration of each epoch onto the "
        "reference epoch{}'\n",
        r.scored ? ", scored against the simulator truth" : "");
    gp += epoch_range(r) + event_marks(r);
    gp +=
        "set title \"Target residuals (length, as the registration stored them; an excluded "
        "target shows its apparent movement)\"\n"
        "set ylabel 'residual (mm, log scale)'\nset logscale y\nset format y '%g'\n";
    gp += target_plot.empty() ? "plot NaN notitle\n" : "plot " + target_plot + "\n";
    gp += "unset logscale y\nset yrange [0:*]\n";
    const std::string own =
        "'' using 1:4 with lines dt 2 lc rgb '#777777' title 'registration sigma 3-D (own)', "
        "'' using 1:5 with lines dt 3 lc rgb '#2ca02c' title 'targets residual RMS (own)', "
        "'registration_rejected.dat' using 1:(0) with points pt 2 ps 1 lc rgb '#d62728' "
        "title 'rejected epoch'\n";
    if (r.scored) {
        gp +=
            "set title 'Error of the transformation at the pier against the truth H0^-1 Hi'\n"
            "set ylabel 'error (mm)'\n"
            "plot 'registration_errors.dat' using 1:2 with linespoints pt 7 ps 0.5 "
            "lc rgb '#1f77b4' title 'at the top centre', "
            "'' using 1:3 with lines lc rgb '#9467bd' title 'largest over the pier samples', " +
            own;
    } else {
        gp +=
            "set title \"The registration's own uncertainty: its largest sigma at the zones and "
            "the targets' residual RMS\"\n"
            "set ylabel 'mm'\n"
            "plot 'registration_errors.dat' using 1:4 with linespoints pt 7 ps 0.5 "
            "lc rgb '#777777' title 'registration sigma 3-D (own)', " +
            own.substr(own.find("'' using 1:5"));
    }
    gp += "unset multiplot\n";
    const fs::path script = dir / "registration.gp";
    write_text(script, gp);
    if (!run_gnuplot(script, png, dir / "registration.log")) {
        files.notes.push_back("registration.png not drawn: see " +
                              (dir / "registration.log").string());
        return false;
    }
    files.plots.push_back(png);
    return true;
}

bool plot_zone(const RunReport& r, const ZoneCheck& z, const fs::path& dir, ReportFiles& files) {
    const std::string base = "zone_" + safe_name(z.zone);
    std::vector<std::string> curves;
    if (z.face && !z.truth.empty()) {
        std::string truth = "# epoch true_normal_median_mm true_normal_mean_mm\n";
        for (const auto& [epoch, t] : z.truth) {
            const auto id = r.epoch_id.find(epoch);
            if (id == r.epoch_id.end()) continue;  // no scan of this truth epoch
            truth += fmt::format("{} {:.5f} {:.5f}\n", id->second, 1e3 * t.normal_median,
                                 1e3 * t.normal_mean);
        }
        write_text(dir / (base + "_truth.dat"), truth);
        curves.push_back(fmt::format(
            "'{0}_truth.dat' using 1:2 with lines lw 2 lc rgb '#222222' title 'truth: median "
            "change along the normal', '' using 1:3 with lines dt 3 lc rgb '#222222' title "
            "'truth: mean change along the normal'",
            base));
    }
    const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
    int k = 0;
    for (const ZoneQuantityCheck& q : z.quantities) {
        if (!q.displacement) continue;
        std::string rows = "# epoch value_mm lod_mm\n";
        for (const auto& row : q.rows) {
            rows += fmt::format("{} {:.5f} {:.5f}\n", row.id, 1e3 * row.value,
                                row.lod ? 1e3 * *row.lod : 0.0);
        }
        const std::string file = base + "_" + safe_name(q.quantity) + ".dat";
        write_text(dir / file, rows);
        curves.push_back(
            fmt::format("'{}' using 1:2:3 with yerrorbars pt 7 ps 0.5 lc rgb '{}' title {}", file,
                        colours[k % 6], gnuplot_quoted(q.quantity + " (bar: LoD95)")));
        ++k;
    }
    if (curves.empty()) return false;
    const fs::path png = dir.parent_path() / (base + ".png");
    std::string gp =
        fmt::format(fmt::runtime(kHeader), 520, gnuplot_quoted(fs::absolute(png).string()));
    gp += epoch_range(r) + event_marks(r);
    const std::string where = z.face ? fmt::format(" ({} face, z {:g}-{:g} m)", z.face->face,
                                                   z.face->z_min, z.face->z_max)
                                     : std::string();
    gp += fmt::format(
        "set title {}\nset ylabel 'change since the reference epoch (mm, + towards the "
        "scanner)'\n",
        gnuplot_quoted(
            fmt::format("Zone {}{}{}", z.zone, where,
                        k == 0 ? ": truth only, no M3C2 or keypoint rows in this run" : "")));
    std::string plot;
    for (const auto& curve : curves) plot += (plot.empty() ? "" : ", ") + curve;
    gp += "plot " + plot + "\n";
    const fs::path script = dir / (base + ".gp");
    write_text(script, gp);
    if (!run_gnuplot(script, png, dir / (base + ".log"))) {
        files.notes.push_back(png.filename().string() + " not drawn: see " +
                              (dir / (base + ".log")).string());
        return false;
    }
    files.plots.push_back(png);
    return true;
}

}  // namespace

void draw_plots(const RunReport& r, const fs::path& out, ReportFiles& files) {
    if (!have_gnuplot()) {
        files.notes.push_back(
            "plots not drawn: gnuplot not found (Debian: apt-get install gnuplot-nox)");
        return;
    }
    const fs::path dir = fs::absolute(out) / "plots";
    fs::create_directories(dir);
    plot_registration(r, dir, files);
    for (const ZoneCheck& z : r.zones) plot_zone(r, z, dir, files);
    draw_keypoint_models(r.database, dir, files);
    draw_area_vectors(r, dir, files);
}

}  // namespace tlsmon::report
