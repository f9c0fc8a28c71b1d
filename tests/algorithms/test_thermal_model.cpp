// The thermal compensation's kernels against known answers: the lag cascade's step response
// (analytic), the daily amplitude of a known harmonic, completeness around gaps and stale air,
// a model with known lags and coefficients recovered from noisy observations (and with gross
// outliers), its σ against the noise it was given, and the model-health tests on residuals that
// are, and are not, the model's.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "algorithms/thermal/model_health.hpp"
#include "algorithms/thermal/thermal_model.hpp"

using namespace tlsmon::thermal;

namespace {

constexpr double kHour = 3600.0;
constexpr double kStart = 1780293600.0;  // 2026-06-01T06:00Z
constexpr double kOmega = 2.0 * std::numbers::pi / 86400.0;

// Air every 15 minutes: a daily cycle whose amplitude and mean change from day to day (seeded),
// as clouds and weather fronts make them.
std::vector<AirReading> air_series(int days, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> amp(1.5, 6.0), mean(10.0, 22.0);
    std::vector<double> a(days + 2), m(days + 2);
    for (int d = 0; d < days + 2; ++d) a[d] = amp(rng), m[d] = mean(rng);
    std::vector<AirReading> out;
    for (int k = 0; k < days * 96; ++k) {
        const double t = kStart + 900.0 * k;
        const double day = (t - kStart) / 86400.0;
        const int d = static_cast<int>(day);
        const double f = day - d;  // linear between the days' values
        const double amplitude = a[d] + (a[d + 1] - a[d]) * f;
        const double mid = m[d] + (m[d + 1] - m[d]) * f;
        out.push_back({t, mid + amplitude * std::sin(kOmega * (t - kStart) - 1.0)});
    }
    return out;
}

DriverOptions options_at_site() {
    DriverOptions o;
    o.location = {49.97, 7.07};
    return o;
}

}  // namespace

TEST(ThermalDrivers, TwoLagsInSeriesFollowAStepOfTheAirAsTheAnalyticResponse) {
    // Constant air, a 10 K step at t0 (over one 15-minute reading interval): the section's
    // response to a unit step through τ1 then τ2 is 1 − (τ1 e^{−t/τ1} − τ2 e^{−t/τ2})/(τ1 − τ2).
    std::vector<AirReading> air;
    const double t0 = kStart + 48 * kHour;
    for (double t = kStart; t <= t0 + 24 * kHour; t += 900.0)
        air.push_back({t, t < t0 ? 10.0 : 20.0});
    std::vector<double> times;
    for (double h : {0.5, 1.0, 2.0, 4.0, 8.0}) times.push_back(t0 + h * kHour);
    const Lags lags{1.0, 3.0};
    const auto d = thermal_drivers(air, times, lags, options_at_site());
    for (std::size_t i = 0; i < times.size(); ++i) {
        // The step rises over the reading interval before t0: its middle is t0 − 450 s.
        const double t = (times[i] - (t0 - 450.0)) / kHour;
        const double unit =
            1.0 - (1.0 * std::exp(-t / 1.0) - 3.0 * std::exp(-t / 3.0)) / (1.0 - 3.0);
        EXPECT_NEAR(d[i].air_c, 10.0 + 10.0 * unit, 0.05) << "t = " << t << " h";
        EXPECT_TRUE(d[i].complete);
    }
}

TEST(ThermalDrivers, DailyAmplitudeIsTheHarmonicsAmplitudeWhateverTheMeanDoes) {
    // A 4 K daily cycle on a mean rising 3 K a day.
    std::vector<AirReading> air;
    for (int k = 0; k < 3 * 96; ++k) {
        const double t = kStart + 900.0 * k;
        air.push_back({t, 15.0 + 3.0 * (t - kStart) / 86400.0 + 4.0 * std::cos(kOmega * t)});
    }
    const auto d = thermal_drivers(air, {kStart + 60 * kHour}, {1, 3}, options_at_site());
    EXPECT_NEAR(d[0].daily_amplitude_c, 4.0, 0.05);
    // The sun is up at 18:00 UTC in June at 50° N, on the west face only (west, east, south,
    // north): lagged, the south face still holds the afternoon's heat.
    EXPECT_GT(d[0].solar[0], 0.0);
}

