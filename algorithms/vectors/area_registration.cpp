#include "algorithms/vectors/area_registration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::vectors {

namespace {

// The parameters: t_u, t_v, t_w, then the epoch's radiometry g, c, c_u, c_v.
constexpr int kParameters = 7;
using Vector7d = Eigen::Matrix<double, kParameters, 1>;
using Matrix7d = Eigen::Matrix<double, kParameters, kParameters>;

constexpr double kMinWeight = 0.135;  // Σw below: no value (no sample within 0.8 of the radius)
constexpr int kUnclippedIterations = 3;
constexpr double kSigmaFloor = 1e-9;     // residuals' σ of identical, noise-free samples
constexpr double kConvergence = 1e-5;    // m: the last step of t below this
constexpr double kSignificantZ2 = 6.63;  // χ²(1) at 99 %
constexpr double kMinCoarseCorrelation = 0.5;
constexpr double kFilledShare = 0.8;  // of the median pixel's Σw: a disc filled with samples

// The samples' mean spacing: √(area / n), the area counted in cells of twice a first guess
// from the bounding box (so holes and a ragged outline do not count).
double spacing_of(std::span<const AreaSample> s) {
    Eigen::AlignedBox2d box;
    for (const auto& p : s) box.extend(Eigen::Vector2d(p.u, p.v));
    const Eigen::Vector2d size = box.sizes();
    const double guess = std::sqrt(std::max(size.x() * size.y(), 1e-12) / double(s.size()));
    const double cell = 2.0 * guess;
    std::vector<std::pair<long, long>> cells;
    cells.reserve(s.size());
    for (const auto& p : s)
        cells.emplace_back(long(std::floor(p.u / cell)), long(std::floor(p.v / cell)));
    std::sort(cells.begin(), cells.end());
    const auto occupied = std::unique(cells.begin(), cells.end()) - cells.begin();
    return std::sqrt(double(occupied) * cell * cell / double(s.size()));
}

// The largest over the smallest sample spacing among the area's blocks of side `block`
// (each √(its occupied area / its samples), the area counted in cells of twice the mean
// spacing `h`, as spacing_of; blocks with fewer than kMinBlockSamples samples left out):
// about 1 over a uniform scan (the range changes by a few per cent across an area), 2–5
// where a detail window's edge crosses the area.
constexpr std::size_t kMinBlockSamples = 20;
double sampling_ratio(std::span<const AreaSample> s, double h, double block) {
    const double cell = 2.0 * h;
    // (block u, block v, cell u, cell v) of every sample, sorted: a block's samples and its
    // distinct cells are runs.
    std::vector<std::array<long, 4>> keys;
    keys.reserve(s.size());
    for (const auto& p : s)
        keys.push_back({long(std::floor(p.u / block)), long(std::floor(p.v / block)),
                        long(std::floor(p.u / cell)), long(std::floor(p.v / cell))});
    std::sort(keys.begin(), keys.end());
    double finest = std::numeric_limits<double>::infinity(), coarsest = 0;
    for (std::size_t i = 0; i < keys.size();) {
        std::size_t j = i, cells = 0;
        for (; j < keys.size() && keys[j][0] == keys[i][0] && keys[j][1] == keys[i][1]; ++j)
            cells += j == i || keys[j] != keys[j - 1];
        if (j - i >= kMinBlockSamples) {
            const double spacing = std::sqrt(double(cells) * cell * cell / double(j - i));
            finest = std::min(finest, spacing), coarsest = std::max(coarsest, spacing);
        }
        i = j;
    }
    return coarsest > 0 ? coarsest / finest : 1.0;
}

// The samples bucketed on square cells of the plane (compressed rows), for the samples
// within a radius of any point.
class SampleGrid {
  public:
    SampleGrid(std::span<const AreaSample> s, double cell) : s_(s), cell_(cell) {
        Eigen::AlignedBox2d box;
        for (const auto& p : s) box.extend(Eigen::Vector2d(p.u, p.v));
        u0_ = box.min().x(), v0_ = box.min().y();
        width_ = long(std::floor((box.max().x() - u0_) / cell)) + 1;
        height_ = long(std::floor((box.max().y() - v0_) / cell)) + 1;
        start_.assign(std::size_t(width_ * height_) + 1, 0);
        for (const auto& p : s) ++start_[std::size_t(index(p.u, p.v)) + 1];
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        members_.resize(s.size());
        std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
        for (std::size_t i = 0; i < s.size(); ++i)
            members_[fill[std::size_t(index(s[i].u, s[i].v))]++] = std::uint32_t(i);
    }

