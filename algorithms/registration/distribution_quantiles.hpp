#pragma once
// Critical values of the tests of an adjustment: the standard normal and the χ²
// distribution, computed here so the kernels need no statistics library.
namespace tlsmon::registration {

// Standard normal distribution function Φ(x) = ½·erfc(−x/√2).
double normal_cdf(double x);
// Φ⁻¹(p) for 0 < p < 1.
double normal_quantile(double p);

// χ²(dof) distribution function: the regularised lower incomplete gamma P(dof/2, x/2).
double chi_square_cdf(double x, double dof);
// Its upper tail 1 − F, computed directly so that small tail probabilities keep their digits.
double chi_square_upper_tail(double x, double dof);
// The x with F(x) = p, for 0 < p < 1 and dof > 0.
double chi_square_quantile(double p, double dof);

}  // namespace tlsmon::registration
