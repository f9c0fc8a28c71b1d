#include "pipeline/icp_registration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

namespace reg = registration;

namespace {

constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);
// Normals from the neighbours within this many voxels; a surface variation above the limit
// (edges, corners, leaves) leaves a point out of the reference surface.
constexpr double kNormalRadiusVoxels = 3.0;
constexpr double kMaxCurvature = 0.02;
// A plane needs beams in two directions: its neighbours' directions must spread across the
// row by more than this many σ of the beam's direction, which is all that one row's
// directions spread by (pcl_adapter.hpp, surface_with_normals).
constexpr double kRowSpreads = 3.0;
// A plane needs the scan points of a surface sampled at least as finely as the voxels: a disc
// of the normals' radius, seen at up to 65° incidence at one point per voxel, holds
// π·3²·cos 65° ≈ 12. Where the scan is coarser (`hochmosel`'s north slope at 230–320 m and
// 0.03°: 0.12–0.17 m between beams, every point its own voxel) a mean is one beam's point, its
// nearest mean in the other epoch the same beam's, and a plane through a few of them leans
// towards their rows' cones, about the scanner's vertical axis: those pairs hardly see the
// scanner turn about it, and drew κ 7 % towards no motion (docs/registration.md, "Planes of
// single beams").
constexpr double kMinPlanePoints = 12.0;

// The voxel means with their planes, by the same tests for the reference and every epoch.
SurfaceSample stable_planes(const IcpConfig& c, const VoxelMeans& means,
                            const Eigen::Vector3d& viewpoint) {
    return surface_with_normals(means.points, kNormalRadiusVoxels * c.voxel_size, kMaxCurvature,
                                viewpoint, means.counts, kRowSpreads * c.noise.angular_sigma(),
                                kMinPlanePoints);
}
// The voxel grid's origin, half a centimetre off the whole centimetres on each axis. Built
// faces and ground lie on whole centimetres of a site's frame (a pier's face at y = 43.5 m, a
// floor at z = 0), and so would the grid's faces at a voxel of whole centimetres. A voxel face
// in a surface splits the surface's points by their noise, and the two sides' count-weighted
// means then follow a motion along the normal by only 1 − 2/π ≈ 0.36 of it (a normal cut at
// its mean, its centroid and count both moving). The re-cuts then settle where the noise puts
// the sides' residuals in balance, 1/0.36 = 2.8 times as far from the truth as one fit's noise
// and its σ say: one error for the whole surface that no cell's scatter shows
// (docs/registration.md, "The voxel grid half a centimetre off"). Half a centimetre is 3.4 σ
// of `pier`'s range noise at 45 m.
const Eigen::Vector3d kGridOrigin = Eigen::Vector3d::Constant(0.005);
// The epoch is cut again at most this many times (measure_icp).
constexpr int kMaxRecuts = 10;

// Whether the cut moved the estimate by less than 0.01″ and 0.5 µm: far below the finest σ the
// ICP gives (0.1″ and 0.05 mm at `pier`'s own step).
bool settled(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
    const Eigen::Matrix4d d = b * a.inverse();
    const double angle = Eigen::AngleAxisd(Eigen::Matrix3d(d.topLeftCorner<3, 3>())).angle();
    return angle < 5e-8 && Eigen::Vector3d(d.topRightCorner<3, 1>()).norm() < 5e-7;
}

std::string region_parameters(const IcpConfig& c) {
    std::string s = fmt::format(
        "voxel={:.17g};normals={:.17g};curvature={:.17g};row_spread={:.17g};points={:.17g}",
        c.voxel_size, kNormalRadiusVoxels, kMaxCurvature, kRowSpreads * c.noise.angular_sigma(),
        kMinPlanePoints);
    const auto boxes = [&s](const std::vector<StableRegion>& list, const char* prefix) {
        for (const auto& r : list) {
            s +=
                fmt::format(";{}{}:{:.17g},{:.17g},{:.17g}:{:.17g},{:.17g},{:.17g}", prefix, r.name,
                            r.min.x(), r.min.y(), r.min.z(), r.max.x(), r.max.y(), r.max.z());
        }
    };
    boxes(c.regions, "");
    boxes(c.excluded, "not ");
    return s;
}

