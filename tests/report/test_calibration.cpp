// The calibration of each method's own σ against the truth (report/calibration.hpp), on
// worked cases: the Wilson interval by its defining equation and a published value, the
// counts of figures within σ and 1.96 σ, the verdicts, and a run whose registration is known
// to be off by 1 mm with a σ of 0.4 mm (outside its 95 % interval) or 2 mm (inside). Without a
// truth, the agreement tests of joined estimates against χ²(6)'s quantiles, each used target
// against the others against χ²(3)'s, and the check zones' values against zero.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/rigid_transform.hpp"
#include "report/calibration.hpp"
#include "report/data.hpp"

namespace tlsmon::report {
namespace {

TEST(Calibration, WilsonIntervalSolvesItsDefiningEquation) {
    const ShareInterval b = wilson_interval(95, 100);
    // 95/100: [0.8882, 0.9785] (Newcombe 1998, method 3, by hand).
    EXPECT_NEAR(b.lower, 0.8882, 5e-4);
    EXPECT_NEAR(b.upper, 0.9785, 5e-4);
    // Each bound p satisfies |p̂ − p| = z·√(p(1 − p)/n).
    for (const double p : {b.lower, b.upper})
        EXPECT_NEAR(std::abs(0.95 - p), 1.96 * std::sqrt(p * (1 - p) / 100), 1e-12);
    // All hits: the upper bound is 1, the lower one below it; no figures: [0, 1].
    const ShareInterval all = wilson_interval(20, 20);
    EXPECT_DOUBLE_EQ(all.upper, 1.0);
    EXPECT_NEAR(all.lower, 20.0 / (20 + 1.96 * 1.96), 1e-12);
    EXPECT_DOUBLE_EQ(wilson_interval(0, 0).lower, 0.0);
    EXPECT_DOUBLE_EQ(wilson_interval(0, 0).upper, 1.0);
}

TEST(Calibration, VerdictsTellASmallSigmaFromAPaddedOne) {
    EXPECT_EQ(sigma_verdict(190, 200, kNominal95), SigmaVerdict::consistent);
    EXPECT_EQ(sigma_verdict(170, 200, kNominal95), SigmaVerdict::too_small);
    EXPECT_EQ(sigma_verdict(200, 200, kNominal95), SigmaVerdict::too_large);
    // 18 of 20 is 90 %, yet 20 figures cannot tell it from 95 % (Wilson: 69.9–97.2 %);
    // 17 of 20 can (up to 94.8 %).
    EXPECT_EQ(sigma_verdict(18, 20, kNominal95), SigmaVerdict::consistent);
    EXPECT_EQ(sigma_verdict(17, 20, kNominal95), SigmaVerdict::too_small);
    EXPECT_EQ(sigma_verdict(0, 0, kNominal95), SigmaVerdict::no_figures);
}

TEST(Calibration, CountsFiguresWithinSigmaAndLod95) {
    // σ = 1: six errors of ±0.5 (within both), three of 1.5 (within 1.96 σ only), one of 2.5.
    std::vector<ScoredFigure> f;
    for (int i = 0; i < 6; ++i) f.push_back({i % 2 ? 0.5 : -0.5, 1.0});
    for (int i = 0; i < 3; ++i) f.push_back({1.5, 1.0});
    f.push_back({2.5, 1.0});
    const CoverageRow row = coverage_of("m3c2_median_m", "top", f);
    EXPECT_EQ(row.n, 10u);
    EXPECT_EQ(row.within68, 6u);
    EXPECT_EQ(row.within95, 9u);
    EXPECT_DOUBLE_EQ(row.coverage95(), 0.9);
    EXPECT_NEAR(row.error.bias, (4.5 + 2.5) / 10, 1e-12);
    EXPECT_NEAR(row.error.max_abs, 2.5, 1e-12);
    EXPECT_DOUBLE_EQ(row.rms_sigma, 1.0);
}

TEST(Calibration, RegistrationParametersAndZonesOfARun) {
    // Three epochs after the reference; each stored transformation is the exact one but 1 mm
    // off in x. Its σ(tx) is 0.4 mm in two epochs (1 mm is 2.5 σ: outside) and 2 mm in one.
    // A zone value 0.5 mm off with an LoD95 of 1.96 mm (σ 1 mm): inside both intervals.
    RunData run;
    run.reference = 1;
    std::vector<TruthEpoch> truth;
    for (int i = 0; i < 4; ++i) {
        TruthEpoch t;
        t.epoch = i;
        t.time_unix = 1'000'000 + 900 * i;
        Eigen::Affine3d pose(Eigen::AngleAxisd(1e-4 * i, Eigen::Vector3d::UnitZ()));
        pose.translation() = Eigen::Vector3d(0.01 * i, 0, 0);
        t.header_to_true = pose;
        t.pier = {2.0, 17.0, 45.0, 52.0, 40.0};
        t.samples = {{"top_centre", {9.5, 48.5, 40.0}, {}}};
        truth.push_back(t);
        RunEpoch e;
        e.epoch.id = i + 1;
        e.epoch.acquired = t.time_unix;
        e.epoch.status = EpochStatus::done;
        RegistrationRow r;
        r.method = "targets-helmert";
        r.accepted = true;
        Eigen::Affine3d T = pose;  // reference pose is the identity
        if (i > 0) T.translation().x() += 0.001;
        for (int k = 0; k < 16; ++k)
            r.transform[static_cast<std::size_t>(k)] = T.matrix()(k / 4, k % 4);
        const Eigen::Vector3d angles = registration::euler_from_rotation(T.linear());
        r.parameters =
            std::array<double, 6>{angles.x(),          angles.y(),          angles.z(),
                                  T.translation().x(), T.translation().y(), T.translation().z()};
        const double sx = i == 3 ? 0.002 : 0.0004;
        r.sigmas = std::array<double, 6>{1e-5, 1e-5, 1e-5, sx, 0.001, 0.001};
        e.registration = r;
        run.epochs.push_back(e);
    }
    RunZone zone;
    zone.id = 1;
    zone.name = "top";
    zone.box = ZoneBox{{2.0, 44.5, 30.0}, {17.0, 45.5, 40.0}};
    for (int i = 0; i < 4; ++i)
        zone.series["m3c2_median_m"].push_back({i + 1, truth[static_cast<std::size_t>(i)].time_unix,
                                                0.0005, 0.00196, 50, false, "targets", true,
                                                std::nullopt});
    run.zones.push_back(zone);

    const auto rows = calibration(analyse(run, truth, "truth"));
    const auto find = [&](const std::string& method, const std::string& part) {
        for (const auto& r : rows)
            if (r.method == method && r.part == part) return r;
        ADD_FAILURE() << method << " " << part;
        return CoverageRow{};
    };
    const CoverageRow tx = find("registration:targets-helmert", "tx");
    EXPECT_EQ(tx.n, 3u);  // the reference left out
    EXPECT_NEAR(tx.error.bias, 0.001, 1e-9);
    EXPECT_EQ(tx.within68, 1u);  // 1 mm ≤ 2 mm only
    EXPECT_EQ(tx.within95, 1u);
    const CoverageRow omega = find("registration:targets-helmert", "omega");
    EXPECT_NEAR(omega.error.max_abs, 0.0, 1e-12);
    EXPECT_EQ(omega.within68, 3u);
    EXPECT_EQ(find("registration:targets-helmert", "all").n, 18u);
    // The zone: four rows, the reference's left out; 0.5 mm within σ = 1 mm.
    const CoverageRow top = find("m3c2_median_m", "top");
    EXPECT_EQ(top.n, 3u);
    EXPECT_EQ(top.within68, 3u);
    EXPECT_NEAR(top.rms_sigma, 0.001, 1e-12);
}

// No truth: the agreement χ² stored by joined estimates of accepted epochs, per estimate,
// against χ²(6)'s quantiles 7.04 (68.27 %) and 12.59 (95 %); a rejected epoch's is left out.
TEST(Calibration, AgreementTestsNeedNoTruth) {
    RunData run;
    run.reference = 1;
    const auto epoch = [&](int id, bool accepted, const std::string& quality) {
        RunEpoch e;
        e.epoch.id = id;
        e.epoch.acquired = 1'000'000 + 900 * id;
        e.epoch.status = accepted ? EpochStatus::done : EpochStatus::rejected;
        RegistrationRow r;
        r.method = "targets+icp";
        r.accepted = accepted;
        r.quality_json = quality;
        e.registration = r;
        run.epochs.push_back(e);
    };
    epoch(1, true, R"({"atmosphere":"not_corrected"})");
    epoch(2, true, R"({"icp":{"agreement_chi2":1.0},"planes":{"agreement_chi2":null}})");
    epoch(3, true, R"({"icp":{"agreement_chi2":10.0}})");
    epoch(4, true, R"({"icp":{"agreement_chi2":20.0},"stable_areas":{"agreement_chi2":3.0}})");
    epoch(5, false, R"({"icp":{"agreement_chi2":2.0}})");
    epoch(6, true, "not json");
    const RunReport report = analyse(run, {}, "");
    EXPECT_FALSE(report.scored);
    ASSERT_EQ(report.chi_square_tests.size(), 4u);
    const auto rows = calibration(report);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].method, "agreement:icp");
    EXPECT_EQ(rows[0].part, "chi2(6)");
    EXPECT_TRUE(rows[0].statistic_only);
    EXPECT_TRUE(rows[0].blank_numbers());
    EXPECT_EQ(rows[0].n, 3u);
    EXPECT_EQ(rows[0].within68, 1u);  // 1.0 only
    EXPECT_EQ(rows[0].within95, 2u);  // 1.0 and 10.0
    EXPECT_EQ(rows[0].verdict95, sigma_verdict(2, 3, kNominal95));
    EXPECT_EQ(rows[1].method, "agreement:stable_areas");
    EXPECT_EQ(rows[1].within68, 1u);
    EXPECT_NEAR(registration::chi_square_quantile(kNominal68, 6), 7.04, 0.01);
    EXPECT_NEAR(registration::chi_square_quantile(kNominal95, 6), 12.592, 0.001);
}

