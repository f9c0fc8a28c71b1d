-- 0016_campaign_frames_and_points: a campaign's own frame and its points (docs/campaigns.md,
-- "The campaign's frame" and "Stored points").
-- How the cloud's own frame (a SLAM cloud's) was brought near the reference before the global
-- registration, and the whole transformation from its frame onto the reference's. Campaigns
-- stored before keep 'none' and no frame.
ALTER TABLE campaigns ADD COLUMN coarse TEXT NOT NULL DEFAULT 'none'
    CHECK (coarse IN ('none', 'planes'));
ALTER TABLE campaigns ADD COLUMN coarse_planes INTEGER CHECK (coarse_planes >= 0);
ALTER TABLE campaigns ADD COLUMN frame BLOB
    CHECK (frame IS NULL OR length(frame) = 128);  -- 16 float64 LE, row-major: x_ref = M·x

-- The registered cloud thinned to one point per `spacing_m` voxel ([campaign] store_spacing).
CREATE TABLE campaign_points (
    campaign_id INTEGER PRIMARY KEY REFERENCES campaigns(id) ON DELETE CASCADE,
    origin_x_m  REAL NOT NULL,   -- the coordinates' arrays are offsets from it
    origin_y_m  REAL NOT NULL,
    origin_z_m  REAL NOT NULL,
    spacing_m   REAL NOT NULL CHECK (spacing_m >= 0),
    count       INTEGER NOT NULL CHECK (count >= 0)
);
-- Its per-point values, float32 little-endian in point order: x_m, y_m, z_m, segment,
-- c2c_dx_m, c2c_dy_m, c2c_dz_m.
CREATE TABLE campaign_point_arrays (
    campaign_id INTEGER NOT NULL REFERENCES campaign_points(campaign_id) ON DELETE CASCADE,
    quantity    TEXT NOT NULL,
    count       INTEGER NOT NULL CHECK (count >= 0),
    data        BLOB NOT NULL CHECK (length(data) = 4 * count),
    PRIMARY KEY (campaign_id, quantity)
);
