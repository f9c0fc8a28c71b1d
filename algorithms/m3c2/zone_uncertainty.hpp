#pragma once
// The uncertainty of a zone's aggregate M3C2 distance — the mean or the median of its core
// points' distances — as its own σ, not one core point's LoD (docs/m3c2.md, "Zones").
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
// - the median of normally distributed values has √(π/2) times the mean's σ (its
//   asymptotic efficiency 2/π).
//   σ_mean = √(k·mean(σ_s,i²)/n + mean(σ_reg,i)²),  σ_median = √(π/2·k·mean(σ_s,i²)/n + …)
// The zone rows' LoD95 is 1.96 σ.
#include <cstddef>
#include <span>

namespace tlsmon::m3c2 {

struct ZoneUncertainty {
    std::size_t n = 0;
    double overlap = 1;        // k
    double sampling_mean = 0;  // σ of the mean from the cylinders' sampling, m
    double registration = 0;   // σ of the registration along the normals, m
    double mean_sigma = 0;     // m
    double median_sigma = 0;   // m
};

// Throws tlsmon::Error for spans of different lengths, a non-positive radius or spacing, or
// a negative or non-finite σ.
ZoneUncertainty zone_uncertainty(std::span<const double> sampling_sigma,
                                 std::span<const double> registration_sigma, double cylinder_radius,
                                 double core_spacing);

// The same for aggregates whose members each see `overlap` (k ≥ 1) times the same surface:
// 1 for patches that do not overlap (patch-based M3C2, docs/pbm3c2.md).
ZoneUncertainty aggregate_uncertainty(std::span<const double> sampling_sigma,
                                      std::span<const double> registration_sigma, double overlap);

}  // namespace tlsmon::m3c2
