-- 0001_initial: the epoch database of tlsmon (docs/schema.md describes every column).
-- Times are UTC seconds since 1970-01-01; lengths in metres unless a name says otherwise.

CREATE TABLE stations (
    id       INTEGER PRIMARY KEY,
    name     TEXT NOT NULL UNIQUE,
    x        REAL NOT NULL,
    y        REAL NOT NULL,
    z        REAL NOT NULL
);

-- One row per distinct scan file (identified by the sha256 of its bytes).
CREATE TABLE epochs (
    id           INTEGER PRIMARY KEY,
    sha256       TEXT NOT NULL UNIQUE CHECK (length(sha256) = 64),
    acquired     INTEGER NOT NULL,
    discovered   INTEGER NOT NULL,
    updated      INTEGER NOT NULL,
    file_path    TEXT NOT NULL,
    file_size    INTEGER NOT NULL CHECK (file_size >= 0),
    station_id   INTEGER REFERENCES stations(id),
    status       TEXT NOT NULL DEFAULT 'pending'
                 CHECK (status IN ('pending', 'processing', 'done', 'failed', 'rejected')),
    reason       TEXT NOT NULL DEFAULT '',
    point_count  INTEGER CHECK (point_count >= 0),
    read_ms      REAL,
    register_ms  REAL,
    analyse_ms   REAL,
    total_ms     REAL,
    archive_path TEXT
);
CREATE INDEX epochs_by_acquired ON epochs (acquired, id);
CREATE INDEX epochs_by_status ON epochs (status, acquired, id);

-- Epoch 0 of the analyses: set once.
CREATE TABLE reference_epoch (
    singleton INTEGER PRIMARY KEY CHECK (singleton = 1),
    epoch_id  INTEGER NOT NULL REFERENCES epochs(id),
    set_at    INTEGER NOT NULL
);

CREATE TABLE registrations (
    epoch_id       INTEGER PRIMARY KEY REFERENCES epochs(id),
    method         TEXT NOT NULL,
    transform      BLOB NOT NULL CHECK (length(transform) = 128),  -- 16 float64 LE, row-major
    target_count   INTEGER NOT NULL CHECK (target_count >= 0),
    rms_m          REAL NOT NULL,
    max_residual_m REAL NOT NULL,
    sigma0         REAL,
    accepted       INTEGER NOT NULL CHECK (accepted IN (0, 1)),
    quality_json   TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(quality_json))
);

CREATE TABLE target_observations (
    epoch_id   INTEGER NOT NULL REFERENCES epochs(id),
    target     TEXT NOT NULL,
    kind       TEXT NOT NULL,
    measured_x REAL NOT NULL,
    measured_y REAL NOT NULL,
    measured_z REAL NOT NULL,
    residual_x REAL NOT NULL,
    residual_y REAL NOT NULL,
    residual_z REAL NOT NULL,
    stable     INTEGER NOT NULL CHECK (stable IN (0, 1)),
    used       INTEGER NOT NULL CHECK (used IN (0, 1)),
    PRIMARY KEY (epoch_id, target)
) WITHOUT ROWID;

CREATE TABLE zones (
    id         INTEGER PRIMARY KEY,
    name       TEXT NOT NULL UNIQUE,
    definition TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(definition))
);

-- Names of the quantities of the time series ("m3c2_mean_m"), stored once.
CREATE TABLE quantities (
    id   INTEGER PRIMARY KEY,
    name TEXT NOT NULL UNIQUE
);

-- The time series: one value per (zone, quantity, epoch). The key order serves the series
-- query (one zone and quantity over a time range) with a single range scan. No index by
-- epoch: epochs are never deleted, and it would cost a third of the bytes per epoch.
CREATE TABLE zone_results (
    zone_id     INTEGER NOT NULL REFERENCES zones(id),
    quantity_id INTEGER NOT NULL REFERENCES quantities(id),
    epoch_id    INTEGER NOT NULL REFERENCES epochs(id),
    value       REAL NOT NULL,
    uncertainty REAL,
    n           INTEGER NOT NULL CHECK (n >= 0),
    significant INTEGER NOT NULL CHECK (significant IN (0, 1)),
    PRIMARY KEY (zone_id, quantity_id, epoch_id)
) WITHOUT ROWID;

-- Per-core-point values of one epoch, float32 little-endian in core point order.
CREATE TABLE core_point_arrays (
    epoch_id INTEGER NOT NULL REFERENCES epochs(id),
    quantity TEXT NOT NULL,
    count    INTEGER NOT NULL CHECK (count >= 0),
    data     BLOB NOT NULL CHECK (length(data) = 4 * count),
    PRIMARY KEY (epoch_id, quantity)
);

CREATE TABLE alarm_rules (
    id         INTEGER PRIMARY KEY,
    name       TEXT NOT NULL UNIQUE,
    zone_id    INTEGER NOT NULL REFERENCES zones(id),
    quantity   TEXT NOT NULL,
    definition TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(definition)),
    enabled    INTEGER NOT NULL DEFAULT 1 CHECK (enabled IN (0, 1))
);

CREATE TABLE alarm_states (
    rule_id  INTEGER PRIMARY KEY REFERENCES alarm_rules(id),
    state    TEXT NOT NULL,
    level    TEXT NOT NULL DEFAULT '',
    since    INTEGER NOT NULL,
    value    REAL,
    epoch_id INTEGER REFERENCES epochs(id)
);

CREATE TABLE alarm_events (
    id       INTEGER PRIMARY KEY,
    time     INTEGER NOT NULL,
    rule_id  INTEGER NOT NULL REFERENCES alarm_rules(id),
    kind     TEXT NOT NULL,
    level    TEXT NOT NULL DEFAULT '',
    value    REAL,
    epoch_id INTEGER REFERENCES epochs(id),
    message  TEXT NOT NULL DEFAULT ''
);
CREATE INDEX alarm_events_by_time ON alarm_events (time);

CREATE TABLE system_events (
    id       INTEGER PRIMARY KEY,
    time     INTEGER NOT NULL,
    level    TEXT NOT NULL CHECK (level IN ('debug', 'info', 'warning', 'error')),
    kind     TEXT NOT NULL,
    message  TEXT NOT NULL DEFAULT '',
    epoch_id INTEGER REFERENCES epochs(id)
);
CREATE INDEX system_events_by_time ON system_events (time);
