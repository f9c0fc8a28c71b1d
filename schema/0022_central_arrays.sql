-- 0022_central_arrays: per-core-point arrays in the outbox when [central] forward_arrays is on
-- (docs/central.md): the daemon sets central_forward.forward_arrays from the configuration;
-- while it and forwarding are on, each array an epoch commits is queued in that commit like
-- its zone results. Arrays committed while it was off are not queued afterwards (a year of
-- maps is gigabytes; the site keeps them).
--
-- The outbox's CHECK on kind gains 'core_point_array'. SQLite cannot alter a CHECK: the table
-- is made anew (SQLite's "other kinds of table schema changes"), its entries and its
-- sequence kept, so no seq is ever used twice; the triggers that write it are dropped first
-- and made again as 0020 made them.

ALTER TABLE central_forward ADD COLUMN forward_arrays INTEGER NOT NULL DEFAULT 0
    CHECK (forward_arrays IN (0, 1));

DROP TRIGGER outbox_epoch;
DROP TRIGGER outbox_registration;
DROP TRIGGER outbox_zone_result;
DROP TRIGGER outbox_alarm_event;
DROP TRIGGER outbox_system_event;

CREATE TABLE outbox_new (
    seq     INTEGER PRIMARY KEY AUTOINCREMENT,
    created INTEGER NOT NULL,
    kind    TEXT NOT NULL CHECK (kind IN ('epoch', 'registration', 'zone_result',
                                          'alarm_event', 'system_event', 'core_point_array')),
    payload TEXT NOT NULL CHECK (json_valid(payload))
);
INSERT INTO outbox_new (seq, created, kind, payload)
SELECT seq, created, kind, payload FROM outbox ORDER BY seq;
-- The sequence goes on from the highest seq ever given out (or committed centrally).
DELETE FROM sqlite_sequence WHERE name = 'outbox_new';
INSERT INTO sqlite_sequence (name, seq)
SELECT 'outbox_new', max(s) FROM (
    SELECT seq AS s FROM sqlite_sequence WHERE name = 'outbox'
    UNION ALL SELECT sent_upto FROM central_forward
    UNION ALL SELECT 0);
DROP TABLE outbox;
ALTER TABLE outbox_new RENAME TO outbox;

-- An array's payload: its epoch, quantity, count and the float32 values (little-endian, in
-- core point order) as lower-case hex.
CREATE VIEW outbox_core_point_arrays AS
SELECT a.epoch_id, a.quantity, e.acquired, json_object(
    'sha256', e.sha256, 'acquired', e.acquired, 'quantity', a.quantity, 'count', a.count,
    'data', lower(hex(a.data))) AS payload
FROM core_point_arrays a JOIN epochs e ON e.id = a.epoch_id;

CREATE TRIGGER outbox_core_point_array AFTER INSERT ON core_point_arrays
WHEN (SELECT enabled = 1 AND forward_arrays = 1 FROM central_forward)
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'core_point_array', payload FROM outbox_core_point_arrays
    WHERE epoch_id = NEW.epoch_id AND quantity = NEW.quantity;
END;

-- As 0020 made them.
CREATE TRIGGER outbox_epoch AFTER UPDATE OF status ON epochs
WHEN NEW.status IN ('done', 'rejected', 'failed') AND OLD.status IS NOT NEW.status
 AND (SELECT enabled FROM central_forward) = 1
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'epoch', payload FROM outbox_epochs WHERE epoch_id = NEW.id;
END;

CREATE TRIGGER outbox_registration AFTER INSERT ON registrations
WHEN (SELECT enabled FROM central_forward) = 1
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'registration', payload FROM outbox_registrations
    WHERE epoch_id = NEW.epoch_id;
END;

CREATE TRIGGER outbox_zone_result AFTER INSERT ON zone_results
WHEN (SELECT enabled FROM central_forward) = 1
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'zone_result', payload FROM outbox_zone_results
    WHERE zone_id = NEW.zone_id AND quantity_id = NEW.quantity_id
      AND acquired = NEW.acquired AND epoch_id = NEW.epoch_id;
END;

CREATE TRIGGER outbox_alarm_event AFTER INSERT ON alarm_events
WHEN (SELECT enabled FROM central_forward) = 1
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'alarm_event', payload FROM outbox_alarm_events WHERE id = NEW.id;
END;

CREATE TRIGGER outbox_system_event AFTER INSERT ON system_events
WHEN (SELECT enabled FROM central_forward) = 1
BEGIN
    INSERT INTO outbox (created, kind, payload)
    SELECT unixepoch(), 'system_event', payload FROM outbox_system_events WHERE id = NEW.id;
END;
