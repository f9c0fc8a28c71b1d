#include "algorithms/registration/checkerboard_centre.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon {

namespace {

constexpr std::size_t kMinPoints = 50;

struct Plane {
    Eigen::Vector3d centroid, normal;
    double offset_variance = 0.0;  // m², of the plane's place along its normal
    std::vector<std::size_t> inliers;
};

// The plane through the points' centroid weighted by `w` (empty: all 1), its normal by
// their weighted principal components; the offset's variance s0²/Σw with
// s0² = Σ w·d² / (n − 3), as for a weighted mean.
Plane fit_plane(const std::vector<Eigen::Vector3d>& xyz, const std::vector<std::size_t>& idx,
                const std::vector<double>& w = {}) {
    const auto weight = [&w](std::size_t k) { return w.empty() ? 1.0 : w[k]; };
    Plane pl;
    pl.centroid.setZero();
    double sw = 0.0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
        pl.centroid += weight(k) * xyz[idx[k]];
        sw += weight(k);
    }
    pl.centroid /= sw;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const Eigen::Vector3d d = xyz[idx[k]] - pl.centroid;
        cov += weight(k) * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    pl.normal = eig.eigenvectors().col(0);  // smallest eigenvalue first
    pl.inliers = idx;
    double ss = 0.0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const double d = pl.normal.dot(xyz[idx[k]] - pl.centroid);
        ss += weight(k) * d * d;
    }
    pl.offset_variance = ss / std::max(1.0, static_cast<double>(idx.size()) - 3.0) / sw;
    return pl;
}

// The points of `candidates` within `tol` of the plane `pl`.
std::vector<std::size_t> within(const std::vector<Eigen::Vector3d>& xyz, const Plane& pl,
                                const std::vector<std::size_t>& candidates, double tol) {
    std::vector<std::size_t> out;
    for (const std::size_t i : candidates) {
        if (std::abs(pl.normal.dot(xyz[i] - pl.centroid)) <= tol) out.push_back(i);
    }
    return out;
}

// The intensity between the dark and the bright squares: the isodata threshold (Ridler &
// Calvard 1978), halfway between the two sides' means, iterated from the median so that a
// board seen with more of one colour is still split between the colours.
double dark_bright_split(const std::vector<float>& intensity,
                         const std::vector<std::size_t>& points) {
    std::vector<double> levels;
    for (const std::size_t i : points) levels.push_back(intensity[i]);
    double split = median(levels);
    for (int pass = 0; pass < 20; ++pass) {
        std::array<double, 2> sum{}, count{};
        for (const double v : levels) sum[v >= split] += v, count[v >= split] += 1;
        if (count[0] == 0 || count[1] == 0) break;
        const double next = 0.5 * (sum[0] / count[0] + sum[1] / count[1]);
        if (next == split) break;
        split = next;
    }
    return split;
}

// Step 1 of the header: PCA plane, refitted on the inliers until they stop changing, then
// weighted by the two colours' σ (why: the header's step 1).
Plane robust_plane(const std::vector<Eigen::Vector3d>& xyz, const std::vector<float>& intensity,
                   std::vector<std::size_t> candidates) {
    constexpr double kWideWindow = 3.0;
    constexpr double kClip = 3.5;         // robust σ: 0.05 % of a normal's tail
    constexpr double kSigmaFloor = 1e-5;  // m: a colour whose ranges do not scatter
    Plane pl = fit_plane(xyz, candidates);
    double tol = 0.0;
    for (int pass = 0; pass < 20; ++pass) {
        std::vector<double> abs_d;
        abs_d.reserve(pl.inliers.size());
        for (const std::size_t i : pl.inliers) {
            abs_d.push_back(std::abs(pl.normal.dot(xyz[i] - pl.centroid)));
        }
        tol = std::max(3.0 * kMadToSigma * median_high(std::move(abs_d)), 5e-4);
        const std::vector<std::size_t> next = within(xyz, pl, candidates, tol);
        if (next.size() < kMinPoints) break;
        const bool same = next == pl.inliers;
        pl = fit_plane(xyz, next);
        if (same) break;
    }
    // Step 1's weighted fit: the two colours' σ from their own residuals, each clipped at
    // 3.5 of its σ, weights 1/σ². The candidates within three windows of the converged plane,
    // so that the window clips neither colour (the noisier one's 3.5 σ lies inside it).
    const std::vector<std::size_t> wide = within(xyz, pl, candidates, kWideWindow * tol);
    const double split = dark_bright_split(intensity, pl.inliers);
    std::vector<double> d(wide.size());  // |distance| from the current plane
    for (int pass = 0; pass < 3; ++pass) {
        std::array<std::vector<double>, 2> distances;  // |d| of the dark, of the bright
        for (std::size_t k = 0; k < wide.size(); ++k) {
            d[k] = std::abs(pl.normal.dot(xyz[wide[k]] - pl.centroid));
            distances[intensity[wide[k]] >= split].push_back(d[k]);
        }
        std::array<double, 2> sigma{};
        for (int g = 0; g < 2; ++g)
            sigma[g] = std::max(
                kMadToSigma * (distances[g].empty() ? 0.0 : median(std::move(distances[g]))),
                kSigmaFloor);
        std::vector<std::size_t> kept;
        std::vector<double> weights;
        for (std::size_t k = 0; k < wide.size(); ++k) {
            const double s = sigma[intensity[wide[k]] >= split];
            if (d[k] > kClip * s) continue;
            kept.push_back(wide[k]);
            weights.push_back(1.0 / (s * s));
        }
        if (kept.size() < kMinPoints) break;
        pl = fit_plane(xyz, kept, weights);
    }
    return pl;
}