// No truth: each used target's T_i (its fit against the transformation of the others)
// against χ²(3)'s quantiles 3.53 (68.27 %) and 7.81 (95 %), in accepted epochs with at least
// four used targets; the reference epoch, an excluded target and a three-target epoch are
// left out.
TEST(Calibration, TargetsAgainstTheOthersNeedNoTruth) {
    RunData run;
    run.reference = 1;
    const auto epoch = [&](int id, const std::vector<double>& used, double excluded) {
        RunEpoch e;
        e.epoch.id = id;
        e.epoch.acquired = 1'000'000 + 900 * id;
        e.epoch.status = EpochStatus::done;
        RegistrationRow r;
        r.method = "targets";
        r.accepted = true;
        e.registration = r;
        for (const double t : used) {
            TargetObservation o;
            o.use = "used";
            o.statistic = t;
            e.targets.push_back(o);
        }
        TargetObservation out;
        out.use = "excluded_outlier";
        out.statistic = excluded;
        e.targets.push_back(out);
        run.epochs.push_back(e);
    };
    epoch(1, {0.1, 0.2, 0.3, 0.4}, 40);  // the reference
    epoch(2, {1.0, 5.0, 9.0, 2.0}, 30);
    epoch(3, {0.5, 0.5, 0.5}, 30);  // three used targets
    const auto rows = calibration(analyse(run, {}, ""));
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].method, "no_change:targets");
    EXPECT_EQ(rows[0].part, "chi2(3)");
    EXPECT_TRUE(rows[0].blank_numbers());
    EXPECT_EQ(rows[0].n, 4u);
    EXPECT_EQ(rows[0].within68, 2u);  // 1.0 and 2.0
    EXPECT_EQ(rows[0].within95, 3u);  // and 5.0
    EXPECT_NEAR(registration::chi_square_quantile(kNominal68, 3), 3.527, 0.001);
    EXPECT_NEAR(registration::chi_square_quantile(kNominal95, 3), 7.815, 0.001);
}

