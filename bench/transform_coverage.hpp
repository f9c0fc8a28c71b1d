#pragma once
// Shared by the benches that score a registration's σ over independent series
// (bench/registration_coverage.cpp for the targets, bench/icp_coverage.cpp for the ICP on
// stable regions, bench/stable_area_coverage.cpp for the stable areas): the scenes by name,
// and the scores of one transformation per series — its six parameters against the exact
// map, and its error at two points of the pier's south face (mid-height and 1 m below its
// top) in x, y and z against the covariance propagated there, what every zone figure there
// carries — printed as `tlsmon calibration` does.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/registration/registration_error.hpp"
#include "algorithms/registration/rigid_transform.hpp"
#include "demo/scene.hpp"
#include "report/calibration.hpp"
#include "simulator/scene_file.hpp"
#include "tests/support/simulated_targets.hpp"

namespace tlsmon::bench {

// `demo` (the scene of `tlsmon demo`: the `small` preset at 0.05° with five spheres), `pier`,
// `hochmosel`, or a scene file.
inline sim::Site scene_named(const std::string& name) {
    if (name == "demo")
        return parse_scene_file(scene_file_text(demo_scene("small", 96)), "demo", std::nullopt);
    if (name == "pier") return sim::preset_pier();
    if (name == "hochmosel") return sim::preset_hochmosel();
    return load_scene_file(name, std::nullopt);
}

// The six parameters (ω, φ, κ, tx, ty, tz) of an exact map, and of an estimate.
inline Eigen::Vector<double, 6> parameters_of(const Eigen::Affine3d& exact) {
    const Eigen::Vector3d angles = registration::euler_from_rotation(exact.linear());
    return {angles.x(),
            angles.y(),
            angles.z(),
            exact.translation().x(),
            exact.translation().y(),
            exact.translation().z()};
}
inline Eigen::Vector<double, 6> parameters_of(const registration::RigidTransform& T) {
    return {T.omega, T.phi, T.kappa, T.translation.x(), T.translation.y(), T.translation.z()};
}

inline void print_coverage_row(const report::CoverageRow& r) {
    const double k = r.display_scale();
    if (r.mixed_units())
        std::printf("  %-6s %5zu  %35s", r.part.c_str(), r.n, "");
    else
        std::printf("  %-6s %5zu  %+8.3f %8.3f %8.3f %8.2f", r.part.c_str(), r.n, k * r.error.bias,
                    k * r.error.rms, k * r.rms_sigma,
                    r.rms_sigma > 0 ? r.error.rms / r.rms_sigma : 0.0);
    std::printf("  %5.1f %%  %4.1f-%4.1f  %-15s %5.1f %%  %4.1f-%4.1f  %s\n", 100 * r.coverage68(),
                100 * r.band68.lower, 100 * r.band68.upper, report::to_string(r.verdict68),
                100 * r.coverage95(), 100 * r.band95.lower, 100 * r.band95.upper,
                report::to_string(r.verdict95));
}

class TransformScores {
  public:
    explicit TransformScores(const sim::Pier& pier) {
        const double mid_x = 0.5 * (pier.x0 + pier.x1);
        at_pier_ = {{"mid", {mid_x, pier.y0, 0.5 * pier.height}},
                    {"top", {mid_x, pier.y0, pier.height - 1}}};
        pier_figures_.resize(3 * at_pier_.size());
    }