    // visit(sample, du, dv) for every sample within `radius` of (u, v), (du, dv) its offset.
    template <class Visit>
    void within(double u, double v, double radius, Visit&& visit) const {
        const long i0 = std::max(0L, long(std::floor((u - radius - u0_) / cell_)));
        const long i1 = std::min(width_ - 1, long(std::floor((u + radius - u0_) / cell_)));
        const long j0 = std::max(0L, long(std::floor((v - radius - v0_) / cell_)));
        const long j1 = std::min(height_ - 1, long(std::floor((v + radius - v0_) / cell_)));
        const double r2 = radius * radius;
        for (long j = j0; j <= j1; ++j)
            for (long i = i0; i <= i1; ++i) {
                const std::size_t c = std::size_t(j * width_ + i);
                for (std::size_t k = start_[c]; k < start_[c + 1]; ++k) {
                    const auto& p = s_[members_[k]];
                    const double du = p.u - u, dv = p.v - v;
                    if (du * du + dv * dv <= r2) visit(p, du, dv);
                }
            }
    }

  private:
    long index(double u, double v) const {
        return long(std::floor((v - v0_) / cell_)) * width_ + long(std::floor((u - u0_) / cell_));
    }
    std::span<const AreaSample> s_;
    double cell_, u0_ = 0, v0_ = 0;
    long width_ = 0, height_ = 0;
    std::vector<std::size_t> start_;
    std::vector<std::uint32_t> members_;
};

// Both channels of the samples at a point x, as local linear regression with the quartic
// (biweight) kernel: z ≈ β₀ + βᵀ(xᵢ − x), weights wᵢ = (1 − |xᵢ − x|²/ρ²)² within the radius
// ρ — an image that slides smoothly with the texture whatever the scan's sample lattice (as
// the orthoimage's Nadaraya–Watson estimate, algorithms/orthoimage.hpp), without that
// estimate's shift where the samples are denser on one side (local linear regression is
// design-adaptive: Fan 1992), and without evaluating an exponential per sample. β₀ is the value, β
// the gradient. For independent samples of variance σ² the estimates' covariance is
// σ²·(XᵀWX)⁻¹XᵀW²X(XᵀWX)⁻¹: its β block is what the samples' noise alone makes of a gradient (the
// shrinkage below), its β₀ entry the value's variance.
struct Local {
    bool valid = false;
    double weight = 0;  // Σw: how much of the kernel's disc the samples fill
    double intensity = 0, height = 0;
    Eigen::Vector2d d_intensity = Eigen::Vector2d::Zero();
    double value_noise = 0;                                    // in units of σ²
    Eigen::Matrix2d gradient_noise = Eigen::Matrix2d::Zero();  // in units of σ²
};

// The symmetric 3 × 3 matrix of the sums (upper triangle 00 01 02 11 12 22).
Eigen::Matrix3d symmetric(const std::array<double, 6>& m) {
    Eigen::Matrix3d out;
    out << m[0], m[1], m[2], m[1], m[3], m[4], m[2], m[4], m[5];
    return out;
}

Local regress(const SampleGrid& grid, const Eigen::Vector2d& x, double radius, bool noise) {
    // Sums of w·aaᵀ and w²·aaᵀ (a = (1, du, dv)), of w·I·a and w·H·a.
    std::array<double, 6> m{}, m2{};
    Eigen::Vector3d xi = Eigen::Vector3d::Zero(), xh = Eigen::Vector3d::Zero();
    const double inv_r2 = 1.0 / (radius * radius);
    grid.within(x.x(), x.y(), radius, [&](const AreaSample& s, double du, double dv) {
        const double q = 1.0 - (du * du + dv * dv) * inv_r2, w = q * q;
        const double a[6] = {1.0, du, dv, du * du, du * dv, dv * dv};
        for (int k = 0; k < 6; ++k) m[k] += w * a[k];
        if (noise)
            for (int k = 0; k < 6; ++k) m2[k] += w * w * a[k];
        const double wi = w * s.intensity, wh = w * s.w;
        xi += Eigen::Vector3d(wi, wi * du, wi * dv), xh += Eigen::Vector3d(wh, wh * du, wh * dv);
    });
    Local out;
    if (m[0] < kMinWeight) return out;
    const Eigen::Matrix3d M = symmetric(m);
    // Samples on one side or on a line (the rim of a hole) give no plane.
    const double det = M.determinant();
    if (!(det > 1e-6 * m[0] * m[3] * m[5])) return out;
    const Eigen::Matrix3d inv = M.inverse();
    const Eigen::Vector3d bi = inv * xi, bh = inv * xh;
    out.valid = true;
    out.weight = m[0];
    out.intensity = bi(0), out.height = bh(0);
    out.d_intensity = bi.tail<2>();
    if (noise) {
        const Eigen::Matrix3d q = inv * symmetric(m2) * inv;
        out.value_noise = q(0, 0), out.gradient_noise = q.bottomRightCorner<2, 2>();
    }
    return out;
}

// A gradient's components kept where each is significant at 99 % (z² = g_k²/(σ²Q_kk) above
// 6.63, χ² on 1 degree of freedom) and shrunk by its noise's share, g_k·(1 − 1/z²): the
// samples' noise has a gradient too, and taken at face value it would observe — and move the
// area along — a direction of a surface that has neither texture nor relief there (along an
// edge, the gradient across it is real and the one along it is noise).
Eigen::Vector2d significant(const Eigen::Vector2d& g, const Eigen::Matrix2d& Q, double variance) {
    if (!(variance > 0)) return g;
    Eigen::Vector2d out = Eigen::Vector2d::Zero();
    for (int k = 0; k < 2; ++k) {
        const double z2 = g(k) * g(k) / (variance * Q(k, k));
        if (z2 > kSignificantZ2) out(k) = g(k) * (1.0 - 1.0 / z2);
    }
    return out;
}

// The coarse step: the whole-pixel offset (a, b) of largest normalised cross-correlation of
// the intensities, T(r, c) against E(r + reach + b, c + reach + a), |(a, b)| ≤ reach.
std::pair<Eigen::Vector2i, double> coarse_offset(const std::vector<Local>& T, Eigen::Index rows,
                                                 Eigen::Index columns, const std::vector<Local>& E,
                                                 int reach) {
    const Eigen::Index ec = columns + 2 * reach;
    Eigen::Vector2i best = Eigen::Vector2i::Zero();  // (column, row)
    double best_ncc = -2.0;
    for (int b = -reach; b <= reach; ++b)
        for (int a = -reach; a <= reach; ++a) {
            if (a * a + b * b > reach * reach) continue;
            double n = 0, st = 0, ss = 0, stt = 0, sss = 0, sts = 0;
            for (Eigen::Index r = 0; r < rows; ++r)
                for (Eigen::Index c = 0; c < columns; ++c) {
                    const Local& t = T[std::size_t(r * columns + c)];
                    const Local& e = E[std::size_t((r + reach + b) * ec + (c + reach + a))];
                    if (!t.valid || !e.valid) continue;
                    n += 1, st += t.intensity, ss += e.intensity;
                    stt += t.intensity * t.intensity, sss += e.intensity * e.intensity;
                    sts += t.intensity * e.intensity;
                }
            if (n < 16) continue;
            const double vt = stt - st * st / n, vs = sss - ss * ss / n;
            if (vt <= 0 || vs <= 0) continue;
            const double ncc = (sts - st * ss / n) / std::sqrt(vt * vs);
            // Ties go to the smaller offset (a uniform area stays where the registration put it).
            if (ncc > best_ncc + 1e-12) best_ncc = ncc, best = Eigen::Vector2i(a, b);
        }
    return {best, best_ncc < -1.0 ? 0.0 : best_ncc};
}

// One Gauss–Newton row: f = observed − predicted and its derivatives by (t_u, t_v, t_w, g, c).
struct Row {
    double f = 0;
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  // the reference's, before shrinking
    const Eigen::Matrix2d* gradient_noise = nullptr;     // its covariance per unit variance
    Vector7d J = Vector7d::Zero();        // the model's: from the reference's shrunk gradients
    Vector7d J_epoch = Vector7d::Zero();  // f's own: from the epoch's image at p + t
    double noise = 0;  // the row's variance in units of the group's sample variance
    int group = 0;     // 0 height, 1 intensity
    std::size_t block = 0;
};

// A group's residuals' median and robust σ (1.4826 × MAD).
MedianAndMad robust_spread(const std::vector<Row>& rows, int group) {
    std::vector<double> f;
    for (const auto& row : rows)
        if (row.group == group) f.push_back(row.f);
    if (f.size() < 3) return {};
    MedianAndMad m = median_and_mad(std::move(f));
    m.mad *= kMadToSigma;
    return m;
}

// The samples' own variance of a group from its rows: Var(f) = σ²·noise per row.
double sample_variance(const std::vector<Row>& rows, int group, double sigma) {
    double mean_noise = 0;
    std::size_t n = 0;
    for (const auto& row : rows)
        if (row.group == group) mean_noise += row.noise, ++n;
    return n && mean_noise > 0 ? sigma * sigma / (mean_noise / double(n)) : 0.0;
}

}  // namespace

