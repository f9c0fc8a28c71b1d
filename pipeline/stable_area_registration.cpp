#include "pipeline/stable_area_registration.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <unordered_map>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "algorithms/registration/supervoxel_covariance.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "core/payload.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/pcl_adapter.hpp"

namespace tlsmon {

namespace reg = registration;

namespace {

// A supervoxel whose voxels lie along a line (one scan row on grazing ground) has no normal.
constexpr double kMinSpread = 0.05;
// A "plane" that holds the scanner is a sheet of rays, not a surface: the mixed returns
// strung along the beams at an edge, or a shadow's border. Its normal is square to the line
// of sight (|cos α| about 0, where real ground 1.5 m below the scanner at 150 m still has 0.01).
constexpr double kMinCosIncidence = 0.005;
// The voxel grid's origin, in voxels: off every round coordinate. A grid aligned on z = 0 cuts
// level ground of a levelled project frame along its plane; each voxel then holds only the
// points whose noise took them above (or below) it, and a supervoxel of one layer, compared
// with an epoch's voxels of both, shows a change of about the noise's σ that is not there.
// The covariance's cells start off alike (in cells), for the same reason at their scale.
const Eigen::Vector3d kGridOrigin(0.382, 0.618, 0.5);

std::vector<Eigen::Vector3d> all_points(const std::vector<Scan>& scans, double range_scale) {
    std::size_t n = 0;
    for (const auto& s : scans) n += s.xyz.size();
    std::vector<Eigen::Vector3d> out;
    out.reserve(n);
    for (const auto& scan : scans) {
        const Eigen::Vector3d o = scan.scanner_position();
        for (const auto& x : scan.xyz) {
            out.push_back(range_scale == 1.0 ? Eigen::Vector3d(x)
                                             : Eigen::Vector3d(o + (x - o) / range_scale));
        }
    }
    return out;
}

Eigen::Vector3d apply(const Eigen::Matrix4d& T, const Eigen::Vector3d& x) {
    return T.topLeftCorner<3, 3>() * x + T.topRightCorner<3, 1>();
}

// The largest movement of the reference's bounding box's corners from A to B.
double largest_movement(const Eigen::AlignedBox3d& box, const Eigen::Matrix4d& A,
                        const Eigen::Matrix4d& B) {
    double m = 0;
    for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d p = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
        m = std::max(m, (apply(A, p) - apply(B, p)).norm());
    }
    return m;
}

template <class Regions>
bool in_regions(const Regions& regions, const Eigen::Vector3d& p) {
    for (const auto& r : regions) {
        if (r.contains(p)) return true;
    }
    return false;
}

std::string refusal_for_conditioning(double conditioning, double limit) {
    return fmt::format(
        "ill-conditioned: the stable areas do not hold all six parameters (conditioning {:.2g} "
        "of the normal matrix below registration.stable_min_conditioning = {:.2g}; e.g. all in "
        "one plane, or planes in only two directions)",
        conditioning, limit);
}

// A voxel's weight in the adjustment, p = (1 mm / σ_k)²: σ_k the scatter of its supervoxel's
// reference voxels about their plane (the noise at its range and incidence, and its roughness),
// at least kMinPatchSigma. Unweighted, the far grazing ground (σ_k 2–2.5 mm) pulled a
// 140 m pier's top by 0.5 mm with a few per cent of the voxels (docs/registration.md).
constexpr double kMinPatchSigma = 0.0002;  // m, as the adjustment's own σ̂ floor
double voxel_weight(const reg::SupervoxelPatch& patch) {
    const double s = std::max(patch.sigma, kMinPatchSigma) / 0.001;
    return 1.0 / (s * s);
}

// λ_min/λ_max of N = Σ a·aᵀ, a = (ρ⁻¹·(x × n), n) about the pairs' centroid, ρ their RMS
// distance from it: a rotation counted as the movement it makes at ρ, so that the ratio has
// no unit and a free direction (a translation along a plane, a turn about its normal) gives 0.
double conditioning_of(std::span<const reg::PointPlanePair> pairs) {
    if (pairs.empty()) return 0.0;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : pairs) c += p.reference;
    c /= static_cast<double>(pairs.size());
    double rho2 = 0;
    for (const auto& p : pairs) rho2 += (p.reference - c).squaredNorm();
    const double rho = std::sqrt(rho2 / static_cast<double>(pairs.size()));
    if (!(rho > 0)) return 0.0;
    Eigen::Matrix<double, 6, 6> N = Eigen::Matrix<double, 6, 6>::Zero();
    for (const auto& p : pairs) {
        Eigen::Matrix<double, 6, 1> a;
        a.head<3>() = (p.reference - c).cross(p.normal) / rho;
        a.tail<3>() = p.normal;
        N.selfadjointView<Eigen::Lower>().rankUpdate(a);
    }
    N = N.selfadjointView<Eigen::Lower>();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(N);
    const auto l = es.eigenvalues();
    return l(5) > 0 ? std::max(0.0, l(0)) / l(5) : 0.0;
}

}  // namespace

