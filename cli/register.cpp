// `tlsmon register REFERENCE EPOCH --config SITE [--method M]`: the registration stage on two
// files, for an analyst checking a scan by hand. The reference's target centres (or planes)
// are measured in REFERENCE (or taken from the survey), EPOCH's against them, and the tested
// transformation printed: its JSON holds `matrix`, the 4×4 rows that map EPOCH's points into
// REFERENCE's frame, and with planes each matched plane's role and change. Nothing is stored
// and no exclusion carries over.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/file_pair.hpp"
#include "cli/transformation_columns.hpp"
#include "config/config.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline/registration_rows.hpp"
#include "pipeline/registration_stage.hpp"

namespace tlsmon {

namespace {

constexpr double kArcsecPerRad = 180.0 * 3600.0 / 3.141592653589793;

nlohmann::json describe_result(const RegistrationResult& r, const StageVerdict& v) {
    namespace reg = registration;
    nlohmann::json j;
    j["status"] = name_of(r.tested.status);
    j["accepted"] = r.accepted();
    // Accepted with a scaled covariance: why and by how much.
    j["reason"] = v.rejected.empty() && r.tested.status == reg::RegistrationStatus::accepted_scaled
                      ? r.tested.reason
                      : v.rejected;
    j["method"] = registration_method(r);
    j["targets_used"] = r.used;
    j["rms_m"] = r.rms;
    if (const auto& T = r.tested.transform) {
        const auto s = T->sigmas();
        const double parameters[6] = {
            T->omega, T->phi, T->kappa, T->translation.x(), T->translation.y(), T->translation.z()};
        for (int k = 0; k < 6; ++k) {
            j[kParameterColumns[k]] = parameters[k] * kParameterUnits[k];
            j[kSigmaColumns[k]] = s(k) * kParameterUnits[k];
        }
        j["quaternion_wxyz"] = {T->quaternion.w(), T->quaternion.x(), T->quaternion.y(),
                                T->quaternion.z()};
        j["variance_factor"] = T->variance_factor;
        j["redundancy"] = T->redundancy;
        const Eigen::Matrix4d M = T->matrix();
        nlohmann::json rows = nlohmann::json::array();
        for (int i = 0; i < 4; ++i) rows.push_back({M(i, 0), M(i, 1), M(i, 2), M(i, 3)});
        j["matrix"] = rows;
    }
    nlohmann::json targets = nlohmann::json::array();
    for (std::size_t i = 0; i < r.measured.size(); ++i) {
        const auto& m = r.measured[i];
        nlohmann::json t;
        t["name"] = m.name;
        t["kind"] = to_string(m.kind);
        t["status"] = m.status;
        t["reason"] = m.reason;
        t["reference_status"] = r.reference[i].status;
        if (i < r.tested.targets.size()) {
            const auto& v = r.tested.targets[i];
            t["use"] = name_of(v.use);
            if (std::isfinite(v.residual.norm())) {
                t["residual_m"] = {v.residual.x(), v.residual.y(), v.residual.z()};
            }
            if (std::isfinite(v.minimal_detectable_bias)) {
                t["minimal_detectable_bias_m"] = v.minimal_detectable_bias;
            }
        }
        if (m.found() || m.status == "excluded") {
            t["centre_m"] = {m.centre.x(), m.centre.y(), m.centre.z()};
        }
        targets.push_back(t);
    }
    j["targets"] = targets;
    if (r.planes) {
        nlohmann::json planes = plane_quality(*r.planes);
        nlohmann::json list = nlohmann::json::array();
        for (const auto& p : plane_rows(r)) {
            list.push_back({{"plane", p.plane},
                            {"zone", p.zone},
                            {"role", p.role},
                            {"normal", p.normal},
                            {"centroid_m", p.centroid},
                            {"tilt_u_arcsec", p.change[0] * kArcsecPerRad},
                            {"tilt_v_arcsec", p.change[1] * kArcsecPerRad},
                            {"shift_mm", 1e3 * p.change[2]},
                            {"sigma_tilt_u_arcsec", p.sigma[0] * kArcsecPerRad},
                            {"sigma_tilt_v_arcsec", p.sigma[1] * kArcsecPerRad},
                            {"sigma_shift_mm", 1e3 * p.sigma[2]},
                            {"statistic", p.statistic},
                            {"critical", p.critical},
                            {"significant", p.significant}});
        }
        planes["planes"] = list;
        j["planes"] = planes;
    }
    return j;
}

void print_table(const nlohmann::json& j) {
    std::vector<std::pair<std::string, Cell>> fields;
    std::vector<const char*> keys{"status", "accepted",     "reason",
                                  "method", "targets_used", "rms_m"};
    keys.insert(keys.end(), kParameterColumns.begin(), kParameterColumns.end());
    keys.insert(keys.end(), kSigmaColumns.begin(), kSigmaColumns.end());
    keys.insert(keys.end(), {"variance_factor", "redundancy"});
    for (const char* key : keys) {
        if (!j.contains(key)) continue;
        const auto& v = j[key];
        if (v.is_boolean()) {
            fields.emplace_back(key, v.get<bool>());
        } else if (v.is_number_integer()) {
            fields.emplace_back(key, v.get<std::int64_t>());
        } else if (v.is_number()) {
            fields.emplace_back(key, v.get<double>());
        } else {
            fields.emplace_back(key, v.get<std::string>());
        }
    }
    print_fields(std::cout, fields, OutputFormat::table);
    if (j.contains("matrix")) {
        std::cout << "matrix (epoch -> reference):\n";
        for (const auto& row : j["matrix"]) {
            std::cout << fmt::format("  {:14.9f} {:14.9f} {:14.9f} {:14.6f}\n",
                                     row[0].get<double>(), row[1].get<double>(),
                                     row[2].get<double>(), row[3].get<double>());
        }
    }
    Table t{{"target", "kind", "status", "use", "residual_mm", "reason"}, {}};
    for (const auto& g : j["targets"]) {
        std::string residual;
        if (g.contains("residual_mm")) {
            residual =
                fmt::format("{:.3f} {:.3f} {:.3f}", g["residual_mm"][0].get<double>(),
                            g["residual_mm"][1].get<double>(), g["residual_mm"][2].get<double>());
        }
        t.rows.push_back({g["name"].get<std::string>(), g["kind"].get<std::string>(),
                          g["status"].get<std::string>(), g.value("use", std::string()), residual,
                          g["reason"].get<std::string>()});
    }
    print(std::cout, t, OutputFormat::table);
    if (!j.contains("planes")) return;
    const auto& planes = j["planes"];
    std::cout << fmt::format(
        "planes: {} in the reference, {} in the epoch, {} matched: {} in the datum, {} moved, "
        "{} in zones{}\n",
        planes["reference_planes"].get<std::size_t>(), planes["epoch_planes"].get<std::size_t>(),
        planes["matched"].get<std::size_t>(), planes["in_datum"].get<std::size_t>(),
        planes["moved"].get<std::size_t>(), planes["monitored"].get<std::size_t>(),
        planes["used"].get<bool>() ? "" : "; not used: " + planes["refused"].get<std::string>());
    Table p{{"plane", "zone", "role", "tilt_u_arcsec", "tilt_v_arcsec", "shift_mm",
             "sigma_shift_mm", "statistic", "significant"},
            {}};
    for (const auto& g : planes["planes"]) {
        p.rows.push_back({g["plane"].get<std::int64_t>(), g["zone"].get<std::string>(),
                          g["role"].get<std::string>(), g["tilt_u_arcsec"].get<double>(),
                          g["tilt_v_arcsec"].get<double>(), g["shift_mm"].get<double>(),
                          g["sigma_shift_mm"].get<double>(), g["statistic"].get<double>(),
                          g["significant"].get<bool>()});
    }
    if (!p.rows.empty()) print(std::cout, p, OutputFormat::table);
}

}  // namespace

int run_register(const RegisterOptions& o) {
    bool accepted = false;
    const int code = run_reporting_errors("register", [&] {
        Config config = load_config(o.config);
        if (!o.method.empty()) {
            const auto method = registration_method_named(o.method);
            if (!method) throw Error("--method " + o.method + ": not a registration method");
            config.registration.method = *method;
        }
        const RegistrationConfig rc = pipeline_config(config).registration;
        if (!can_register(rc)) {
            throw ConfigError(o.config + ": " + kNoRegistrationWarning);
        }
        // The registration stage itself, with each file's meteo sidecar when it has one
        // (cli/file_pair.hpp).
        const FilePair pair = read_files(o.reference, o.epoch, config);
        RegistrationResult r;
        const StageVerdict v = register_file_pair(pair, config, r);
        accepted = r.accepted();
        const nlohmann::json j = describe_result(r, v);
        if (o.format == OutputFormat::json) {
            std::cout << j.dump(2) << '\n';
        } else {
            print_table(j);
        }
    });
    if (code != 0) return code;
    return accepted ? 0 : 3;
}

}  // namespace tlsmon
