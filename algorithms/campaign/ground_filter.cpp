#include "algorithms/campaign/ground_filter.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kGravity = 0.2;        // CSF's
constexpr double kSettled = 0.005;      // m: the largest move of an iteration that ends it
constexpr double kSmoothingStep = 0.3;  // m: CSF's slope-smoothing height threshold

struct Cloth {
    int rows = 0, columns = 0;
    std::vector<double> height, floor;  // floor: the cell's lowest point (NaN: none)
    std::vector<std::uint8_t> fixed;
    int index(int r, int c) const { return r * columns + c; }
};

// CSF's scan-line fill: an empty cell takes the nearest filled cell's floor along its row
// and its column, the nearer of the four.
void fill_empty(Cloth& cloth) {
    const std::vector<double> f = cloth.floor;
    for (int r = 0; r < cloth.rows; ++r)
        for (int c = 0; c < cloth.columns; ++c) {
            if (std::isfinite(f[cloth.index(r, c)])) continue;
            int best = std::numeric_limits<int>::max();
            const int steps[4][2] = {{0, 1}, {0, -1}, {1, 0}, {-1, 0}};
            for (const auto& s : steps)
                for (int k = 1, rr = r + s[0], cc = c + s[1];
                     k < best && rr >= 0 && rr < cloth.rows && cc >= 0 && cc < cloth.columns;
                     ++k, rr += s[0], cc += s[1])
                    if (std::isfinite(f[cloth.index(rr, cc)])) {
                        best = k;
                        cloth.floor[cloth.index(r, c)] = f[cloth.index(rr, cc)];
                        break;
                    }
        }
}

// One spring between particles a and b (heights only, as CSF).
void satisfy(Cloth& cloth, int a, int b, double single, double both) {
    const bool fa = cloth.fixed[a], fb = cloth.fixed[b];
    if (fa && fb) return;
    const double gap = cloth.height[b] - cloth.height[a];
    if (!fa && !fb) {
        cloth.height[a] += both * gap;
        cloth.height[b] -= both * gap;
    } else if (!fa) {
        cloth.height[a] += single * gap;
    } else {
        cloth.height[b] -= single * gap;
    }
}

void smooth_slopes(Cloth& cloth) {
    std::deque<int> queue;
    for (int i = 0; i < cloth.rows * cloth.columns; ++i)
        if (cloth.fixed[i]) queue.push_back(i);
    while (!queue.empty()) {
        const int i = queue.front();
        queue.pop_front();
        const int r = i / cloth.columns, c = i % cloth.columns;
        const int steps[4][2] = {{0, 1}, {0, -1}, {1, 0}, {-1, 0}};
        for (const auto& s : steps) {
            const int rr = r + s[0], cc = c + s[1];
            if (rr < 0 || rr >= cloth.rows || cc < 0 || cc >= cloth.columns) continue;
            const int j = cloth.index(rr, cc);
            if (cloth.fixed[j] || !std::isfinite(cloth.floor[j])) continue;
            if (std::abs(cloth.floor[j] - cloth.height[j]) < kSmoothingStep) {
                cloth.height[j] = cloth.floor[j];
                cloth.fixed[j] = 1;
                queue.push_back(j);
            }
        }
    }
}

}  // namespace

void validate(const GroundFilterParameters& p) {
    if (!(p.cloth_resolution > 0 && p.cloth_resolution <= 100))
        throw Error("campaign: cloth_resolution must lie in (0, 100] m");
    if (p.rigidness < 1 || p.rigidness > 3) throw Error("campaign: rigidness must be 1, 2 or 3");
    if (!(p.class_threshold > 0)) throw Error("campaign: class_threshold must be positive");
    if (p.max_iterations < 1) throw Error("campaign: max_iterations must be at least 1");
    if (!(p.time_step > 0 && p.time_step <= 2))
        throw Error("campaign: time_step must lie in (0, 2]");
}

