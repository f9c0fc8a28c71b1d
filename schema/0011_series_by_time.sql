-- 0011_series_by_time: the time series keyed by acquisition time (docs/schema.md,
-- "zone_results"). Each row carries its epoch's acquisition time, and the key becomes
-- (zone_id, quantity_id, acquired, epoch_id): one zone quantity over any window is one range
-- scan in time order, and its newest value one seek, without visiting the epochs table
-- (a year of 15-minute epochs: 35,040 rows per quantity). No index is added, so the bytes per
-- row grow only by the time itself. acquired is a function of epoch_id, so the key stays
-- unique per (zone_id, quantity_id, epoch_id).
CREATE TABLE zone_results_by_time (
    zone_id     INTEGER NOT NULL REFERENCES zones(id),
    quantity_id INTEGER NOT NULL REFERENCES quantities(id),
    acquired    INTEGER NOT NULL,
    epoch_id    INTEGER NOT NULL REFERENCES epochs(id),
    value       REAL NOT NULL,
    uncertainty REAL,
    n           INTEGER NOT NULL CHECK (n >= 0),
    significant INTEGER NOT NULL CHECK (significant IN (0, 1)),
    PRIMARY KEY (zone_id, quantity_id, acquired, epoch_id)
) WITHOUT ROWID;

INSERT INTO zone_results_by_time
    (zone_id, quantity_id, acquired, epoch_id, value, uncertainty, n, significant)
SELECT r.zone_id, r.quantity_id, e.acquired, r.epoch_id, r.value, r.uncertainty, r.n,
       r.significant
FROM zone_results r JOIN epochs e ON e.id = r.epoch_id;

DROP TABLE zone_results;
ALTER TABLE zone_results_by_time RENAME TO zone_results;
