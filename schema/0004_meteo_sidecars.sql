-- 0004_meteo_sidecars: the meteo sidecar files found beside the scans (<stem>.meteo.csv),
-- what became of each, and for the epoch that used one the weather station's row nearest
-- its acquisition time (docs/schema.md, "meteo_sidecars").

CREATE TABLE meteo_sidecars (
    id                    INTEGER PRIMARY KEY,
    epoch_id              INTEGER REFERENCES epochs(id),  -- NULL only for an orphan
    outcome               TEXT NOT NULL
                          CHECK (outcome IN ('used', 'rejected', 'unused', 'orphan')),
    file_name             TEXT NOT NULL CHECK (length(file_name) > 0),
    sha256                TEXT NOT NULL CHECK (length(sha256) = 64),
    path                  TEXT,  -- where the file was moved; NULL: left where it was found
    reason                TEXT NOT NULL DEFAULT '',
    recorded              INTEGER NOT NULL,
    time                  INTEGER,  -- the row used (outcome 'used' only) ...
    line                  INTEGER CHECK (line >= 1),
    air_temperature_c     REAL,
    pressure_hpa          REAL,
    relative_humidity_pct REAL,
    CHECK ((outcome = 'orphan') = (epoch_id IS NULL)),
    CHECK ((outcome = 'used') = (time IS NOT NULL AND line IS NOT NULL AND
                                 air_temperature_c IS NOT NULL AND pressure_hpa IS NOT NULL AND
                                 relative_humidity_pct IS NOT NULL))
);
-- The sidecar an epoch was processed with (used or rejected) is one per epoch.
CREATE UNIQUE INDEX meteo_sidecars_processed ON meteo_sidecars (epoch_id)
    WHERE outcome IN ('used', 'rejected');
CREATE INDEX meteo_sidecars_by_epoch ON meteo_sidecars (epoch_id);
CREATE INDEX meteo_sidecars_by_sha256 ON meteo_sidecars (sha256);
