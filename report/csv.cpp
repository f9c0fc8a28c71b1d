// The report's CSV tables: one row per epoch (registration), per zone, quantity and epoch
// (zones), per alarm rule (alarms). Lengths in millimetres, times ISO-8601 UTC.
#include "core/csv.hpp"

#include <fmt/format.h>

#include <fstream>

#include "core/error.hpp"
#include "core/utc_time.hpp"
#include "report/output.hpp"

namespace tlsmon::report {

namespace {

std::string mm(const std::optional<double>& v) {
    return v ? fmt::format("{:.4f}", 1e3 * *v) : std::string();
}

std::string joined(const std::vector<std::string>& v, const char* sep) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
    return out;
}

void write_file(const std::filesystem::path& path, const std::string& text, ReportFiles& files) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) throw Error("cannot write " + path.string());
    files.csv.push_back(path);
}

}  // namespace

void write_csv(const RunReport& r, const std::filesystem::path& out, ReportFiles& files) {
    std::string reg =
        "epoch_id,truth_epoch,acquired,status,reference,registered,accepted,targets_used,"
        "target_rms_mm,excluded_targets,top_error_x_mm,top_error_y_mm,top_error_z_mm,"
        "top_error_mm,pier_max_error_mm,registration_sigma_3d_mm,reason\n";
    for (const RegistrationCheck& c : r.registration) {
        const auto top = c.top_error;
        reg += fmt::format(
            "{},{},{},{},{},{},{},{},{:.4f},{},{},{},{},{},{},{},{}\n", c.id, c.truth_epoch,
            format_utc(c.acquired), c.status, c.is_reference ? 1 : 0, c.registered ? 1 : 0,
            c.accepted ? 1 : 0, c.targets_used, 1e3 * c.target_rms_m, joined(c.excluded, " "),
            top ? mm(top->x()) : "", top ? mm(top->y()) : "", top ? mm(top->z()) : "",
            top ? mm(top->norm()) : "", mm(c.max_error), mm(c.zone_sigma_m), csv_field(c.reason));
    }
    write_file(out / "registration.csv", reg, files);

    std::string zones =
        "zone,quantity,epoch_id,truth_epoch,acquired,value_mm,lod_mm,truth_mm,"
        "error_mm,significant,compared_with\n";
    for (const ZoneCheck& z : r.zones) {
        for (const ZoneQuantityCheck& q : z.quantities) {
            for (const auto& row : q.rows) {
                zones += fmt::format("{},{},{},{},{},{:.4f},{},{},{},{},{}\n", csv_field(z.zone),
                                     q.quantity, row.id, row.truth_epoch, format_utc(row.acquired),
                                     1e3 * row.value, mm(row.lod), mm(row.truth),
                                     row.truth ? mm(row.value - *row.truth) : std::string(),
                                     row.significant ? 1 : 0, csv_field(q.truth_kind));
            }
        }
    }
    write_file(out / "zones.csv", zones, files);

    std::string alarms =
        "rule,zone,quantity,evaluated,step_zone,step_truth_epoch,first_raise_truth_epoch,"
        "first_raise_epoch_id,latency_epochs,false_alarms,events\n";
    for (const AlarmCheck& a : r.alarms) {
        const auto opt = [](const std::optional<int>& v) {
            return v ? std::to_string(*v) : std::string();
        };
        const auto id =
            a.first_raise_epoch ? r.epoch_id.find(*a.first_raise_epoch) : r.epoch_id.end();
        alarms += fmt::format(
            "{},{},{},{},{},{},{},{},{},{},{}\n", csv_field(a.rule), csv_field(a.zone), a.quantity,
            a.evaluated ? 1 : 0, a.step_zone ? 1 : 0, opt(a.step_epoch), opt(a.first_raise_epoch),
            id != r.epoch_id.end() ? std::to_string(id->second) : std::string(),
            opt(a.latency_epochs), a.false_alarms, csv_field(joined(a.events, "; ")));
    }
    write_file(out / "alarms.csv", alarms, files);
}

}  // namespace tlsmon::report