const char* name_of(SupervoxelState state) {
    switch (state) {
        case SupervoxelState::stable:
            return "stable";
        case SupervoxelState::unstable:
            return "unstable";
        case SupervoxelState::unknown:
            return "unknown";
        case SupervoxelState::not_planar:
            return "not_planar";
    }
    return "unknown";
}

std::string ReferenceSupervoxels::encode() const {
    PayloadWriter w;
    std::vector<double> s;
    s.reserve(3 * samples.size());
    for (const auto& p : samples)
        for (int k = 0; k < 3; ++k) s.push_back(p(k));
    w.put_array(s);
    w.put_array(label);
    std::vector<double> p;
    p.reserve(10 * patches.size());
    for (const auto& q : patches) {
        for (int k = 0; k < 3; ++k) p.push_back(q.centroid(k));
        for (int k = 0; k < 3; ++k) p.push_back(q.normal(k));
        p.push_back(q.surface_variation);
        p.push_back(q.spread);
        p.push_back(q.sigma);
        p.push_back(static_cast<double>(q.samples));
    }
    w.put_array(p);
    for (int k = 0; k < 3; ++k) w.put(viewpoint(k));
    w.put(milliseconds);
    return w.take();
}

ReferenceSupervoxels ReferenceSupervoxels::decode(std::string_view payload) {
    PayloadReader r(payload);
    ReferenceSupervoxels out;
    const auto s = r.get_array<double>();
    out.label = r.get_array<std::int32_t>();
    const auto p = r.get_array<double>();
    if (s.size() % 3 != 0 || s.size() / 3 != out.label.size() || p.size() % 10 != 0) {
        throw Error("reference cache payload: supervoxels of inconsistent sizes");
    }
    for (std::size_t i = 0; i < s.size(); i += 3)
        out.samples.emplace_back(s[i], s[i + 1], s[i + 2]);
    for (std::size_t i = 0; i < p.size(); i += 10) {
        reg::SupervoxelPatch q;
        q.centroid = Eigen::Vector3d(p[i], p[i + 1], p[i + 2]);
        q.normal = Eigen::Vector3d(p[i + 3], p[i + 4], p[i + 5]);
        q.surface_variation = p[i + 6];
        q.spread = p[i + 7];
        q.sigma = p[i + 8];
        q.samples = static_cast<std::size_t>(p[i + 9]);
        out.patches.push_back(q);
    }
    const auto n = static_cast<std::int32_t>(out.patches.size());
    for (const auto l : out.label) {
        if (l < -1 || l >= n) throw Error("reference cache payload: supervoxel label out of range");
    }
    for (int k = 0; k < 3; ++k) out.viewpoint(k) = r.get<double>();
    out.milliseconds = r.get<double>();
    r.finish();
    return out;
}

std::string supervoxel_parameters(const StableAreaConfig& c) {
    return fmt::format("voxel={:.17g};seed={:.17g};spatial=0.4;normal=1;grid=0.382,0.618,0.5",
                       c.voxel, c.seed);
}

std::shared_ptr<const ReferenceSupervoxels> cached_supervoxels(const StableAreaConfig& config,
                                                               ReferenceEpoch& reference,
                                                               ReferenceCache& cache) {
    return cache.get<ReferenceSupervoxels>(
        reference, ProductKey{"registration.supervoxels", supervoxel_parameters(config), 1},
        [&](const std::vector<Scan>& scans) { return build_supervoxels(config, scans); });
}

