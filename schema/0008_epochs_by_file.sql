-- 0008_epochs_by_file: an epoch found by the file it was recorded from. After a restart the
-- files still in the ingest folder (queued, or kept with ingest.archive = "keep") are known
-- by path, size and modification time instead of being read and hashed again
-- (docs/schema.md, "epochs").
CREATE INDEX epochs_by_file ON epochs (file_path, id);
