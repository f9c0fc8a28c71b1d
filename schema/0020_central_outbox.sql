-- 0020_central_outbox: what the site forwards to a central PostgreSQL (docs/central.md),
-- written by triggers in the same transaction as the rows it copies, so an epoch's commit and
-- its outbox entries are one: both stored or neither. The triggers write only while
-- central_forward.enabled = 1 (the daemon sets it from [central] enabled), so a site without
-- a central database keeps no outbox. Switched on, the whole history is queued once (the
-- central writes ignore rows they already hold), so rows committed while it was off arrive
-- too.
--
-- Each entry's payload is a JSON object. Its reals are written with 17 significant digits
-- (printf's '%!.17g'), which read back to the stored double; json_object's own rendering
-- keeps 15. Rows are named by their epoch's sha256, zones and rules by name: the site's ids
-- mean nothing centrally.

CREATE TABLE outbox (
    seq     INTEGER PRIMARY KEY AUTOINCREMENT,  -- the forwarding order; never reused
    created INTEGER NOT NULL,                   -- when the entry was written (UTC seconds)
    kind    TEXT NOT NULL CHECK (kind IN ('epoch', 'registration', 'zone_result',
                                          'alarm_event', 'system_event')),
    payload TEXT NOT NULL CHECK (json_valid(payload))
);

-- The forwarder's state: one row. sent_upto is the highest seq the central database has
-- committed; entries up to it are deleted in the same transaction that advances it.
CREATE TABLE central_forward (
    singleton      INTEGER PRIMARY KEY CHECK (singleton = 1),
    -- This database's identity centrally (tlsmon.site_cursors.source): a rebuilt or
    -- replaced site database starts its own count there.
    database_id    TEXT NOT NULL DEFAULT (lower(hex(randomblob(16)))),
    enabled        INTEGER NOT NULL DEFAULT 0 CHECK (enabled IN (0, 1)),
    sent_upto      INTEGER NOT NULL DEFAULT 0,
    sent_at        INTEGER,
    last_error     TEXT NOT NULL DEFAULT '',
    last_error_at  INTEGER,
    failing_since  INTEGER
);
INSERT INTO central_forward (singleton) VALUES (1);

-- One payload per forwarded row, as a view: the triggers select the new row's payload from
-- it, and enabling forwarding on a site with history selects every row's (storage/
-- central_outbox.cpp), so both write the same JSON.
CREATE VIEW outbox_epochs AS
SELECT e.id AS epoch_id, e.acquired, json_object(
    'sha256', e.sha256, 'acquired', e.acquired, 'status', e.status, 'reason', e.reason,
    'file', e.file_path, 'file_size', e.file_size, 'points', e.point_count,
    'total_ms', CASE WHEN e.total_ms IS NULL THEN NULL ELSE json(printf('%!.17g', e.total_ms)) END)
    AS payload
FROM epochs e WHERE e.status IN ('done', 'rejected', 'failed');

CREATE VIEW outbox_registrations AS
SELECT r.epoch_id, e.acquired, json_object(
    'sha256', e.sha256, 'acquired', e.acquired, 'method', r.method, 'accepted', r.accepted,
    'status', r.status, 'reason', r.reason, 'target_count', r.target_count,
    'rms_m', json(printf('%!.17g', r.rms_m)),
    'max_residual_m', json(printf('%!.17g', r.max_residual_m)),
    'sigma0', CASE WHEN r.sigma0 IS NULL THEN NULL ELSE json(printf('%!.17g', r.sigma0)) END,
    'parameters', CASE WHEN r.omega_rad IS NULL THEN NULL ELSE json_array(
        json(printf('%!.17g', r.omega_rad)), json(printf('%!.17g', r.phi_rad)),
        json(printf('%!.17g', r.kappa_rad)), json(printf('%!.17g', r.tx_m)),
        json(printf('%!.17g', r.ty_m)), json(printf('%!.17g', r.tz_m))) END,
    'sigmas', CASE WHEN r.sigma_omega_rad IS NULL THEN NULL ELSE json_array(
        json(printf('%!.17g', r.sigma_omega_rad)), json(printf('%!.17g', r.sigma_phi_rad)),
        json(printf('%!.17g', r.sigma_kappa_rad)), json(printf('%!.17g', r.sigma_tx_m)),
        json(printf('%!.17g', r.sigma_ty_m)), json(printf('%!.17g', r.sigma_tz_m))) END,
    'variance_factor', CASE WHEN r.variance_factor IS NULL THEN NULL
                            ELSE json(printf('%!.17g', r.variance_factor)) END,
    'redundancy', r.redundancy) AS payload
FROM registrations r JOIN epochs e ON e.id = r.epoch_id;

CREATE VIEW outbox_zone_results AS
SELECT r.zone_id, r.quantity_id, r.acquired, r.epoch_id, json_object(
    'sha256', (SELECT sha256 FROM epochs WHERE id = r.epoch_id), 'acquired', r.acquired,
    'zone', (SELECT name FROM zones WHERE id = r.zone_id),
    'quantity', (SELECT name FROM quantities WHERE id = r.quantity_id),
    'value', json(printf('%!.17g', r.value)),
    'uncertainty', CASE WHEN r.uncertainty IS NULL THEN NULL
                        ELSE json(printf('%!.17g', r.uncertainty)) END,
    'n', r.n, 'significant', r.significant) AS payload
FROM zone_results r;

CREATE VIEW outbox_alarm_events AS
SELECT a.id, a.time, json_object(
    'id', a.id, 'time', a.time, 'rule', r.name,
    'zone', (SELECT name FROM zones WHERE id = r.zone_id), 'quantity', r.quantity,
    'kind', a.kind, 'level', a.level,
    'value', CASE WHEN a.value IS NULL THEN NULL ELSE json(printf('%!.17g', a.value)) END,
    'sha256', (SELECT sha256 FROM epochs WHERE id = a.epoch_id),
    'message', a.message, 'actor', a.actor) AS payload
FROM alarm_events a JOIN alarm_rules r ON r.id = a.rule_id;

CREATE VIEW outbox_system_events AS
SELECT s.id, s.time, json_object(
    'id', s.id, 'time', s.time, 'level', s.level, 'kind', s.kind, 'message', s.message,
    'sha256', (SELECT sha256 FROM epochs WHERE id = s.epoch_id)) AS payload
FROM system_events s;

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