const char* outcome_name(AreaOutcome outcome) {
    switch (outcome) {
        case AreaOutcome::measured:
            return "measured";
        case AreaOutcome::few_points:
            return "few points";
        case AreaOutcome::few_blocks:
            return "few blocks";
        case AreaOutcome::singular:
            return "singular";
        case AreaOutcome::untextured:
            return "untextured";
        case AreaOutcome::diverged:
            return "diverged";
        case AreaOutcome::mixed_sampling:
            return "mixed sampling";
        case AreaOutcome::undersampled:
            return "undersampled";
    }
    return "?";
}

void validate(const Parameters& p) {
    if (!(p.search_radius >= 0 && p.search_radius <= 1))
        throw Error("vectors: search_radius must lie in [0, 1] m");
    if (!(p.block > 0 && p.block <= 100)) throw Error("vectors: block must lie in (0, 100] m");
    if (p.min_points < 10) throw Error("vectors: min_points must be at least 10");
    if (p.min_blocks < 2) throw Error("vectors: min_blocks must be at least 2");
    if (!(p.clip >= 1)) throw Error("vectors: clip must be at least 1");
    if (p.max_iterations < 1) throw Error("vectors: max_iterations must be at least 1");
    if (!(p.max_spacing > 0 && p.max_spacing <= 1))
        throw Error("vectors: max_spacing must lie in (0, 1] m");
    if (!(p.max_sigma > 0)) throw Error("vectors: max_sigma must be positive");
}