    // T (epoch -> reference) against `exact`, the map of the epoch's coordinates into the
    // reference's.
    void add(const Eigen::Affine3d& exact, const registration::RigidTransform& T) {
        const Eigen::Vector<double, 6> truth = parameters_of(exact);
        const Eigen::Vector<double, 6> value = parameters_of(T);
        const auto sigma = T.sigmas();
        for (int p = 0; p < 6; ++p) {
            figures_[p].push_back({value(p) - truth(p), sigma(p)});
            truths_[p].push_back(truth(p));
        }
        // Where T puts the epoch's point that truly lies at y, less y, against the covariance
        // propagated there (registration_error.hpp), per axis.
        const test::RegistrationError error_at(exact, T);
        for (std::size_t q = 0; q < at_pier_.size(); ++q) {
            const Eigen::Vector3d error = error_at(at_pier_[q].second);
            const Eigen::Matrix3d S = registration::registration_covariance_at(
                T, error_at.exact_inverse * at_pier_[q].second);
            for (int a = 0; a < 3; ++a)
                pier_figures_[3 * q + std::size_t(a)].push_back({error(a), std::sqrt(S(a, a))});
        }
    }

    // Every parameter and point, or (`pooled_only`) the two pooled rows.
    void print(const std::string& method, bool pooled_only = false) const {
        std::printf("  %-6s %5s  %8s %8s %8s %8s  %-30s %s\n", "param", "n", "bias", "rms", "rms σ",
                    "rms/σ", "within σ (band, verdict)", "within 1.96 σ");
        static constexpr std::array<const char*, 6> names{"omega", "phi", "kappa",
                                                          "tx",    "ty",  "tz"};
        std::vector<report::ScoredFigure> pooled;
        for (int p = 0; p < 6; ++p) {
            if (!pooled_only)
                print_coverage_row(report::coverage_of(method, names[p], figures_[p]));
            pooled.insert(pooled.end(), figures_[p].begin(), figures_[p].end());
        }
        print_coverage_row(report::coverage_of(method, "all", pooled));
        if (!pooled_only) {
            std::printf("  (angles in µrad, lengths in mm)\n");
            print_gains(names);
            std::printf("the transformation's error at the pier's south face, per axis (mm):\n");
        }
        std::vector<report::ScoredFigure> pier_pooled;
        for (std::size_t q = 0; q < at_pier_.size(); ++q) {
            for (std::size_t a = 0; a < 3; ++a) {
                const auto& f = pier_figures_[3 * q + a];
                if (!pooled_only)
                    print_coverage_row(
                        report::coverage_of(method, at_pier_[q].first + " " + "xyz"[a], f));
                pier_pooled.insert(pier_pooled.end(), f.begin(), f.end());
            }
        }
        print_coverage_row(report::coverage_of(method, "pier", pier_pooled));
    }

  private:
    // The error's least-squares slope on the true motion, with its standard error: an error
    // that follows the motion (a gain other than 1) is no noise, and no σ from residuals
    // covers it.
    void print_gains(const std::array<const char*, 6>& names) const {
        std::printf("error against the true motion: slope ± its SE, correlation, RMS motion\n");
        for (int p = 0; p < 6; ++p) {
            const auto& x = truths_[p];
            const auto& f = figures_[p];
            const double n = double(x.size());
            if (n < 3) continue;
            double mx = 0, my = 0;
            for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += f[i].error / n;
            double sxx = 0, sxy = 0, syy = 0;
            for (std::size_t i = 0; i < x.size(); ++i) {
                sxx += (x[i] - mx) * (x[i] - mx);
                sxy += (x[i] - mx) * (f[i].error - my);
                syy += (f[i].error - my) * (f[i].error - my);
            }
            const double slope = sxy / sxx;
            const double se = std::sqrt((syy - slope * sxy) / (n - 2) / sxx);
            std::printf("  %-6s %+8.4f ± %.4f  r %+5.2f  %9.3g\n", names[p], slope, se,
                        sxy / std::sqrt(sxx * syy), std::sqrt(sxx / n + mx * mx));
        }
    }

    std::array<std::vector<report::ScoredFigure>, 6> figures_;
    std::array<std::vector<double>, 6> truths_;
    std::vector<std::pair<std::string, Eigen::Vector3d>> at_pier_;
    std::vector<std::vector<report::ScoredFigure>> pier_figures_;
};

}  // namespace tlsmon::bench
