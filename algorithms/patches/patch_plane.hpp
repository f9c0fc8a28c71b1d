#pragma once
// A patch of plane in its own frame, and the plane of a set of points fitted in that frame.
//
// Frame: origin o on the reference plane, unit normal n, in-plane axes u, v; a point p has
// the coordinates (u, v, w) = (uᵀ(p − o), vᵀ(p − o), nᵀ(p − o)).
//
// Fit (Gauss–Markov model, Niemeier 2008, §4): w_i = a + b·(u_i − ū) + c·(v_i − v̄) + e_i,
// e_i ~ N(0, σ²) independent — the heights along the patch normal over the patch plane.
// With the centred sums S = [[Suu, Suv], [Suv, Svv]], the slopes are (b, c) = S⁻¹·(Suw, Svw),
// a = w̄, and σ̂² = (Sww − (b, c)·(Suw, Svw)) / (m − 3). The covariance is σ̂²·diag(1/m, S⁻¹):
// the height at the centroid is uncorrelated with the slopes. The height at (u₀, v₀) is
// h = a + b·(u₀ − ū) + c·(v₀ − v̄), with σ_h² = σ̂²·(1/m + gᵀ S⁻¹ g), g = (u₀ − ū, v₀ − v̄).
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace tlsmon::patches {

struct PatchFrame {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY();

    // A right-handed frame (u, v, n) about a unit normal.
    static PatchFrame about(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal);
    Eigen::Vector3d local(const Eigen::Vector3d& p) const {
        const Eigen::Vector3d d = p - origin;
        return {u.dot(d), v.dot(d), normal.dot(d)};
    }
};

// The sums of a set of points' (u, v, w) that the fit needs, added point by point.
struct PlaneMoments {
    double m = 0, su = 0, sv = 0, sw = 0, suu = 0, suv = 0, svv = 0, suw = 0, svw = 0, sww = 0;
    void add(const Eigen::Vector3d& uvw) {
        const double u = uvw.x(), v = uvw.y(), w = uvw.z();
        m += 1;
        su += u, sv += v, sw += w;
        suu += u * u, suv += u * v, svv += v * v;
        suw += u * w, svw += v * w, sww += w * w;
    }
    PlaneMoments& operator+=(const PlaneMoments& o);
    std::size_t count() const { return static_cast<std::size_t>(m); }
};

struct PlaneFit {
    std::size_t count = 0;
    bool valid = false;                                        // at least 4 points, not on a line
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();        // (ū, v̄)
    double height = std::numeric_limits<double>::quiet_NaN();  // a = w̄
    Eigen::Vector2d slope = Eigen::Vector2d::Zero();           // (b, c)
    Eigen::Matrix2d slope_normal = Eigen::Matrix2d::Zero();    // S (centred)
    double sigma = std::numeric_limits<double>::quiet_NaN();   // σ̂, m: RMS residual

    double height_at(const Eigen::Vector2d& at) const { return height + slope.dot(at - centroid); }
    // σ_h at (u₀, v₀); NaN when not valid.
    double height_sigma_at(const Eigen::Vector2d& at) const;
};

PlaneFit fit_plane(const PlaneMoments& moments);

// The moments of the points that belong to the plane: a least-squares fit of all, then the
// points whose residual lies more than `clip` robust σ (1.4826·MAD of the residuals) from
// the residuals' median left out and the plane fitted again, until no point leaves or after
// `rounds`. Stray returns inside the footprint and depth — mixed returns strung along the
// beams behind an edge, a bird, a cable — would otherwise tilt and shift the plane, and its
// σ̂ would no longer describe the patch. For normally distributed heights the clip at 3.5 σ
// leaves out 0.05 % of the points.
PlaneMoments inlier_moments(const std::vector<Eigen::Vector3f>& uvw, double clip = 3.5,
                            int rounds = 3);

// Which of the points inlier_moments keeps (1) and leaves out (0).
std::vector<std::uint8_t> plane_inliers(const std::vector<Eigen::Vector3f>& uvw, double clip = 3.5,
                                        int rounds = 3);

}  // namespace tlsmon::patches