bool in_regions(const IcpConfig& c, const Eigen::Vector3d& p) {
    for (const auto& r : c.excluded) {
        if (r.contains(p)) return false;
    }
    for (const auto& r : c.regions) {
        if (r.contains(p)) return true;
    }
    return false;
}

// Whether the beam's angular noise scatters a point on a plane of normal n along the beam more
// than the range noise does: an elevation error ε moves the beam's hit along the beam by
// r·ε·tan β (β the incidence), and the scanner reports that range on the beam it meant.
bool along_the_beam(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                    const Eigen::Vector3d& viewpoint, const ScannerNoise& noise) {
    const Eigen::Vector3d ray = p - viewpoint;
    const double r = ray.norm();
    const double cos_b = std::abs(n.dot(ray)) / r;
    const double sin_b = std::sqrt(std::max(0.0, 1.0 - cos_b * cos_b));
    return r * noise.angular_sigma() * sin_b > noise.range_sigma(r) * cos_b;
}

// Too few targets, or (with the planes) no registration on planes either.
bool too_few_targets(const RegistrationResult& r) {
    return r.tested.status == reg::RegistrationStatus::too_few_targets ||
           r.tested.status == reg::RegistrationStatus::degenerate_geometry ||
           r.tested.status == reg::RegistrationStatus::planes_refused ||
           r.tested.status == reg::RegistrationStatus::stable_areas_refused;
}

}  // namespace

std::string StableSurface::encode() const {
    PayloadWriter w;
    std::vector<double> p, n;
    p.reserve(3 * sample.points.size());
    n.reserve(3 * sample.normals.size());
    for (std::size_t i = 0; i < sample.points.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            p.push_back(sample.points[i](k));
            n.push_back(sample.normals[i](k));
        }
    }
    w.put_array(p);
    w.put_array(n);
    w.put_array(sample.plane_offsets);
    for (int k = 0; k < 3; ++k) w.put(viewpoint(k));
    w.put<std::uint64_t>(cropped);
    return w.take();
}

StableSurface StableSurface::decode(std::string_view payload) {
    PayloadReader r(payload);
    StableSurface s;
    const auto p = r.get_array<double>();
    const auto n = r.get_array<double>();
    auto offsets = r.get_array<double>();
    if (p.size() != n.size() || p.size() % 3 != 0 || 3 * offsets.size() != p.size()) {
        throw Error("reference cache payload: stable surface points, normals and offsets differ");
    }
    s.sample.plane_offsets.assign(offsets.begin(), offsets.end());
    for (std::size_t i = 0; i < p.size(); i += 3) {
        s.sample.points.emplace_back(p[i], p[i + 1], p[i + 2]);
        s.sample.normals.emplace_back(n[i], n[i + 1], n[i + 2]);
    }
    for (int k = 0; k < 3; ++k) s.viewpoint(k) = r.get<double>();
    s.cropped = r.get<std::uint64_t>();
    r.finish();
    return s;
}

StableSurface build_stable_surface(const IcpConfig& config, const std::vector<Scan>& scans) {
    StableSurface s;
    const std::vector<Eigen::Vector3d> inside =
        points_in_stable_regions(config, scans, Eigen::Matrix4d::Identity());
    s.cropped = inside.size();
    if (!scans.empty()) s.viewpoint = scans.front().scanner_position();
    const VoxelMeans thinned = voxel_means(inside, config.voxel_size, kGridOrigin);
    s.sample = stable_planes(config, thinned, s.viewpoint);
    s.sample.counts.clear();  // the pairs weigh the epoch's voxels; the cache keeps no counts
    return s;
}

