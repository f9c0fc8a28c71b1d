// report.md: the run in the order a reader checks it — registration, zones, alarms — then
// where to look further; scored against the truth when there is one, else the run's own
// figures (a real site).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/utc_time.hpp"
#include "report/calibration.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"

namespace tlsmon::report {

namespace {

std::string mm(double v) {
    return fmt::format("{:.3f}", 1e3 * v);
}

std::string quantity_family_note(const ZoneCheck& z, const std::string& prefix,
                                 const std::string& what) {
    for (const ZoneQuantityCheck& q : z.quantities) {
        if (q.quantity.rfind(prefix, 0) == 0) return "";
    }
    return fmt::format("- {}: not computed (no `{}*` rows for this zone in the database)\n", what,
                       prefix);
}

std::string tlsmon_db(const ReportContext& c, const RunReport& r) {
    return c.config.empty() ? "--db " + r.database.string() : "--config " + c.config.string();
}

// A truth epoch as the database numbers it, the number `tlsmon query epochs` and `tlsmon
// alarms history` show, with the simulator's own.
std::string epoch_name(const RunReport& r, int truth_epoch) {
    const auto id = r.epoch_id.find(truth_epoch);
    if (id == r.epoch_id.end()) return fmt::format("simulator epoch {}", truth_epoch);
    return fmt::format("epoch {} (simulator epoch {})", id->second, truth_epoch);
}

// A database epoch, with the simulator's number when there is a truth for it.
std::string epoch_label(EpochId id, int truth_epoch) {
    return truth_epoch < 0 ? fmt::format("epoch {}", id)
                           : fmt::format("epoch {} (simulator epoch {})", id, truth_epoch);
}

std::string median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? std::string("–") : mm(v[v.size() / 2]);
}

// The registration's own figures over the accepted epochs (the reference left out).
std::string registration_own_table(const RunReport& r) {
    std::int64_t used_min = 1 << 30, used_max = 0;
    std::vector<double> own_rms, sigma;
    for (const RegistrationCheck& x : r.registration) {
        if (!x.accepted || x.is_reference) continue;
        used_min = std::min(used_min, x.targets_used);
        used_max = std::max(used_max, x.targets_used);
        own_rms.push_back(x.target_rms_m);
        if (x.zone_sigma_m) sigma.push_back(*x.zone_sigma_m);
    }
    if (own_rms.empty()) return "No accepted registration besides the reference.\n";
    std::string md = "| the registration's own | epochs | median | max |\n|---|---|---|---|\n";
    md += fmt::format("| targets' residual RMS (mm) | {} | {} | {} |\n", own_rms.size(),
                      median_of(own_rms), mm(*std::max_element(own_rms.begin(), own_rms.end())));
    if (!sigma.empty()) {
        md += fmt::format("| largest σ at a zone, 3-D (mm) | {} | {} | {} |\n", sigma.size(),
                          median_of(sigma), mm(*std::max_element(sigma.begin(), sigma.end())));
    }
    md += fmt::format("\nTargets used per accepted epoch: {}–{}.\n", used_min, used_max);
    return md;
}

std::string percent(double share) {
    return fmt::format("{:.1f} %", 100 * share);
}

// One row per method: its pooled row ("all") where it has one, else its only part.
std::vector<CoverageRow> method_rows(const std::vector<CoverageRow>& rows) {
    std::vector<CoverageRow> out;
    for (const CoverageRow& c : rows) {
        const bool pooled = std::any_of(rows.begin(), rows.end(), [&](const CoverageRow& o) {
            return o.method == c.method && o.part == "all";
        });
        if (!pooled || c.part == "all") out.push_back(c);
    }
    return out;
}

// Every method's coverage of its true errors by its own σ (report/calibration.hpp).
std::string calibration_section(const RunReport& r) {
    const auto rows = calibration(r);
    std::string md =
        "\n## Calibration: does each σ cover its true error?\n\n"
        "Each scored figure's error against the truth, and whether it lies within the figure's "
        "own σ (68 % nominal) and LoD95 = 1.96 σ (95 % nominal); the band is the Wilson 95 % "
        "interval of the share, and the verdict says whether the nominal rate lies inside it "
        "(docs/calibration.md). Lengths in mm, registration angles in µrad. Rows "
        "`no_change:…` and `agreement:…` need no truth: a check zone's values against zero "
        "(ground known not to move, never in the datum); each used target against the "
        "transformation of the others (χ² with 3 degrees of freedom), and two independent "
        "estimates of an epoch's transformation against their σ (χ² with 6), within χ²'s 68 % "
        "and 95 % quantiles. The same "
        "table: `tlsmon calibration --db DB [--truth DIR]`.\n\n";
    if (rows.empty()) return md + "No scored figure with an uncertainty.\n";
    md +=
        "| method | part | n | bias | RMS | RMS σ | within σ | band | verdict | within "
        "LoD95 | band | verdict |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CoverageRow& c : rows) {
        const auto number = [&](double v) {
            return c.blank_numbers() ? std::string("–")
                                     : fmt::format("{:.3f}", c.display_scale() * v);
        };
        md += fmt::format(
            "| {} | {} | {} | {} | {} | {} | {} | {:.1f}–{:.1f} | {} | {} | {:.1f}–{:.1f} | {} "
            "|\n",
            c.method, c.part, c.n, number(c.error.bias), number(c.error.rms), number(c.rms_sigma),
            percent(c.coverage68()), 100 * c.band68.lower, 100 * c.band68.upper,
            to_string(c.verdict68), percent(c.coverage95()), 100 * c.band95.lower,
            100 * c.band95.upper, to_string(c.verdict95));
    }
    return md + "\n";
}

