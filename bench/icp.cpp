// The ICP on stable regions on one full `pier` epoch (≈ 6.8 M points, 0.013°), rendered in
// memory with drift (standing axis 60″, tilt 10″, translation σ 1.5 mm) against a reference
// epoch: `bench_icp [runs]`. Timed: the reference's stable surface (a reference-cache product,
// built once per reference), and the ICP of an epoch as the fallback from the identity —
// cropping the 6.8 M points to the stable regions, thinning, PCL's point-to-plane ICP, the
// adjustment and its covariance. Printed with the error at the pier's top against the truth.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "bench/bench_support.hpp"
#include "pipeline/icp_registration.hpp"
#include "simulator/render.hpp"
#include "simulator/stable_ground.hpp"

int main(int argc, char** argv) {
    using namespace tlsmon;
    const int runs = argc > 1 ? std::atoi(argv[1]) : 3;
    sim::Site site = sim::preset_pier();
    site.drift.yaw_amplitude_arcsec = 60.0;
    site.drift.tilt_amplitude_arcsec = 10.0;
    site.drift.translation_sigma = 0.0015;
    site.atmosphere.enabled = false;
    const auto seconds_since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    auto t = std::chrono::steady_clock::now();
    const sim::RenderedScan r0 = sim::render_epoch(site, 0, 0.0, 2);
    const sim::RenderedScan r1 = sim::render_epoch(site, 1, 6.5, 2);
    std::printf("rendered two epochs of %zu and %zu points in %.1f s\n", r0.scan.size(),
                r1.scan.size(), seconds_since(t));
    RegistrationConfig config;
    config.icp.mode = IcpMode::fallback;
    for (const auto& b : sim::stable_ground(site))
        config.icp.regions.push_back({b.name, b.min, b.max});
    const std::vector<Scan> e0{r0.scan}, e1{r1.scan};

    t = std::chrono::steady_clock::now();
    const StableSurface surface = build_stable_surface(config.icp, e0);
    std::printf("reference surface: %zu points in %zu regions, %zu thinned with normals, %.2f s\n",
                surface.cropped, config.icp.regions.size(), surface.sample.points.size(),
                seconds_since(t));

    // Wall time, and the process's CPU time (both threads): on a machine shared with other
    // work the wall time mostly measures the waiting.
    std::vector<double> crop, total, cpu;
    IcpMeasurement m;
    for (int run = 0; run < runs; ++run) {
        t = std::chrono::steady_clock::now();
        const auto inside = points_in_stable_regions(config.icp, e1, Eigen::Matrix4d::Identity());
        crop.push_back(seconds_since(t));
        t = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        m = measure_icp(config, surface, e1, Eigen::Matrix4d::Identity());
        cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
        total.push_back(seconds_since(t));
    }
    const auto u = bench::spread_of(cpu);
    std::printf("ICP of the epoch, CPU time: median %.3f s (min %.3f, max %.3f)\n", u.median, u.min,
                u.max);
    const auto c = bench::spread_of(crop), s = bench::spread_of(total);
    std::printf("crop of %zu points to the regions: median %.3f s (min %.3f, max %.3f)\n",
                r1.scan.size(), c.median, c.min, c.max);
    std::printf(
        "ICP of the epoch (crop, thin, ICP, adjustment): median %.3f s (min %.3f, max "
        "%.3f) over %zu runs; %zu points, %zu pairs, %d iterations, RMS %.2f mm, %s\n",
        s.median, s.min, s.max, s.runs, m.epoch_points, m.pairs, m.iterations, 1e3 * m.rms,
        m.refused.empty() ? "passed" : m.refused.c_str());
    if (m.transform) {
        const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
        const Eigen::Affine3d H0 = N * r0.pose_error.transform() * N.inverse();
        const Eigen::Affine3d H1 = N * r1.pose_error.transform() * N.inverse();
        const Eigen::Vector3d top(site.pier.x0, site.pier.y0, site.pier.height);
        const Eigen::Vector3d e = m.transform->apply(H1.inverse() * top) - H0.inverse() * top;
        std::printf("error at the pier's top: (%.3f, %.3f, %.3f) mm\n", 1e3 * e.x(), 1e3 * e.y(),
                    1e3 * e.z());
    }
    return 0;
}
