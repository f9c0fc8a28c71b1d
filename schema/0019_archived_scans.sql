-- 0019_archived_scans: what the archive policy did to an epoch's scan file (docs/retention.md):
-- 'reencoded' (the file at epochs.archive_path is now the E57 written from it; the ingested
-- file was `original_path`, sha256 epochs.sha256) or 'removed' (no file is kept; it was
-- `original_path`), or 'not_reencoded' (re-encoding failed, `reason` says why: the file
-- stays as it was ingested and is not tried again). The file is deleted only after this row is committed: a pass that finds
-- `original_path` still there finishes the deletion.
CREATE TABLE archived_scans (
    epoch_id      INTEGER PRIMARY KEY REFERENCES epochs(id),
    action        TEXT NOT NULL CHECK (action IN ('reencoded', 'removed', 'not_reencoded')),
    at            INTEGER NOT NULL,
    original_path TEXT NOT NULL,
    bytes_before  INTEGER NOT NULL CHECK (bytes_before >= 0),  -- the file(s) given up
    bytes_after   INTEGER NOT NULL CHECK (bytes_after >= 0),   -- the file kept (0: removed)
    sha256_after  TEXT,                                         -- the re-encoded file's
    reason        TEXT NOT NULL DEFAULT ''
);
