#include "algorithms/vectors/between_area_variance.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace tlsmon::vectors {

BetweenAreaVariance between_area_variance(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                                          const Eigen::VectorXd& variances) {
    BetweenAreaVariance out;
    const Eigen::Index n = X.rows(), p = X.cols();
    if (n <= p + 1 || y.size() != n || variances.size() != n || !(variances.array() > 0).all())
        return out;
    const Eigen::VectorXd w = variances.cwiseInverse();
    const Eigen::MatrixXd XtW = X.transpose() * w.asDiagonal();
    const Eigen::LDLT<Eigen::MatrixXd> normal(XtW * X);
    if (normal.info() != Eigen::Success) return out;
    const Eigen::VectorXd residuals = y - X * normal.solve(XtW * y);
    out.q = residuals.cwiseAbs2().dot(w);
    out.dof = n - p;
    // tr((XᵀWX)⁻¹ XᵀW²X): the weight the fitted field takes of τ².
    const double fitted = normal.solve(XtW * w.asDiagonal() * X).trace();
    const double scale = w.sum() - fitted;
    if (scale > 0) out.tau2 = std::max(0.0, (out.q - double(out.dof)) / scale);
    return out;
}

Eigen::MatrixXd zone_field(const Eigen::MatrixX2d& positions) {
    const Eigen::Index n = positions.rows();
    const bool quadratic = n >= kQuadraticAreas;
    Eigen::MatrixXd X(n, quadratic ? 6 : 3);
    if (n == 0) return X;
    const Eigen::RowVector2d centre = positions.colwise().mean();
    for (Eigen::Index k = 0; k < n; ++k) {
        const double h = positions(k, 0) - centre(0), v = positions(k, 1) - centre(1);
        X(k, 0) = 1.0, X(k, 1) = h, X(k, 2) = v;
        if (quadratic) X(k, 3) = h * h, X(k, 4) = h * v, X(k, 5) = v * v;
    }
    return X;
}

}  // namespace tlsmon::vectors