TEST(ThermalDrivers, StaleOrGappedAirIsNeverComplete) {
    auto air = air_series(5, 3);
    const double late = air.back().t + 3 * kHour;  // no reading for 3 h
    // A 4-hour gap on day 3.
    std::vector<AirReading> gapped;
    const double gap_from = kStart + 72 * kHour, gap_to = gap_from + 4 * kHour;
    for (const auto& r : air)
        if (r.t < gap_from || r.t > gap_to) gapped.push_back(r);
    const DriverOptions o = options_at_site();  // max gap 2 h
    const auto d = thermal_drivers(
        gapped,
        {kStart + 30 * kHour, kStart + 60 * kHour, gap_to + kHour, gap_to + 30 * kHour, late},
        {1, 3}, o);
    EXPECT_TRUE(d[0].complete);  // 30 h of readings: the 24-h spin-up is covered
    EXPECT_TRUE(d[1].complete);
    EXPECT_FALSE(d[2].complete);  // an hour after the gap: its memory holds the gap
    EXPECT_TRUE(d[3].complete);   // a full spin-up after it
    EXPECT_FALSE(d[4].complete);  // the newest reading 3 h old
    EXPECT_NEAR(d[4].air_age_h, 3.0, 1e-9);
    // Before any reading: nothing.
    EXPECT_FALSE(thermal_drivers(air, {kStart - kHour}, {1, 3}, o)[0].complete);
}

namespace {

// Observations of a zone quantity that is exactly the model with lags (1 h, 3 h) and these
// coefficients, plus Gaussian noise σ.
struct Synthetic {
    std::vector<AirReading> air;
    std::vector<Observation> observations;
    Eigen::VectorXd beta;
};
Synthetic synthetic(int days, double sigma, std::uint64_t seed) {
    Synthetic s;
    s.air = air_series(days, seed);
    s.beta.resize(6);
    // m, m/K, m per (K·W/m²) on the four faces
    s.beta << 1e-3, 2.4e-4, 6e-7, -4.5e-7, 9e-7, 0.0;
    std::vector<double> times;
    for (const auto& a : s.air) times.push_back(a.t);
    const auto d = thermal_drivers(s.air, times, {1.0, 3.0}, options_at_site());
    std::mt19937_64 rng(seed + 1);
    std::normal_distribution<double> noise(0.0, sigma);
    ThermalModel exact;
    exact.coefficients = s.beta;
    for (std::size_t i = 0; i < times.size(); ++i)
        s.observations.push_back(
            {times[i], design_row(exact, d[i], times[i]).dot(s.beta) + noise(rng), sigma});
    return s;
}

}  // namespace

