-- 0009_plane_observations: the reference's planes matched in an epoch by the registration on
-- planes (docs/schema.md, "plane_observations"; docs/registration.md, "Registration on planes
-- and the congruence test"). Each plane's change under the epoch's accepted transformation:
-- the tilt of its normal towards the reference plane's long axis u and towards v = n × u,
-- the shift of its centroid along n, their σ (a-priori, σ0 = 1), and its test statistic
-- T = wᵀ·Q⁻¹·w against χ²(3, 1 − α). `role`: `datum` (in the adjustment), `moved` (left
-- out by the congruence test), `monitored` (inside a zone: never in the datum).
CREATE TABLE plane_observations (
    epoch_id         INTEGER NOT NULL REFERENCES epochs(id),
    plane            INTEGER NOT NULL CHECK (plane >= 0),  -- the reference plane's index
    zone             TEXT,                                 -- NULL outside every zone
    role             TEXT NOT NULL CHECK (role IN ('datum', 'moved', 'monitored')),
    normal_x         REAL NOT NULL,  -- the reference plane, reference frame
    normal_y         REAL NOT NULL,
    normal_z         REAL NOT NULL,
    centroid_x       REAL NOT NULL,
    centroid_y       REAL NOT NULL,
    centroid_z       REAL NOT NULL,
    reference_points INTEGER NOT NULL,
    epoch_points     INTEGER NOT NULL,
    tilt_u_rad       REAL NOT NULL,
    tilt_v_rad       REAL NOT NULL,
    shift_m          REAL NOT NULL,
    sigma_tilt_u_rad REAL NOT NULL,
    sigma_tilt_v_rad REAL NOT NULL,
    sigma_shift_m    REAL NOT NULL,
    statistic        REAL NOT NULL,
    critical         REAL NOT NULL,
    significant      INTEGER NOT NULL CHECK (significant IN (0, 1)),
    PRIMARY KEY (epoch_id, plane)
) WITHOUT ROWID;
