-- 0015_campaigns: campaign epochs (docs/campaigns.md, "Campaign epochs"). A cloud of an
-- [[instrument]] other than the station (a personal or mobile laser scanner) compared with
-- the station's reference epoch segment by segment. Kept apart from `epochs`: a campaign is
-- not in the station's zone series, its registrations or its alarms. The sha256 of the file's
-- bytes is its identity, as an epoch's is.
CREATE TABLE campaigns (
    id                  INTEGER PRIMARY KEY,
    sha256              TEXT NOT NULL UNIQUE CHECK (length(sha256) = 64),
    instrument          TEXT NOT NULL,
    kind                TEXT NOT NULL CHECK (kind IN ('tls', 'pls', 'mls')),
    acquired            INTEGER NOT NULL,   -- UTC seconds
    added               INTEGER NOT NULL,   -- UTC seconds, when it was compared and stored
    file_path           TEXT NOT NULL,      -- where it was read (then archived, if moved)
    file_size           INTEGER NOT NULL CHECK (file_size >= 0),
    reference_epoch_id  INTEGER NOT NULL REFERENCES epochs(id),
    points              INTEGER NOT NULL CHECK (points >= 0),
    ground_points       INTEGER NOT NULL CHECK (ground_points >= 0),
    -- The whole cloud's registration on the reference: its parameters about the cloud's
    -- centroid (rotation vector, rad; translation, m), pairs and RMSE.
    global_rx_rad REAL NOT NULL, global_ry_rad REAL NOT NULL, global_rz_rad REAL NOT NULL,
    global_tx_m   REAL NOT NULL, global_ty_m   REAL NOT NULL, global_tz_m   REAL NOT NULL,
    global_pairs        INTEGER NOT NULL,
    global_rmse_m       REAL NOT NULL,
    segments            INTEGER NOT NULL,
    registered_segments INTEGER NOT NULL,
    -- Whether the segments moved as one (NULL: not testable).
    test_statistic      REAL,
    test_dof            INTEGER,
    test_p              REAL,
    segments_differ     INTEGER CHECK (segments_differ IN (0, 1)),
    alpha               REAL NOT NULL,
    c2c_mean_m          REAL,
    c2c_sigma_m         REAL,
    c2c_median_m        REAL,
    c2c_p95_m           REAL,
    c2c_missing         INTEGER NOT NULL,
    parameters_json     TEXT NOT NULL,      -- the comparison's effective parameters
    seconds             REAL NOT NULL       -- wall time of the comparison
);
CREATE INDEX campaigns_by_time ON campaigns (acquired);

-- One row per segment of a campaign, as `tlsmon campaign compare` writes segments.csv: a
-- parameter and its σ are NULL where the segment's surfaces do not observe it.
CREATE TABLE campaign_segments (
    campaign_id    INTEGER NOT NULL REFERENCES campaigns(id) ON DELETE CASCADE,
    segment        INTEGER NOT NULL,
    class          TEXT NOT NULL,
    cluster        INTEGER NOT NULL,
    points         INTEGER NOT NULL,
    voxels         INTEGER NOT NULL,
    outcome        TEXT NOT NULL,
    -- The reference's segment (the reference segmented as the campaign) most of its points lie
    -- on after the global registration, NULL below the overlap asked; the share that does.
    reference_segment INTEGER,
    reference_overlap REAL,
    pairs          INTEGER NOT NULL,
    rank           INTEGER NOT NULL,
    centroid_x_m REAL, centroid_y_m REAL, centroid_z_m REAL,
    tx_m REAL, ty_m REAL, tz_m REAL, sigma_tx_m REAL, sigma_ty_m REAL, sigma_tz_m REAL,
    rx_rad REAL, ry_rad REAL, rz_rad REAL, sigma_rx_rad REAL, sigma_ry_rad REAL, sigma_rz_rad REAL,
    cut_fraction   REAL,
    cut_bias_m     REAL,
    rmse_m         REAL,
    iterations     INTEGER NOT NULL,
    converged      INTEGER NOT NULL CHECK (converged IN (0, 1)),
    test_statistic REAL,
    test_dof       INTEGER,
    test_p         REAL,
    c2c_mean_m REAL, c2c_sigma_m REAL, c2c_median_m REAL, c2c_p95_m REAL, c2c_max_m REAL,
    PRIMARY KEY (campaign_id, segment)
);
