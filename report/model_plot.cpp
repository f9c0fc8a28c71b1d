// The report's plot of the keypoint displacement model d(t, z) (docs/keypoints.md, step 7):
// for each modelled quantity the last defined fit of the run, drawn as one curve d(t) per
// height z of the segments it was fitted to, with each segment's stored values as points in
// the curve's colour. Read from the database the report scores; drawn by gnuplot like the
// other plots (report_plots.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "core/error.hpp"
#include "pipeline/keypoint_results.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon::report {

namespace {

namespace fs = std::filesystem;

bool plot_model(const EpochDatabase& db, const StoredKeypointModel& fit, const fs::path& dir,
                ReportFiles& files) {
    const KeypointModelRow& m = fit.model;
    if (m.residuals.empty()) return false;
    // t = hours since the reference epoch: the fitting epoch's own t gives the reference's
    // acquisition time.
    const double reference_acquired = double(fit.acquired) - 3600.0 * m.residuals.front().t;
    const std::string base = "keypoint_model_" + m.quantity;
    std::string plot;
    double t_max = 0;
    int k = 0;
    for (const auto& r : m.residuals) {
        std::string points = "# t_h d_mm\n";
        for (const auto& p : db.series().points(r.zone, m.quantity, {})) {
            if (p.acquired > fit.acquired) continue;  // the fit saw the epochs up to its own
            const double t = (double(p.acquired) - reference_acquired) / 3600.0;
            t_max = std::max(t_max, t);
            points += fmt::format("{:.6f} {:.5f}\n", t, 1e3 * p.value);
        }
        const std::string file = fmt::format("{}_{}.dat", base, k);
        write_text(dir / file, points);
        // The curve d(x, z) at this segment's height: Σ a_pq u^p w^q, u = (x − t_centre)/t_scale,
        // w = (z − z_centre)/z_scale, the terms in keypoints::kModelTerms order.
        std::string curve = "0";
        for (std::size_t j = 0; j < keypoints::kModelTerms.size(); ++j) {
            const auto [p, q] = keypoints::kModelTerms[j];
            curve += fmt::format(" + ({:.12g})*((x-({:.12g}))/({:.12g}))**{}*({:.12g})**{}",
                                 1e3 * (*m.coefficients)[j], *m.t_centre, *m.t_scale, p,
                                 (r.z - *m.z_centre) / *m.z_scale, q);
        }
        plot += fmt::format(
            "{}{} with lines lw 2 lc {} title '{} (z {:.1f} m): model', '{}' using 1:2 with points "
            "pt 7 ps 0.7 lc {} title 'stored'",
            plot.empty() ? "" : ", ", curve, k + 1, r.zone, r.z, file, k + 1);
        ++k;
    }
    const fs::path png = dir.parent_path() / (base + ".png");
    std::string gp = fmt::format(
        "set terminal pngcairo size 1100,600 font 'DejaVu Sans,10' noenhanced\n"
        "set output '{}'\nset grid lc rgb '#dddddd'\nset key outside right top\n"
        "set samples 200\nset xrange [0:{:.6f}]\n"
        "set xlabel 't, hours since the reference epoch'\nset ylabel '{} (mm)'\n"
        "set title \"Keypoint displacement model d(t, z) of {}\\nfitted at epoch {} to {} "
        "observations (least absolute residuals, {} iterations; residual scale {:.3f} mm)\"\n",
        fs::absolute(png).string(), t_max > 0 ? t_max : 1.0, m.quantity, m.quantity, fit.epoch,
        m.observations, m.iterations, 1e3 * m.residual_scale.value_or(0));
    gp += "plot " + plot + "\n";
    const fs::path script = dir / (base + ".gp");
    write_text(script, gp);
    const fs::path log = dir / (base + ".log");
    if (!run_gnuplot(script, png, log)) {
        files.notes.push_back(png.filename().string() + " not drawn: see " + log.string());
        return false;
    }
    files.plots.push_back(png);
    return true;
}

}  // namespace

void draw_keypoint_models(const fs::path& database, const fs::path& dir, ReportFiles& files) {
    const auto db = EpochDatabase::open(database, EpochDatabase::Mode::read_only);
    std::map<std::string, StoredKeypointModel> last;  // per quantity, the last defined fit
    std::map<std::string, std::string> why;
    for (auto& fit : db.keypoint_models().in_range({})) {
        if (fit.model.defined) {
            last[fit.model.quantity] = fit;
        } else {
            why[fit.model.quantity] = fit.model.reason;
        }
    }
    for (const auto& [quantity, reason] : why) {
        if (!last.count(quantity))
            files.notes.push_back("keypoint model of " + quantity + " not drawn: never defined (" +
                                  reason + ")");
    }
    for (const auto& [quantity, fit] : last) plot_model(db, fit, dir, files);
}

}  // namespace tlsmon::report