TEST(ThermalModel, RecoversAKnownResponseAndPredictsUnseenDaysWithinItsSigma) {
    const double sigma = 0.15e-3;
    const Synthetic s = synthetic(16, sigma, 5);
    // Trained on the first 8 days, scored on the other 8.
    const std::size_t split = 8 * 96;
    const std::vector<Observation> train(s.observations.begin(), s.observations.begin() + split);
    ModelOptions options;
    options.drivers = options_at_site();
    std::string why;
    const auto m = fit_thermal_model(s.air, train, options, why);
    ASSERT_TRUE(m) << why;
    // The section's lag as simulated; the surface's is barely told from its neighbours.
    EXPECT_EQ(m->lags.section_h, 3.0);
    EXPECT_LE(m->lags.surface_h, 2.0);
    EXPECT_NEAR(m->coefficients(1), s.beta(1), 0.1 * s.beta(1));
    // The σ describes the noise: in sample and out of sample within 25 % of it.
    EXPECT_NEAR(m->residual_sigma, sigma, 0.25 * sigma);
    EXPECT_NEAR(m->prediction_sigma, sigma, 0.25 * sigma);
    EXPECT_LT(m->day_mean_sigma, 0.3 * sigma);  // white noise: a day's mean strays σ/√96
    EXPECT_GT(m->explained_share, 0.95);
    EXPECT_TRUE(m->converged);
    // Observations before the 30-h spin-up of the grid's longest lags are left out.
    EXPECT_LE(m->observations, static_cast<int>(split) - 100);
    EXPECT_EQ(model_terms(false).size(), 6u);
    // The daily amplitudes of the epochs it used: those of the training window's drivers.
    std::vector<double> trained;
    for (const auto& o : train)
        if (o.t >= m->training_from && o.t <= m->training_to) trained.push_back(o.t);
    double lowest = 1e9, highest = -1e9;
    for (const auto& d : thermal_drivers(s.air, trained, m->lags, options.drivers)) {
        lowest = std::min(lowest, d.daily_amplitude_c);
        highest = std::max(highest, d.daily_amplitude_c);
    }
    EXPECT_DOUBLE_EQ(m->amplitude_min_c, lowest);
    EXPECT_DOUBLE_EQ(m->amplitude_max_c, highest);
    EXPECT_GT(highest - lowest, 1.0);
    // The unseen days: the prediction within half the noise of the exact response, and the
    // residual within ±1.96σ at close to 95 %.
    std::vector<double> times;
    for (const auto& o : s.observations) times.push_back(o.t);
    const auto exact_drivers = thermal_drivers(s.air, times, {1.0, 3.0}, options.drivers);
    const auto model_drivers = thermal_drivers(s.air, times, m->lags, options.drivers);
    ThermalModel exact;
    exact.coefficients = s.beta;
    double sum2 = 0;
    int n = 0, covered = 0;
    for (std::size_t i = split; i < times.size(); ++i) {
        const Prediction p = predict(*m, model_drivers[i], times[i], sigma);
        const double truth = design_row(exact, exact_drivers[i], times[i]).dot(s.beta);
        sum2 += std::pow(p.value - truth, 2);
        covered += std::abs(s.observations[i].value - p.value) <= 1.96 * p.sigma;
        ++n;
    }
    EXPECT_LT(std::sqrt(sum2 / n), 0.5 * sigma);
    EXPECT_GT(covered, 0.92 * n);
    EXPECT_LT(covered, 0.99 * n);
}

TEST(ThermalModel, BeyondTheTrainingsAmplitudesTheSigmaHoldsWhatTheScalingAdds) {
    ThermalModel m;
    m.coefficients.resize(6);
    m.coefficients << 1e-3, 2e-4, 6e-7, -4e-7, 9e-7, 0.0;
    m.covariance = Eigen::MatrixXd::Zero(6, 6);
    m.prediction_sigma = 0.2e-3;
    m.measurement_variance = std::pow(0.1e-3, 2);
    m.amplitude_min_c = 3.0;
    m.amplitude_max_c = 5.0;
    // The drivers of one time on a day of amplitude a: the solar terms ∝ a.
    const auto at = [](double a) {
        Drivers d;
        d.air_c = 12.0;
        d.solar = {a * 150.0, a * 20.0, a * 300.0, 0.0};
        d.daily_amplitude_c = a;
        d.complete = true;
        return d;
    };
    const double t = kStart;
    // Within the training's amplitudes: nothing added.
    for (const double a : {3.0, 4.2, 5.0}) {
        const Prediction p = predict(m, at(a), t, 0.1e-3);
        EXPECT_EQ(p.extrapolation_sigma, 0.0);
        EXPECT_DOUBLE_EQ(p.sigma, 0.2e-3);
        EXPECT_DOUBLE_EQ(p.thermal_sigma, std::sqrt(std::pow(0.2e-3, 2) - std::pow(0.1e-3, 2)));
    }
    // Beyond: what the prediction gains from the amplitude past the training's edge, as a σ.
    for (const auto& [a, edge] : {std::pair{1.5, 3.0}, std::pair{7.0, 5.0}}) {
        const Prediction p = predict(m, at(a), t, 0.1e-3);
        const double gained = predict(m, at(a), t, 0.1e-3).value - predict(m, at(edge), t, 0).value;
        EXPECT_NEAR(p.extrapolation_sigma, std::abs(gained), 1e-15);
        EXPECT_GT(p.extrapolation_sigma, 0.1e-3);  // a visible share of the σ here
        EXPECT_NEAR(p.sigma, std::hypot(0.2e-3, std::abs(gained)), 1e-15);
        EXPECT_NEAR(p.thermal_sigma,
                    std::sqrt(std::pow(0.2e-3, 2) - std::pow(0.1e-3, 2) + gained * gained), 1e-15);
    }
}

