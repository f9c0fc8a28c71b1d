-- 0014_notifications: the notification outbox (docs/notifications.md). The notifier turns
-- each new alarm event into one row per channel its routes name, in the same transaction
-- that advances its cursor over alarm_events, so an event is routed exactly once even
-- across a crash; a row is then sent (or retried with back-off, or given up) and its
-- outcome kept. The daily summary is a row of its own; summary_day remembers the last one.
CREATE TABLE notify_cursor (
    id             INTEGER PRIMARY KEY CHECK (id = 1),
    alarm_event_id INTEGER NOT NULL,   -- the last alarm event routed
    summary_day    TEXT NOT NULL DEFAULT ''  -- local date of the last daily summary
);
-- Events before this migration are history, not news.
INSERT INTO notify_cursor (id, alarm_event_id)
    SELECT 1, COALESCE(MAX(id), 0) FROM alarm_events;

CREATE TABLE notifications (
    id             INTEGER PRIMARY KEY,
    channel        TEXT NOT NULL,         -- a [[notify.channel]] name
    created        INTEGER NOT NULL,      -- UTC seconds
    first_due      INTEGER NOT NULL,      -- when it was to go first (after quiet hours)
    due            INTEGER NOT NULL,      -- not sent before (quiet hours, back-off)
    status         TEXT NOT NULL CHECK (status IN ('pending', 'sent', 'failed', 'suppressed')),
    attempts       INTEGER NOT NULL DEFAULT 0,
    dedup_key      TEXT NOT NULL,         -- rule/event/level, or summary/day
    alarm_event_id INTEGER REFERENCES alarm_events(id),
    subject        TEXT NOT NULL,
    body           TEXT NOT NULL,         -- the JSON document of docs/notifications.md
    last_error     TEXT NOT NULL DEFAULT '',
    finished       INTEGER                -- when sent, given up or suppressed
);
CREATE INDEX notifications_pending ON notifications (status, due) WHERE status = 'pending';
CREATE INDEX notifications_dedup ON notifications (channel, dedup_key, created);
