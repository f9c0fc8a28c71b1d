#pragma once
// The alarm rules of one epoch, evaluated inside its commit (ResultsWriter::commit with an
// AlarmEvaluation) once its zone results are written: every stage's zone rows flow through
// here. Value rules take the epoch's ZoneResult of their zone and quantity; rate rules the
// stored series over their window (this epoch included). The epoch's time is its
// acquisition time, so a backlog replays the rules in time order (pending epochs are taken
// by acquisition time, Epochs::pending).
#include <vector>

#include "alarms/alarm_rule.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// Rules not (yet) stored in alarm_rules are left out: the daemon stores the configured rules
// at start (store_alarm_rules). Rules on a campaign quantity are not the station's: an epoch
// leaves them alone.
AlarmRows evaluate_epoch_alarms(const std::vector<AlarmRuleSpec>& rules, const Epoch& epoch,
                                const EpochResults& results, const AlarmStore& alarms,
                                const SeriesReader& series);
// The same for a stored campaign (docs/campaigns.md, "Zone series"): only the rules on a
// campaign quantity, at the campaign's acquisition time; their states and events carry no
// epoch, their messages name the campaign.
AlarmRows evaluate_campaign_alarms(const std::vector<AlarmRuleSpec>& rules, std::int64_t campaign,
                                   UtcSeconds acquired, const std::vector<ZoneResult>& results,
                                   const AlarmStore& alarms, const SeriesReader& series);

// The rule's definition as JSON for alarm_rules.definition (levels, deadband, delays).
std::string rule_definition_json(const AlarmRuleSpec& rule);
// Stores the configured rules (their zones must exist: Site::upsert_zone).
void store_alarm_rules(EpochDatabase& db, const std::vector<AlarmRuleSpec>& rules);

}  // namespace tlsmon
