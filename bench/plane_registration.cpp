// Registration on planes and the congruence test on the synthetic site of
// tests/support/synthetic_planes.hpp, on seeds the tests do not use (nothing is tuned: α is
// 5 %, the planes' covariances come from the a-priori 2 mm): how often the drift lies within
// 2σ, the variance factor, the rate of epochs with a plane flagged when nothing moved, how
// often a foundation face moved 3 mm and tilted 20″ is found, and the time of the
// adjustment and of the congruence test for 12 and for 200 planes; then the plane detection
// on one epoch of the simulator's `pier` scene (its whole grid).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <vector>

#include "algorithms/registration/plane_detection.hpp"
#include "simulator/render.hpp"
#include "tests/support/synthetic_planes.hpp"

namespace {

using namespace tlsmon::registration;
using namespace tlsmon::test::synthetic_planes;

struct Coverage {
    int components = 0, within = 0;
    double sum_sq_top = 0;
    int epochs = 0;
    void add(const RigidTransform& T, const Eigen::Affine3d& truth) {
        const Eigen::AngleAxisd d(T.rotation * truth.rotation().transpose());
        Eigen::Matrix<double, 6, 1> err;
        err << d.angle() * d.axis(), T.translation - truth.translation();
        for (int i = 0; i < 6; ++i) {
            ++components;
            within += std::fabs(err(i)) <= 2.0 * std::sqrt(T.small_rotation_covariance(i, i));
        }
        const Eigen::Vector3d top(10, 45, 40);
        sum_sq_top += (T.apply(truth.inverse() * top) - top).squaredNorm();
        ++epochs;
    }
};

double cpu_seconds() {
    return double(std::clock()) / CLOCKS_PER_SEC;
}

// `n` patches with random normals 10–100 m away, for the timing of a plane-rich scan.
std::vector<PlaneCorrespondence> many_planes(int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1), r(10, 100);
    const Eigen::Affine3d station = drift(rng);
    std::vector<PlaneCorrespondence> out;
    while (int(out.size()) < n) {
        const Eigen::Vector3d dir(u(rng), u(rng), 0.3 * u(rng));
        const Eigen::Vector3d normal(u(rng), u(rng), u(rng));
        if (dir.norm() < 0.1 || normal.norm() < 0.1) continue;
        const SitePlane s{normal.normalized(), r(rng) * dir.normalized()};
        const Eigen::Affine3d I = Eigen::Affine3d::Identity();
        out.push_back({fit_plane(sample(s, I, I, rng), kSigma),
                       fit_plane(sample(s, I, station.inverse(), rng), kSigma)});
    }
    return out;
}

}  // namespace

int main() {
    std::mt19937 rng(9001);
    const CongruenceParams params;

    Coverage still;
    int flagged = 0;
    const int calm_epochs = 1000;
    for (int k = 0; k < calm_epochs; ++k) {
        const Epoch e = epoch(rng);
        const CongruenceResult r = congruence_test(e.planes, {});
        flagged += !r.moved.empty();
        still.add(adjust_planes(e.planes, {}, {}).transform, e.truth);
    }
    std::printf(
        "nothing moved, %d epochs of 12 planes: drift within 2 sigma %.1f %% of %d components; "
        "error at the pier top RMS %.3f mm; epochs with a plane flagged %.1f %% (alpha %.0f %%)\n",
        calm_epochs, 100.0 * still.within / still.components, still.components,
        1e3 * std::sqrt(still.sum_sq_top / still.epochs), 100.0 * flagged / calm_epochs,
        100.0 * params.alpha);

    const Eigen::Vector3d c = site_planes()[5].centre;
    const Eigen::Affine3d motion = Eigen::Translation3d(0, -0.003, 0) * Eigen::Translation3d(c) *
                                   Eigen::AngleAxisd(20 * kArcsec, Eigen::Vector3d::UnitX()) *
                                   Eigen::Translation3d(-c);
    Coverage moved;
    int found = 0, others = 0;
    double shift = 0, tilt = 0;  // sums over the epochs where the face was found
    const int moved_epochs = 500;
    for (int k = 0; k < moved_epochs; ++k) {
        const Epoch e = epoch(rng, 5, motion);
        const CongruenceResult r = congruence_test(e.planes, {});
        if (!r.moved.empty() && r.moved.front() == 5) {
            ++found;
            shift += r.adjustment.planes[5].shift();
            // towards +z: the 20″ about +x turns (0, −1, 0) into (0, −cos, −sin)
            tilt += (r.adjustment.transform.rotation * e.planes[5].epoch.normal -
                     e.planes[5].reference.normal)
                        .z();
        }
        others += int(r.moved.size()) - (!r.moved.empty() && r.moved.front() == 5);
        moved.add(r.adjustment.transform, e.truth);
    }
    std::printf(
        "foundation face moved 3 mm, tilted 20\", %d epochs: found %.1f %% (mean shift %+.3f mm, "
        "tilt %+.1f\"), other planes flagged %d; datum within 2 sigma %.1f %%; error at the pier "
        "top RMS %.3f mm\n",
        moved_epochs, 100.0 * found / moved_epochs, 1e3 * shift / found, tilt / found / kArcsec,
        others, 100.0 * moved.within / moved.components,
        1e3 * std::sqrt(moved.sum_sq_top / moved.epochs));

    for (const int n : {12, 200}) {
        const auto planes = n == 12 ? epoch(rng).planes : many_planes(n, rng);
        const int reps = n == 12 ? 2000 : 100;
        const auto w0 = std::chrono::steady_clock::now();
        const double c0 = cpu_seconds();
        for (int k = 0; k < reps; ++k) congruence_test(planes, {});
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        const double cpu = cpu_seconds() - c0;
        std::printf(
            "congruence test (adjustment and global test) on %d planes: %.3f ms wall, %.3f ms CPU "
            "each\n",
            n, 1e3 * wall / reps, 1e3 * cpu / reps);
    }

    const auto rendered = tlsmon::sim::render_epoch(tlsmon::sim::preset_pier(), 0, 0.0, 2);
    for (int run = 0; run < 3; ++run) {
        const auto w0 = std::chrono::steady_clock::now();
        const double c0 = cpu_seconds();
        const auto planes = detect_planes(rendered.scan);
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        std::size_t in_planes = 0, large = 0;
        for (const auto& d : planes) {
            in_planes += d.points.size();
            large += d.points.size() >= 1000;
        }
        std::printf(
            "plane detection, pier epoch (%zu points, %u x %u grid): %zu planes (%zu of >= 1000 "
            "points) holding %.1f %% of the points; %.2f s wall, %.2f s CPU\n",
            rendered.scan.size(), rendered.scan.grid->rows, rendered.scan.grid->columns,
            planes.size(), large, 100.0 * in_planes / rendered.scan.size(), wall,
            cpu_seconds() - c0);
    }
}
