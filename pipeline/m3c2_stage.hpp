#pragma once
// Stage "m3c2": M3C2 distances (Lague, Brodu & Leroux 2013; algorithms/m3c2/) of each epoch
// against the reference epoch at fixed core points, aggregated per zone into the time series.
//
// Reference product (the reference cache, stage "m3c2"): the core points, taken once from
// the reference's points inside the zones (cubes of `core_spacing`), their normals and the
// reference's side of every cylinder, the zones' core points and the reference's scanner
// position. Reused from memory, or from the database after a restart.
//
// Each epoch: its points are mapped into the reference frame by the range scale about the
// scanner and the registration (StageOutputs); instead of copying millions of points, the
// cylinders are pulled back into the epoch's own frame through the inverse of that map (a
// similarity: the projections scale by its factor) and the epoch's points streamed through
// them. The LoD's registration term at each core point is the registration's σ along its
// normal, σ_n = √(nᵀ·Σ_p·n), Σ_p = J·Σ·Jᵀ (algorithms/registration/registration_error.hpp;
// Niemeier 2008, §2.4), or `registration_error` without a registration.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/m3c2_config.hpp"
#include "pipeline/m3c2_reference.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/stage.hpp"
#include "storage/epoch_results.hpp"

namespace tlsmon {

// The zone quantities the stage writes, per zone and epoch (the alarm rules name them).
inline constexpr std::array<const char*, 6> kM3c2Quantities = {
    "m3c2_valid_count", "m3c2_median_m",       "m3c2_mean_m",
    "m3c2_spread_m",    "m3c2_lod95_median_m", "m3c2_significant_share"};

// The points M3C2 measures of some scans, the reference's and every epoch's: all of them but
// those at a depth discontinuity of their scan's grid (algorithms/depth_discontinuity.hpp). At
// a face's edge the beams that straddle it return blends a little behind the face, and which
// beams do so changes with the grid's phase on the edge from epoch to epoch; on a face seen at
// grazing incidence the blends line its far edge, and the cylinders there read the face off
// by an amount that changes every epoch (docs/m3c2.md, "Edge points"). A scan without a grid
// keeps every point. One scan's points are not copied: those left out are marked.
struct M3c2Cloud {
    const std::vector<Eigen::Vector3d>* scan_points = nullptr;  // one scan's own points, or
    std::vector<Eigen::Vector3d> joined;                        // several scans' kept points
    std::vector<std::uint8_t> left_out;  // per point of points(), 1: left out; empty: none
    const std::vector<Eigen::Vector3d>& points() const {
        return scan_points ? *scan_points : joined;
    }
    bool is_left_out(std::size_t i) const { return !left_out.empty() && left_out[i]; }
    std::size_t kept() const;                          // how many points are not left out
    std::vector<Eigen::Vector3d> kept_points() const;  // a copy of them
};
M3c2Cloud m3c2_cloud(const std::vector<Scan>& scans, unsigned threads = 0);

// The canonical text of the zones' geometry, as part of a product's cache key.
std::string zone_parameters(const std::vector<ZoneShape>& zones);

// The canonical text of every parameter the reference product depends on (its cache key).
std::string m3c2_reference_parameters(const M3c2Config& config);

M3c2Reference prepare_m3c2_reference(const M3c2Config& config, const std::vector<Scan>& scans);

// The map of the epoch's points into the reference frame as a similarity q = f·R·p + t:
// the range scale 1/k_e about the epoch's scanner, the registration T, and back to the
// reference's own ranges, k_r about its scanner (registration_stage.cpp corrects both
// epochs' ranges, or neither).
struct EpochToReference {
    double factor = 1.0;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    bool identity() const;
    Eigen::Vector3d apply(const Eigen::Vector3d& p) const {
        return factor * (rotation * p) + translation;
    }
    Eigen::Vector3d inverse(const Eigen::Vector3d& q) const {
        return rotation.transpose() * (q - translation) / factor;
    }
};
EpochToReference epoch_to_reference(const StageOutputs& outputs,
                                    const Eigen::Vector3d& reference_scanner);

// One epoch's M3C2 at every core point.
struct M3c2Epoch {
    std::vector<m3c2::CylinderSide> compared;  // in the reference frame's units
    std::vector<double> registration_sigma;    // m, σ_n per core point (the LoD's reg)
    std::vector<m3c2::Distance> distances;
};

M3c2Epoch measure_m3c2(const M3c2Config& config, const M3c2Reference& reference,
                       const std::vector<Scan>& scans, const StageOutputs& outputs);

// The zone rows (docs/m3c2.md, "Zones"): m3c2_median_m and m3c2_mean_m with their own LoD95
// (algorithms/m3c2/zone_uncertainty.hpp; `config` gives the core spacing), m3c2_spread_m,
// m3c2_valid_count, m3c2_lod95_median_m, m3c2_significant_share; a zone without a valid
// core point has only m3c2_valid_count (0).
std::vector<ZoneResult> m3c2_zone_results(const M3c2Config& config, const M3c2Reference& reference,
                                          const M3c2Epoch& epoch);

// The per-core-point float32 arrays: m3c2_distance_m, m3c2_lod95_m, m3c2_n1, m3c2_n2 (NaN:
// no distance at that core point).
std::vector<CorePointArray> m3c2_core_point_arrays(const M3c2Reference& reference,
                                                   const M3c2Epoch& epoch);

// The stage: runs when enabled with at least one zone (site_stages).
class M3c2Stage final : public ReferenceStage<M3c2Reference> {
  public:
    explicit M3c2Stage(M3c2Config config) : config_(std::move(config)) {}
    const char* name() const override { return "m3c2"; }
    std::string reference_parameters() const override;
    M3c2Reference prepare_reference(const std::vector<Scan>& reference_scans) const override;
    // measure_m3c2, then its zone rows and core point arrays.
    StageVerdict measure(StageContext& ctx, const M3c2Reference& reference) const override;

  private:
    M3c2Config config_;
};

}  // namespace tlsmon
