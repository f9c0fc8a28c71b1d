// Campaign cloud benchmark (reported, not asserted), 2 threads: the TLS reference's local
// planes, segments and planes, then compare_campaign (pipeline/campaign_comparison.hpp) step
// by step — the coarse frame on planes (the default, auto), the global registration, the
// ground, verticality at the study's 0.10 m, the two-stage segmentation, segment-wise ICP
// with the test of whether the segments moved as one, and C2C of every point — for an
// unstructured cloud like a personal laser scanner's: a ground 60 × 30 m, two piers
// (3 × 6 m, 20 m high, four faces each) and a deck (60 × 12 m, its soffit and top), points
// drawn uniformly over the surfaces with N(0, 15 mm) noise along their normals, the second
// pier's stretch of the walk drifted by 10 mm; the reference the same scene with half as many
// points and 2 mm noise.
// Usage: bench_campaign_segmentation [MILLION_POINTS=5] [THINNING_M=0.03]
#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "pipeline/campaign_comparison.hpp"

namespace {

using Eigen::Vector3d;

struct Face {
    Vector3d origin, a, b;  // the rectangle origin + s·a + t·b, s, t in [0, 1]
    double area() const { return a.cross(b).norm(); }
};

std::vector<Face> scene() {
    std::vector<Face> f = {{{0, 0, 0}, {60, 0, 0}, {0, 30, 0}},      // ground
                           {{0, 9, 20}, {60, 0, 0}, {0, 12, 0}},     // deck soffit
                           {{0, 9, 21.5}, {60, 0, 0}, {0, 12, 0}}};  // deck top
    for (const double x0 : {18.0, 39.0}) {
        const Vector3d o(x0, 12, 0), up(0, 0, 20);
        f.push_back({o, {3, 0, 0}, up});
        f.push_back({o + Vector3d(0, 6, 0), {3, 0, 0}, up});
        f.push_back({o, {0, 6, 0}, up});
        f.push_back({o + Vector3d(3, 0, 0), {0, 6, 0}, up});
    }
    return f;
}

// n points drawn uniformly over the faces, N(0, σ) along their normals.
std::vector<Vector3d> sample(const std::vector<Face>& faces, std::size_t n, double sigma,
                             unsigned seed) {
    double total_area = 0;
    for (const auto& f : faces) total_area += f.area();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<Vector3d> cloud;
    cloud.reserve(n);
    for (const auto& f : faces) {
        const auto k = static_cast<std::size_t>(double(n) * f.area() / total_area);
        const Vector3d normal = f.a.cross(f.b).normalized();
        for (std::size_t i = 0; i < k; ++i)
            cloud.push_back(f.origin + U(rng) * f.a + U(rng) * f.b + noise(rng) * normal);
    }
    return cloud;
}

// The process's peak resident memory (VmHWM), GB.
double peak_gb() {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / (1024.0 * 1024.0);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace tlsmon;
    const double million = argc > 1 ? std::atof(argv[1]) : 5.0;
    CampaignParameters p;
    p.threads = 2;
    if (argc > 2) p.thinning = std::atof(argv[2]);
    const auto faces = scene();
    std::vector<Vector3d> cloud = sample(faces, static_cast<std::size_t>(million * 1e6), 0.015, 1);
    // The second pier's stretch of the walk: 10 mm off along y.
    for (auto& q : cloud)
        if (q.x() > 38.5 && q.x() < 42.5 && q.z() > 0.5 && q.z() < 19.5) q.y() += 0.010;
    const std::vector<Vector3d> reference =
        sample(faces, static_cast<std::size_t>(million * 0.5e6), 0.002, 2);
    std::printf("campaign %zu points, reference %zu points, thinning %.3f m\n", cloud.size(),
                reference.size(), p.thinning);

    auto t0 = std::chrono::steady_clock::now();
    double c0 = bench::process_cpu_seconds();
    const CampaignReference prepared(reference, p);
    std::printf("reference local planes and segments: %.1f s wall (segments %.1f s), %.1f s CPU\n",
                bench::seconds_since(t0), prepared.seconds, bench::process_cpu_seconds() - c0);

    t0 = std::chrono::steady_clock::now();
    c0 = bench::process_cpu_seconds();
    const CampaignComparison c = compare_campaign(prepared, cloud, p);
    const double wall = bench::seconds_since(t0), cpu = bench::process_cpu_seconds() - c0;
    const auto& s = c.seconds;
    std::printf(
        "compare_campaign: %.1f s wall, %.1f s CPU (%zu voxels)\n  coarse frame (%s, %zu of %zu "
        "planes on the reference's %zu) %.1f s, global registration %.1f s, ground %.1f s, "
        "verticality %.1f s, segmentation %.1f s, matching %.1f s, segment-wise ICP and the test "
        "%.1f s, C2C %.1f s\n",
        wall, cpu, c.thinned, coarse_name(c.coarse.used), c.coarse.support,
        c.coarse.campaign_planes, c.coarse.reference_planes, s.coarse, s.global, s.ground,
        s.verticality, s.segmentation, s.matching, s.segments, s.c2c);
    std::printf("global: %zu pairs, %d iterations, rank %d\n", c.global.pairs, c.global.iterations,
                c.global.rank());
    std::printf("ground %zu points; %zu segments (spacing %.1f mm)\n", c.ground.ground_points,
                c.segments.size(), 1e3 * c.segmentation.spacing);
    const auto& t = c.consistency;
    std::printf("%zu segments registered, T = %.1f (dof %d), segments differ: %s\n", t.segments,
                t.statistic, t.dof, t.differ ? "yes" : "no");
    for (std::size_t k = 0; k < std::min<std::size_t>(c.segments.size(), 12); ++k) {
        const auto& r = c.segments[k].transform;
        if (!r.registered()) continue;
        std::printf(
            "  segment %zu: %s, %zu points, rank %d, t = (%+.1f, %+.1f, %+.1f) mm at (%.0f, %.0f, "
            "%.0f), p = %.2g\n",
            k, campaign::class_name(c.segments[k].segment.kind), c.segments[k].segment.points,
            r.rank(), 1e3 * r.parameters(3), 1e3 * r.parameters(4), 1e3 * r.parameters(5),
            r.centroid.x(), r.centroid.y(), r.centroid.z(), t.segment_p_value[k]);
    }
    std::printf("C2C (local plane): mean %.1f mm, σ %.1f mm, 95 %% %.1f mm, %zu without\n",
                1e3 * c.c2c_all.mean, 1e3 * c.c2c_all.sigma, 1e3 * c.c2c_all.p95,
                c.c2c_all.missing);
    std::printf("peak resident memory %.2f GB\n", peak_gb());
    return 0;
}
