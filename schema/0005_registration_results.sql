-- 0005_registration_results: what the registration stage measured per epoch (docs/schema.md,
-- "registrations", "target_observations", "target_exclusions", "registration_zone_sigmas").

-- The test's verdict and the parameters of the transformation epoch -> reference frame
-- (X_ref = R·x + t, R = R_z(κ)·R_y(φ)·R_x(ω)), their σ, the quaternion and the variance factor.
-- NULL where no transformation was estimated (too few targets).
ALTER TABLE registrations ADD COLUMN status TEXT NOT NULL DEFAULT '';
ALTER TABLE registrations ADD COLUMN reason TEXT NOT NULL DEFAULT '';
ALTER TABLE registrations ADD COLUMN omega_rad REAL;
ALTER TABLE registrations ADD COLUMN phi_rad REAL;
ALTER TABLE registrations ADD COLUMN kappa_rad REAL;
ALTER TABLE registrations ADD COLUMN tx_m REAL;
ALTER TABLE registrations ADD COLUMN ty_m REAL;
ALTER TABLE registrations ADD COLUMN tz_m REAL;
ALTER TABLE registrations ADD COLUMN qw REAL;
ALTER TABLE registrations ADD COLUMN qx REAL;
ALTER TABLE registrations ADD COLUMN qy REAL;
ALTER TABLE registrations ADD COLUMN qz REAL;
ALTER TABLE registrations ADD COLUMN sigma_omega_rad REAL;
ALTER TABLE registrations ADD COLUMN sigma_phi_rad REAL;
ALTER TABLE registrations ADD COLUMN sigma_kappa_rad REAL;
ALTER TABLE registrations ADD COLUMN sigma_tx_m REAL;
ALTER TABLE registrations ADD COLUMN sigma_ty_m REAL;
ALTER TABLE registrations ADD COLUMN sigma_tz_m REAL;
ALTER TABLE registrations ADD COLUMN variance_factor REAL;
ALTER TABLE registrations ADD COLUMN redundancy INTEGER;

-- Per target: found / not_found / bad_fit / excluded and why; its use in the adjustment
-- (used, not_usable, excluded_outlier, suspect), the σ of its centre, its test statistic and
-- minimal detectable bias.
ALTER TABLE target_observations ADD COLUMN status TEXT NOT NULL DEFAULT '';
ALTER TABLE target_observations ADD COLUMN reason TEXT NOT NULL DEFAULT '';
ALTER TABLE target_observations ADD COLUMN use TEXT NOT NULL DEFAULT '';
ALTER TABLE target_observations ADD COLUMN sigma_x REAL;
ALTER TABLE target_observations ADD COLUMN sigma_y REAL;
ALTER TABLE target_observations ADD COLUMN sigma_z REAL;
ALTER TABLE target_observations ADD COLUMN statistic REAL;
ALTER TABLE target_observations ADD COLUMN critical REAL;
ALTER TABLE target_observations ADD COLUMN minimal_detectable_bias_m REAL;

-- A target excluded as moved stays excluded until an operator re-surveys it (resurveyed set).
CREATE TABLE target_exclusions (
    target       TEXT NOT NULL CHECK (length(target) > 0),
    epoch_id     INTEGER NOT NULL REFERENCES epochs(id),  -- the epoch that excluded it
    resurveyed   INTEGER,                                 -- unix time of the re-survey
    PRIMARY KEY (target, epoch_id)
) WITHOUT ROWID;

-- The registration's σ propagated to each zone (largest 3-D σ over the zone's box), for M3C2's
-- level of detection.
CREATE TABLE registration_zone_sigmas (
    epoch_id       INTEGER NOT NULL REFERENCES epochs(id),
    zone           TEXT NOT NULL,
    max_sigma_3d_m REAL NOT NULL CHECK (max_sigma_3d_m >= 0),
    PRIMARY KEY (epoch_id, zone)
) WITHOUT ROWID;
