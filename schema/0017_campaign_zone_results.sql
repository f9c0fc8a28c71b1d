-- 0017_campaign_zone_results: a campaign's values in the station's zones, when
-- [campaign] zone_series is set (docs/campaigns.md, "Zone series"). Under quantities of their
-- own (campaign_*), never under a station quantity, and apart from zone_results: a campaign is
-- not an epoch. The series reader takes a campaign quantity's points from here, by the
-- campaign's acquisition time (kept on the row, as zone_results keeps the epoch's).
CREATE TABLE campaign_zone_results (
    zone_id     INTEGER NOT NULL REFERENCES zones(id),
    quantity_id INTEGER NOT NULL REFERENCES quantities(id),
    acquired    INTEGER NOT NULL,
    campaign_id INTEGER NOT NULL REFERENCES campaigns(id) ON DELETE CASCADE,
    value       REAL NOT NULL,
    uncertainty REAL,
    n           INTEGER NOT NULL CHECK (n >= 0),
    significant INTEGER NOT NULL CHECK (significant IN (0, 1)),
    PRIMARY KEY (zone_id, quantity_id, acquired, campaign_id)
) WITHOUT ROWID;
