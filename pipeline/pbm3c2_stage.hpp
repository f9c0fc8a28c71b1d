#pragma once
// Stage "pbm3c2": patch-based M3C2 (docs/pbm3c2.md; the thesis on rigid patches in TLS point
// clouds, §5.1) of each epoch against the reference epoch, on the reference's supervoxels
// inside the zones, aggregated per zone into the time series.
//
// Reference product (the reference cache, stage "pbm3c2"): the supervoxels — those of the
// registration on stable areas, from the same cache entry, segmented once — inside a zone,
// each a patch with its frame (centroid, normal towards the scanner) and footprint, and the
// reference points' plane moments on it.
//
// Each epoch: its points mapped into the reference frame (the registration and the range
// scales, as for M3C2: epoch_to_reference), each accumulated into the patch it belongs to
// (algorithms/patches/patch_index.hpp), a plane fitted per patch, and the distance between
// the two planes along the patch normal with its LoD95 (algorithms/patches/
// patch_distance.hpp); the registration's σ along the normal at each patch as for M3C2, 0
// without a registration (the epoch then carries that quality and raises no deformation
// alarm).
#include <array>
#include <string>
#include <vector>

#include "algorithms/patches/patch_distance.hpp"
#include "pipeline/pbm3c2_config.hpp"
#include "pipeline/pbm3c2_reference.hpp"
#include "pipeline/stable_area_registration.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

// The zone quantities the stage writes, per zone and epoch (the alarm rules name them).
inline constexpr std::array<const char*, 6> kPbM3c2Quantities = {
    "pbm3c2_valid_count", "pbm3c2_median_m",       "pbm3c2_mean_m",
    "pbm3c2_spread_m",    "pbm3c2_lod95_median_m", "pbm3c2_significant_share"};

// The canonical text of every parameter the reference product depends on (its cache key).
std::string pbm3c2_reference_parameters(const PbM3c2Config& config);

PbM3c2Reference prepare_pbm3c2_reference(const PbM3c2Config& config,
                                         const ReferenceSupervoxels& supervoxels,
                                         const std::vector<Scan>& scans);

// One epoch's patch-based M3C2 at every patch.
struct PbM3c2Epoch {
    std::vector<patches::PlaneMoments> moments;  // the epoch's points on each patch's plane
    std::vector<double> registration_sigma;      // m, σ_T along each patch's normal
    std::vector<patches::PatchResult> results;
};

PbM3c2Epoch measure_pbm3c2(const PbM3c2Config& config, const PbM3c2Reference& reference,
                           const std::vector<Scan>& scans, const StageOutputs& outputs);

// The zone rows: pbm3c2_median_m, the median over the zone's area (every footprint cell one
// vote: algorithms/patches/zone_median.hpp), and pbm3c2_mean_m, the mean over its patches,
// each with its own LoD95 (the patches do not overlap: their fits' errors average out, the
// registration's does not; algorithms/m3c2/zone_uncertainty.hpp), pbm3c2_spread_m,
// pbm3c2_valid_count, pbm3c2_lod95_median_m, pbm3c2_significant_share; a zone without a measured
// patch has only pbm3c2_valid_count (0).
std::vector<ZoneResult> pbm3c2_zone_results(const PbM3c2Reference& reference,
                                            const PbM3c2Epoch& epoch);

// The per-patch float32 arrays, in this order: pbm3c2_distance_m, pbm3c2_lod95_m (NaN: no
// distance on that patch), pbm3c2_n1, pbm3c2_n2 (the reference's and the epoch's points the
// distance rests on: the part both saw alike, when only part was), and where the distance was
// taken less where the whole patch's is (PbM3c2Reference::measured_in_frame), along the patch's
// u, v and normal: 0 unless only part of the patch was compared, and left out when 0 at every
// patch (a reader takes a missing shift as 0, as for an epoch stored before them).
inline constexpr const char* kPbM3c2PatchArrays[] = {
    "pbm3c2_distance_m", "pbm3c2_lod95_m",   "pbm3c2_n1",       "pbm3c2_n2",
    "pbm3c2_shift_u_m",  "pbm3c2_shift_v_m", "pbm3c2_shift_w_m"};
inline constexpr std::size_t kPbM3c2FirstShift = 4;  // the shifts' place in kPbM3c2PatchArrays
std::vector<CorePointArray> pbm3c2_patch_arrays(const PbM3c2Reference& reference,
                                                const PbM3c2Epoch& epoch);

// The stage: runs when enabled with at least one zone (site_stages).
class PbM3c2Stage final : public Stage {
  public:
    explicit PbM3c2Stage(PbM3c2Config config) : config_(std::move(config)) {}
    const char* name() const override { return "pbm3c2"; }
    // The supervoxels and the product from the cache, measure_pbm3c2, its rows and arrays.
    StageVerdict run(StageContext& ctx) const override;
    // The product from the reference's supervoxels, through `cache` (a one-shot command's
    // in-memory one, or the daemon's).
    std::shared_ptr<const PbM3c2Reference> reference(ReferenceEpoch& reference,
                                                     ReferenceCache& cache) const;

  private:
    PbM3c2Config config_;
};

}  // namespace tlsmon