// The registration against the exact answer of the truth, then its own figures.
std::string registration_scored(const RunReport& r) {
    std::string md =
        "\n## Registration against the truth\n\n"
        "Each epoch's transformation T (epoch frame → reference frame, as stored) against the "
        "exact answer H₀⁻¹·Hᵢ from the truth's `header_to_true` (docs/simulator.md): the error "
        "T·q − H₀⁻¹·Hᵢ·q where the epoch sees each of the truth's pier sample points "
        "(faces at 5–39 m and the top centre). Accepted epochs, the reference left out.\n\n";
    const ErrorSummary& top = r.registration_top_error;
    const ErrorSummary& any = r.registration_max_error;
    if (top.n == 0) return md + "Not computed: no accepted registration with a truth file.\n";
    md += "| quantity | epochs | bias | RMS | max |\n|---|---|---|---|---|\n";
    md += fmt::format(
        "| error at the pier's top centre (mm) | {} | ({:+.3f}, {:+.3f}, {:+.3f}) | "
        "{} | {} |\n",
        top.n, r.bias_vector_mm[0], r.bias_vector_mm[1], r.bias_vector_mm[2], mm(top.rms),
        mm(top.max_abs));
    md += fmt::format("| largest error over the pier samples (mm) | {} | | {} | {} |\n\n", any.n,
                      mm(any.rms), mm(any.max_abs));
    return md + registration_own_table(r);
}

// A stored value as the table shows it: lengths (`_m`) in mm, signed as a change (not an
// uncertainty), other quantities as they are.
std::string value_text(const std::string& quantity, double v, bool change = true) {
    if (!std::isfinite(v)) return "–";
    const bool length = quantity.size() > 2 && quantity.compare(quantity.size() - 2, 2, "_m") == 0;
    if (!length) return fmt::format("{:g}", v);
    return change ? fmt::format("{:+.3f}", 1e3 * v) : mm(v);
}

// Each change of the surface (M3C2 along the normal, keypoints along the surface) as the run
// measured it: the latest value with its LoD95, the range and the share of epochs where the
// change was significant. The other quantities (counts, spreads, shares) are in zones.csv.
std::string zone_own_table(const ZoneCheck& z) {
    if (std::none_of(z.quantities.begin(), z.quantities.end(),
                     [](const ZoneQuantityCheck& q) { return q.displacement && !q.rows.empty(); }))
        return "No M3C2 or keypoint changes for this zone in the database.\n";
    std::string md =
        "| quantity | epochs | latest | LoD95 | min | max | significant |\n"
        "|---|---|---|---|---|---|---|\n";
    for (const ZoneQuantityCheck& q : z.quantities) {
        if (!q.displacement || q.rows.empty()) continue;
        double lo = q.rows.front().value, hi = lo;
        int significant = 0;
        for (const auto& row : q.rows) {
            lo = std::min(lo, row.value);
            hi = std::max(hi, row.value);
            significant += row.significant;
        }
        const auto& last = q.rows.back();
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {:.0f} % |\n", q.quantity, q.rows.size(),
                          value_text(q.quantity, last.value),
                          last.lod ? value_text(q.quantity, *last.lod, false) : std::string("–"),
                          value_text(q.quantity, lo), value_text(q.quantity, hi),
                          100.0 * significant / double(q.rows.size()));
    }
    return md +
           "\n(mm; M3C2 + towards the scanner along the normal; every quantity of the zone "
           "is in zones.csv)\n";
}

}  // namespace