// Parameters of the intensity model: centre (a, b), θ, ln σ, m, h.
using Params = Eigen::Matrix<double, 6, 1>;
using Row = Eigen::Matrix<double, 1, 6>;

// The model I = m + h·Ea·Eb at (a, b) and its gradient in the parameters.
double model(const Params& x, double a, double b, Row* grad) {
    const double ct = std::cos(x(2)), st = std::sin(x(2));
    const double da = a - x(0), db = b - x(1);
    const double ap = ct * da + st * db, bp = -st * da + ct * db;
    const double sigma = std::exp(x(3));
    const double k = 1.0 / (std::numbers::sqrt2 * sigma);
    const double ea = std::erf(ap * k), eb = std::erf(bp * k);
    if (grad) {
        // d erf(x / (√2 σ)) / dx = √(2/π) / σ · exp(−x² / (2σ²))
        const double g = std::sqrt(2.0 / std::numbers::pi) / sigma;
        const double ga = g * std::exp(-ap * ap * k * k), gb = g * std::exp(-bp * bp * k * k);
        const double h = x(5);
        // ∂a′/∂(c_a, c_b, θ) = (−cos θ, −sin θ, b′); ∂b′/∂(c_a, c_b, θ) = (sin θ, −cos θ, −a′)
        (*grad)(0) = h * (ga * -ct * eb + ea * gb * st);
        (*grad)(1) = h * (ga * -st * eb + ea * gb * -ct);
        (*grad)(2) = h * (ga * bp * eb - ea * gb * ap);
        // ∂E/∂ln σ = −x′ · ∂E/∂x′
        (*grad)(3) = h * (-ap * ga * eb - bp * gb * ea);
        (*grad)(4) = 1.0;
        (*grad)(5) = ea * eb;
    }
    return x(4) + x(5) * ea * eb;
}

struct Points2 {
    std::vector<double> a, b, i;
    std::vector<double> w;  // weights 1/σᵢ², empty for all 1
    double weight(std::size_t k) const { return w.empty() ? 1.0 : w[k]; }
};

// Σ wᵢ eᵢ², the weighted sum of squared intensity residuals.
double cost(const Params& x, const Points2& p) {
    double s = 0.0;
    for (std::size_t k = 0; k < p.a.size(); ++k) {
        const double e = p.i[k] - model(x, p.a[k], p.b[k], nullptr);
        s += p.weight(k) * e * e;
    }
    return s;
}

// m and h by linear least squares for the other parameters fixed; returns the cost.
double fit_levels(Params& x, const Points2& p) {
    Eigen::Matrix2d n = Eigen::Matrix2d::Zero();
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    Params y = x;
    y(4) = 0.0;
    y(5) = 1.0;
    for (std::size_t k = 0; k < p.a.size(); ++k) {
        const double e = model(y, p.a[k], p.b[k], nullptr);
        const Eigen::Vector2d j(1.0, e);
        n += j * j.transpose();
        r += j * p.i[k];
    }
    const Eigen::Vector2d mh = n.ldlt().solve(r);
    x(4) = mh(0);
    x(5) = mh(1);
    return cost(x, p);
}

struct Fit {
    Params x;
    Eigen::Matrix<double, 6, 6> normal;
    double sum_sq = 0.0;
    int iterations = 0;
    bool converged = false;
};