double GroundClassification::cloth_height(double x, double y, double resolution) const {
    const double u = (x - origin.x()) / resolution, v = (y - origin.y()) / resolution;
    if (!(u >= 0 && v >= 0 && u <= columns - 1 && v <= rows - 1)) return kNaN;
    const int c = std::min(int(u), columns - 2), r = std::min(int(v), rows - 2);
    const double fu = u - c, fv = v - r;
    const auto h = [&](int rr, int cc) { return cloth[std::size_t(rr) * columns + cc]; };
    return (1 - fv) * ((1 - fu) * h(r, c) + fu * h(r, c + 1)) +
           fv * ((1 - fu) * h(r + 1, c) + fu * h(r + 1, c + 1));
}

GroundClassification classify_ground(std::span<const Eigen::Vector3d> points,
                                     const GroundFilterParameters& p, unsigned threads) {
    validate(p);
    GroundClassification out;
    out.ground.assign(points.size(), 0);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (const auto& x : points)
        if (x.allFinite()) {
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
        }
    if (!(lo.x() <= hi.x())) return out;
    const double res = p.cloth_resolution;
    // One cell of margin all round, so that every point has four particles about it.
    out.origin = lo.head<2>() - Eigen::Vector2d::Constant(res);
    Cloth cloth;
    cloth.columns = int(std::ceil((hi.x() - out.origin.x()) / res)) + 2;
    cloth.rows = int(std::ceil((hi.y() - out.origin.y()) / res)) + 2;
    const std::size_t n = std::size_t(cloth.rows) * cloth.columns;
    cloth.floor.assign(n, kNaN);
    for (const auto& x : points) {
        if (!x.allFinite()) continue;
        const int c = int(std::lround((x.x() - out.origin.x()) / res));
        const int r = int(std::lround((x.y() - out.origin.y()) / res));
        double& f = cloth.floor[cloth.index(r, c)];
        if (!(f <= x.z())) f = x.z();
    }
    fill_empty(cloth);
    // The cloth starts below everything (CSF: above the inverted cloud).
    cloth.height.assign(n, lo.z() - 1.0);
    cloth.fixed.assign(n, 0);

    const double single = 1.0 - std::pow(0.7, p.rigidness);
    const double both = 0.5 * (1.0 - std::pow(0.4, p.rigidness));
    const double push = kGravity * p.time_step * p.time_step;
    std::vector<double> before(n);
    for (out.iterations = 1; out.iterations <= p.max_iterations; ++out.iterations) {
        before = cloth.height;
        for (std::size_t i = 0; i < n; ++i)
            if (!cloth.fixed[i]) cloth.height[i] += push;
        for (int r = 0; r < cloth.rows; ++r)
            for (int c = 0; c < cloth.columns; ++c) {
                const int i = cloth.index(r, c);
                if (c + 1 < cloth.columns) satisfy(cloth, i, cloth.index(r, c + 1), single, both);
                if (r + 1 < cloth.rows) satisfy(cloth, i, cloth.index(r + 1, c), single, both);
            }
        double largest = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (cloth.fixed[i]) continue;
            if (std::isfinite(cloth.floor[i]) && cloth.height[i] >= cloth.floor[i]) {
                cloth.height[i] = cloth.floor[i];
                cloth.fixed[i] = 1;
            }
            largest = std::max(largest, std::abs(cloth.height[i] - before[i]));
        }
        if (largest < kSettled) break;
    }
    out.iterations = std::min(out.iterations, p.max_iterations);
    if (p.slope_smoothing) smooth_slopes(cloth);

    out.rows = cloth.rows;
    out.columns = cloth.columns;
    out.cloth = std::move(cloth.height);
    parallel_for(
        points.size(),
        [&](std::size_t i) {
            const Eigen::Vector3d& x = points[i];
            if (!x.allFinite()) return;
            const double h = out.cloth_height(x.x(), x.y(), res);
            out.ground[i] = std::abs(x.z() - h) < p.class_threshold ? 1 : 0;
        },
        threads);
    out.ground_points = std::size_t(std::count(out.ground.begin(), out.ground.end(), 1));
    return out;
}

}  // namespace tlsmon::campaign