std::vector<Eigen::Vector3d> points_in_stable_regions(const IcpConfig& config,
                                                      const std::vector<Scan>& scans,
                                                      const Eigen::Matrix4d& start,
                                                      double range_scale) {
    std::vector<Eigen::Vector3d> out;
    if (config.regions.empty()) return out;
    const Eigen::Matrix3d R = start.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = start.topRightCorner<3, 1>();
    // The union of the boxes, pulled back into the epoch's frame with a margin for the
    // rotation: a cheap first test before the boxes themselves.
    Eigen::Vector3d lo = config.regions.front().min, hi = config.regions.front().max;
    for (const auto& r : config.regions) {
        lo = lo.cwiseMin(r.min);
        hi = hi.cwiseMax(r.max);
    }
    for (const auto& scan : scans) {
        const Eigen::Vector3d o = scan.scanner_position();
        for (const auto& x : scan.xyz) {
            const Eigen::Vector3d p =
                range_scale == 1.0 ? x : Eigen::Vector3d(o + (x - o) / range_scale);
            const Eigen::Vector3d X = R * p + t;
            if ((X.array() < lo.array()).any() || (X.array() > hi.array()).any()) continue;
            if (in_regions(config, X)) out.push_back(p);
        }
    }
    return out;
}

IcpMeasurement measure_icp(const RegistrationConfig& config, const StableSurface& surface,
                           const std::vector<Scan>& scans, const Eigen::Matrix4d& start,
                           const RangeScales& scales) {
    const auto t0 = std::chrono::steady_clock::now();
    const IcpConfig& c = config.icp;
    IcpMeasurement m;
    const bool correct = scales.epoch && scales.reference;
    SurfaceSample reference = surface.sample;
    if (correct) {
        for (auto& p : reference.points) {
            p = surface.viewpoint + (p - surface.viewpoint) / *scales.reference;
        }
    }
    m.reference_points = reference.points.size();
    // On grazing ground the beam's elevation noise scatters a row's points along their beams,
    // so a mean lies off the ground by where it falls along its beam, and its nearest reference
    // mean lies at the same place along the same row's beam: paired as they are, the two
    // measure how the beams (the scanner) moved, not the ground, and drew the estimate towards
    // no motion. There a pair joins both means' feet on their neighbours' planes, which average
    // the rows' scatter (docs/registration.md, "ICP on stable regions", step 2).
    std::vector<std::uint8_t> on_plane(reference.points.size());
    for (std::size_t i = 0; i < on_plane.size(); ++i) {
        on_plane[i] =
            along_the_beam(reference.points[i], reference.normals[i], surface.viewpoint, c.noise);
    }
    // The epoch's centroids kept by the same test as the reference's: a centroid on an edge,
    // a pipe or a corner has no plane, and paired with a neighbour's plane it pulls the
    // adjustment off (the real pump room, moved rigidly, gave half its rotation back).
    const Eigen::Vector3d viewpoint =
        scans.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(scans.front().scanner_position());
    // Each pair weighs its voxel's number of points: a mean of n points is n times as precise,
    // and only that sum is free of the voxel cut's offset (pcl_adapter.hpp, voxel_means).
    const std::vector<Eigen::Vector3d> cropped =
        points_in_stable_regions(c, scans, start, correct ? *scales.epoch : 1.0);
    // The epoch cut by the reference's own voxel grid where T puts it, so that at the solution
    // each epoch voxel holds the part of the surface its reference voxel holds.
    const auto thinned_under = [&](const Eigen::Matrix4d& T) {
        const Eigen::Affine3d to_reference(T);
        std::vector<Eigen::Vector3d> moved(cropped.size());
        for (std::size_t i = 0; i < cropped.size(); ++i) moved[i] = to_reference * cropped[i];
        VoxelMeans v = voxel_means(moved, c.voxel_size, kGridOrigin);
        const Eigen::Affine3d back = to_reference.inverse();
        for (auto& q : v.points) q = back * q;
        return stable_planes(c, v, viewpoint);
    };
    SurfaceSample epoch = thinned_under(start);
    m.epoch_points = epoch.points.size();
    const auto finish = [&] {
        m.milliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        return m;
    };
    if (epoch.points.empty() || reference.points.empty()) {
        m.refused = fmt::format("no points in the stable regions (epoch {}, reference {})",
                                epoch.points.size(), reference.points.size());
        return finish();
    }
    IcpParams p;
    p.max_correspondence_distance = c.max_correspondence_distance;
    p.max_iterations = c.max_iterations;
    const NearestPoints nearest(reference.points);  // the pairs', built once for every cut
    const IcpAlignment a = align_point_to_plane(epoch, reference, nearest, start, p, on_plane);
    m.iterations = a.iterations;
    m.converged = a.converged;
    m.pairs = a.pairs.size();
    m.overlap = a.overlap;
    try {
        reg::PointToPlaneParams fp;
        fp.cluster_size = c.cluster_size;
        fp.cell_origin = kGridOrigin;  // the cells off the whole centimetres, as the voxels
        reg::PointToPlaneFit f = reg::fit_point_to_plane(a.pairs, a.transform, fp);
        // The epoch cut again where the adjustment put it, paired there and adjusted, until the
        // adjustment returns to where the epoch was already cut: to the last cut, or to an
        // earlier one, since at the scanner's step the cuts may circle a few points 0.01 µrad and
        // 2 µm apart (docs/registration.md, "ICP on stable regions", step 4).
        std::vector<Eigen::Matrix4d> cuts{start};
        const auto cut_before = [&cuts](const Eigen::Matrix4d& T) {
            return std::any_of(cuts.begin(), cuts.end(),
                               [&T](const Eigen::Matrix4d& c) { return settled(c, T); });
        };
        while (m.recuts < kMaxRecuts && !cut_before(f.transform.matrix())) {
            const Eigen::Matrix4d cut_at = cuts.emplace_back(f.transform.matrix());
            epoch = thinned_under(cut_at);
            const auto pairs = point_plane_pairs(epoch, reference, nearest, cut_at,
                                                 c.max_correspondence_distance, on_plane);
            m.overlap =
                static_cast<double>(pairs.size()) / static_cast<double>(epoch.points.size());
            f = reg::fit_point_to_plane(pairs, cut_at, fp);
            ++m.recuts;
        }
        m.epoch_points = epoch.points.size();
        m.rms = f.rms;
        m.pairs = f.pairs;
        m.outliers = f.outliers;
        m.clusters = f.clusters;
        m.inflation = f.inflation;
        m.transform = reg::rigid_transform_from(
            f.transform.rotation, f.transform.translation,
            c.sigma_factor * c.sigma_factor *
                f.transform.small_rotation_covariance.topLeftCorner<6, 6>());
        m.transform->variance_factor = f.variance_factor;
        m.transform->redundancy = f.transform.redundancy;
        m.fit = std::move(f);
    } catch (const Error& e) {
        m.refused = e.what();
        return finish();
    }
    if (!m.converged) {
        m.refused =
            fmt::format("not converged in registration.icp_max_iterations = {}", c.max_iterations);
    } else if (static_cast<int>(m.pairs) < c.min_points) {
        m.refused = fmt::format("{} pairs, fewer than registration.icp_min_points = {}", m.pairs,
                                c.min_points);
    } else if (m.overlap < c.min_overlap) {
        m.refused = fmt::format("overlap {:.2f} below registration.icp_min_overlap = {}", m.overlap,
                                c.min_overlap);
    } else if (m.rms > c.max_rms) {
        m.refused = fmt::format("RMS {:.2f} mm above registration.icp_max_rms = {:.2f} mm",
                                1e3 * m.rms, 1e3 * c.max_rms);
    }
    return finish();
}

