-- 0018_retention: epochs an operator pinned (`tlsmon epochs pin N`): the retention policy
-- never thins their per-core-point maps (docs/retention.md). Pinning and unpinning are
-- recorded as system events naming who did it.
CREATE TABLE epoch_pins (
    epoch_id  INTEGER PRIMARY KEY REFERENCES epochs(id),
    pinned_at INTEGER NOT NULL,
    pinned_by TEXT NOT NULL,
    note      TEXT NOT NULL DEFAULT ''
);


-- Epochs whose per-core-point maps the retention policy deleted, when, and how many bytes:
-- a map asked for later is then "thinned on ...", not "never made".
CREATE TABLE thinned_maps (
    epoch_id   INTEGER PRIMARY KEY REFERENCES epochs(id),
    thinned_at INTEGER NOT NULL,
    bytes      INTEGER NOT NULL CHECK (bytes >= 0)
);