ReferenceSupervoxels build_supervoxels(const StableAreaConfig& config,
                                       const std::vector<Scan>& scans) {
    const auto t0 = std::chrono::steady_clock::now();
    ReferenceSupervoxels out;
    if (!scans.empty()) out.viewpoint = scans.front().scanner_position();
    out.samples = voxel_centroids(all_points(scans, 1.0), config.voxel, config.voxel * kGridOrigin);
    if (out.samples.empty()) return out;
    SupervoxelParams p;
    p.voxel = config.voxel;
    p.seed = config.seed;
    const std::vector<std::uint32_t> labels = supervoxel_labels(out.samples, p);
    // Labels 1.. to dense indices, in order of first appearance.
    std::unordered_map<std::uint32_t, std::int32_t> index;
    std::vector<std::vector<Eigen::Vector3d>> members;
    out.label.assign(out.samples.size(), -1);
    for (std::size_t i = 0; i < labels.size(); ++i) {
        if (labels[i] == 0) continue;
        const auto [it, inserted] =
            index.try_emplace(labels[i], static_cast<std::int32_t>(members.size()));
        if (inserted) members.emplace_back();
        members[static_cast<std::size_t>(it->second)].push_back(out.samples[i]);
        out.label[i] = it->second;
    }
    out.patches.resize(members.size());
    parallel_for(members.size(), [&](std::size_t k) {
        if (members[k].size() >= 3)
            out.patches[k] = reg::patch_of(members[k], out.viewpoint);
        else
            out.patches[k].samples = members[k].size();
    });
    out.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

bool is_planar(const StableAreaConfig& config, const reg::SupervoxelPatch& patch,
               const Eigen::Vector3d& viewpoint) {
    const Eigen::Vector3d sight = patch.centroid - viewpoint;
    return patch.samples >= static_cast<std::size_t>(config.min_samples) &&
           patch.sigma <= config.max_roughness && patch.spread >= kMinSpread &&
           std::fabs(patch.normal.dot(sight)) >= kMinCosIncidence * sight.norm();
}

namespace {

// The epoch's voxels on the reference's supervoxels: each voxel assigned to the supervoxel of
// its nearest reference voxel under a transformation, ranges corrected.
class EpochOnSupervoxels {
  public:
    EpochOnSupervoxels(const RegistrationConfig& config, const ReferenceSupervoxels& reference,
                       const std::vector<Scan>& scans, const RangeScales& scales)
        : config_(config.stable_areas), reference_(reference) {
        const bool correct = scales.epoch && scales.reference;
        // The reference scaled by 1/scale about its scanner (its patches alike, to first
        // order: a plane's offset scales, its normal does not).
        samples_ = reference.samples;
        patches = reference.patches;
        if (correct) {
            const Eigen::Vector3d o = reference.viewpoint;
            for (auto& p : samples_) p = o + (p - o) / *scales.reference;
            for (auto& p : patches) p.centroid = o + (p.centroid - o) / *scales.reference;
        }
        planar.resize(patches.size());
        candidate.resize(patches.size());
        monitored.resize(patches.size());
        for (std::size_t k = 0; k < patches.size(); ++k) {
            planar[k] = is_planar(config_, patches[k], reference.viewpoint);
            monitored[k] = in_regions(config.zones, reference.patches[k].centroid);
            candidate[k] = planar[k] && !monitored[k];
        }
        voxels = voxel_centroids(all_points(scans, correct ? *scales.epoch : 1.0), config_.voxel,
                                 config_.voxel * kGridOrigin);
        for (const auto& p : samples_) box_.extend(p);
        if (!samples_.empty()) tree_ = std::make_unique<NearestPoints>(samples_);
        members.resize(patches.size());
    }
    bool empty() const { return voxels.empty() || samples_.empty(); }
    std::size_t reference_size() const { return samples_.size(); }

    // Assigns every voxel under T, unless T moves no reference point by a quarter voxel from
    // the last assignment's (a sub-voxel move keeps each voxel on its supervoxel).
    void assign(const Eigen::Matrix4d& T, bool always = false) {
        if (!always && assigned_ && largest_movement(box_, T, T_assigned_) <= 0.25 * config_.voxel)
            return;
        std::vector<std::int32_t> label(voxels.size(), -1);
        parallel_for(voxels.size(), [&](std::size_t i) {
            const std::int64_t j =
                tree_->nearest(apply(T, voxels[i]), config_.max_correspondence_distance);
            label[i] = j < 0 ? -1 : reference_.label[static_cast<std::size_t>(j)];
        });
        for (auto& v : members) v.clear();
        for (std::size_t i = 0; i < voxels.size(); ++i) {
            if (label[i] >= 0)
                members[static_cast<std::size_t>(label[i])].push_back(
                    static_cast<std::uint32_t>(i));
        }
        T_assigned_ = T;
        assigned_ = true;
    }

    // Every supervoxel's state, change and LoD under T (whose covariance gives σ_T) into m;
    // returns which are stable.
    std::vector<char> test(const reg::RigidTransform& T, double z, StableAreaMeasurement& m) {
        const Eigen::Matrix4d H = T.matrix();
        std::vector<char> stable(patches.size(), 0);
        variance.assign(patches.size(), 0.0);
        parallel_for(patches.size(), [&](std::size_t k) {
            m.changes[k] = m.lods[k] = std::numeric_limits<float>::quiet_NaN();
            if (!planar[k]) {
                m.states[k] = SupervoxelState::not_planar;
                return;
            }
            if (members[k].size() < static_cast<std::size_t>(config_.min_samples)) {
                m.states[k] = SupervoxelState::unknown;
                return;
            }
            const auto& q = patches[k];
            std::vector<double> d;
            d.reserve(members[k].size());
            Eigen::Vector3d mean = Eigen::Vector3d::Zero();
            for (const auto i : members[k]) {
                d.push_back(q.normal.dot(apply(H, voxels[i]) - q.centroid));
                mean += voxels[i];
            }
            mean /= static_cast<double>(members[k].size());
            const double sigma_T = reg::registration_sigma_along(T, mean, q.normal);
            const reg::SupervoxelChange ch = reg::change_of(q, d, sigma_T, z);
            variance[k] = ch.sigma_epoch * ch.sigma_epoch / static_cast<double>(ch.samples) +
                          q.sigma * q.sigma / static_cast<double>(q.samples);
            m.changes[k] = static_cast<float>(ch.change);
            m.lods[k] = static_cast<float>(ch.lod);
            stable[k] = !ch.significant();
            m.states[k] = stable[k] ? SupervoxelState::stable : SupervoxelState::unstable;
        });
        return stable;
    }

    std::vector<Eigen::Vector3d> voxels;  // the epoch's, epoch frame
    std::vector<reg::SupervoxelPatch> patches;
    std::vector<char> planar;
    // Inside a [[zone]]: the monitored structure, tested but never in the datum (as the
    // planes' congruence test keeps the zones' planes out).
    std::vector<char> monitored;
    std::vector<char> candidate;  // planar and outside the zones: may enter the datum
    // Per supervoxel, of its change at the last test: s_e²/m_e + s_r²/m (m²; 0 without one).
    std::vector<double> variance;
    std::vector<std::vector<std::uint32_t>> members;  // each supervoxel's voxels

  private:
    const StableAreaConfig& config_;
    const ReferenceSupervoxels& reference_;
    std::vector<Eigen::Vector3d> samples_;
    Eigen::AlignedBox3d box_;
    std::unique_ptr<NearestPoints> tree_;
    Eigen::Matrix4d T_assigned_ = Eigen::Matrix4d::Identity();
    bool assigned_ = false;
};

// The supervoxels of the datum as observations of their changes, for the supervoxel-level
// covariance (supervoxel_covariance.hpp), each weighted as the adjustment weighs its voxels.
std::vector<reg::SupervoxelObservation> datum_observations(const EpochOnSupervoxels& e,
                                                           const std::vector<char>& in_datum,
                                                           const StableAreaMeasurement& m) {
    std::vector<reg::SupervoxelObservation> out;
    for (std::size_t k = 0; k < e.patches.size(); ++k) {
        if (!in_datum[k]) continue;
        const auto& q = e.patches[k];
        out.push_back({q.centroid, q.normal,
                       voxel_weight(q) * static_cast<double>(e.members[k].size()),
                       static_cast<double>(m.changes[k]), e.variance[k]});
    }
    return out;
}

StableAreaMeasurement empty_measurement(std::size_t supervoxels) {
    StableAreaMeasurement m;
    m.supervoxels = supervoxels;
    m.states.assign(supervoxels, SupervoxelState::not_planar);
    m.changes.assign(supervoxels, std::numeric_limits<float>::quiet_NaN());
    m.lods.assign(supervoxels, std::numeric_limits<float>::quiet_NaN());
    return m;
}

// The counts and the stable share from the states; the zones' supervoxels apart.
void count_states(const EpochOnSupervoxels& e, StableAreaMeasurement& m) {
    std::size_t stable_samples = 0, known_samples = 0;
    m.stable = m.unstable = m.unknown = m.not_planar = m.monitored = 0;
    for (std::size_t k = 0; k < m.states.size(); ++k) {
        const std::size_t n = e.members[k].size();
        if (e.monitored[k] && e.planar[k]) {
            ++m.monitored;
            continue;
        }
        switch (m.states[k]) {
            case SupervoxelState::stable:
                ++m.stable;
                stable_samples += n;
                known_samples += n;
                break;
            case SupervoxelState::unstable:
                ++m.unstable;
                known_samples += n;
                break;
            case SupervoxelState::unknown:
                ++m.unknown;
                break;
            case SupervoxelState::not_planar:
                ++m.not_planar;
                break;
        }
    }
    m.stable_share = known_samples ? double(stable_samples) / double(known_samples) : 0.0;
}

}  // namespace

StableAreaMeasurement supervoxel_changes(const RegistrationConfig& config,
                                         const ReferenceSupervoxels& reference,
                                         const std::vector<Scan>& scans,
                                         const registration::RigidTransform& T,
                                         const RangeScales& scales) {
    StableAreaMeasurement m = empty_measurement(reference.patches.size());
    EpochOnSupervoxels e(config, reference, scans, scales);
    m.epoch_samples = e.voxels.size();
    if (e.empty()) return m;
    e.assign(T.matrix(), true);
    e.test(T, reg::normal_quantile(1.0 - config.stable_areas.alpha / 2.0), m);
    count_states(e, m);
    return m;
}

StableAreaMeasurement measure_stable_areas(const RegistrationConfig& config,
                                           const ReferenceSupervoxels& reference,
                                           const std::vector<Scan>& scans,
                                           const Eigen::Matrix4d& start,
                                           const RangeScales& scales) {
    const auto t0 = std::chrono::steady_clock::now();
    const StableAreaConfig& c = config.stable_areas;
    StableAreaMeasurement m = empty_measurement(reference.patches.size());
    const auto finish = [&] {
        m.milliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        return m;
    };
    EpochOnSupervoxels e(config, reference, scans, scales);
    m.epoch_samples = e.voxels.size();
    if (e.empty()) {
        m.refused =
            fmt::format("no points (epoch {}, reference {})", e.voxels.size(), e.reference_size());
        return finish();
    }
    e.assign(start, true);
    const std::size_t n_patches = e.patches.size();
    // The first round's set: the candidates inside the hints when they hold every direction
    // (tried below), else every candidate.
    std::vector<char> stable = e.candidate;
    std::vector<char> hinted(n_patches, 0);
    bool hints = false;
    for (std::size_t k = 0; k < n_patches; ++k) {
        hinted[k] = e.candidate[k] && in_regions(config.icp.regions, e.patches[k].centroid);
        hints = hints || hinted[k];
    }
    const double z = reg::normal_quantile(1.0 - c.alpha / 2.0);
    // Leaving the set takes significance over the whole family of candidates (Bonferroni, α/n):
    // at α alone about α of the good supervoxels look significant by chance in every round,
    // and dropping them (more often those a face's common error pushes one way) moved the
    // datum and kept the rounds from settling. Their state still says what the test at α saw.
    const auto n_candidates =
        static_cast<double>(std::count(e.candidate.begin(), e.candidate.end(), char{1}));
    const double leave_ratio =
        reg::normal_quantile(1.0 - c.alpha / (2.0 * std::max(n_candidates, 1.0))) / z;
    reg::PointToPlaneParams fp;
    // Every pair of a supervoxel refers to its centroid, so a cell of the cluster-robust
    // covariance holds whole supervoxels: their voxels err together (the supervoxel's own
    // plane offset, the beam's footprint over it), and neighbouring supervoxels alike (a
    // slowly moving part that stayed within its LoD).
    fp.cluster_size = c.cluster_size;
    fp.cell_origin = c.cluster_size * kGridOrigin;
    fp.cell_effect = false;  // supervoxel_covariance models the cells at supervoxel level
    Eigen::Matrix4d T = start;
    std::optional<reg::PointToPlaneFit> fit;
    std::vector<reg::PointPlanePair> pairs;
    for (int round = 1; round <= c.max_iterations; ++round) {
        m.iterations = round;
        const bool on_hints = round == 1 && hints;
        const std::vector<char>& in_datum = on_hints ? hinted : stable;
        pairs.clear();
        for (std::size_t k = 0; k < n_patches; ++k) {
            if (!in_datum[k]) continue;
            const double w = voxel_weight(e.patches[k]);
            for (const auto i : e.members[k]) {
                pairs.push_back({e.voxels[i], e.patches[k].centroid, e.patches[k].normal, w});
            }
        }
        try {
            fit = reg::fit_point_to_plane(pairs, T, fp);
        } catch (const Error& err) {
            if (on_hints) {  // the hints alone do not hold: every planar supervoxel
                hints = false;
                --round;
                continue;
            }
            m.refused = std::string("ill-conditioned: ") + err.what();
            return finish();
        }
        T = fit->transform.matrix();
        e.assign(T);
        // Tested with σ_T from s0²·N⁻¹, not from the cluster-robust covariance: while moving
        // parts are still in the set, their own residuals inflate that one, every LoD grows
        // with it and hides them (a moved abutment stayed in and pulled the `pier` datum by
        // 1 mm; docs/registration.md).
        const reg::RigidTransform tested = reg::rigid_transform_from(
            fit->transform.rotation, fit->transform.translation, fit->independent);
        std::vector<char> next = e.test(tested, z, m);
        for (std::size_t k = 0; k < n_patches; ++k) next[k] = next[k] && e.candidate[k];
        // A fit on a set that still holds moving parts is pulled towards them, and the change
        // of good supervoxels looks significant against it: only the worst leave per round,
        // those beyond half the largest |change|/LoD (as the congruence test drops its worst
        // plane first) and beyond the family's ratio; a supervoxel within its LoD (re)enters
        // at once.
        double worst = 0;
        for (std::size_t k = 0; k < n_patches; ++k) {
            if (stable[k] && !next[k] && e.planar[k] && m.lods[k] > 0)
                worst = std::max(worst, double(std::fabs(m.changes[k]) / m.lods[k]));
        }
        const double leave = std::max(worst > 2.0 ? 0.5 * worst : 0.0, leave_ratio);
        for (std::size_t k = 0; k < n_patches; ++k) {
            if (stable[k] && !next[k] && m.states[k] == SupervoxelState::unstable &&
                std::fabs(m.changes[k]) / m.lods[k] < leave) {
                next[k] = 1;  // kept this round; its state says what it looks like now
            }
        }
        const bool same = next == stable && !on_hints;
        stable = std::move(next);
        if (same) {
            m.settled = true;
            break;
        }
    }
    // The figures of the last adjustment.
    m.pairs = fit->pairs;
    m.outliers = fit->outliers;
    m.clusters = fit->clusters;
    m.rms = fit->rms;
    m.conditioning = conditioning_of(pairs);
    m.inflation = fit->inflation;
    m.variance_factor = fit->variance_factor;
    m.transform = fit->transform;
    const Eigen::Vector3d t = fit->transform.translation;
    m.fit = fit;
    const auto supervoxels = reg::supervoxel_covariance(datum_observations(e, stable, m), t,
                                                        {c.cluster_size, fp.cell_origin});
    if (supervoxels) {
        m.supervoxel_covariance = supervoxels->covariance;
        m.cell_sigma = supervoxels->cell_sigma;
    }
    if (const auto& C = m.supervoxel_covariance) {
        const reg::Covariance6 reported =
            reg::larger_of(fit->transform.small_rotation_covariance.topLeftCorner<6, 6>(), *C);
        m.transform = reg::rigid_transform_from(fit->transform.rotation, t, reported);
        m.transform->variance_factor = fit->transform.variance_factor;
        m.transform->redundancy = fit->transform.redundancy;
        m.transform->iterations = fit->transform.iterations;
        for (int k = 0; k < 6; ++k) {
            m.inflation = std::max(m.inflation, std::sqrt(reported(k, k) / fit->independent(k, k)));
        }
    }
    count_states(e, m);
    if (m.conditioning < c.min_conditioning) {
        m.refused = refusal_for_conditioning(m.conditioning, c.min_conditioning);
    } else if (static_cast<int>(m.stable) < c.min_supervoxels) {
        m.refused = fmt::format(
            "{} stable supervoxels, fewer than registration.stable_min_supervoxels = {}", m.stable,
            c.min_supervoxels);
    } else if (m.stable_share < c.min_share) {
        m.refused = fmt::format("stable share {:.2f} below registration.stable_min_share = {:.2f}",
                                m.stable_share, c.min_share);
    }
    return finish();
}

void apply_stable_areas(const RegistrationConfig& config, const ReferenceSupervoxels& reference,
                        const std::vector<Scan>& scans, const RangeScales& scales,
                        RegistrationResult& result, const std::optional<reg::RigidTransform>& prior,
                        const CoarsePoseSearch& coarse) {
    if (!config.uses_stable_areas()) return;
    const bool rms_gate = result.gate.rfind("RMS", 0) == 0;
    const bool joint = result.tested.accepted() && result.tested.transform && !rms_gate;
    Eigen::Matrix4d start = Eigen::Matrix4d::Identity();
    std::string from = "the identity";
    if (joint) {
        start = result.tested.transform->matrix();
        from = "the " + registration_method(result) + " transformation";
    } else if (prior) {
        start = prior->matrix();
        from = "the last accepted registration's pose";
    }
    StableAreaMeasurement m = measure_stable_areas(config, reference, scans, start, scales);
    m.start = from;
    // Refused alone from the last pose (a knocked or re-set scanner, or no pose yet): the
    // rounds once more from a coarse pose found without a prior.
    if (!joint && !m.refused.empty() && coarse) {
        const reg::RigidTransform from_pose = reg::rigid_transform_from(
            start.topLeftCorner<3, 3>(), start.topRightCorner<3, 1>(), reg::Covariance6::Zero());
        if (const auto found = coarse(from_pose)) {
            const StationChange& c = found->change;
            StableAreaMeasurement again =
                measure_stable_areas(config, reference, scans, found->approximate.matrix(), scales);
            if (again.refused.empty()) {
                again.start = fmt::format(
                    "the planes matched without a prior ({} planes explained)", c.support);
                if (c.shift_m > config.planes.max_offset ||
                    c.turn_deg > config.planes.max_angle_deg)
                    again.station_change = c;
                m = std::move(again);
            } else {
                m.refused += fmt::format(
                    "; from the planes matched without a prior ({} planes explained, the scanner "
                    "{:.3f} m and {:.2f}° away): {}",
                    c.support, c.shift_m, c.turn_deg, again.refused);
            }
        } else {
            m.refused += "; the planes matched without a prior found no pose either";
        }
    }
    m.role = joint ? "joint" : "alone";
    if (joint) {
        if (m.refused.empty()) {
            m.refused = join_estimate(config, result, *m.transform, registration_method(result),
                                      m.agreement);
            m.used = m.refused.empty();
        }
    } else {
        if (config.uses_targets() || config.uses_planes()) {
            m.targets_status =
                std::string(name_of(result.tested.status)) + ": " + result.tested.reason;
        }
        const std::string accepted = fmt::format(
            "registered on stable areas: {} of {} supervoxels stable ({:.0f} % of the voxels), {} "
            "unstable",
            m.stable, m.stable + m.unstable, 100.0 * m.stable_share, m.unstable);
        m.used =
            stand_in(config, result, m.transform, m.refused, accepted,
                     reg::RegistrationStatus::stable_areas_refused,
                     m.targets_status.empty() ? "" : "refused before (" + m.targets_status + ")");
    }
    if (m.used) result.zones = zone_sigmas(config, *result.tested.transform);
    result.stable_areas = std::move(m);
}

// The measurement's supervoxels with this epoch's changes, as the grouping sees them.
std::vector<registration::AreaPatch> area_patches(const StableAreaMeasurement& m) {
    std::vector<registration::AreaPatch> out(m.patches.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
        out[k] = {m.patches[k].centroid, m.patches[k].normal, m.changes.at(k), m.lods.at(k)};
    }
    return out;
}

std::vector<registration::UnstableArea> new_unstable_areas(
    const RegistrationConfig& config, const StableAreaMeasurement& m,
    const std::vector<std::vector<std::uint8_t>>& before) {
    std::vector<std::uint8_t> now(m.states.size());
    for (std::size_t k = 0; k < now.size(); ++k) now[k] = static_cast<std::uint8_t>(m.states[k]);
    std::vector<std::uint32_t> outside;
    for (const auto k :
         registration::unstable_run(now, before, config.stable_areas.persistent_epochs,
                                    static_cast<std::uint8_t>(SupervoxelState::unstable), true)) {
        if (k < m.patches.size() && !in_regions(config.zones, m.patches[k].centroid))
            outside.push_back(k);
    }
    return registration::unstable_areas(area_patches(m), outside, 2.0 * config.stable_areas.seed);
}

void apply_stable_areas(const RegistrationConfig& config, const EpochInput& input,
                        ReferenceEpoch& reference, ReferenceCache& cache, const RangeScales& scales,
                        RegistrationResult& result, const StageHistory& history) {
    if (!config.uses_stable_areas() || reference.epoch().id == input.epoch.id) return;
    const auto supervoxels = cached_supervoxels(config.stable_areas, reference, cache);
    apply_stable_areas(config, *supervoxels, *input.scans, scales, result, history.last_transform,
                       [&](const reg::RigidTransform& start) {
                           return coarse_pose_from_planes(config, input, reference, cache, scales,
                                                          start);
                       });
    if (auto& m = result.stable_areas) {
        m->reference_epoch = reference.epoch().id;
        m->segmentation = supervoxel_parameters(config.stable_areas);
        m->patches = supervoxels->patches;
        m->persistent_epochs = config.stable_areas.persistent_epochs;
        if (history.stable_area_states) {
            m->new_unstable_areas = new_unstable_areas(
                config, *m, history.stable_area_states(m->segmentation, m->persistent_epochs));
        }
    }
}

nlohmann::json stable_area_quality(const StableAreaMeasurement& m) {
    return nlohmann::json{
        {"role", m.role},
        {"used", m.used},
        {"refused", m.refused},
        {"start", m.start},
        {"supervoxels", m.supervoxels},
        {"stable", m.stable},
        {"unstable", m.unstable},
        {"unknown", m.unknown},
        {"not_planar", m.not_planar},
        {"monitored", m.monitored},
        {"stable_share", m.stable_share},
        {"iterations", m.iterations},
        {"settled", m.settled},
        {"epoch_voxels", m.epoch_samples},
        {"pairs", m.pairs},
        {"outliers", m.outliers},
        {"clusters", m.clusters},
        {"rms_m", m.rms},
        {"conditioning", m.conditioning},
        {"sigma_inflation", m.inflation},
        {"cell_sigma_m", m.cell_sigma},
        {"variance_factor_m2", m.variance_factor},
        {"agreement_chi2", m.agreement ? nlohmann::json(*m.agreement) : nlohmann::json(nullptr)},
        {"targets_status", m.targets_status},
        {"station_change", station_change_json(m.station_change)},
        {"milliseconds", m.milliseconds}};
}

}  // namespace tlsmon
