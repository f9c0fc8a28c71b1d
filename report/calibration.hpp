#pragma once
// Is each method's own uncertainty honest? On a series with the simulator's truth, every
// scored figure (a zone quantity with its LoD95, a registration parameter with its σ) gives an
// error e = value − truth and a σ (LoD95 / 1.96, or the parameter's σ); the figure's 68 %
// interval covers the truth when |e| ≤ σ, its 95 % interval when |e| ≤ 1.96·σ. Per method
// and part (zone, parameter) and pooled over the parts: the counts, the shares covered and
// their Wilson score intervals (Wilson 1927; Agresti & Coull 1998 recommend it over the
// normal approximation for shares near 0 or 1), so that a coverage of 90 % from 20 figures
// is told apart from one from 2000. docs/calibration.md.
#include <cstddef>
#include <string>
#include <vector>

#include "report/analysis.hpp"

namespace tlsmon::report {

// The nominal rates: P(|Z| ≤ 1) and P(|Z| ≤ 1.96) for a normal Z.
inline constexpr double kNominal68 = 0.6827;
inline constexpr double kNominal95 = 0.95;
inline constexpr double kLod95Factor = 1.96;

// The Wilson score interval of a binomial share hits/n at z (1.96: 95 %); [0, 1] for n = 0.
struct ShareInterval {
    double lower = 0, upper = 1;
};
ShareInterval wilson_interval(std::size_t hits, std::size_t n, double z = 1.96);

// What the coverage says about the σ: the nominal rate inside the interval (consistent),
// above it (the σ is too small: the truth falls outside too often), or below it (too large:
// padded, real change hides inside it).
enum class SigmaVerdict { consistent, too_small, too_large, no_figures };
SigmaVerdict sigma_verdict(std::size_t hits, std::size_t n, double nominal);
const char* to_string(SigmaVerdict verdict);

// One scored figure.
struct ScoredFigure {
    double error = 0;  // value − truth
    double sigma = 0;  // the method's own standard deviation of it
};

struct CoverageRow {
    std::string method;  // a zone quantity, or "registration:<method>"
    std::string part;    // the zone, the parameter (omega … tz), or "all"
    std::size_t n = 0;
    ErrorSummary error;
    double rms_sigma = 0;  // RMS of the σ the method gave
    std::size_t within68 = 0, within95 = 0;
    ShareInterval band68, band95;
    SigmaVerdict verdict68 = SigmaVerdict::no_figures, verdict95 = SigmaVerdict::no_figures;
    double coverage68() const { return n ? double(within68) / double(n) : 0.0; }
    double coverage95() const { return n ? double(within95) / double(n) : 0.0; }
    // A registration angle (rad; shown in µrad), else a length (m; shown in mm).
    bool angle() const { return part == "omega" || part == "phi" || part == "kappa"; }
    // A registration's pooled row mixes angles and lengths: its coverage only has a meaning.
    bool mixed_units() const { return part == "all" && method.starts_with("registration:"); }
    // A row of χ² test statistics: shares only, no error or σ.
    bool statistic_only = false;
    bool blank_numbers() const { return statistic_only || mixed_units(); }
    // The factor to the unit shown: 1e6 (µrad) or 1e3 (mm).
    double display_scale() const { return angle() ? 1e6 : 1e3; }
};

// The row of a list of figures.
CoverageRow coverage_of(std::string method, std::string part,
                        const std::vector<ScoredFigure>& figures);

// Every method of a scored run: the zone quantities with a truth and an LoD (the reference
// epoch's own rows left out: they are zero by construction), and each registration method's
// six parameters on its accepted epochs. Per part, then "all" for the method. None of these for
// a run without truth.
//
// Truth or not, the check zones ([[zone]] no_change: ground known not to move, never in the
// datum): each displacement quantity with an LoD scored against zero, as
// "no_change:<quantity>" per zone — the no-change check a real site can make.
//
// And, truth or not, the χ² tests of the accepted epochs (analysis.hpp, ChiSquareTest): per
// joined estimate ("agreement:icp", "agreement:planes", "agreement:stable_areas", part
// "chi2(6)") and for the used targets ("no_change:targets", "chi2(3)"), the shares within
// χ²(dof)'s 68.27 % and 95 % quantiles, with their bands and verdicts. Honest σ give the
// nominal rates; fewer within: the σ are too small; more: too large — or the two sides share
// an error (the same air, the same scan's drift, an error common to all targets), which
// makes them agree better than their σ say.
std::vector<CoverageRow> calibration(const RunReport& report);

}  // namespace tlsmon::report
