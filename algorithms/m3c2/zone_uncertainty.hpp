#pragma once
// The uncertainty of a zone's aggregate M3C2 distance — the mean or the median of its core
// points' distances — as its own σ, not one core point's LoD (docs/m3c2.md, "Zone rows").
//
// A core point's distance errs by its cylinders' sampling, σ_s,i = √(s1²/n1 + s2²/n2)
// (Lague 2013, eq. 1 without reg), and by the registration, σ_reg,i along its normal. The
// two are independent and add in quadrature; aggregated over the zone's n core points they
// behave differently:
// - the sampling errors average out, but not as n independent ones: cylinders of radius r
//   around core points every s overlap, each point of the surface falls into
//   k = max(1, π·r²/s²) of them, and the mean's variance is k · mean(σ_s,i²) / n;
// - the registration's error is one transformation seen at every core point: fully
//   correlated, it does not average out; its σ at the zone is the mean of σ_reg,i;
// - the median's sampling variance is k · median_sampling_variance (below): π/2 times the
//   mean's where the core points' true changes are equal, more where they differ across
//   the zone (a face in bending), since then only the few core points whose change lies
//   near the median's decide it.
//   σ_mean = √(k·mean(σ_s,i²)/n + mean(σ_reg,i)²),  σ_median = √(k·v_median + mean(σ_reg,i)²)
// The zone rows' LoD95 is 1.96 σ.
#include <cstddef>
#include <span>

namespace tlsmon::m3c2 {

struct ZoneUncertainty {
    std::size_t n = 0;
    double overlap = 1;          // k
    double sampling_mean = 0;    // σ of the mean from the cylinders' sampling, m
    double sampling_median = 0;  // σ of the median from the cylinders' sampling, m
    double registration = 0;     // σ of the registration along the normals, m
    double mean_sigma = 0;       // m
    double median_sigma = 0;     // m
};

// The sampling variance of the median of d_i = t_i + e_i, e_i ~ N(0, σ_i²) independent, at
// fixed places with true values t_i that may differ. The median m̂ is where the count of
// d_i ≤ m crosses n/2; linearised there (Bahadur's representation, for members not alike:
// Serfling 1980, §2.5),
//   var(m̂) ≈ Σ F_i(1 − F_i) / (Σ f_i)²,  F_i = Φ((m̂ − t_i)/σ_i), f_i = φ((m̂ − t_i)/σ_i)/σ_i.
// Equal t_i give π σ²/(2n), the median's familiar √(π/2); t_i spread evenly over R ≫ σ give
// σR/(√π n). Where the middle member lies more than a few σ from its neighbours (a zone whose
// change varies across it by far more than a core point's σ) the count's slope vanishes at
// the median and the linearisation fails; there the median is the middle member's value, or
// the mean of the middle two's, and errs by their σ alone: var(m̂) is the smaller of the
// two, σ_mid² (or (σ_a² + σ_b²)/4 for an even count).
// The t_i are unknown: the measured d_i stand in for them with a kernel of width κσ_i for
// σ_i, κ = 0.8257, at which equal t_i give π σ²/(2n) in expectation (the d_i then already
// spread by σ_i: κ² = 1/c − 1 with c = 1 − (2/π)·arcsin c). Where the t_i spread over R ≫ σ the
// count's variance takes the kernel's width for σ, and the estimate is √κ = 0.91 of the true
// σ: exact when nothing moves, where a false alarm would come from, and 5–12 % short in
// between (simulated over spreads up to 60σ and 11 to 501 members;
// tests/algorithms/test_m3c2_zone_uncertainty.cpp). The result is never below π/2·mean(σ_i²)/n,
// its value for equal t_i: where the d_i spread less than their σ_i (a surface's relief in a
// core point's σ_s cancels in its distance) the kernel estimate would fall below it, by up to
// κ², and a middle member far more precise than the rest does not decide alone while they
// reach it. Members with σ_i = 0 add no variance.
// Throws tlsmon::Error for spans of different lengths or a negative or non-finite value.
double median_sampling_variance(std::span<const double> values,
                                std::span<const double> sampling_sigma);

// The same for members that hold several values each and err together: member j holds
// values[first[j]] … values[first[j + 1] − 1] (a patch's footprint cells, each the patch's
// change at its place: algorithms/patches/zone_median.hpp) with one error e_j ~ N(0, σ_j²)
// common to them, so that the count of values ≤ m moves by a member's block at once:
//   var(count) = Σ_j [Σ_{c,c'∈j} P_j(min(s_c, s_c')) − (Σ_{c∈j} P_j(s_c))²],  s_c = m − t_c,
// with P_j the kernel's Φ(·/h_j), and the density Σ_j Σ_{c∈j} f_j(s_c) as above. The kernel's
// width h_j is κσ_j for a member whose values lie together (one value: the form above) and
// σ_j for one whose values spread over more than σ_j: a member that straddles m then counts
// in proportion to its error, its count's variance goes as h_j², and only h_j = σ_j gives it
// (κσ_j would leave the σ short by κ, not √κ). In between, h_j² = κ²σ_j² + (1 − κ²)·min(σ_j²,
// s_j²), s_j² the variance of the member's values — the two limits are derived, the blend
// between them is a choice, not fitted (simulated in
// tests/algorithms/test_patch_zone_median.cpp: 0.89–1.02 of the true σ). The middle
// value's member decides alone in a gap (σ_j², or (σ_a² + σ_b²)/4 for two members); the floor
// is π/2 times the variance of the values' mean, π/2 · Σ_j n_j² σ_j² / N². One value per
// member is the form above. Throws tlsmon::Error unless `first` runs from 0 to the number of
// values in order with one more entry than `member_sigma`, for a non-finite value or a
// negative or non-finite σ.
double median_sampling_variance(std::span<const double> values, std::span<const std::size_t> first,
                                std::span<const double> member_sigma);

// Throws tlsmon::Error for spans of different lengths, a non-positive radius or spacing, or
// a negative or non-finite σ.
ZoneUncertainty zone_uncertainty(std::span<const double> values,
                                 std::span<const double> sampling_sigma,
                                 std::span<const double> registration_sigma, double cylinder_radius,
                                 double core_spacing);

// The same for aggregates whose members each see `overlap` (k ≥ 1) times the same surface:
// 1 for patches that do not overlap (patch-based M3C2, docs/pbm3c2.md).
ZoneUncertainty aggregate_uncertainty(std::span<const double> values,
                                      std::span<const double> sampling_sigma,
                                      std::span<const double> registration_sigma, double overlap);

}  // namespace tlsmon::m3c2