TEST(ThermalModel, GrossOutliersDoNotMoveTheFit) {
    const double sigma = 0.15e-3;
    Synthetic s = synthetic(8, sigma, 6);
    // One observation in twenty off by 5 mm (a wrong registration that slipped through).
    for (std::size_t i = 0; i < s.observations.size(); i += 20) s.observations[i].value += 5e-3;
    ModelOptions options;
    options.drivers = options_at_site();
    std::string why;
    const auto m = fit_thermal_model(s.air, s.observations, options, why);
    ASSERT_TRUE(m) << why;
    EXPECT_NEAR(m->coefficients(1), s.beta(1), 0.1 * s.beta(1));
    EXPECT_NEAR(m->residual_sigma, sigma, 0.3 * sigma);
    EXPECT_GT(m->downweighted, static_cast<int>(s.observations.size() / 25));
}

TEST(ThermalModel, ItsSigmaIsNeverBelowTheMeasurementsOwn) {
    // The values carry 0.1 mm of noise; the measurement says 0.3 mm on some epochs, 0.5 mm on
    // the others: the left-out days alone would give about 0.1 mm.
    Synthetic s = synthetic(8, 0.1e-3, 8);
    for (std::size_t i = 0; i < s.observations.size(); ++i)
        s.observations[i].sigma = i % 2 ? 0.3e-3 : 0.5e-3;
    ModelOptions options;
    options.drivers = options_at_site();
    std::string why;
    const auto m = fit_thermal_model(s.air, s.observations, options, why);
    ASSERT_TRUE(m) << why;
    EXPECT_LT(m->residual_sigma, 0.15e-3);
    EXPECT_NEAR(m->measurement_variance, 0.5 * (0.09e-6 + 0.25e-6), 1e-12);
    EXPECT_LT(m->prediction_sigma, 0.15e-3);  // what the left-out days showed
    // An epoch within the training's amplitudes with the training's mean σ_m: the σ is that.
    std::vector<double> times;
    for (const auto& o : s.observations) times.push_back(o.t);
    const auto d = thermal_drivers(s.air, times, m->lags, options.drivers);
    const std::size_t i = s.observations.size() - 10;
    ASSERT_TRUE(d[i].complete);
    const Prediction p = predict(*m, d[i], times[i], std::sqrt(m->measurement_variance));
    ASSERT_EQ(p.extrapolation_sigma, 0.0);
    const Eigen::VectorXd x = design_row(*m, d[i], times[i]);
    EXPECT_NEAR(p.sigma, std::sqrt(m->measurement_variance + x.dot(m->covariance * x)), 1e-15);
    EXPECT_NEAR(p.thermal_sigma, std::sqrt(x.dot(m->covariance * x)), 1e-15);
}

TEST(ThermalModel, RefusesWithoutEnoughCompleteDrivers) {
    const Synthetic s = synthetic(1, 1e-4, 7);  // one day: no observation after the spin-up
    ModelOptions options;
    options.drivers = options_at_site();
    std::string why;
    EXPECT_FALSE(fit_thermal_model(s.air, s.observations, options, why));
    EXPECT_NE(why.find("complete drivers"), std::string::npos) << why;
}

