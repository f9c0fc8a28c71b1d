#include "algorithms/registration/plane_detection.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <unordered_set>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/plane_registration.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::registration {

namespace {

constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);

struct Block {
    std::uint32_t r0, r1, c0, c1;  // half-open rows and columns
    std::uint32_t rows() const { return r1 - r0; }
    std::uint32_t columns() const { return c1 - c0; }
};

struct Kept {
    FittedPlane plane;
    std::vector<Block> blocks;
    std::vector<std::uint32_t> points;
};

class Detector {
  public:
    Detector(const Scan& scan, const PlaneDetectionParams& p)
        : scan_(scan), p_(p), scanner_(scan.scanner_position()) {
        const ScanGrid& g = *scan.grid;
        cell_.assign(g.cells(), -1);
        for (std::size_t i = 0; i < scan.size(); ++i)
            cell_[std::uint64_t{g.row[i]} * g.columns + g.column[i]] = static_cast<std::int32_t>(i);
    }

    // The blocks of one tile that are planar, after splitting what is not.
    void split(const Block& b, std::vector<Kept>& out) const {
        std::vector<std::uint32_t> points = points_of(b);
        if (points.size() < p_.min_points) return;
        if (auto plane = planar(points)) {  // significant or not: small blocks merge first
            out.push_back({*plane, {b}, std::move(points)});
            return;
        }
        const bool rows = b.rows() >= 2 * p_.min_cells, columns = b.columns() >= 2 * p_.min_cells;
        if (!rows && !columns) return;
        const std::uint32_t rm = rows ? b.r0 + b.rows() / 2 : b.r1;
        const std::uint32_t cm = columns ? b.c0 + b.columns() / 2 : b.c1;
        for (const Block& q : {Block{b.r0, rm, b.c0, cm}, Block{rm, b.r1, b.c0, cm},
                               Block{b.r0, rm, cm, b.c1}, Block{rm, b.r1, cm, b.c1}}) {
            if (q.rows() > 0 && q.columns() > 0) split(q, out);
        }
    }

    // The plane of the points when they pass the planarity test, with the covariance of the
    // stochastic model (header).
    std::optional<FittedPlane> planar(const std::vector<std::uint32_t>& points) const {
        FittedPlane f;
        try {
            f = fit_plane(scan_.xyz, points, 0.0, scanner_);
        } catch (const Error&) {
            return std::nullopt;  // on a line
        }
        const double sigma_theta = p_.noise.angular_sigma();
        double model = 0.0;  // Σ σᵢ²
        for (const auto i : points) {
            const Eigen::Vector3d beam = scan_.xyz[i] - scanner_;
            const double r = beam.norm();
            const double cos_a = r > 0.0 ? std::min(1.0, std::fabs(f.normal.dot(beam)) / r) : 1.0;
            const double sigma_r = p_.noise.range_sigma(r);
            model += std::pow(sigma_r * cos_a, 2) +
                     std::pow(r * sigma_theta, 2) * (1.0 - cos_a * cos_a) +
                     p_.flatness * p_.flatness;
        }
        const double n = double(points.size());
        const double mean_variance = model / n;
        const double dof = n - 3.0;
        const double limit = mean_variance * chi_square_quantile(1.0 - p_.alpha, dof) / dof;
        if (!(f.residual_sigma * f.residual_sigma <= limit)) return std::nullopt;
        // The covariance from the model's σ instead of the fit's own scatter.
        const double scale = mean_variance / (f.point_sigma * f.point_sigma);
        f.normal_covariance *= scale;
        f.centroid_variance *= scale;
        f.point_sigma = std::sqrt(mean_variance);
        return f;
    }

    // Whether the plane's normal is significant: the σ of its tip below the limit.
    bool significant(const FittedPlane& f) const {
        const double tilt = std::sqrt(
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(f.normal_covariance).eigenvalues()(2));
        return tilt <= p_.max_normal_sigma_arcsec * kArcsec;
    }

