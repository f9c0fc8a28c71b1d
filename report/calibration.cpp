#include "report/calibration.hpp"

#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "algorithms/registration/distribution_quantiles.hpp"

namespace tlsmon::report {

namespace {

constexpr std::array<const char*, 6> kParameterNames{"omega", "phi", "kappa", "tx", "ty", "tz"};

}  // namespace

ShareInterval wilson_interval(std::size_t hits, std::size_t n, double z) {
    if (n == 0) return {};
    // Wilson 1927: the p with |p̂ − p| = z·√(p(1 − p)/n), solved for p.
    const double nn = static_cast<double>(n);
    const double p = static_cast<double>(hits) / nn;
    const double z2 = z * z;
    const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
    const double half = z / (1 + z2 / nn) * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn));
    return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

SigmaVerdict sigma_verdict(std::size_t hits, std::size_t n, double nominal) {
    if (n == 0) return SigmaVerdict::no_figures;
    const ShareInterval band = wilson_interval(hits, n);
    if (nominal > band.upper) return SigmaVerdict::too_small;
    if (nominal < band.lower) return SigmaVerdict::too_large;
    return SigmaVerdict::consistent;
}

const char* to_string(SigmaVerdict verdict) {
    switch (verdict) {
        case SigmaVerdict::consistent:
            return "consistent";
        case SigmaVerdict::too_small:
            return "sigma too small";
        case SigmaVerdict::too_large:
            return "sigma too large";
        case SigmaVerdict::no_figures:
            break;
    }
    return "no figures";
}

CoverageRow coverage_of(std::string method, std::string part,
                        const std::vector<ScoredFigure>& figures) {
    CoverageRow row;
    row.method = std::move(method);
    row.part = std::move(part);
    row.n = figures.size();
    std::vector<double> errors;
    double sum_sigma2 = 0;
    for (const ScoredFigure& f : figures) {
        errors.push_back(f.error);
        sum_sigma2 += f.sigma * f.sigma;
        row.within68 += std::abs(f.error) <= f.sigma;
        row.within95 += std::abs(f.error) <= kLod95Factor * f.sigma;
    }
    row.error = summarise(errors);
    if (row.n) row.rms_sigma = std::sqrt(sum_sigma2 / static_cast<double>(row.n));
    row.band68 = wilson_interval(row.within68, row.n);
    row.band95 = wilson_interval(row.within95, row.n);
    row.verdict68 = sigma_verdict(row.within68, row.n, kNominal68);
    row.verdict95 = sigma_verdict(row.within95, row.n, kNominal95);
    return row;
}

std::vector<CoverageRow> calibration(const RunReport& report) {
    // method -> part -> figures, in a stable order
    std::map<std::string, std::map<std::string, std::vector<ScoredFigure>>> scored;
    for (const ZoneCheck& zone : report.zones) {
        for (const ZoneQuantityCheck& q : zone.quantities) {
            for (const auto& row : q.rows) {
                if (!row.truth || !row.lod || !std::isfinite(row.value)) continue;
                if (report.reference && row.id == *report.reference) continue;
                // A check zone's truth is zero by what it is, truth files or not.
                const std::string method = (zone.no_change ? "no_change:" : "") + q.quantity;
                scored[method][zone.zone].push_back(
                    {row.value - *row.truth, *row.lod / kLod95Factor});
            }
        }
    }
    for (const RegistrationCheck& c : report.registration) {
        if (!c.accepted || c.is_reference || !c.parameter_error || !c.parameter_sigma) continue;
        auto& parts = scored["registration:" + c.method];
        for (std::size_t k = 0; k < 6; ++k)
            parts[kParameterNames[k]].push_back({(*c.parameter_error)[k], (*c.parameter_sigma)[k]});
    }
    std::vector<CoverageRow> rows;
    for (const auto& [method, parts] : scored) {
        std::vector<ScoredFigure> all;
        for (const auto& [part, figures] : parts) {
            rows.push_back(coverage_of(method, part, figures));
            all.insert(all.end(), figures.begin(), figures.end());
        }
        if (parts.size() > 1) rows.push_back(coverage_of(method, "all", all));
    }
    std::map<std::pair<std::string, int>, std::vector<double>> tests;
    for (const ChiSquareTest& a : report.chi_square_tests)
        tests[{a.method, a.dof}].push_back(a.chi2);
    for (const auto& [key, chi2] : tests) {
        const auto& [method, dof] = key;
        CoverageRow row;
        row.method = method;
        row.part = "chi2(" + std::to_string(dof) + ")";
        row.statistic_only = true;
        row.n = chi2.size();
        const double q68 = registration::chi_square_quantile(kNominal68, dof);
        const double q95 = registration::chi_square_quantile(kNominal95, dof);
        for (const double x : chi2) {
            row.within68 += x <= q68;
            row.within95 += x <= q95;
        }
        row.band68 = wilson_interval(row.within68, row.n);
        row.band95 = wilson_interval(row.within95, row.n);
        row.verdict68 = sigma_verdict(row.within68, row.n, kNominal68);
        row.verdict95 = sigma_verdict(row.within95, row.n, kNominal95);
        rows.push_back(std::move(row));
    }
    return rows;
}

}  // namespace tlsmon::report
