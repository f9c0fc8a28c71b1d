#include "algorithms/image_correlation.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/cubic_bspline.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace {

void check_shape(const Image& im, const char* what) {
    if (im.valid.rows() != im.value.rows() || im.valid.cols() != im.value.cols()) {
        throw Error(std::string("image correlation: the ") + what +
                    "'s mask and values differ in shape");
    }
}

struct Ncc {
    double value = -2.0;
    bool ok = false;
};

// NCC at an integer offset over the template's valid pixels that meet valid search pixels.
Ncc ncc_at(const Image& t, const Image& s, Eigen::Index off_r, Eigen::Index off_c,
           std::size_t needed) {
    double n = 0, st = 0, ss = 0, stt = 0, sss = 0, sts = 0;
    for (Eigen::Index c = 0; c < t.columns(); ++c) {
        const Eigen::Index sc = c + off_c;
        if (sc < 0 || sc >= s.columns()) continue;
        for (Eigen::Index r = 0; r < t.rows(); ++r) {
            const Eigen::Index sr = r + off_r;
            if (sr < 0 || sr >= s.rows() || !t.valid(r, c) || !s.valid(sr, sc)) continue;
            const double a = t.value(r, c), b = s.value(sr, sc);
            n += 1;
            st += a;
            ss += b;
            stt += a * a;
            sss += b * b;
            sts += a * b;
        }
    }
    if (n < static_cast<double>(needed) || n < 2) return {};
    const double vt = stt - st * st / n, vs = sss - ss * ss / n;
    if (vt <= 0.0 || vs <= 0.0) return {0.0, true};
    return {(sts - st * ss / n) / std::sqrt(vt * vs), true};
}

// Vertex of the parabola through (−1, a), (0, b), (1, c); 0 when it has no maximum.
double parabola_vertex(double a, double b, double c) {
    const double curvature = a - 2.0 * b + c;
    if (!(curvature < 0.0)) return 0.0;
    const double x = 0.5 * (a - c) / curvature;
    return std::abs(x) <= 1.0 ? x : 0.0;
}

}  // namespace

double normalised_cross_correlation(const Eigen::ArrayXd& a, const Eigen::ArrayXd& b) {
    if (a.size() != b.size() || a.size() < 2) return 0.0;
    const Eigen::ArrayXd da = a - a.mean(), db = b - b.mean();
    const double va = da.square().sum(), vb = db.square().sum();
    if (va <= 0.0 || vb <= 0.0) return 0.0;
    return (da * db).sum() / std::sqrt(va * vb);
}