void apply_icp(const RegistrationConfig& config, const StableSurface& surface,
               const std::vector<Scan>& scans, const RangeScales& scales,
               RegistrationResult& result) {
    const IcpConfig& c = config.icp;
    if (c.mode == IcpMode::off || c.regions.empty()) return;
    // A σ refused by the gate may come within it once combined; a targets' RMS cannot.
    const bool rms_gate = result.gate.rfind("RMS", 0) == 0;
    const bool refine =
        c.refines() && result.tested.accepted() && result.tested.transform && !rms_gate;
    const bool fallback = c.falls_back() && too_few_targets(result);
    if (!refine && !fallback) return;
    const Eigen::Matrix4d start =
        refine ? result.tested.transform->matrix() : Eigen::Matrix4d::Identity();
    IcpMeasurement m = measure_icp(config, surface, scans, start, scales);
    m.role = refine ? "refine" : "fallback";
    if (refine) {
        if (m.refused.empty()) {
            m.refused = join_estimate(config, result, *m.transform, "targets", m.agreement);
            m.used = m.refused.empty();
        }
    } else {
        m.targets_status = std::string(name_of(result.tested.status)) + ": " + result.tested.reason;
        if (m.refused.empty()) m.refused = sigma_gate(config, *m.transform);
        if (m.refused.empty()) {
            result.tested.transform = *m.transform;
            result.tested.status = reg::RegistrationStatus::accepted;
            result.tested.reason = "targets refused (" + m.targets_status +
                                   "); registered by ICP on the stable regions";
            result.gate.clear();
            m.used = true;
        } else {
            result.tested.reason += "; the ICP fallback was refused: " + m.refused;
        }
    }
    if (m.used) result.zones = zone_sigmas(config, *result.tested.transform);
    result.icp = std::move(m);
}

