// The JSON the pipeline stores (registration quality, alarm rule definitions, keypoint band
// zones) is written by nlohmann-json: valid whatever the values, a NaN or an absent value as
// null, text with quotes and control characters escaped.
#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "pipeline/alarm_evaluation.hpp"
#include "pipeline/icp_registration.hpp"

namespace tlsmon::test {
namespace {

TEST(QualityJson, NanIsNullAndTextIsEscaped) {
    IcpMeasurement m;
    m.role = "fallback";
    m.refused = "fitness 0.1 below \"min_overlap\"\n0.3";
    m.rms = std::numeric_limits<double>::quiet_NaN();
    m.overlap = 0.1;
    const auto parsed = nlohmann::json::parse(icp_quality(m).dump());
    EXPECT_TRUE(parsed.at("rms_m").is_null());
    EXPECT_TRUE(parsed.at("agreement_chi2").is_null());
    EXPECT_EQ(parsed.at("refused"), m.refused);
    EXPECT_EQ(parsed.at("fitness"), 0.1);
}

TEST(QualityJson, AlarmRuleDefinitionReadsBack) {
    AlarmRuleSpec r;
    r.name = "top";
    r.levels[1] = LevelLimits{0.005, std::nullopt, 0.001};
    r.rate_window_seconds = 7200;
    r.on_delay = 2;
    const auto j = nlohmann::json::parse(rule_definition_json(r));
    EXPECT_EQ(j.at("levels").size(), 1u);
    EXPECT_EQ(j.at("levels").at("alert").at("high"), 0.005);
    EXPECT_TRUE(j.at("levels").at("alert").at("low").is_null());
    EXPECT_EQ(j.at("levels").at("alert").at("deadband"), 0.001);
    EXPECT_EQ(j.at("rate_window_seconds"), 7200.0);
    EXPECT_EQ(j.at("on_delay"), 2);
    EXPECT_EQ(j.at("evaluate_unregistered"), false);
    r.rate_window_seconds.reset();
    EXPECT_TRUE(nlohmann::json::parse(rule_definition_json(r)).at("rate_window_seconds").is_null());
}

}  // namespace
}  // namespace tlsmon::test
