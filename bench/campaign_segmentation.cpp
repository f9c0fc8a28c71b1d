// Campaign cloud benchmark (reported, not asserted), 2 threads: verticality at the study's
// 0.10 m, the two-stage segmentation, the TLS reference's local planes, segment-wise ICP with
// the test of whether the segments moved as one, and C2C of every point (algorithms/campaign/)
// for an unstructured cloud like a personal laser scanner's: a ground 60 × 30 m, two piers
// (3 × 6 m, 20 m high, four faces each) and a deck (60 × 12 m, its soffit and top), points
// drawn uniformly over the surfaces with N(0, 15 mm) noise along their normals, the second
// pier's stretch of the walk drifted by 10 mm; the reference the same scene with half as many
// points and 2 mm noise.
// Usage: bench_campaign_segmentation [MILLION_POINTS=5]
#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <vector>

#include "algorithms/campaign/c2c.hpp"
#include "algorithms/campaign/segment_consistency.hpp"
#include "algorithms/campaign/segment_registration.hpp"
#include "algorithms/campaign/segmentation.hpp"
#include "algorithms/campaign/verticality.hpp"
#include "bench/bench_support.hpp"
#include "core/parallel_for.hpp"

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

}  // namespace

int main(int argc, char** argv) {
    using namespace tlsmon;
    const double million = argc > 1 ? std::atof(argv[1]) : 5.0;
    const auto faces = scene();
    std::vector<Vector3d> cloud = sample(faces, static_cast<std::size_t>(million * 1e6), 0.015, 1);
    // The second pier's stretch of the walk: 10 mm off along y.
    for (auto& p : cloud)
        if (p.x() > 38.5 && p.x() < 42.5 && p.z() > 0.5 && p.z() < 19.5) p.y() += 0.010;
    std::printf("%zu points\n", cloud.size());
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

    const std::vector<Vector3d> reference =
        sample(faces, static_cast<std::size_t>(million * 0.5e6), 0.002, 2);
    t0 = std::chrono::steady_clock::now();
    c0 = bench::process_cpu_seconds();
    const campaign::ReferenceSurface surface(reference, {}, 2);
    std::printf("reference local planes (%zu points): %.1f s wall, %.1f s CPU\n", reference.size(),
                bench::seconds_since(t0), bench::process_cpu_seconds() - c0);

    t0 = std::chrono::steady_clock::now();
    c0 = bench::process_cpu_seconds();
    std::vector<std::vector<Vector3d>> members(s.segments.size());
    for (std::size_t i = 0; i < cloud.size(); ++i)
        if (s.segment[i] >= 0) members[std::size_t(s.segment[i])].push_back(cloud[i]);
    std::vector<campaign::SegmentTransform> transforms(s.segments.size());
    for (std::size_t k = 0; k < s.segments.size(); ++k)
        if (s.segments[k].points >= 1000)
            transforms[k] = campaign::register_segment(surface, members[k], {}, 2);
    const campaign::SegmentConsistency consistency = campaign::test_segment_consistency(transforms);
    std::printf(
        "segment-wise ICP and the test: %.1f s wall, %.1f s CPU; %zu segments registered, "
        "T = %.1f (dof %d), segments differ: %s\n",
        bench::seconds_since(t0), bench::process_cpu_seconds() - c0, consistency.segments,
        consistency.statistic, consistency.dof, consistency.differ ? "yes" : "no");
    for (std::size_t k = 0; k < std::min<std::size_t>(transforms.size(), 12); ++k) {
        const auto& r = transforms[k];
        if (!r.registered()) continue;
        std::printf(
            "  segment %zu: rank %d, t = (%+.1f, %+.1f, %+.1f) mm at (%.0f, %.0f, %.0f), "
            "%d iterations, p = %.2g\n",
            k, r.rank(), 1e3 * r.parameters(3), 1e3 * r.parameters(4), 1e3 * r.parameters(5),
            r.centroid.x(), r.centroid.y(), r.centroid.z(), r.iterations,
            consistency.segment_p_value[k]);
    }

    t0 = std::chrono::steady_clock::now();
    c0 = bench::process_cpu_seconds();
    std::vector<Eigen::Matrix4d> matrices;
    for (const auto& r : transforms)
        matrices.push_back(r.registered() ? r.matrix() : Eigen::Matrix4d::Identity());
    std::vector<Vector3d> registered = cloud;
    parallel_for(
        registered.size(),
        [&](std::size_t i) {
            if (s.segment[i] >= 0)
                registered[i] =
                    (matrices[std::size_t(s.segment[i])] * cloud[i].homogeneous()).head<3>();
        },
        2);
    const auto c2c = campaign::c2c_vectors(surface, registered, campaign::C2cModel::local_plane, 2);
    const auto stats = campaign::summarise(c2c);
    std::printf(
        "C2C (local plane): %.1f s wall, %.1f s CPU; mean %.1f mm, σ %.1f mm, 95 %% %.1f mm, "
        "%zu without\n",
        bench::seconds_since(t0), bench::process_cpu_seconds() - c0, 1e3 * stats.mean,
        1e3 * stats.sigma, 1e3 * stats.p95, stats.missing);
    return 0;
}
