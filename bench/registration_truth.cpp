// The registration stage against the simulator's truth, on scans rendered once by
// `tlsmon simulate` (docs/simulator.md): `bench_registration_truth SITE.toml E0.ptx E1.ptx ...
// [--truth-air]`, each scan with its `<name>.truth.json` beside it. Prints
//   - per epoch and target: how it was found and its centre's error against the truth's
//     centre (header_to_true · measured − truth), along the line of sight, across it
//     horizontally and across it vertically, each with the σ the fit gives;
//   - per later epoch: the registration onto the first (its status, s0², targets used) and
//     its error at the pier against the exact answer H₀⁻¹·Hᵢ (RMS over the pier's faces
//     every 2.5 m, and at the top corner with the predicted 3-D σ there).
// `--truth-air` scales every range back by the truth's own range scale, as exact meteo
// would, to tell the atmosphere's share from the fits'.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "algorithms/registration/registration_error.hpp"
#include "config/config.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/sha256.hpp"

namespace {

using namespace tlsmon;

struct Truth {
    Eigen::Affine3d header_to_true = Eigen::Affine3d::Identity();
    std::map<std::string, Eigen::Vector3d> centres;
    Eigen::Vector3d pier_min, pier_max;
    double range_scale = 1.0;
};

Truth read_truth(const std::string& ptx) {
    const std::string path = ptx.substr(0, ptx.size() - 4) + ".truth.json";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    const auto j = nlohmann::json::parse(in);
    Truth t;
    const auto& h = j.at("scanner").at("header_to_true");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = h.at(r).at(c).get<double>();
    t.header_to_true.matrix() = m;
    for (const auto& tj : j.at("targets")) {
        const auto& c = tj.at("centre");
        t.centres[tj.at("name").get<std::string>()] =
            Eigen::Vector3d(c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>());
    }
    const auto& p = j.at("pier");
    t.pier_min = Eigen::Vector3d(p.at("x0").get<double>(), p.at("y0").get<double>(), 0.0);
    t.pier_max = Eigen::Vector3d(p.at("x1").get<double>(), p.at("y1").get<double>(),
                                 p.at("height").get<double>());
    if (j.contains("atmosphere") && j.at("atmosphere").value("enabled", false))
        t.range_scale = j.at("atmosphere").at("range_scale").get<double>();
    return t;
}

// Error of a measured centre (header frame) against the truth, split along the line of sight
// from the scanner, across it horizontally and across it vertically; with the fit's σ in the
// same directions.
void print_centre(const TargetMeasurement& m, const Truth& truth, const Eigen::Vector3d& scanner) {
    if (!m.found()) {
        std::printf("    %-4s %-11s %6zu pts  %s\n", m.name.c_str(), m.status.c_str(), m.points,
                    m.reason.c_str());
        return;
    }
    const Eigen::Vector3d c_true = truth.centres.at(m.name);
    const Eigen::Vector3d e = truth.header_to_true * m.centre - c_true;
    const Eigen::Vector3d los = (c_true - scanner).normalized();
    const Eigen::Vector3d h = Eigen::Vector3d::UnitZ().cross(los).normalized();
    const Eigen::Vector3d v = los.cross(h);
    const Eigen::Matrix3d R = truth.header_to_true.linear();
    const Eigen::Matrix3d S = R * m.covariance * R.transpose();
    const auto sig = [&](const Eigen::Vector3d& d) { return std::sqrt(d.dot(S * d)); };
    std::printf(
        "    %-4s %6.1f m %6zu pts  error los %+7.3f (σ %.3f)  across %+7.3f (σ %.3f)  vertical "
        "%+7.3f (σ %.3f) mm\n",
        m.name.c_str(), (c_true - scanner).norm(), m.points, 1e3 * e.dot(los), 1e3 * sig(los),
        1e3 * e.dot(h), 1e3 * sig(h), 1e3 * e.dot(v), 1e3 * sig(v));
}

std::vector<Eigen::Vector3d> pier_points(const Truth& t) {
    std::vector<Eigen::Vector3d> p;
    for (double z = 0.0; z <= t.pier_max.z(); z += 2.5) {
        for (double x = t.pier_min.x(); x <= t.pier_max.x(); x += 2.5)
            p.emplace_back(x, t.pier_min.y(), z);
        for (double y = t.pier_min.y(); y <= t.pier_max.y(); y += 2.5)
            p.emplace_back(t.pier_min.x(), y, z);
    }
    return p;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> files;
    bool truth_air = false;
    for (int i = 2; i < argc; ++i) {
        if (std::strcmp(argv[i], "--truth-air") == 0)
            truth_air = true;
        else
            files.emplace_back(argv[i]);
    }
    if (argc < 3 || files.size() < 2) {
        std::fprintf(stderr,
                     "usage: bench_registration_truth SITE.toml E0.ptx E1.ptx ... [--truth-air]\n");
        return 2;
    }
    try {
        const RegistrationConfig config = pipeline_config(load_config(argv[1])).registration;
        std::vector<Truth> truths;
        ReferenceTargets reference;
        for (std::size_t i = 0; i < files.size(); ++i) {
            const HashedBytes content = read_file_hashed(files[i]);
            const std::vector<Scan> scans = parse_scans(content.bytes, files[i]);
            truths.push_back(read_truth(files[i]));
            const Truth& t = truths.back();
            const Eigen::Vector3d scanner = t.header_to_true * scans.front().scanner_position();
            std::printf("%s (range scale %+.2f ppm)\n", files[i].c_str(),
                        (t.range_scale - 1) * 1e6);
            RangeScales scales;
            if (truth_air) scales = {t.range_scale, truths.front().range_scale};
            if (i == 0) {
                reference = measure_reference_targets(config, scans);
                for (auto& m : reference.targets) {
                    if (truth_air && m.found())
                        m.centre = m.viewpoint + (m.centre - m.viewpoint) / t.range_scale;
                    print_centre(m, t, scanner);
                    if (truth_air && m.found())  // back as measured: the stage corrects it
                        m.centre = m.viewpoint + (m.centre - m.viewpoint) * t.range_scale;
                }
                continue;
            }
            const RegistrationResult r = register_epoch(config, reference, scans, {}, scales);
            for (auto m : r.measured) {
                if (truth_air && m.found())
                    m.centre = m.viewpoint + (m.centre - m.viewpoint) / t.range_scale;
                print_centre(m, t, scanner);
            }
            std::printf("  registration: %s%s%s, %d used, s0² %.2f, r %d\n",
                        name_of(r.tested.status), r.gate.empty() ? "" : ", gate: ", r.gate.c_str(),
                        r.used, r.tested.transform ? r.tested.transform->variance_factor : 0.0,
                        r.tested.transform ? r.tested.transform->redundancy : 0);
            for (std::size_t k = 0; k < r.tested.targets.size(); ++k) {
                const auto& v = r.tested.targets[k];
                if (v.use == registration::TargetUse::not_usable) continue;
                std::printf("    %-4s %-16s T %7.2f (crit %.2f)  residual %.3f mm\n",
                            config.targets[k].name.c_str(), name_of(v.use), v.statistic, v.critical,
                            1e3 * v.residual.norm());
            }
            if (!r.tested.transform) continue;
            const auto& T = *r.tested.transform;
            const Eigen::Affine3d& H0 = truths.front().header_to_true;
            const Eigen::Affine3d& Hi = t.header_to_true;
            const auto pier = pier_points(t);
            double rms = 0;
            for (const auto& P : pier)
                rms += (T.apply(Hi.inverse() * P) - H0.inverse() * P).squaredNorm();
            rms = std::sqrt(rms / pier.size());
            const Eigen::Vector3d top = Hi.inverse() * pier.back();
            const Eigen::Vector3d e = T.apply(top) - H0.inverse() * pier.back();
            const Eigen::Matrix3d S = registration::registration_covariance_at(T, top);
            int within = 0;
            for (int k = 0; k < 3; ++k) within += std::fabs(e(k)) <= 2 * std::sqrt(S(k, k));
            std::printf(
                "  pier: RMS error %.3f mm; top corner error %.3f mm (x %+.3f y %+.3f z %+.3f), "
                "predicted 3-D σ %.3f mm, %d/3 components within 2σ\n",
                1e3 * rms, 1e3 * e.norm(), 1e3 * e.x(), 1e3 * e.y(), 1e3 * e.z(),
                1e3 * std::sqrt(S.trace()), within);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_registration_truth: %s\n", e.what());
        return 1;
    }
    return 0;
}