// Levenberg–Marquardt (Marquardt 1963, the damping scaled by the diagonal of JᵀJ).
Fit levenberg_marquardt(Params x, const Points2& p, int max_iterations) {
    Fit f;
    double lambda = 1e-3;
    double current = cost(x, p);
    for (int it = 0; it < max_iterations; ++it) {
        Eigen::Matrix<double, 6, 6> n = Eigen::Matrix<double, 6, 6>::Zero();
        Params g = Params::Zero();
        for (std::size_t k = 0; k < p.a.size(); ++k) {
            Row j;
            const double e = p.i[k] - model(x, p.a[k], p.b[k], &j);
            n += p.weight(k) * j.transpose() * j;
            g += p.weight(k) * j.transpose() * e;
        }
        f.iterations = it + 1;
        bool accepted = false;
        Params step = Params::Zero();
        for (int tries = 0; tries < 20 && !accepted; ++tries) {
            Eigen::Matrix<double, 6, 6> damped = n;
            damped.diagonal() *= 1.0 + lambda;
            step = damped.ldlt().solve(g);
            const double c = step.allFinite() ? cost(x + step, p) : current + 1.0;
            if (c <= current) {
                x += step;
                current = c;
                lambda = std::max(lambda / 10.0, 1e-12);
                accepted = true;
            } else {
                lambda *= 10.0;
            }
        }
        // Converged when no damped step lowers the cost any more, or the centre and the
        // rotation have stopped moving (1 nm, 1 nrad).
        if (!accepted || (step.head<2>().norm() < 1e-9 && std::abs(step(2)) < 1e-9)) {
            f.converged = true;
            break;
        }
    }
    f.x = x;
    f.normal.setZero();
    for (std::size_t k = 0; k < p.a.size(); ++k) {
        Row j;
        model(x, p.a[k], p.b[k], &j);
        f.normal += p.weight(k) * j.transpose() * j;
    }
    f.sum_sq = current;
    return f;
}

// Step 4 of the header: the residuals' variance σᵢ² = σ_I² + σ_p² |∇Iᵢ|², fitted to the
// squared residuals by least squares, as weights 1/σᵢ². False when the residuals vanish
// (noise-free data: nothing to weight).
bool weights_from_residuals(const Params& x, Points2& p) {
    Eigen::Matrix2d n = Eigen::Matrix2d::Zero();
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    std::vector<double> g2(p.a.size());
    double mean_e2 = 0.0;
    for (std::size_t k = 0; k < p.a.size(); ++k) {
        Row j;
        const double e = p.i[k] - model(x, p.a[k], p.b[k], &j);
        g2[k] = j(0) * j(0) + j(1) * j(1);  // ∂I/∂c = −∇I
        const Eigen::Vector2d row(1.0, g2[k]);
        n += row * row.transpose();
        r += row * (e * e);
        mean_e2 += e * e;
    }
    mean_e2 /= static_cast<double>(p.a.size());
    if (!(mean_e2 > 1e-20)) return false;
    Eigen::Vector2d ab = n.ldlt().solve(r);
    if (!ab.allFinite()) return false;
    // Both variances non-negative; the floor keeps a weight finite where |∇I| = 0.
    ab(1) = std::max(ab(1), 0.0);
    ab(0) = std::max(ab(0), 1e-3 * mean_e2);
    p.w.resize(p.a.size());
    for (std::size_t k = 0; k < p.a.size(); ++k) p.w[k] = 1.0 / (ab(0) + ab(1) * g2[k]);
    return true;
}

}  // namespace

