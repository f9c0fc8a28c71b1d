// The report's plots, drawn by gnuplot (Debian `gnuplot-nox`, pngcairo terminal): the data
// and the script of each plot are written under plots/ so that anyone can redraw or change
// them, then `gnuplot` renders the PNG.
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include "core/error.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"

namespace tlsmon::report {

namespace {

namespace fs = std::filesystem;

std::string safe_name(const std::string& s) {
    std::string out;
    for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

// Vertical dashed lines at the truth's events.
std::string event_marks(const RunReport& r) {
    std::string s;
    if (r.knocked) {
        s += fmt::format(
            "set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lc rgb '#aa5500'\n"
            "set label 'target {1} knocked' at {0},graph 0.95 offset 0.5,0 textcolor rgb "
            "'#aa5500' font ',9'\n",
            r.knocked->since_epoch, r.knocked->target);
    }
    if (r.step) {
        s += fmt::format(
            "set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lc rgb '#cc0000'\n"
            "set label 'step z {1:g}-{2:g} m' at {0},graph 0.88 offset 0.5,0 textcolor rgb "
            "'#cc0000' font ',9'\n",
            r.step->since_epoch, r.step->z_min, r.step->z_max);
    }
    return s;
}

// The epochs of the run on the x axis of every plot.
std::string epoch_range(const RunReport& r) {
    int lo = 1 << 30, hi = -1;
    for (const RegistrationCheck& c : r.registration) {
        if (c.truth_epoch < 0) continue;
        lo = std::min(lo, c.truth_epoch);
        hi = std::max(hi, c.truth_epoch);
    }
    return hi > lo ? fmt::format("set xrange [{}:{}]\n", lo, hi) : std::string();
}

const char* kHeader =
    "set terminal pngcairo size 1100,{} font 'DejaVu Sans,10' noenhanced\n"
    "set output {}\n"
    "set grid lc rgb '#dddddd'\n"
    "set key outside right top\n"
    "set xlabel 'epoch (15 min each)'\n";

bool plot_registration(const RunReport& r, const fs::path& dir, ReportFiles& files) {
    // Residual length per target (one data block each), and the errors against the truth.
    std::map<std::string, std::string> per_target;
    std::string errors =
        "# epoch top_error_mm pier_max_error_mm registration_sigma_3d_mm target_rms_mm\n";
    std::string rejected = "# epoch (rejected or not registered)\n";
    for (const RegistrationCheck& c : r.registration) {
        if (c.truth_epoch < 0) continue;
        // The reference's residuals are zero by construction; a target excluded in an
        // earlier epoch is not measured (stored as zero): neither is drawn.
        for (const auto& [name, len] : c.target_residuals) {
            if (c.is_reference || len <= 0.0) continue;
            per_target[name] += fmt::format("{} {:.5f}\n", c.truth_epoch, 1e3 * len);
        }
        if (c.accepted && c.top_error) {
            errors += fmt::format(
                "{} {:.5f} {:.5f} {} {:.5f}\n", c.truth_epoch, 1e3 * c.top_error->norm(),
                1e3 * c.max_error.value_or(NAN),
                c.zone_sigma_m ? fmt::format("{:.5f}", 1e3 * *c.zone_sigma_m) : std::string("NaN"),
                1e3 * c.target_rms_m);
        } else if (!c.is_reference) {
            rejected += fmt::format("{}\n", c.truth_epoch);
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
    std::string gp = fmt::format(fmt::runtime(kHeader), 900, gnuplot_quoted(png.string()));
    // The same plot area in both panels, so the epochs line up.
    gp += "set lmargin at screen 0.07\nset rmargin at screen 0.76\n";
    gp +=
        "set multiplot layout 2,1 title 'Registration of each epoch onto the reference "
        "epoch, scored against the simulator truth'\n";
    gp += epoch_range(r) + event_marks(r);
    gp +=
        "set title \"Target residuals (length, as the registration stored them; an excluded "
        "target shows its apparent movement)\"\n"
        "set ylabel 'residual (mm, log scale)'\nset logscale y\nset format y '%g'\n";
    gp += target_plot.empty() ? "plot NaN notitle\n" : "plot " + target_plot + "\n";
    gp += "unset logscale y\n";
    gp +=
        "set title 'Error of the transformation at the pier against the truth H0^-1 Hi'\n"
        "set ylabel 'error (mm)'\nset yrange [0:*]\n";
    gp +=
        "plot 'registration_errors.dat' using 1:2 with linespoints pt 7 ps 0.5 lc rgb '#1f77b4' "
        "title 'at the top centre', "
        "'' using 1:3 with lines lc rgb '#9467bd' title 'largest over the pier samples', "
        "'' using 1:4 with lines dt 2 lc rgb '#777777' title 'registration sigma 3-D (own)', "
        "'registration_rejected.dat' using 1:(0) with points pt 2 ps 1 lc rgb '#d62728' "
        "title 'rejected epoch'\n";
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
    if (!z.face || z.truth.empty()) return false;
    const std::string base = "zone_" + safe_name(z.zone);
    std::string truth = "# epoch true_normal_median_mm true_normal_mean_mm\n";
    for (const auto& [epoch, t] : z.truth) {
        truth +=
            fmt::format("{} {:.5f} {:.5f}\n", epoch, 1e3 * t.normal_median, 1e3 * t.normal_mean);
    }
    write_text(dir / (base + "_truth.dat"), truth);
    std::string plot = fmt::format(
        "'{0}_truth.dat' using 1:2 with lines lw 2 lc rgb '#222222' title 'truth: median change "
        "along the normal', '' using 1:3 with lines dt 3 lc rgb '#222222' title 'truth: mean "
        "change along the normal'",
        base);
    const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
    int k = 0;
    for (const ZoneQuantityCheck& q : z.quantities) {
        if (q.truth_kind.empty()) continue;
        std::string rows = "# epoch value_mm lod_mm\n";
        for (const auto& row : q.rows) {
            if (row.truth_epoch < 0) continue;
            rows += fmt::format("{} {:.5f} {:.5f}\n", row.truth_epoch, 1e3 * row.value,
                                row.lod ? 1e3 * *row.lod : 0.0);
        }
        const std::string file = base + "_" + safe_name(q.quantity) + ".dat";
        write_text(dir / file, rows);
        plot += fmt::format(", '{}' using 1:2:3 with yerrorbars pt 7 ps 0.5 lc rgb '{}' title {}",
                            file, colours[k % 6], gnuplot_quoted(q.quantity + " (bar: LoD95)"));
        ++k;
    }
    const fs::path png = dir.parent_path() / (base + ".png");
    std::string gp = fmt::format(fmt::runtime(kHeader), 520, gnuplot_quoted(png.string()));
    gp += epoch_range(r) + event_marks(r);
    gp += fmt::format(
        "set title {}\nset ylabel 'change since the reference epoch (mm, + towards the "
        "scanner)'\n",
        gnuplot_quoted(fmt::format(
            "Zone {} ({} face, z {:g}-{:g} m){}", z.zone, z.face->face, z.face->z_min,
            z.face->z_max, k == 0 ? ": truth only, no M3C2 or keypoint rows in this run" : "")));
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
}

}  // namespace tlsmon::report