  private:
    std::vector<std::uint32_t> points_of(const Block& b) const {
        const std::uint32_t columns = scan_.grid->columns;
        std::vector<std::uint32_t> out;
        for (std::uint32_t r = b.r0; r < b.r1; ++r)
            for (std::uint32_t c = b.c0; c < b.c1; ++c)
                if (const auto i = cell_[std::uint64_t{r} * columns + c]; i >= 0)
                    out.push_back(static_cast<std::uint32_t>(i));
        return out;
    }

    const Scan& scan_;
    const PlaneDetectionParams& p_;
    Eigen::Vector3d scanner_;
    std::vector<std::int32_t> cell_;  // point index per cell, −1: no return
};

// Union–find over the kept blocks.
struct Groups {
    std::vector<std::size_t> parent;
    explicit Groups(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    std::size_t find(std::size_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    }
    void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

// Pairs of kept blocks that touch in the grid (a cell of one beside a cell of the other).
std::vector<std::pair<std::size_t, std::size_t>> touching(const std::vector<Kept>& kept,
                                                          const ScanGrid& g) {
    std::vector<std::int32_t> label(g.cells(), -1);
    for (std::size_t k = 0; k < kept.size(); ++k)
        for (const Block& b : kept[k].blocks)
            for (std::uint32_t r = b.r0; r < b.r1; ++r)
                for (std::uint32_t c = b.c0; c < b.c1; ++c)
                    label[std::uint64_t{r} * g.columns + c] = static_cast<std::int32_t>(k);
    std::unordered_set<std::uint64_t> seen;
    std::vector<std::pair<std::size_t, std::size_t>> out;
    const auto pair = [&](std::int32_t a, std::int32_t b) {
        if (a < 0 || b < 0 || a == b) return;
        const auto lo = std::uint64_t(std::min(a, b)), hi = std::uint64_t(std::max(a, b));
        if (seen.insert(lo << 32 | hi).second) out.emplace_back(lo, hi);
    };
    for (std::uint32_t r = 0; r < g.rows; ++r)
        for (std::uint32_t c = 0; c < g.columns; ++c) {
            const std::int32_t a = label[std::uint64_t{r} * g.columns + c];
            if (c + 1 < g.columns) pair(a, label[std::uint64_t{r} * g.columns + c + 1]);
            if (r + 1 < g.rows) pair(a, label[std::uint64_t{r + 1} * g.columns + c]);
        }
    return out;
}

// The points of each plane that lie more than `edge` cells inside it along the grid's row
// and column (the points' cells labelled by plane first); a plane left with fewer than
// `min_points` keeps all its points.
void erode_edges(std::vector<DetectedPlane>& planes, const Scan& scan, std::uint32_t edge,
                 std::size_t min_points) {
    if (edge == 0) return;
    const ScanGrid& g = *scan.grid;
    std::vector<std::int32_t> label(g.cells(), -1);
    const auto cell = [&](std::uint32_t r, std::uint32_t c) {
        return std::uint64_t{r} * g.columns + c;
    };
    for (std::size_t k = 0; k < planes.size(); ++k)
        for (const auto i : planes[k].points)
            label[cell(g.row[i], g.column[i])] = static_cast<std::int32_t>(k);
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const auto own = static_cast<std::int32_t>(k);
        const auto inside = [&](std::int64_t r, std::int64_t c) {
            return r >= 0 && c >= 0 && r < std::int64_t{g.rows} && c < std::int64_t{g.columns} &&
                   label[cell(static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c))] == own;
        };
        std::vector<std::uint32_t> inner;
        for (const auto i : planes[k].points) {
            const std::int64_t r = g.row[i], c = g.column[i];
            bool keep = true;
            for (std::int64_t d = 1; d <= std::int64_t{edge} && keep; ++d)
                keep = inside(r - d, c) && inside(r + d, c) && inside(r, c - d) && inside(r, c + d);
            if (keep) inner.push_back(i);
        }
        if (inner.size() >= min_points) planes[k].points = std::move(inner);
    }
}

