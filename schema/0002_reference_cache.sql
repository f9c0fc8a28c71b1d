-- 0002_reference_cache: what each pipeline stage derived once from the reference epoch
-- (docs/schema.md, "reference_cache"). One entry per stage; a new entry replaces the old.

CREATE TABLE reference_cache (
    stage            TEXT PRIMARY KEY CHECK (length(stage) > 0),
    reference_sha256 TEXT NOT NULL CHECK (length(reference_sha256) = 64),
    params_hash      TEXT NOT NULL,
    format_version   INTEGER NOT NULL,
    created          INTEGER NOT NULL,
    payload          BLOB NOT NULL,
    payload_sha256   TEXT NOT NULL CHECK (length(payload_sha256) = 64)
);