// A check zone ([[zone]] no_change): its displacement quantities are scored against zero
// with no truth at all, the reference epoch's own row and the counts left out; an ordinary
// zone without a truth is not scored.
TEST(Calibration, CheckZonesAreScoredAgainstZeroWithoutATruth) {
    RunData run;
    run.reference = 1;
    const auto point = [](EpochId id, double value, std::optional<double> lod) {
        SeriesPoint p;
        p.epoch = id;
        p.acquired = 1'000'000 + 900 * id;
        p.value = value;
        p.uncertainty = lod;
        return p;
    };
    RunZone check;
    check.id = 1;
    check.name = "abutment";
    check.no_change = true;
    // LoD95 1.96 mm (σ 1 mm): 0.0 (reference), 0.5 and −0.9 within σ, 1.5 and −1.9 within
    // LoD95 only, 2.5 outside both; NaN and a row without an LoD are not figures.
    check.series["m3c2_median_m"] = {point(1, 0.0, 0.00196),          point(2, 0.0005, 0.00196),
                                     point(3, -0.0009, 0.00196),      point(4, 0.0015, 0.00196),
                                     point(5, -0.0019, 0.00196),      point(6, 0.0025, 0.00196),
                                     point(7, std::nan(""), 0.00196), point(8, 0.0001, {})};
    check.series["m3c2_valid_count"] = {point(2, 43, {}), point(3, 43, {})};
    RunZone face = check;
    face.id = 2;
    face.name = "pier face";
    face.no_change = false;
    run.zones = {check, face};
    EXPECT_TRUE(
        parse_zone_no_change(R"({"type":"box","min":[0,0,0],"max":[1,1,1],"no_change":true})"));
    EXPECT_FALSE(parse_zone_no_change(R"({"type":"box","no_change":"yes"})"));
    EXPECT_FALSE(parse_zone_no_change("not json"));

    const RunReport report = analyse(run, {}, "");
    EXPECT_FALSE(report.scored);
    const auto rows = calibration(report);
    ASSERT_EQ(rows.size(), 1u);
    const CoverageRow& r = rows[0];
    EXPECT_EQ(r.method, "no_change:m3c2_median_m");
    EXPECT_EQ(r.part, "abutment");
    EXPECT_EQ(r.n, 5u);
    EXPECT_EQ(r.within68, 2u);
    EXPECT_EQ(r.within95, 4u);
    EXPECT_NEAR(r.error.bias, (0.0005 - 0.0009 + 0.0015 - 0.0019 + 0.0025) / 5, 1e-12);
    EXPECT_NEAR(r.rms_sigma, 0.001, 1e-12);
    EXPECT_EQ(r.verdict95, sigma_verdict(4, 5, kNominal95));
}

}  // namespace
}  // namespace tlsmon::report