DetectedPlane detected(Kept&& k) {
    DetectedPlane d;
    d.plane = k.plane;
    d.points = std::move(k.points);
    d.blocks = k.blocks.size();
    d.row_min = d.column_min = UINT32_MAX;
    for (const Block& b : k.blocks) {
        d.row_min = std::min(d.row_min, b.r0);
        d.row_max = std::max(d.row_max, b.r1 - 1);
        d.column_min = std::min(d.column_min, b.c0);
        d.column_max = std::max(d.column_max, b.c1 - 1);
    }
    return d;
}

}  // namespace

double plane_difference_statistic(const FittedPlane& a, const FittedPlane& b) {
    return plane_misclosure({a, b}, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero())
        .test_statistic;
}

std::vector<DetectedPlane> detect_planes(const Scan& scan, const PlaneDetectionParams& p) {
    if (!scan.grid)
        throw Error("plane detection: " + scan.source + " has no grid (not structured)");
    if (scan.grid->too_sparse())
        throw Error("plane detection: " + scan.source + "'s grid has far more cells than points");
    if (p.tile < 2 * p.min_cells || p.min_cells < 2)
        throw Error("plane detection: tile must be at least twice min_cells, min_cells at least 2");
    const ScanGrid& g = *scan.grid;
    const Detector detector(scan, p);

    // 1. The split, tile by tile (in parallel; the tiles' results in tile order).
    std::vector<Block> tiles;
    for (std::uint32_t r = 0; r < g.rows; r += p.tile)
        for (std::uint32_t c = 0; c < g.columns; c += p.tile)
            tiles.push_back({r, std::min(r + p.tile, g.rows), c, std::min(c + p.tile, g.columns)});
    std::vector<std::vector<Kept>> per_tile(tiles.size());
    parallel_for(tiles.size(), [&](std::size_t t) { detector.split(tiles[t], per_tile[t]); });
    std::vector<Kept> kept;
    for (auto& v : per_tile)
        for (auto& k : v) kept.push_back(std::move(k));

    // 2. Touching blocks with equal planes merge; a merged group that is not planar as a
    // whole (a chain along a curved surface) stays in its blocks.
    Groups groups(kept.size());
    const double limit = chi_square_quantile(1.0 - p.merge_alpha, 3.0);
    for (const auto& [a, b] : touching(kept, g)) {
        if (plane_difference_statistic(kept[a].plane, kept[b].plane) <= limit) groups.unite(a, b);
    }
    std::vector<std::vector<std::size_t>> members(kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) members[groups.find(k)].push_back(k);
    std::vector<DetectedPlane> out;
    for (auto& m : members) {
        if (m.empty()) continue;
        // 3. What is kept: a plane whose normal is significant (a small face's blocks are
        // not, alone; merged they may be).
        const auto keep = [&](Kept&& k) {
            if (detector.significant(k.plane)) out.push_back(detected(std::move(k)));
        };
        if (m.size() == 1) {
            keep(std::move(kept[m[0]]));
            continue;
        }
        Kept merged;
        for (const auto k : m) {
            merged.blocks.insert(merged.blocks.end(), kept[k].blocks.begin(), kept[k].blocks.end());
            merged.points.insert(merged.points.end(), kept[k].points.begin(), kept[k].points.end());
        }
        if (auto plane = detector.planar(merged.points)) {
            merged.plane = *plane;
            keep(std::move(merged));
        } else {
            for (const auto k : m) keep(std::move(kept[k]));
        }
    }
    // 4. The edges left out, each plane fitted again on its inner points (dropped if they
    // are not planar or not significant on their own).
    erode_edges(out, scan, p.edge_cells, p.min_points);
    std::vector<std::optional<FittedPlane>> refit(out.size());  // in parallel, per plane
    parallel_for(out.size(), [&](std::size_t k) {
        auto plane = detector.planar(out[k].points);
        if (plane && detector.significant(*plane)) refit[k] = plane;
    });
    std::vector<DetectedPlane> inner;
    for (std::size_t k = 0; k < out.size(); ++k) {
        if (!refit[k]) continue;
        out[k].plane = *refit[k];
        inner.push_back(std::move(out[k]));
    }
    std::sort(inner.begin(), inner.end(), [](const DetectedPlane& a, const DetectedPlane& b) {
        return a.points.size() > b.points.size();
    });
    return inner;
}

}  // namespace tlsmon::registration
