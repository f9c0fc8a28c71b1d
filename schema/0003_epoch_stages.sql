-- 0003_epoch_stages: each pipeline stage that ran for an epoch, in order, with its time and,
-- what it measured in a few words and, for the stage that rejected the epoch, why (docs/schema.md, "epoch_stages").

CREATE TABLE epoch_stages (
    epoch_id INTEGER NOT NULL REFERENCES epochs(id),
    position INTEGER NOT NULL CHECK (position >= 0),
    stage    TEXT NOT NULL CHECK (length(stage) > 0),
    ms       REAL NOT NULL CHECK (ms >= 0),
    rejected TEXT NOT NULL DEFAULT '',
    note     TEXT NOT NULL DEFAULT '',  -- what the stage measured, in a few words
    PRIMARY KEY (epoch_id, position)
);
