#pragma once
// Private to storage/: row reads and single-row writes used by more than one store (the
// epoch commit writes alarm and system events in its own transaction). No transaction here.
#include <SQLiteCpp/SQLiteCpp.h>

#include <cstdint>
#include <string>
#include <vector>

#include "storage/alarm_store.hpp"
#include "storage/epochs.hpp"
#include "storage/event_log.hpp"
#include "storage/ids.hpp"
#include "storage/keypoint_models.hpp"
#include "storage/meteo_sidecar.hpp"
#include "storage/thermal_store.hpp"

namespace tlsmon {

// The columns of an epoch row in the order read_epoch expects.
extern const char* const kEpochColumns;
Epoch read_epoch(SQLite::Statement& s);

// Lookups by name; an unknown name is a StorageError naming it.
ZoneId zone_id_by_name(Connection& c, const std::string& zone);
AlarmRuleId rule_id_by_name(Connection& c, const std::string& rule);
// The id of a quantity name, inserted on first use.
std::int64_t quantity_id(Connection& c, const std::string& name);

void write_alarm_state(Connection& c, const AlarmState& state);
void write_alarm_event(Connection& c, const AlarmEvent& event);
void write_system_event(Connection& c, const SystemEvent& event);
// "12.3 MiB", for event messages.
std::string format_mib(std::int64_t bytes);
// meteo_store.cpp
void write_meteo_sidecar(Connection& c, const MeteoSidecar& sidecar);
// keypoint_models.cpp: the epoch's model rows (checked whole: StorageError otherwise).
void write_keypoint_models(Connection& c, EpochId id, const std::vector<KeypointModelRow>& models);
// thermal_store.cpp: the epoch's thermal models (each the next version of its zone quantity)
// and compensations (checked: StorageError otherwise).
void write_thermal_rows(Connection& c, EpochId id, const std::vector<ThermalModelRow>& models,
                        const std::vector<ThermalCompensationRow>& compensations);

}  // namespace tlsmon