CorrelationResult correlate_template(const Image& templ, const Image& search,
                                     const Eigen::Vector2i& origin,
                                     const CorrelationParameters& p) {
    check_shape(templ, "template");
    check_shape(search, "search image");
    if (p.search_radius < 0) throw Error("image correlation: search_radius must be >= 0");
    const auto template_valid = static_cast<std::size_t>(templ.valid.count());
    if (template_valid < 4) throw Error("image correlation: the template has no valid pixels");
    const auto needed = static_cast<std::size_t>(std::ceil(p.min_overlap * template_valid));

    // 1. Integer offsets: the NCC surface and its peak.
    const int R = p.search_radius, side = 2 * R + 1;
    Eigen::ArrayXXd surface = Eigen::ArrayXXd::Constant(side, side, -2.0);
    Ncc best;
    int best_r = 0, best_c = 0;
    for (int dr = -R; dr <= R; ++dr) {
        for (int dc = -R; dc <= R; ++dc) {
            const Ncc n = ncc_at(templ, search, origin.x() + dr, origin.y() + dc, needed);
            if (!n.ok) continue;
            surface(dr + R, dc + R) = n.value;
            if (!best.ok || n.value > best.value) {
                best = n;
                best_r = dr;
                best_c = dc;
            }
        }
    }
    CorrelationResult out;
    if (!best.ok) return out;
    out.peak_ncc = best.value;
    if (R > 0 && (std::abs(best_r) == R || std::abs(best_c) == R)) return out;

    // 2. Parabola through the peak and its neighbours, per axis.
    Eigen::Vector2d s(best_c, best_r);
    if (R > 0) {
        const auto at = [&](int dr, int dc) { return surface(best_r + dr + R, best_c + dc + R); };
        if (at(0, -1) > -2.0 && at(0, 1) > -2.0)
            s.x() += parabola_vertex(at(0, -1), at(0, 0), at(0, 1));
        if (at(-1, 0) > -2.0 && at(1, 0) > -2.0)
            s.y() += parabola_vertex(at(-1, 0), at(0, 0), at(1, 0));
    }

    // 3. Least-squares matching. The residual e = S(p + o + s) − g·T(p) − b is minimised
    // with the Jacobian built from the template's gradient (central differences): ∂e/∂s =
    // ∇S ≈ g·∇T at the solution, so the fixed point is the same as with ∇S, and the search
    // image's noise never enters the Jacobian. With ∇S it would: Σ e·∇e then contains
    // ½ ∇Σ n(s)², the interpolated noise's energy, which is lowest at half-pixel shifts and
    // pulls every estimate there by ≈ σ_n² / |∇S|² pixels.
    struct Pixel {
        Eigen::Index r, c;
        double t, gx, gy;  // template value and gradient (columns, rows)
    };
    std::vector<Pixel> pixels;
    for (Eigen::Index c = 1; c + 1 < templ.columns(); ++c) {
        for (Eigen::Index r = 1; r + 1 < templ.rows(); ++r) {
            if (!templ.valid(r, c) || !templ.valid(r, c - 1) || !templ.valid(r, c + 1) ||
                !templ.valid(r - 1, c) || !templ.valid(r + 1, c)) {
                continue;
            }
            pixels.push_back({r, c, templ.value(r, c),
                              0.5 * (templ.value(r, c + 1) - templ.value(r, c - 1)),
                              0.5 * (templ.value(r + 1, c) - templ.value(r - 1, c))});
        }
    }
    const BSplineImage spline = bspline_image(search);
    double gain = 1.0, offset = 0.0;
    Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
    double sum_sq = 0.0;
    std::size_t used = 0;
    bool converged = false;
    std::vector<double> tv, sv;
    const std::size_t needed_lsm = static_cast<std::size_t>(p.min_overlap * pixels.size());
    for (int it = 0; it < p.max_iterations; ++it) {
        normal.setZero();
        Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
        sum_sq = 0.0;
        used = 0;
        tv.clear();
        sv.clear();
        for (const Pixel& px : pixels) {
            CubicSample smp;
            if (!bspline_interpolate(spline, static_cast<double>(px.r + origin.x()) + s.y(),
                                     static_cast<double>(px.c + origin.y()) + s.x(), smp)) {
                continue;
            }
            const double e = smp.value - gain * px.t - offset;
            const Eigen::Vector4d j(gain * px.gx, gain * px.gy, -px.t, -1.0);
            normal += j * j.transpose();
            rhs -= j * e;
            sum_sq += e * e;
            ++used;
            tv.push_back(px.t);
            sv.push_back(smp.value);
        }
        out.iterations = it + 1;
        if (used < needed_lsm || used < 8) return out;
        const Eigen::Vector4d delta = normal.ldlt().solve(rhs);
        if (!delta.allFinite()) return out;
        s += delta.head<2>();
        gain += delta(2);
        offset += delta(3);
        if ((s - Eigen::Vector2d(best_c, best_r)).cwiseAbs().maxCoeff() > 1.5) return out;
        if (delta.head<2>().norm() < p.convergence) {
            converged = true;
            break;
        }
    }
    if (!converged) return out;
    out.found = true;
    out.shift = s;
    out.pixels = used;
    const double dof = static_cast<double>(used) - 4.0;
    const Eigen::Matrix4d inv = normal.inverse();
    out.covariance = (sum_sq / dof) * inv.topLeftCorner<2, 2>();
    out.ncc = normalised_cross_correlation(
        Eigen::Map<const Eigen::ArrayXd>(tv.data(), static_cast<Eigen::Index>(tv.size())),
        Eigen::Map<const Eigen::ArrayXd>(sv.data(), static_cast<Eigen::Index>(sv.size())));
    return out;
}

}  // namespace tlsmon