void apply_icp(const RegistrationConfig& config, const EpochInput& input, ReferenceEpoch& reference,
               ReferenceCache& cache, const RangeScales& scales, RegistrationResult& result) {
    if (config.icp.mode == IcpMode::off || config.icp.regions.empty()) return;
    // The reference's own frame is the datum: its targets register it onto itself exactly,
    // and an ICP onto itself could only move it.
    if (reference.epoch().id == input.epoch.id) return;
    const auto surface = cache.get<StableSurface>(
        reference, ProductKey{"registration.icp_surface", region_parameters(config.icp), 5},
        [&](const std::vector<Scan>& scans) { return build_stable_surface(config.icp, scans); });
    apply_icp(config, *surface, *input.scans, scales, result);
}

std::string registration_method(const RegistrationResult& r) {
    std::string m = "targets";
    if (r.planes && r.planes->used) m = r.planes->role == "joint" ? "targets+planes" : "planes";
    if (r.stable_areas && r.stable_areas->used) {
        m = r.stable_areas->role == "joint" ? m + "+stable_areas" : "stable_areas";
    }
    if (r.icp && r.icp->used) m = r.icp->role == "fallback" ? "icp" : m + "+icp";
    if (r.epoch_range_scale) m += "+atmosphere";
    return m;
}

nlohmann::json icp_quality(const IcpMeasurement& m) {
    return nlohmann::json{
        {"role", m.role},
        {"used", m.used},
        {"refused", m.refused},
        {"fitness", m.overlap},
        {"rms_m", m.rms},
        {"iterations", m.iterations},
        {"recuts", m.recuts},
        {"converged", m.converged},
        {"points", m.epoch_points},
        {"reference_points", m.reference_points},
        {"pairs", m.pairs},
        {"outliers", m.outliers},
        {"clusters", m.clusters},
        {"sigma_inflation", m.inflation},
        {"agreement_chi2", m.agreement ? nlohmann::json(*m.agreement) : nlohmann::json(nullptr)},
        {"milliseconds", m.milliseconds}};
}

}  // namespace tlsmon
