// report.md: the run scored against the truth, in the order a reader checks it —
// registration, zones, alarms — then where to look further.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>

#include "core/utc_time.hpp"
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

}  // namespace

std::vector<std::string> summary_lines(const RunReport& r) {
    std::vector<std::string> out;
    out.push_back(fmt::format("epochs: {} done, {} rejected, {} failed, {} not processed",
                              r.epochs_done, r.epochs_rejected, r.epochs_failed, r.epochs_pending));
    const ErrorSummary& t = r.registration_top_error;
    if (t.n > 0) {
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
            out.push_back(fmt::format(
                "{} {} vs truth: bias {} mm, RMS {} mm, max {} mm ({} epochs)", z.zone, q.quantity,
                mm(q.error.bias), mm(q.error.rms), mm(q.error.max_abs), q.error.n));
        }
    }
    if (!any_zone) out.push_back("zones (M3C2, keypoints): not computed in this run");
    for (const AlarmCheck& a : r.alarms) {
        if (!a.evaluated) {
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

std::string markdown(const RunReport& r, const ReportFiles& files, const ReportContext& c) {
    std::string md = "# tlsmon run scored against the simulator's truth\n\n";
    md += fmt::format(
        "- Epoch database: `{}`\n- Truth files: `{}` ({} epochs)\n- Epochs processed: {} done, "
        "{} rejected, {} failed; {} not processed\n",
        r.database.string(), r.truth_folder.string(), r.truth_epochs, r.epochs_done,
        r.epochs_rejected, r.epochs_failed, r.epochs_pending);
    md += r.reference_truth_epoch
              ? fmt::format(
                    "- Reference epoch: simulator epoch {}. Every comparison below is "
                    "against the change of the truth since that epoch (epoch 0 of a "
                    "simulated series is neither undeformed nor at the nominal pose).\n",
                    *r.reference_truth_epoch)
              : std::string("- Reference epoch: none with a truth file, nothing can be scored.\n");
    md += "\nTables: ";
    for (std::size_t i = 0; i < files.csv.size(); ++i) {
        md += fmt::format("{}[{}]({})", i ? ", " : "", files.csv[i].filename().string(),
                          files.csv[i].filename().string());
    }
    md += " (lengths in mm).\n";

    // ---- Registration ----
    md +=
        "\n## Registration against the truth\n\n"
        "Each epoch's transformation T (epoch frame → reference frame, as stored) against the "
        "exact answer H₀⁻¹·Hᵢ from the truth's `header_to_true` (docs/simulator.md): the error "
        "T·q − H₀⁻¹·Hᵢ·q where the epoch sees each of the truth's pier sample points "
        "(faces at 5–39 m and the top centre). Accepted epochs, the reference left out.\n\n";
    const ErrorSummary& top = r.registration_top_error;
    const ErrorSummary& any = r.registration_max_error;
    if (top.n == 0) {
        md += "Not computed: no accepted registration with a truth file.\n";
    } else {
        std::int64_t used_min = 1 << 30, used_max = 0;
        double rms_max = 0;
        std::vector<double> own_rms;
        for (const RegistrationCheck& x : r.registration) {
            if (!x.accepted || x.is_reference) continue;
            used_min = std::min(used_min, x.targets_used);
            used_max = std::max(used_max, x.targets_used);
            rms_max = std::max(rms_max, x.target_rms_m);
            own_rms.push_back(x.target_rms_m);
        }
        std::sort(own_rms.begin(), own_rms.end());
        md += "| quantity | epochs | bias | RMS | max |\n|---|---|---|---|---|\n";
        md +=
            fmt::format("| error at the pier's top centre (mm) | {} | ({}, {}, {}) | {} | {} |\n",
                        top.n, fmt::format("{:+.3f}", r.bias_vector_mm[0]),
                        fmt::format("{:+.3f}", r.bias_vector_mm[1]),
                        fmt::format("{:+.3f}", r.bias_vector_mm[2]), mm(top.rms), mm(top.max_abs));
        md += fmt::format("| largest error over the pier samples (mm) | {} | | {} | {} |\n", any.n,
                          mm(any.rms), mm(any.max_abs));
        md += fmt::format(
            "| targets' residual RMS, the registration's own (mm) | {} | | median {} | {} |\n\n",
            own_rms.size(), mm(own_rms[own_rms.size() / 2]), mm(rms_max));
        md += fmt::format("Targets used per accepted epoch: {}–{}.\n", used_min, used_max);
    }
    std::vector<std::string> rejected;
    for (const RegistrationCheck& x : r.registration) {
        if (x.status == "rejected" || x.status == "failed") {
            rejected.push_back(fmt::format("{} ({}): {}", epoch_name(r, x.truth_epoch), x.status,
                                           x.reason.substr(0, 160)));
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
    md += others.empty() ? std::string("No other target was excluded.\n")
                         : fmt::format("Also excluded, though the truth did not move them: {}.\n",
                                       fmt::join(others, ", "));
    md += "\n![registration](registration.png)\n";

    // ---- Zones ----
    md +=
        "\n## Zones against the truth\n\n"
        "Each zone quantity against the true change of the zone since the reference epoch "
        "(the truth's displacement field, docs/simulator.md \"Deformation\", over the zone's "
        "part of the pier face): M3C2 along the face's outward normal (+ towards the "
        "scanner), keypoint components against the mean true vector. Error = value − truth.\n\n";
    for (const ZoneCheck& z : r.zones) {
        md += fmt::format("### {}\n\n", z.zone);
        if (!z.face) {
            md += "Not on one face of the pier: no truth to compare with.\n\n";
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
        const std::string png = "zone_" + [&] {
            std::string s;
            for (const char ch : z.zone)
                s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
            return s;
        }() + ".png";
        for (const auto& p : files.plots) {
            if (p.filename() == png) md += fmt::format("\n![{}]({})\n", z.zone, png);
        }
        md += "\n";
    }

    // ---- Alarms ----
    md += "## Alarms against the truth\n\n";
    md += r.step ? fmt::format(
                       "Step event (truth): pier points at z {:g}–{:g} m move by ({:+.1f}, "
                       "{:+.1f}, {:+.1f}) mm from {}.\n\n",
                       r.step->z_min, r.step->z_max, 1e3 * r.step->displacement.x(),
                       1e3 * r.step->displacement.y(), 1e3 * r.step->displacement.z(),
                       epoch_name(r, r.step->since_epoch))
                 : std::string("No step event in the truth.\n\n");
    if (r.alarms.empty()) md += "No alarm rules configured.\n";
    for (const AlarmCheck& a : r.alarms) {
        md += fmt::format("- **{}** ({} in zone {}{}): ", a.rule, a.quantity, a.zone,
                          a.step_zone ? ", moved by the step" : ", not moved by the step");
        if (!a.evaluated) {
            md += fmt::format(
                "not evaluated — the database has no `{}` rows for zone {} (the "
                "stage that computes them did not run).\n",
                a.quantity, a.zone);
            continue;
        }
        if (a.step_epoch) {
            md += a.latency_epochs
                      ? fmt::format("first raised at {}, a detection latency of {} epoch(s); ",
                                    epoch_name(r, *a.first_raise_epoch), *a.latency_epochs)
                      : std::string("the step was **not** detected; ");
        }
        md += fmt::format("{} false alarm(s).\n", a.false_alarms);
        for (const auto& e : a.events) md += "  - " + e + "\n";
    }

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
        for (const ZoneQuantityCheck& q : z.quantities) {
            md += fmt::format("    tlsmon query series {} --zone {} --quantity {}\n", db, z.zone,
                              q.quantity);
            break;
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
