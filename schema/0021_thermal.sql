-- 0021_thermal: the thermal compensation's models and how each epoch was compensated
-- (docs/thermal.md; docs/schema.md, "thermal_models", "thermal_compensations"). The values
-- themselves are zone quantities (<name>_thermal_m, <name>_compensated_m, ...) in zone_results.

-- One fit of a zone quantity's thermal model; versions count from 1, the newest is in use.
CREATE TABLE thermal_models (
    zone                 TEXT NOT NULL CHECK (length(zone) > 0),
    quantity             TEXT NOT NULL CHECK (length(quantity) > 0),
    version              INTEGER NOT NULL CHECK (version >= 1),
    epoch_id             INTEGER NOT NULL REFERENCES epochs(id),  -- whose commit fitted it
    training_from        INTEGER NOT NULL,  -- acquisition of the first and last epoch used
    training_to          INTEGER NOT NULL CHECK (training_to >= training_from),
    observations         INTEGER NOT NULL CHECK (observations > 0),
    excluded             INTEGER NOT NULL CHECK (excluded >= 0),
    surface_lag_h        REAL NOT NULL CHECK (surface_lag_h >= 0),
    section_lag_h        REAL NOT NULL CHECK (section_lag_h >= 0),
    terms                TEXT NOT NULL CHECK (json_valid(terms)),  -- JSON array of names
    coefficients         BLOB NOT NULL,  -- float64 little-endian, one per term
    covariance           BLOB NOT NULL,  -- float64 little-endian, terms × terms, row-major
    trend_origin         REAL NOT NULL,  -- UTC seconds where a trend term is zero
    residual_sigma       REAL NOT NULL CHECK (residual_sigma >= 0),
    prediction_sigma     REAL NOT NULL CHECK (prediction_sigma >= 0),
    day_mean_sigma       REAL NOT NULL CHECK (day_mean_sigma >= 0),
    day_spread_max       REAL NOT NULL CHECK (day_spread_max >= 0),
    cv_days              INTEGER NOT NULL CHECK (cv_days >= 0),
    lag1_autocorrelation REAL NOT NULL,
    measurement_variance REAL NOT NULL CHECK (measurement_variance >= 0),
    explained_share      REAL NOT NULL,
    amplitude_min_c      REAL NOT NULL,  -- the daily amplitudes of the training epochs
    amplitude_max_c      REAL NOT NULL,
    iterations           INTEGER NOT NULL CHECK (iterations >= 0),
    converged            INTEGER NOT NULL CHECK (converged IN (0, 1)),
    PRIMARY KEY (zone, quantity, version),
    CHECK (length(coefficients) = 8 * json_array_length(terms)),
    CHECK (length(covariance) = 8 * json_array_length(terms) * json_array_length(terms))
) WITHOUT ROWID;

-- Per epoch and modelled zone quantity: how it was compensated, or why not, and the model
-- health of the trailing window.
CREATE TABLE thermal_compensations (
    epoch_id          INTEGER NOT NULL REFERENCES epochs(id),
    zone              TEXT NOT NULL CHECK (length(zone) > 0),
    quantity          TEXT NOT NULL CHECK (length(quantity) > 0),
    quality           TEXT NOT NULL
                      CHECK (quality IN ('compensated', 'extrapolated', 'no_meteo', 'no_model')),
    model_version     INTEGER,  -- NULL: no model
    reason            TEXT NOT NULL DEFAULT '',
    air_age_h         REAL,  -- hours since the newest air reading
    daily_amplitude_c REAL,
    drift_z           REAL,  -- NULL: the window was not judged
    spread_ratio      REAL,
    drifted           INTEGER NOT NULL DEFAULT 0 CHECK (drifted IN (0, 1)),
    spread_grew       INTEGER NOT NULL DEFAULT 0 CHECK (spread_grew IN (0, 1)),
    PRIMARY KEY (epoch_id, zone, quantity),
    FOREIGN KEY (zone, quantity, model_version)
        REFERENCES thermal_models (zone, quantity, version),
    CHECK ((quality IN ('compensated', 'extrapolated')) = (model_version IS NOT NULL))
) WITHOUT ROWID;
CREATE INDEX thermal_compensations_by_zone ON thermal_compensations (zone, quantity, epoch_id);
