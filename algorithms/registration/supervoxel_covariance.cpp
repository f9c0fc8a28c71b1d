#include "algorithms/registration/supervoxel_covariance.hpp"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "algorithms/registration/distribution_quantiles.hpp"

namespace tlsmon::registration {

std::optional<SupervoxelCovariance> supervoxel_covariance(
    std::span<const SupervoxelObservation> observations, const Eigen::Vector3d& t,
    const CellGrid& grid) {
    using Vector6 = Eigen::Matrix<double, 6, 1>;
    struct Cell {
        Vector6 b = Vector6::Zero();
        double w = 0, wd = 0, w2s2 = 0;
    };
    std::map<std::array<std::int64_t, 3>, Cell> cells;
    Covariance6 N = Covariance6::Zero(), M = Covariance6::Zero();
    for (const auto& o : observations) {
        if (!(o.weight > 0) || !(o.variance > 0) || !std::isfinite(o.change)) continue;
        Vector6 a;
        a.head<3>() = (o.centroid - t).cross(o.normal);
        a.tail<3>() = o.normal;
        N.selfadjointView<Eigen::Lower>().rankUpdate(a, o.weight);
        M.selfadjointView<Eigen::Lower>().rankUpdate(a, o.weight * o.weight * o.variance);
        std::array<std::int64_t, 3> key;
        for (std::size_t j = 0; j < 3; ++j) {
            const auto i = static_cast<Eigen::Index>(j);
            key[j] =
                static_cast<std::int64_t>(std::floor((o.centroid(i) - grid.origin(i)) / grid.size));
        }
        Cell& c = cells[key];
        c.b += o.weight * a;
        c.w += o.weight;
        c.wd += o.weight * o.change;
        c.w2s2 += o.weight * o.weight * o.variance;
    }
    if (cells.size() <= 6) return std::nullopt;
    N = N.selfadjointView<Eigen::Lower>();
    M = M.selfadjointView<Eigen::Lower>();
    const Eigen::LDLT<Covariance6> ldlt(N);
    if (ldlt.info() != Eigen::Success) return std::nullopt;

    SupervoxelCovariance out;
    out.cells = cells.size();
    // Each cell's weighted mean residual change and its variance without a common error.
    std::vector<std::pair<double, double>> means;
    means.reserve(cells.size());
    for (const auto& [key, c] : cells) {
        const double r = c.wd / c.w, v = c.w2s2 / (c.w * c.w);
        means.emplace_back(r * r, v);
        out.q += r * r / v;
    }
    const double dof = static_cast<double>(out.cells) - 6.0;
    out.significant = out.q > chi_square_quantile(0.95, dof);
    // Paule & Mandel (1982): the τ² at which Σ_c r̄_c²/(v_c + τ²) = C − 6, by bisection (the
    // sum falls as τ² grows).
    const auto standardized = [&](double tau2) {
        double sum = 0;
        for (const auto& [r2, v] : means) sum += r2 / (v + tau2);
        return sum;
    };
    double tau2 = 0.0;
    if (out.significant) {
        double low = 0.0, high = 1e-10;  // m²
        while (standardized(high) > dof) high *= 4.0;
        for (int i = 0; i < 100 && high - low > 1e-6 * high; ++i) {
            const double mid = 0.5 * (low + high);
            (standardized(mid) > dof ? low : high) = mid;
        }
        tau2 = 0.5 * (low + high);
    }
    out.cell_sigma = std::sqrt(tau2);
    for (const auto& [key, c] : cells) M.selfadjointView<Eigen::Lower>().rankUpdate(c.b, tau2);
    M = M.selfadjointView<Eigen::Lower>();
    const Covariance6 Ninv = ldlt.solve(Covariance6::Identity());
    out.covariance = Ninv * M * Ninv;
    out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
    return out;
}

}  // namespace tlsmon::registration
