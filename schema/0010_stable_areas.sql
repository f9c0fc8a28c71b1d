-- 0010_stable_areas: the registration on stable areas (docs/schema.md, "stable_area_masks";
-- docs/registration.md, "Registration on stable areas"). The reference's supervoxels once per
-- reference and segmentation (their parameters): centroid and normal in the reference frame,
-- voxel count and roughness (RMS distance of the voxels from their plane). Each epoch's mask
-- compactly, in the supervoxels' order: one state byte each (0 stable, 1 unstable, 2 unknown,
-- 3 not planar), the change along the normal and its LoD as little-endian int16 in units of
-- 0.01 mm (−32768: none), saturated at ±327.67 mm.
CREATE TABLE stable_area_supervoxels (
    reference_epoch_id INTEGER NOT NULL REFERENCES epochs(id),
    segmentation       TEXT NOT NULL,
    supervoxel         INTEGER NOT NULL CHECK (supervoxel >= 0),
    centroid_x         REAL NOT NULL,
    centroid_y         REAL NOT NULL,
    centroid_z         REAL NOT NULL,
    normal_x           REAL NOT NULL,
    normal_y           REAL NOT NULL,
    normal_z           REAL NOT NULL,
    voxels             INTEGER NOT NULL,
    roughness_m        REAL NOT NULL,
    PRIMARY KEY (reference_epoch_id, segmentation, supervoxel)
) WITHOUT ROWID;

CREATE TABLE stable_area_masks (
    epoch_id           INTEGER PRIMARY KEY REFERENCES epochs(id),
    reference_epoch_id INTEGER NOT NULL REFERENCES epochs(id),
    segmentation       TEXT NOT NULL,
    supervoxels        INTEGER NOT NULL CHECK (supervoxels >= 0),
    stable             INTEGER NOT NULL,
    unstable           INTEGER NOT NULL,
    stable_share       REAL NOT NULL,
    states             BLOB NOT NULL CHECK (length(states) = supervoxels),
    changes            BLOB NOT NULL CHECK (length(changes) = 2 * supervoxels),
    lods               BLOB NOT NULL CHECK (length(lods) = 2 * supervoxels)
);