AreaVector register_area(std::span<const AreaSample> reference, std::span<const AreaSample> epoch,
                         const Parameters& P) {
    validate(P);
    AreaVector out;
    out.reference_points = reference.size();
    out.epoch_points = epoch.size();
    if (reference.size() < std::size_t(P.min_points) || epoch.size() < std::size_t(P.min_points))
        return out;
    const double h = spacing_of(reference);  // also the template's pixel
    out.spacing = h;
    // An area across a change of the scan's sampling (a detail window's edge) is sharp on one
    // side and blurred on the other, and with the scanner's drift that boundary moves over the
    // surface between the epochs: the match follows it (millimetres along the surface, far
    // beyond the covariance, on the simulated detail strip's edge). Such an area has no vector.
    if (h > P.max_spacing || spacing_of(epoch) > P.max_spacing)
        return out.outcome = AreaOutcome::undersampled, out;
    if (sampling_ratio(reference, h, P.block) > kMaxSamplingRatio ||
        sampling_ratio(epoch, spacing_of(epoch), P.block) > kMaxSamplingRatio)
        return out.outcome = AreaOutcome::mixed_sampling, out;
    const double radius = kKernelRadiusSpacings * h;
    const SampleGrid ref_grid(reference, radius);
    const SampleGrid epoch_grid(epoch, radius);

    // The template: the reference at pixel centres (u0 + c·h, v0 + r·h) over its extent.
    Eigen::AlignedBox2d box;
    for (const auto& p : reference) box.extend(Eigen::Vector2d(p.u, p.v));
    const double u0 = std::floor(box.min().x() / h) * h, v0 = std::floor(box.min().y() / h) * h;
    const auto columns = Eigen::Index(std::floor((box.max().x() - u0) / h)) + 1;
    const auto rows_ = Eigen::Index(std::floor((box.max().y() - v0) / h)) + 1;
    const auto centre = [&](double r, double c) { return Eigen::Vector2d(u0 + c * h, v0 + r * h); };
    std::vector<Local> T(std::size_t(rows_ * columns));
    for (Eigen::Index r = 0; r < rows_; ++r)
        for (Eigen::Index c = 0; c < columns; ++c)
            T[std::size_t(r * columns + c)] =
                regress(ref_grid, centre(double(r), double(c)), radius, true);

    // Start: the coarse offset along the surface (the epoch's intensities on the template's
    // pixels widened by the search radius), the mean height difference along the normal.
    const int reach = int(std::ceil(P.search_radius / h));
    std::vector<Local> E(std::size_t((rows_ + 2 * reach) * (columns + 2 * reach)));
    for (Eigen::Index r = 0; r < rows_ + 2 * reach; ++r)
        for (Eigen::Index c = 0; c < columns + 2 * reach; ++c)
            E[std::size_t(r * (columns + 2 * reach) + c)] =
                regress(epoch_grid, centre(double(r - reach), double(c - reach)), radius, false);
    auto [offset, ncc] = coarse_offset(T, rows_, columns, E, reach);
    out.coarse_correlation = ncc;
    // A peak of noise is no match: without texture the area starts where the registration
    // put it.
    if (ncc < kMinCoarseCorrelation) offset.setZero();
    double dh = 0;
    int nh = 0;
    for (Eigen::Index r = 0; r < rows_; ++r)
        for (Eigen::Index c = 0; c < columns; ++c) {
            const Local& t = T[std::size_t(r * columns + c)];
            const Local& e = E[std::size_t((r + reach + offset.y()) * (columns + 2 * reach) +
                                           (c + reach + offset.x()))];
            if (t.valid && e.valid) dh += e.height - t.height, ++nh;
        }
    Vector7d x;
    x << offset.x() * h, offset.y() * h, nh ? dh / nh : 0.0, 1.0, 0.0, 0.0, 0.0;
    // A weak prior about the start: a direction the area does not observe (along a smooth,
    // uniform face) keeps its start with the prior's σ instead of making N singular.
    const Vector7d x0 = x;
    Vector7d prior_sigma;
    prior_sigma << kPriorSigma, kPriorSigma, kPriorSigma, 1.0, 1.0, 1.0, 1.0;
    const Matrix7d N_prior = prior_sigma.cwiseInverse().cwiseAbs2().asDiagonal();

    // The template's pixels and their blocks (the covariance's clusters), numbered in order.
    struct Pixel {
        Eigen::Vector2d at;
        std::size_t k, block;
    };
    std::vector<Pixel> pixels;
    std::map<std::pair<long, long>, std::size_t> block_of;
    // A template pixel whose kernel reaches beyond the reference's samples (the window's rim, a
    // hole) is one-sided there while the epoch's, measured on a wider window, is not: the
    // texture just outside would enter one side only and shift the match. Only pixels whose
    // disc lies inside the samples' extent and is filled as well as the typical one take part.
    std::vector<double> weights;
    for (const auto& t : T)
        if (t.valid) weights.push_back(t.weight);
    const double full = weights.empty() ? 0.0 : median(weights);
    const Eigen::AlignedBox2d inner(box.min() + Eigen::Vector2d::Constant(radius),
                                    box.max() - Eigen::Vector2d::Constant(radius));
    std::vector<Pixel> sparse;  // every second pixel in each direction
    for (Eigen::Index r = 0; r < rows_; ++r)
        for (Eigen::Index c = 0; c < columns; ++c) {
            const std::size_t k = std::size_t(r * columns + c);
            if (!T[k].valid || T[k].weight < kFilledShare * full ||
                !inner.contains(centre(double(r), double(c))))
                continue;
            const Eigen::Vector2d at = centre(double(r), double(c));
            const std::pair<long, long> key{long(std::floor(at.x() / P.block)),
                                            long(std::floor(at.y() / P.block))};
            const std::size_t b = block_of.try_emplace(key, block_of.size()).first->second;
            pixels.push_back({at, k, b});
            if (r % 2 == 0 && c % 2 == 0) sparse.push_back(pixels.back());
        }

    double sigma[2] = {0, 0}, variance[2] = {0, 0};  // rows' robust σ; the samples' variance
    std::vector<Row> rows;
    rows.reserve(2 * pixels.size());
    Matrix7d N = Matrix7d::Zero();
    // The iterations run on every second pixel until they converge, then once on every pixel:
    // neighbouring pixels share most of their samples, so the sparse grid brings the images
    // together at a quarter of the cost; from there one Gauss–Newton step on the whole grid
    // is its solution to second order, and the covariance is the whole grid's.
    bool whole = false;
    for (int it = 0; it < P.max_iterations; ++it) {
        rows.clear();
        for (const auto& px : whole ? pixels : sparse) {
            // The epoch at the template's pixel moved by (t_u, t_v).
            const Local e = regress(epoch_grid, px.at + x.head<2>(), radius, false);
            if (!e.valid) continue;
            const Local& t = T[px.k];
            // Var(f) in units of the samples' variance: the template's and the epoch's values,
            // the epoch's taken as the template's (the same density).
            const double v = t.value_noise;
            Row hr;
            hr.f = e.height - (t.height + x(2));
            hr.J << 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0;
            hr.J_epoch = hr.J;
            hr.noise = 2.0 * v, hr.group = 0, hr.block = px.block;
            rows.push_back(hr);
            Row ir;
            const double du = px.at.x(), dv = px.at.y();
            ir.f = e.intensity - (x(3) * t.intensity + x(4) + x(5) * du + x(6) * dv);
            ir.gradient = x(3) * t.d_intensity, ir.gradient_noise = &t.gradient_noise;
            ir.J << 0.0, 0.0, 0.0, -t.intensity, -1.0, -du, -dv;
            ir.J_epoch << e.d_intensity.x(), e.d_intensity.y(), 0.0, -t.intensity, -1.0, -du, -dv;
            ir.noise = (1.0 + x(3) * x(3)) * v, ir.group = 1, ir.block = px.block;
            rows.push_back(ir);
        }
        double centre[2];  // the groups' median residuals
        for (int g = 0; g < 2; ++g) {
            const MedianAndMad m = robust_spread(rows, g);
            centre[g] = m.median, sigma[g] = m.mad;
            variance[g] = sample_variance(rows, g, sigma[g]);
        }
        if (rows.empty()) return out.outcome = AreaOutcome::singular, out;
        for (double& sg : sigma) sg = std::max(sg, kSigmaFloor);
        // The model's Jacobian along the surface: the significant gradients only, judged
        // against this iteration's noise.
        for (auto& r : rows)
            if (r.group == 1)
                r.J.head<2>() = significant(r.gradient, *r.gradient_noise, variance[r.group]);
        // Rows beyond the clip about their group's median leave (once the first iterations
        // brought the images together: before, an edge's own misfit would leave, and with it
        // what fixes the motion across the edge); the rest weigh 1/σ² of their group. About
        // the median, not zero: heights still a step off along the normal (an edge moved the
        // start) would all leave, and the normal with them.
        if (it >= kUnclippedIterations)
            std::erase_if(rows, [&](const Row& r) {
                return std::abs(r.f - centre[r.group]) > P.clip * sigma[r.group];
            });
        N = N_prior;
        Vector7d n = N_prior * (x0 - x);
        for (const auto& r : rows) {
            const double p = 1.0 / (sigma[r.group] * sigma[r.group]);
            N.noalias() += p * r.J * r.J.transpose();
            n -= p * r.J * r.f;
        }
        const Eigen::LDLT<Matrix7d> ldlt(N);
        if (ldlt.info() != Eigen::Success) return out.outcome = AreaOutcome::singular, out;
        Vector7d dx = ldlt.solve(n);
        // At most one spacing along the surface per step: the linearisation holds over the
        // texture's own scale, and a weakly textured direction must not be thrown far.
        if (const double step = dx.head<2>().norm(); step > h) dx.head<2>() *= h / step;
        x += dx;
        out.iterations = it + 1;
        if (whole) {
            // The residuals at the solution, to first order: the covariance's scores are the
            // solution's (they sum to the prior's pull), not the step's start.
            for (auto& r : rows) r.f += r.J.dot(dx);
            break;
        }
        whole = (dx.head<3>().norm() < kConvergence && it >= kUnclippedIterations) ||
                it + 2 >= P.max_iterations;
    }

    // The covariance over the blocks: the jackknife of the estimating equations, each
    // block's one-step influence d_b = (B − B_b)⁻¹·g_b (the solution without block b, less
    // the solution), with the sensitivity B = Σ J w ∂f/∂xᵀ taken from the epoch's own image —
    // a gradient of noise in the reference meets an independent one there, so what only noise
    // observes averages out of B, and N's count of it does not enter.
    std::vector<Vector7d> score(block_of.size(), Vector7d::Zero());
    std::vector<Matrix7d> block_B(block_of.size(), Matrix7d::Zero());
    std::vector<char> used_block(block_of.size(), 0);
    Matrix7d B = N_prior;
    for (const auto& r : rows) {
        const double p = 1.0 / (sigma[r.group] * sigma[r.group]);
        score[r.block] += r.J * r.f * p;
        block_B[r.block].noalias() += p * r.J * r.J_epoch.transpose();
        used_block[r.block] = 1;
    }
    for (const auto& Bb : block_B) B += Bb;
    const auto G = std::size_t(std::count(used_block.begin(), used_block.end(), 1));
    out.blocks = G;
    out.used = rows.size();
    if (G < std::size_t(P.min_blocks)) return out.outcome = AreaOutcome::few_blocks, out;
    const Eigen::FullPivLU<Matrix7d> lu(B);
    if (!lu.isInvertible()) return out.outcome = AreaOutcome::singular, out;
    std::vector<Vector7d> influence(block_of.size(), Vector7d::Zero());
    for (std::size_t b = 0; b < block_of.size(); ++b) {
        if (!used_block[b]) continue;
        const Eigen::FullPivLU<Matrix7d> without(B - block_B[b]);
        influence[b] = without.isInvertible() ? Vector7d(without.solve(score[b]))
                                              : Vector7d(lu.solve(score[b]));
    }
    // Neighbouring blocks share the pixels along their border (a pixel's value draws on the
    // samples within the kernel's radius): their influences' cross-products enter with the
    // product Bartlett weights (1 − |Δi|/2)(1 − |Δj|/2), 1/2 beside and 1/4 across a corner
    // (Conley 1999, spatial HAC; the product of Bartlett kernels keeps the sum positive
    // semi-definite).
    Matrix7d raw = Matrix7d::Zero();
    for (const auto& [key, b] : block_of)
        for (long dj = -1; dj <= 1; ++dj)
            for (long di = -1; di <= 1; ++di) {
                const auto other = block_of.find({key.first + di, key.second + dj});
                if (other == block_of.end()) continue;
                const double w =
                    (1.0 - 0.5 * double(std::abs(di))) * (1.0 - 0.5 * double(std::abs(dj)));
                raw.noalias() += w * influence[b] * influence[other->second].transpose();
            }
    // With G blocks the estimate has G − 1 degrees of freedom: the covariance is scaled so that
    // 1.96σ is Student's t(G − 1) interval (Cameron & Miller 2015, §VI: few clusters).
    const double t_ratio =
        registration::student_t_quantile(0.975, double(G - 1)) / 1.959963984540054;
    raw *= double(G - 1) / double(G) * t_ratio * t_ratio;
    // The prior's own variance beside the data's: where the data say nothing, the prior's σ.
    const Matrix7d Binv = lu.inverse();
    raw += Binv * N_prior * Binv.transpose();
    const Matrix7d Ninv = N.inverse();
    // Symmetric and positive semi-definite against rounding (B's entries span the prior's
    // 1/σ² to the data's).
    const Eigen::SelfAdjointEigenSolver<Matrix7d> eig(0.5 * (raw + raw.transpose()));
    const Matrix7d sandwich = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
                              eig.eigenvectors().transpose();
    out.displacement = x.head<3>();
    out.covariance = sandwich.topLeftCorner<3, 3>();
    out.model_covariance = Ninv.topLeftCorner<3, 3>();
    out.gain = x(3), out.offset = x(4);
    out.sigma_height = sigma[0], out.sigma_intensity = sigma[1];
    // Along the surface: where the texture does not observe it (its larger σ beyond
    // max_sigma) or the solution left the search, the area gives no vector.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> along(
        out.covariance.topLeftCorner<2, 2>());
    if (!(along.eigenvalues()(1) <= P.max_sigma * P.max_sigma))
        return out.outcome = AreaOutcome::untextured, out;
    if ((x - x0).head<2>().norm() > P.search_radius + 2.0 * h)
        return out.outcome = AreaOutcome::diverged, out;
    out.outcome = AreaOutcome::measured;
    return out;
}

}  // namespace tlsmon::vectors