std::vector<std::string> summary_lines(const RunReport& r) {
    std::vector<std::string> out;
    out.push_back(fmt::format("epochs: {} done, {} rejected, {} failed, {} not processed",
                              r.epochs_done, r.epochs_rejected, r.epochs_failed, r.epochs_pending));
    const ErrorSummary& t = r.registration_top_error;
    if (!r.scored) {
        std::vector<double> own;
        for (const RegistrationCheck& x : r.registration) {
            if (x.accepted && !x.is_reference) own.push_back(x.target_rms_m);
        }
        out.push_back(
            fmt::format("registration: {} accepted epochs, targets' residual RMS median "
                        "{} mm (no truth: nothing scored)",
                        own.size(), median_of(own)));
    } else if (t.n > 0) {
        out.push_back(fmt::format(
            "registration vs truth at the pier top ({} accepted epochs): RMS {} mm, max {} mm; "
            "largest over the pier {} mm",
            t.n, mm(t.rms), mm(t.max_abs), mm(r.registration_max_error.max_abs)));
    } else {
        out.push_back("registration vs truth: not computed (no accepted registration)");
    }
    if (r.knocked) {
        out.push_back(r.knocked_excluded_from
                          ? fmt::format("knocked target {} (truth: {}): excluded from {}",
                                        r.knocked->target, epoch_name(r, r.knocked->since_epoch),
                                        epoch_name(r, *r.knocked_excluded_from))
                          : fmt::format("knocked target {} (truth: {}): never excluded",
                                        r.knocked->target, epoch_name(r, r.knocked->since_epoch)));
    }
    bool any_zone = false;
    for (const ZoneCheck& z : r.zones) {
        for (const ZoneQuantityCheck& q : z.quantities) {
            if (q.error.n == 0) continue;
            any_zone = true;
            out.push_back(
                fmt::format("{} {} vs {}: bias {} mm, RMS {} mm, max {} mm ({} epochs)", z.zone,
                            q.quantity, z.no_change ? "zero (a check zone)" : "truth",
                            mm(q.error.bias), mm(q.error.rms), mm(q.error.max_abs), q.error.n));
        }
    }
    if (!any_zone && r.scored) out.push_back("zones (M3C2, keypoints): not computed in this run");
    for (const CoverageRow& c : method_rows(calibration(r))) {
        // A χ² row's shares are within its distribution's 68 % and 95 % quantiles.
        const bool chi2 = c.statistic_only;
        out.push_back(fmt::format("calibration {}: {} of {} within {} ({}), {} within {} ({})",
                                  c.method, percent(c.coverage68()), c.n,
                                  chi2 ? c.part + "'s 68 % quantile" : "1 sigma",
                                  to_string(c.verdict68), percent(c.coverage95()),
                                  chi2 ? "its 95 % quantile" : "LoD95", to_string(c.verdict95)));
    }
    for (const AlarmCheck& a : r.alarms) {
        if (!r.scored) {
            out.push_back(fmt::format("alarm {}: raised {} time(s)", a.rule, a.raises));
        } else if (!a.evaluated) {
            out.push_back(fmt::format("alarm {}: not evaluated (no {} rows in zone {})", a.rule,
                                      a.quantity, a.zone));
        } else {
            out.push_back(fmt::format(
                "alarm {}: {}; {} false alarm(s)", a.rule,
                a.latency_epochs
                    ? fmt::format("step detected {} epoch(s) after it happened", *a.latency_epochs)
                : a.step_epoch ? std::string("step not detected")
                               : std::string("no step in its zone"),
                a.false_alarms));
        }
    }
    return out;
}

