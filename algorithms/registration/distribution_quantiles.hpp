#pragma once
// Critical values of the tests of an adjustment: the standard normal and the χ²
// distribution, computed here so the kernels need no statistics library.
namespace tlsmon::registration {

// Standard normal distribution function Φ(x) = ½·erfc(−x/√2).
double normal_cdf(double x);
// Φ⁻¹(p) for 0 < p < 1.
double normal_quantile(double p);

// Student's t(dof) quantile: the x with F(x) = p, for 0 < p < 1 and dof > 0 (Boost.Math).
double student_t_quantile(double p, double dof);

// χ²(dof) distribution function: the regularised lower incomplete gamma P(dof/2, x/2).
double chi_square_cdf(double x, double dof);
// Its upper tail 1 − F, computed directly so that small tail probabilities keep their digits.
double chi_square_upper_tail(double x, double dof);
// The x with F(x) = p, for 0 < p < 1 and dof > 0.
double chi_square_quantile(double p, double dof);

// Noncentral χ²(dof, λ) distribution function, as the Poisson(λ/2) mixture of central
// χ²(dof + 2j) (Johnson, Kotz & Balakrishnan 1995, "Continuous univariate distributions",
// vol. 2, eq. 29.2).
double noncentral_chi_square_cdf(double x, double dof, double lambda);
// The noncentrality λ0 at which a test with critical value χ²(dof, 1 − α) rejects with
// probability `power` (Baarda 1968's λ0; 17.07 for dof 1, α = 0.1 %, power 80 %).
double detectable_noncentrality(double alpha, double power, double dof);

}  // namespace tlsmon::registration