namespace {

// The health of 100 windows of a day's (96) white residuals drawn from `noise`.
std::vector<ModelHealth> white_windows(const ThermalModel& m, std::mt19937_64& rng,
                                       std::normal_distribution<double>& noise) {
    std::vector<ModelHealth> health;
    for (int w = 0; w < 100; ++w) {
        std::vector<double> r(96);
        for (double& x : r) x = noise(rng);
        health.push_back(model_health(m, r, {}));
    }
    return health;
}

}  // namespace

TEST(ModelHealth, JudgesTheModelsOwnResidualsHealthyAndAChangedResponseNot) {
    ThermalModel m;
    m.prediction_sigma = 0.2e-3;
    m.day_mean_sigma = 0.1e-3;  // a left-out day's mean strayed by 0.1 mm (RMS)
    m.lag1_autocorrelation = 0.5;
    std::mt19937_64 rng(9);
    std::normal_distribution<double> noise(0.0, m.prediction_sigma);
    // White residuals are not the AR(1) the model expects, which makes the tests conservative:
    // nothing flagged in 100 windows.
    int flagged = 0;
    for (const ModelHealth& h : white_windows(m, rng, noise)) {
        ASSERT_TRUE(h.judged);
        flagged += h.drifted || h.spread_grew;
    }
    EXPECT_EQ(flagged, 0);
    // A daily cycle of 1 mm left in the residuals (the bending halved): the spread grew.
    std::vector<double> cycle(96);
    for (int i = 0; i < 96; ++i)
        cycle[i] = noise(rng) + 1e-3 * std::sin(2 * std::numbers::pi * i / 96.0);
    const ModelHealth grew = model_health(m, cycle, {});
    EXPECT_TRUE(grew.spread_grew);
    EXPECT_GT(grew.spread_ratio, grew.spread_critical);
    // A day's residuals shifted by 1 mm (10 day-mean σ): the mean drifted.
    std::vector<double> shifted(96);
    for (double& x : shifted) x = noise(rng) + 1e-3;
    const ModelHealth drift = model_health(m, shifted, {});
    EXPECT_TRUE(drift.drifted);
    EXPECT_FALSE(drift.spread_grew);
    // Too few residuals: not judged.
    EXPECT_FALSE(model_health(m, std::vector<double>(10, 0.0), {}).judged);
}

TEST(ModelHealth, ComparesTheSpreadWithTheMeasurementsOwnSigmaWhereTheLeftOutDaysShowedLess) {
    // The left-out days showed 0.2 mm, the measurement's own σ is 0.35 mm: a week whose
    // residuals carry the measurement's whole 0.35 mm is the model's, not a changed structure
    // (against 0.2 mm their spread would be 1.75×, above the critical ≈ 1.4).
    ThermalModel m;
    m.prediction_sigma = 0.2e-3;
    m.measurement_variance = 0.35e-3 * 0.35e-3;
    m.day_mean_sigma = 0.1e-3;
    m.day_spread_max = 2.0;  // 0.4 mm: below the χ² term once taken against 0.35 mm
    m.lag1_autocorrelation = 0.5;
    ASSERT_DOUBLE_EQ(residual_reference_sigma(m), 0.35e-3);
    std::mt19937_64 rng(10);
    std::normal_distribution<double> noise(0.0, 0.35e-3);
    int flagged = 0;
    for (const ModelHealth& h : white_windows(m, rng, noise)) {
        ASSERT_TRUE(h.judged);
        EXPECT_NEAR(h.spread_ratio, h.spread / 0.35e-3, 1e-12);
        EXPECT_GE(h.spread_critical, 2.0 * 0.2 / 0.35 - 1e-12);
        flagged += h.drifted || h.spread_grew;
    }
    EXPECT_EQ(flagged, 0);
    // The 1 mm daily cycle of a halved bending still shows against the larger reference.
    std::vector<double> cycle(96);
    for (int i = 0; i < 96; ++i)
        cycle[i] = noise(rng) + 1e-3 * std::sin(2 * std::numbers::pi * i / 96.0);
    EXPECT_TRUE(model_health(m, cycle, {}).spread_grew);
}