namespace {

// The campaign epochs of the window (docs/campaigns.md): kept apart from the station's series,
// so listed, not scored.
std::string campaigns_section(const RunReport& r) {
    if (r.campaigns.empty()) return "";
    std::string md =
        "\n## Campaigns\n\n"
        "Clouds of a personal or mobile scanner compared with the reference segment by segment "
        "(docs/campaigns.md); apart from the zone series and the alarms. \"Moved as one: no\" "
        "says the campaign's cloud is deformed in itself (SLAM drift) or a part moved.\n\n"
        "| campaign | acquired | instrument | frame | segments registered | moved as one | C2C "
        "mean | C2C 95 % |\n|---|---|---|---|---|---|---|---|\n";
    const auto mm = [](const std::optional<double>& v) {
        return v ? fmt::format("{:.1f} mm", 1e3 * *v) : std::string("—");
    };
    for (const CampaignRow& k : r.campaigns) {
        const std::string moved =
            !k.segments_differ
                ? "not testable"
                : fmt::format("{} (p {})", *k.segments_differ ? "**no**" : "yes",
                              *k.test_p < 1e-4 ? "< 0.0001" : fmt::format("{:.4f}", *k.test_p));
        const std::string frame =
            k.coarse_planes ? fmt::format("found on {} planes", *k.coarse_planes) : "as given";
        md += fmt::format("| {} | {} | {} ({}) | {} | {} of {} | {} | {} | {} |\n", k.id,
                          format_utc(k.acquired), k.instrument, k.kind, frame,
                          k.registered_segments, k.segments, moved, mm(k.c2c_mean), mm(k.c2c_p95));
    }
    md += fmt::format(
        "\nEach campaign's segments: `tlsmon query campaign-segments --db {} --campaign N`; its "
        "points: `tlsmon query campaign-points`; on the dashboard, /campaigns/N.\n",
        r.database.string());
    return md;
}

}  // namespace