CheckerboardCentre checkerboard_centre(const std::vector<Eigen::Vector3d>& xyz,
                                       const std::vector<float>& intensity,
                                       const CheckerboardSearch& search) {
    if (xyz.size() != intensity.size()) {
        throw Error("checkerboard centre: " + std::to_string(xyz.size()) + " points but " +
                    std::to_string(intensity.size()) + " intensities");
    }
    if (!(search.size > 0.0)) throw Error("checkerboard centre: size must be > 0");
    const Eigen::Vector3d& c0 = search.approximate_centre;
    std::vector<std::size_t> near;
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        if ((xyz[i] - c0).norm() <= 0.75 * search.size) near.push_back(i);
    }
    if (near.size() < kMinPoints) {
        throw Error("checkerboard centre: " + std::to_string(near.size()) +
                    " points within 0.75 · size of the approximate centre, need " +
                    std::to_string(kMinPoints));
    }
    const Plane plane = robust_plane(xyz, intensity, near);
    const Eigen::Vector3d n =
        plane.normal.dot(search.viewpoint - plane.centroid) >= 0.0 ? plane.normal : -plane.normal;
    Eigen::Vector3d e1 = Eigen::Vector3d::UnitZ().cross(n);
    if (e1.norm() < 0.1) e1 = Eigen::Vector3d::UnitX().cross(n);  // a board lying flat
    e1.normalize();
    const Eigen::Vector3d e2 = n.cross(e1);
    const Eigen::Vector3d origin = c0 - n * n.dot(c0 - plane.centroid);

    Points2 all;
    for (const std::size_t i : plane.inliers) {
        const Eigen::Vector3d d = xyz[i] - origin;
        all.a.push_back(e1.dot(d));
        all.b.push_back(e2.dot(d));
        all.i.push_back(intensity[i]);
    }
    const double radius = 0.4 * search.size;
    const auto window = [&](double ca, double cb) {
        Points2 w;
        for (std::size_t k = 0; k < all.a.size(); ++k) {
            if (std::hypot(all.a[k] - ca, all.b[k] - cb) > radius) continue;
            w.a.push_back(all.a[k]);
            w.b.push_back(all.b[k]);
            w.i.push_back(all.i[k]);
        }
        if (w.a.size() < kMinPoints) {
            throw Error("checkerboard centre: " + std::to_string(w.a.size()) +
                        " points on the board within 0.4 · size of the centre, need " +
                        std::to_string(kMinPoints));
        }
        return w;
    };

    // Start: centre at the approximate one, a wide blur (a wide basin), the rotation among
    // a few that explains the intensities best with m, h fitted linearly.
    Points2 pts = window(0.0, 0.0);
    Params x;
    x << 0.0, 0.0, 0.0, std::log(0.05 * search.size), 0.0, 0.0;
    double best = std::numeric_limits<double>::infinity();
    Params start = x;
    for (const double deg : {-30.0, -15.0, 0.0, 15.0, 30.0, 45.0}) {
        Params y = x;
        y(2) = deg * std::numbers::pi / 180.0;
        const double c = fit_levels(y, pts);
        if (c < best) {
            best = c;
            start = y;
        }
    }
    Fit fit = levenberg_marquardt(start, pts, search.max_iterations);
    // Recentre the window on the first estimate and fit again from there.
    pts = window(fit.x(0), fit.x(1));
    fit = levenberg_marquardt(fit.x, pts, search.max_iterations);
    // Weighted by the residuals' variance model, twice (the weights from the refined fit).
    for (int pass = 0; pass < 2 && fit.converged; ++pass) {
        if (!weights_from_residuals(fit.x, pts)) break;
        fit = levenberg_marquardt(fit.x, pts, search.max_iterations);
    }
    if (!fit.converged) {
        throw Error("checkerboard centre: the intensity fit did not converge in " +
                    std::to_string(search.max_iterations) + " iterations");
    }

    CheckerboardCentre out;
    const double m = static_cast<double>(pts.a.size());
    // σ̂₀² = Σ wᵢ eᵢ² / (n − 6): 1 when the variance model is right, else its scale.
    const double var = fit.sum_sq / std::max(1.0, m - 6.0);
    const Eigen::Matrix2d cov2 = var * fit.normal.inverse().topLeftCorner<2, 2>();
    Eigen::Matrix<double, 3, 2> axes;
    axes << e1, e2;
    out.centre = origin + axes * fit.x.head<2>();
    const double offset_var = plane.offset_variance;
    out.covariance = axes * cov2 * axes.transpose() + offset_var * n * n.transpose();
    out.normal = n;
    // θ within ±45°: a quarter turn swaps the colours, i.e. the sign of h.
    double theta = fit.x(2), h = fit.x(5);
    const double quarter = 0.5 * std::numbers::pi;
    const double turns = std::round(theta / quarter);
    theta -= turns * quarter;
    if (static_cast<long>(turns) % 2 != 0) h = -h;
    out.rotation = theta;
    out.blur_sigma = std::exp(fit.x(3));
    out.dark = fit.x(4) - std::abs(h);
    out.bright = fit.x(4) + std::abs(h);
    double ss = 0.0;
    for (std::size_t k = 0; k < pts.a.size(); ++k) {
        const double e = pts.i[k] - model(fit.x, pts.a[k], pts.b[k], nullptr);
        ss += e * e;
    }
    out.residual_rms = std::sqrt(ss / m);
    out.plane_points = plane.inliers.size();
    out.fit_points = pts.a.size();
    out.iterations = fit.iterations;
    // Sampling: with the points farther apart than a few blur widths, most rows across an
    // edge hold no mixed return, the centre is pinned only to within a fraction of the
    // spacing, and the fit's cost is a staircase with local minima the covariance knows
    // nothing of (the `hochmosel` boards at 0.03°: blur/spacing 0.04–0.21, centre errors up
    // to 18 mm at up to 5.7σ). An edge of blur σ sampled at spacing s is resolved for σ ≳ s/4.
    out.point_spacing = std::sqrt(std::numbers::pi * radius * radius / m);
    if (out.blur_sigma < search.min_blur_to_spacing * out.point_spacing) {
        throw Error("checkerboard centre: undersampled, the pattern's blur " +
                    std::to_string(1e3 * out.blur_sigma).substr(0, 5) +
                    " mm against a point spacing of " +
                    std::to_string(1e3 * out.point_spacing).substr(0, 5) +
                    " mm (the edges are not resolved; a finer scan step or a sphere is needed)");
    }
    return out;
}

}  // namespace tlsmon
