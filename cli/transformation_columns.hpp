#pragma once
// A registration's six parameters and their σ as `tlsmon register` and `tlsmon query
// registrations` show them: rotations ω, φ, κ in arcseconds, translations in metres (as
// every length tlsmon prints), in the order of RigidTransform's parameter vector.
#include <array>

namespace tlsmon {

inline constexpr double kArcsecPerRadian = 180.0 * 3600.0 / 3.141592653589793;

inline constexpr std::array<const char*, 6> kParameterColumns{
    "omega_arcsec", "phi_arcsec", "kappa_arcsec", "tx_m", "ty_m", "tz_m"};
inline constexpr std::array<const char*, 6> kSigmaColumns{"sigma_omega_arcsec", "sigma_phi_arcsec",
                                                          "sigma_kappa_arcsec", "sigma_tx_m",
                                                          "sigma_ty_m",         "sigma_tz_m"};
// Per parameter: the factor from radians or metres to the columns' unit.
inline constexpr std::array<double, 6> kParameterUnits{
    kArcsecPerRadian, kArcsecPerRadian, kArcsecPerRadian, 1.0, 1.0, 1.0};

}  // namespace tlsmon
