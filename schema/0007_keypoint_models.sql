-- 0007_keypoint_models: the keypoint displacement model d(t, z) refitted at each epoch over
-- all epochs so far (docs/keypoints.md, step 7; docs/schema.md, "keypoint_models").
-- (0007 is left to the M3C2 stage's migration.)

-- One fit per epoch and modelled quantity. The coefficients a_pq are those of
-- u^p w^q with u = (t − t_centre)/t_scale, w = (z − z_centre)/z_scale, in the order
-- 00 10 01 20 11 02 30 21 12 03; NULL when the model is undefined (reason given).
CREATE TABLE keypoint_models (
    epoch_id          INTEGER NOT NULL REFERENCES epochs(id),
    quantity          TEXT NOT NULL CHECK (length(quantity) > 0),  -- the modelled d
    variable          TEXT NOT NULL CHECK (length(variable) > 0),  -- what t is: time_h, ...
    defined           INTEGER NOT NULL CHECK (defined IN (0, 1)),
    reason            TEXT NOT NULL DEFAULT '',
    observations      INTEGER NOT NULL CHECK (observations >= 0),
    iterations        INTEGER NOT NULL CHECK (iterations >= 0),
    converged         INTEGER NOT NULL CHECK (converged IN (0, 1)),
    t_centre          REAL,
    t_scale           REAL,
    z_centre          REAL,
    z_scale           REAL,
    a00 REAL, a10 REAL, a01 REAL, a20 REAL, a11 REAL,
    a02 REAL, a30 REAL, a21 REAL, a12 REAL, a03 REAL,
    sum_abs_residuals REAL,
    residual_scale    REAL,                                        -- 1.4826 · MAD
    PRIMARY KEY (epoch_id, quantity)
) WITHOUT ROWID;

-- The residuals d − model of the fitting epoch's own segments (the older epochs' residuals
-- change with every refit and are not kept: that would grow with the square of the epochs).
CREATE TABLE keypoint_model_residuals (
    epoch_id INTEGER NOT NULL,
    quantity TEXT NOT NULL,
    zone     TEXT NOT NULL CHECK (length(zone) > 0),
    t        REAL NOT NULL,
    z        REAL NOT NULL,
    d        REAL NOT NULL,
    residual REAL NOT NULL,
    PRIMARY KEY (epoch_id, quantity, zone),
    FOREIGN KEY (epoch_id, quantity) REFERENCES keypoint_models (epoch_id, quantity)
) WITHOUT ROWID;
