// Campaign cloud segmentation benchmark (reported, not asserted): verticality at the study's
// 0.10 m and the two-stage segmentation (algorithms/campaign/) of an unstructured cloud like
// a personal laser scanner's, 2 threads: a ground 60 × 30 m, two piers (3 × 6 m, 20 m high,
// four faces each) and a deck (60 × 12 m, its soffit and top), points drawn uniformly over
// the surfaces with N(0, 15 mm) noise along their normals.
// Usage: bench_campaign_segmentation [MILLION_POINTS=5]
#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <vector>

#include "algorithms/campaign/segmentation.hpp"
#include "algorithms/campaign/verticality.hpp"
#include "bench/bench_support.hpp"

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

}  // namespace

int main(int argc, char** argv) {
    using namespace tlsmon;
    const double million = argc > 1 ? std::atof(argv[1]) : 5.0;
    const auto faces = scene();
    double total_area = 0;
    for (const auto& f : faces) total_area += f.area();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.015);
    std::vector<Vector3d> cloud;
    const auto n = static_cast<std::size_t>(million * 1e6);
    cloud.reserve(n);
    for (const auto& f : faces) {
        const auto k = static_cast<std::size_t>(double(n) * f.area() / total_area);
        const Vector3d normal = f.a.cross(f.b).normalized();
        for (std::size_t i = 0; i < k; ++i)
            cloud.push_back(f.origin + U(rng) * f.a + U(rng) * f.b + noise(rng) * normal);
    }
    std::printf("%zu points over %.0f m²\n", cloud.size(), total_area);

    const campaign::VerticalityParameters vp;
    auto t0 = std::chrono::steady_clock::now();
    double c0 = bench::process_cpu_seconds();
    const auto v = campaign::verticality(cloud, vp, 2);
    std::printf("verticality (r = %.2f m): %.1f s wall, %.1f s CPU\n", vp.radius,
                bench::seconds_since(t0), bench::process_cpu_seconds() - c0);
    std::vector<campaign::VerticalityClass> classes;
    classes.reserve(v.size());
    std::map<campaign::VerticalityClass, std::size_t> per_class;
    for (const float x : v) ++per_class[classes.emplace_back(campaign::classify(x, vp))];
    for (const auto& [c, count] : per_class)
        std::printf("  %s: %.1f %%\n", campaign::class_name(c),
                    100.0 * double(count) / double(v.size()));

    t0 = std::chrono::steady_clock::now();
    c0 = bench::process_cpu_seconds();
    const auto s = campaign::segment_cloud(cloud, classes, {}, 2);
    std::printf(
        "segmentation: %.1f s wall, %.1f s CPU; spacing %.1f mm, distance %.1f mm, %zu "
        "clusters, %zu segments of at least 50 points\n",
        bench::seconds_since(t0), bench::process_cpu_seconds() - c0, 1e3 * s.spacing,
        1e3 * s.distance, s.clusters, s.segments.size());
    for (std::size_t k = 0; k < std::min<std::size_t>(s.segments.size(), 12); ++k)
        std::printf("  segment %zu: %s, cluster %d, %zu points\n", k,
                    campaign::class_name(s.segments[k].kind), s.segments[k].cluster,
                    s.segments[k].points);
    return 0;
}
