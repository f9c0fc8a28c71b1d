#include "pipeline/alarm_evaluation.hpp"

#include <fmt/format.h>

#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "alarms/alarm_rate.hpp"
#include "core/utc_time.hpp"
#include "pipeline/alarm_rows.hpp"
#include "storage/campaign_store.hpp"

namespace tlsmon {

namespace {

// Registration not accepted by the quality gate but the epoch analysed anyway: degraded.
EpochQuality epoch_quality(const EpochResults& r) {
    if (r.outcome != EpochStatus::done) return EpochQuality::rejected;
    if (r.registration && r.registration->method == kUnregistered)
        return EpochQuality::unregistered;
    if (r.registration && !r.registration->accepted) return EpochQuality::degraded;
    return EpochQuality::accepted;
}

// What the rules are evaluated on: a station epoch or a stored campaign.
struct Occasion {
    UtcSeconds acquired = 0;
    std::optional<EpochId> epoch;  // none for a campaign
    std::string name;              // "epoch 12", "campaign 3"
    bool campaign = false;         // only the rules on campaign quantities, or only the others
    EpochQuality quality = EpochQuality::accepted;
};

std::optional<RuleInput> rule_input(const AlarmRuleSpec& rule, const Occasion& at,
                                    const std::vector<ZoneResult>& results,
                                    const SeriesReader& series) {
    EpochQuality quality = at.quality;
    if (quality == EpochQuality::unregistered && rule.evaluate_unregistered) {
        quality = EpochQuality::accepted;
    }
    if (quality != EpochQuality::accepted) return RuleInput{0, false, quality};
    const ZoneResult* own = nullptr;
    for (const auto& z : results) {
        if (z.zone == rule.zone && z.quantity == rule.quantity) own = &z;
    }
    if (!own) return std::nullopt;  // this epoch says nothing about the rule's quantity
    if (!rule.rate_window_seconds) return RuleInput{own->value, own->significant, quality};
    const auto window = static_cast<UtcSeconds>(*rule.rate_window_seconds);
    std::vector<TimedValue> pts;
    for (const auto& p :
         series.points(rule.zone, rule.quantity, TimeRange{at.acquired - window, at.acquired})) {
        pts.push_back({p.acquired, p.value});
    }
    const auto rate = rate_mm_per_day(pts, at.acquired, *rule.rate_window_seconds);
    if (!rate) return std::nullopt;
    return RuleInput{*rate, true, quality};
}

AlarmRows evaluate_alarms(const std::vector<AlarmRuleSpec>& rules, const Occasion& at,
                          const std::vector<ZoneResult>& results, const AlarmStore& alarms,
                          const SeriesReader& series) {
    std::set<std::string> stored;
    for (const auto& r : alarms.rules()) stored.insert(r.name);
    std::map<std::string, AlarmState> rows;
    for (const auto& s : alarms.states()) rows.emplace(s.rule, s);
    AlarmRows out;
    for (const auto& rule : rules) {
        if (!stored.count(rule.name) || is_campaign_quantity(rule.quantity) != at.campaign)
            continue;
        const auto row = rows.find(rule.name);
        const AlarmRuleStatus status =
            row == rows.end() ? AlarmRuleStatus{} : rule_status(row->second);
        const auto input = rule_input(rule, at, results, series);
        const auto step = step_rule(rule, status, input, at.acquired);
        if (step.late) {
            // Never silently: the value is stored in the series, the rule keeps its time.
            out.system_events.push_back(SystemEvent{
                now_utc(), "warning", "alarm_rule_late_epoch",
                fmt::format("rule {}: {} was acquired {}, before the newest {} the rule "
                            "evaluated ({}); its values are stored, the rule does not step "
                            "back in time",
                            rule.name, at.name, format_utc(at.acquired),
                            at.campaign ? "campaign" : "epoch", format_utc(*status.evaluated)),
                at.epoch});
        }
        if (!step.evaluated && step.events.empty()) continue;
        const std::optional<double> value =
            step.evaluated ? std::optional<double>(input->value) : std::nullopt;
        const std::optional<EpochId> id = step.evaluated ? at.epoch : std::nullopt;
        auto state = state_row(rule.name, step.status, value, id);
        if (!step.evaluated && row != rows.end()) {  // keep the last value and its epoch
            state.value = row->second.value;
            state.epoch = row->second.epoch;
        }
        out.states.push_back(state);
        for (const auto& t : step.events) {
            auto event = event_row(rule.name, t, value, id);
            if (at.campaign && step.evaluated) event.message += " (" + at.name + ")";
            out.events.push_back(std::move(event));
        }
    }
    return out;
}

}  // namespace

AlarmRows evaluate_epoch_alarms(const std::vector<AlarmRuleSpec>& rules, const Epoch& epoch,
                                const EpochResults& results, const AlarmStore& alarms,
                                const SeriesReader& series) {
    const Occasion at{epoch.acquired, epoch.id, "epoch " + std::to_string(epoch.id), false,
                      epoch_quality(results)};
    return evaluate_alarms(rules, at, results.zone_results, alarms, series);
}

AlarmRows evaluate_campaign_alarms(const std::vector<AlarmRuleSpec>& rules, std::int64_t campaign,
                                   UtcSeconds acquired, const std::vector<ZoneResult>& results,
                                   const AlarmStore& alarms, const SeriesReader& series) {
    const Occasion at{acquired, std::nullopt, "campaign " + std::to_string(campaign), true,
                      EpochQuality::accepted};
    return evaluate_alarms(rules, at, results, alarms, series);
}

std::string rule_definition_json(const AlarmRuleSpec& r) {
    static const char* names[3] = {"warning", "alert", "alarm"};
    const auto number = [](const std::optional<double>& v) {
        return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
    };
    nlohmann::json levels = nlohmann::json::object();
    for (int k = 0; k < 3; ++k) {
        if (!r.levels[k]) continue;
        const auto& l = *r.levels[k];
        levels[names[k]] = {
            {"high", number(l.high)}, {"low", number(l.low)}, {"deadband", l.deadband}};
    }
    return nlohmann::json{{"levels", levels},
                          {"on_delay", r.on_delay},
                          {"off_delay", r.off_delay},
                          {"significant_only", r.significant_only},
                          {"rate_window_seconds", number(r.rate_window_seconds)},
                          {"latching", r.latching},
                          {"evaluate_unregistered", r.evaluate_unregistered}}
        .dump();
}

void store_alarm_rules(EpochDatabase& db, const std::vector<AlarmRuleSpec>& rules) {
    for (const auto& r : rules) {
        db.alarms().upsert_rule(
            AlarmRule{0, r.name, r.zone, r.quantity, rule_definition_json(r), r.enabled});
    }
}

}  // namespace tlsmon
