-- What the alarm state machine needs to survive a restart beyond state and level: the
-- process condition (the level the rule evaluates to, also while shelved), the shelve
-- expiry, the rule's memory between epochs (per level: active after deadband and delays,
-- and the consecutive-epoch count toward a delay; alarms/alarm_rule.hpp), and the
-- acquisition time of the newest epoch the rule evaluated (acquisition order).
-- Alarm events name who caused them: the rule, SCADA or the CLI.
ALTER TABLE alarm_states ADD COLUMN process TEXT NOT NULL DEFAULT '';
ALTER TABLE alarm_states ADD COLUMN shelved_until INTEGER;
ALTER TABLE alarm_states ADD COLUMN memory TEXT NOT NULL DEFAULT '';
ALTER TABLE alarm_states ADD COLUMN evaluated INTEGER;
ALTER TABLE alarm_events ADD COLUMN actor TEXT NOT NULL DEFAULT 'rule';