std::string markdown(const RunReport& r, const ReportFiles& files, const ReportContext& c) {
    std::string md =
        r.scored ? "# tlsmon run scored against the simulator's truth\n\n" : "# tlsmon run\n\n";
    md += fmt::format("- Epoch database: `{}`\n", r.database.string());
    if (!c.window.empty()) {
        md +=
            fmt::format("- Window: epochs acquired from {} (and the reference epoch)\n", c.window);
    }
    if (r.scored) {
        md += fmt::format("- Truth files: `{}` ({} epochs)\n", r.truth_folder.string(),
                          r.truth_epochs);
    }
    md += fmt::format("- Epochs processed: {} done, {} rejected, {} failed; {} not processed\n",
                      r.epochs_done, r.epochs_rejected, r.epochs_failed, r.epochs_pending);
    if (!r.reference) {
        md += "- Reference epoch: none yet.\n";
    } else if (!r.scored) {
        md += fmt::format(
            "- Reference epoch: epoch {}. Every change below is since that epoch. The figures are "
            "the run's own: its registration residuals and σ, each zone's series with its "
            "LoD95, the alarm events.\n",
            *r.reference);
    } else {
        md += r.reference_truth_epoch
                  ? fmt::format(
                        "- Reference epoch: {}. Every comparison below is against the change of "
                        "the truth since that epoch (epoch 0 of a simulated series is neither "
                        "undeformed nor at the nominal pose).\n",
                        epoch_name(r, *r.reference_truth_epoch))
                  : std::string(
                        "- Reference epoch: none with a truth file, nothing can be scored.\n");
    }
    md += "\nTables: ";
    for (std::size_t i = 0; i < files.csv.size(); ++i) {
        md += fmt::format("{}[{}]({})", i ? ", " : "", files.csv[i].filename().string(),
                          files.csv[i].filename().string());
    }
    md += " (lengths in mm).\n";

    // ---- Registration ----
    if (!r.scored) {
        md +=
            "\n## Registration\n\n"
            "Each epoch's transformation onto the reference epoch, as the registration "
            "measured its own quality: the residuals of the targets it used and its σ at the "
            "zones (docs/registration.md).\n\n";
        md += registration_own_table(r);
    } else {
        md += registration_scored(r);
    }
    std::vector<std::string> rejected;
    for (const RegistrationCheck& x : r.registration) {
        if (x.status == "rejected" || x.status == "failed") {
            rejected.push_back(fmt::format("{} ({}): {}", epoch_label(x.id, x.truth_epoch),
                                           x.status, x.reason.substr(0, 160)));
        }
    }
    md += fmt::format("Rejected or failed epochs: {}.\n",
                      rejected.empty() ? std::string("none") : std::to_string(rejected.size()));
    for (std::size_t i = 0; i < rejected.size() && i < 10; ++i) md += "- " + rejected[i] + "\n";
    if (rejected.size() > 10) md += "- … (registration.csv has every epoch)\n";
    md += "\n";
    if (r.knocked) {
        md += fmt::format(
            "Knocked target (truth): **{}** moved by ({:+.1f}, {:+.1f}, {:+.1f}) mm "
            "from {}. ",
            r.knocked->target, 1e3 * r.knocked->displacement.x(), 1e3 * r.knocked->displacement.y(),
            1e3 * r.knocked->displacement.z(), epoch_name(r, r.knocked->since_epoch));
        md += r.knocked_excluded_from
                  ? fmt::format(
                        "The registration excluded it from {} on ({} epoch(s) after "
                        "it moved).\n",
                        epoch_name(r, *r.knocked_excluded_from),
                        *r.knocked_excluded_from - r.knocked->since_epoch)
                  : std::string("The registration never excluded it.\n");
    }
    std::vector<std::string> others;
    for (const auto& t : r.excluded_targets) {
        if (!r.knocked || t != r.knocked->target) others.push_back(t);
    }
    if (!r.scored) {
        md += others.empty() ? std::string("No target was excluded as moved.\n")
                             : fmt::format(
                                   "Targets excluded as moved: {} (`tlsmon targets` says "
                                   "since when and why).\n",
                                   fmt::join(others, ", "));
    } else {
        md += others.empty()
                  ? std::string("No other target was excluded.\n")
                  : fmt::format("Also excluded, though the truth did not move them: {}.\n",
                                fmt::join(others, ", "));
    }
    md += "\n![registration](registration.png)\n";

    // ---- Zones ----
    md += r.scored
              ? "\n## Zones against the truth\n\n"
                "Each zone quantity against the true change of the zone since the reference "
                "epoch (the truth's displacement field, docs/simulator.md \"Deformation\", over "
                "the zone's part of the pier face): M3C2 along the face's outward normal (+ "
                "towards the scanner), keypoint components against the mean true vector. "
                "Error = value − truth.\n\n"
              : "\n## Zones\n\n"
                "Each zone quantity's change since the reference epoch as stored (M3C2 along "
                "the normal, keypoints along the surface; docs/m3c2.md, docs/keypoints.md).\n\n";
    for (const ZoneCheck& z : r.zones) {
        md += fmt::format("### {}\n\n", z.zone);
        if (z.no_change) {
            md +=
                "A check zone on ground known not to move (`no_change`): its change is zero by "
                "what it is, and the calibration below scores it so (`no_change:…`).\n\n";
        }
        if (!r.scored) {
            md += zone_own_table(z);
        } else if (!z.face) {
            if (!z.no_change) md += "Not on one face of the pier: no truth to compare with.\n\n";
        } else {
            std::string moved;
            if (z.step_zone && r.step) {
                moved = fmt::format("; the truth's step moves its part at z {:g}–{:g} m",
                                    std::max(r.step->z_min, z.face->z_min),
                                    std::min(r.step->z_max, z.face->z_max));
            }
            md += fmt::format("{} face, z {:g}–{:g} m{}.\n\n", z.face->face, z.face->z_min,
                              z.face->z_max, moved);
        }
        bool table = false;
        for (const ZoneQuantityCheck& q : z.quantities) {
            if (!r.scored) break;
            if (!table) {
                md +=
                    "| quantity | compared with | epochs | bias (mm) | RMS (mm) | max (mm) |\n"
                    "|---|---|---|---|---|---|\n";
                table = true;
            }
            if (q.error.n == 0) {
                md += fmt::format("| {} | no truth for this quantity | {} | | | |\n", q.quantity,
                                  q.rows.size());
            } else {
                md += fmt::format("| {} | {} | {} | {:+.3f} | {} | {} |\n", q.quantity,
                                  q.truth_kind, q.error.n, 1e3 * q.error.bias, mm(q.error.rms),
                                  mm(q.error.max_abs));
            }
        }
        if (table) md += "\n";
        md += quantity_family_note(z, "m3c2_", "M3C2");
        md += quantity_family_note(z, "keypoint_", "Keypoints");
        const std::string png = "zone_" + safe_name(z.zone) + ".png",
                          vectors = "vectors_" + safe_name(z.zone) + ".png";
        for (const auto& p : files.plots) {
            if (p.filename() == png) md += fmt::format("\n![{}]({})\n", z.zone, png);
            if (p.filename() == vectors)
                md += fmt::format("\n![3-D vectors of {}]({})\n", z.zone, vectors);
        }
        md += "\n";
    }

    if (r.scored || !calibration(r).empty()) md += calibration_section(r);

    // ---- Alarms ----
    md += r.scored ? "## Alarms against the truth\n\n" : "\n## Alarms\n\n";
    if (r.scored) {
        md += r.step ? fmt::format(
                           "Step event (truth): pier points at z {:g}–{:g} m move by ({:+.1f}, "
                           "{:+.1f}, {:+.1f}) mm from {}.\n\n",
                           r.step->z_min, r.step->z_max, 1e3 * r.step->displacement.x(),
                           1e3 * r.step->displacement.y(), 1e3 * r.step->displacement.z(),
                           epoch_name(r, r.step->since_epoch))
                     : std::string("No step event in the truth.\n\n");
    }
    if (r.alarms.empty()) md += "No alarm rules configured.\n";
    for (const AlarmCheck& a : r.alarms) {
        md += fmt::format("- **{}** ({} in zone {}{}): ", a.rule, a.quantity, a.zone,
                          !r.scored     ? ""
                          : a.step_zone ? ", moved by the step"
                                        : ", not moved by the step");
        if (!a.evaluated) {
            md += fmt::format(
                "not evaluated — the database has no `{}` rows for zone {} (the "
                "stage that computes them did not run).\n",
                a.quantity, a.zone);
            continue;
        }
        if (!r.scored) {
            md += fmt::format("raised {} time(s).\n", a.raises);
        } else {
            if (a.step_epoch) {
                md += a.latency_epochs
                          ? fmt::format("first raised at {}, a detection latency of {} epoch(s); ",
                                        epoch_name(r, *a.first_raise_epoch), *a.latency_epochs)
                          : std::string("the step was **not** detected; ");
            }
            md += fmt::format("{} false alarm(s).\n", a.false_alarms);
        }
        for (const auto& e : a.events) md += "  - " + e + "\n";
    }

    md += campaigns_section(r);

    // ---- Look further ----
    const std::string db = tlsmon_db(c, r);
    md += "\n## Look further\n\n";
    md += fmt::format("The database is `{}`. For example:\n\n", r.database.string());
    md += fmt::format(
        "    tlsmon status {0}\n    tlsmon query epochs {0}\n"
        "    tlsmon query registrations {0} --format csv\n    tlsmon events {0}\n"
        "    tlsmon alarms history {0}\n",
        db);
    for (const ZoneCheck& z : r.zones) {
        // The zone's first change of the surface, else its first quantity.
        const auto q = std::find_if(z.quantities.begin(), z.quantities.end(),
                                    [](const ZoneQuantityCheck& x) { return x.displacement; });
        const auto* shown = q != z.quantities.end() ? &*q
                            : z.quantities.empty()  ? nullptr
                                                    : &z.quantities.front();
        if (shown) {
            md += fmt::format("    tlsmon query series {} --zone {} --quantity {}\n", db, z.zone,
                              shown->quantity);
        }
    }
    if (!c.config.empty()) {
        md += fmt::format(
            "\nModbus (docs/modbus.md), with the daemon running (`tlsmon run --config {0}`):\n\n"
            "    tlsmon modbus-map --config {0}\n"
            "    mbpoll -m tcp -p {1} -0 -1 -t 3:float -B -r 7 127.0.0.1      # test float: "
            "123456\n"
            "    mbpoll -m tcp -p {1} -0 -1 -t 3 -r 0 -c 7 127.0.0.1          # map version, "
            "heartbeat, status, last epoch\n"
            "    mbpoll -m tcp -p {1} -0 -1 -t 1 -r 0 -c 3 127.0.0.1          # any alarm, "
            "unacknowledged, system fault\n",
            c.config.string(), c.modbus_port);
        for (const ZoneCheck& z : r.zones) {
            if (z.id <= 0) continue;
            md += fmt::format(
                "    mbpoll -m tcp -p {} -0 -1 -t 3:float -B -r {} -c 2 127.0.0.1   "
                "# {}: first quantity's value and LoD\n",
                c.modbus_port, 100 + 80 * (z.id - 1), z.zone);
        }
        for (const AlarmCheck& a : r.alarms) {
            if (a.id <= 0) continue;
            md += fmt::format(
                "    mbpoll -m tcp -p {} -0 -1 -t 0 -r {} 127.0.0.1 1            "
                "# acknowledge {}\n",
                c.modbus_port, 16 + (a.id - 1), a.rule);
        }
    }
    if (!files.notes.empty()) {
        md += "\n## Notes\n\n";
        for (const auto& n : files.notes) md += "- " + n + "\n";
    }
    return md;
}

}  // namespace tlsmon::report
