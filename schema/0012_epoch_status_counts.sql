-- 0012_epoch_status_counts: how many epochs are in each status, kept by triggers (docs/schema.md,
-- "epoch_status_counts"). `tlsmon status` and the dashboard's overview ask for these counts on
-- every call; counting them from the index epochs_by_status reads every page of that index
-- (a year of 15-minute epochs: about 200 pages scattered through the file), the counters are
-- one page. The triggers run in the transaction that changes the epoch, so the counts are
-- exact in every snapshot a reader sees.
CREATE TABLE epoch_status_counts (
    status TEXT PRIMARY KEY
           CHECK (status IN ('pending', 'processing', 'done', 'failed', 'rejected')),
    n      INTEGER NOT NULL CHECK (n >= 0)
) WITHOUT ROWID;

INSERT INTO epoch_status_counts (status, n)
SELECT s.status, (SELECT count(*) FROM epochs e WHERE e.status = s.status)
FROM (SELECT 'pending' AS status UNION ALL SELECT 'processing' UNION ALL SELECT 'done'
      UNION ALL SELECT 'failed' UNION ALL SELECT 'rejected') s;

CREATE TRIGGER epochs_counted_on_insert AFTER INSERT ON epochs BEGIN
    UPDATE epoch_status_counts SET n = n + 1 WHERE status = NEW.status;
END;

CREATE TRIGGER epochs_counted_on_status AFTER UPDATE OF status ON epochs
WHEN OLD.status <> NEW.status BEGIN
    UPDATE epoch_status_counts SET n = n - 1 WHERE status = OLD.status;
    UPDATE epoch_status_counts SET n = n + 1 WHERE status = NEW.status;
END;

CREATE TRIGGER epochs_counted_on_delete AFTER DELETE ON epochs BEGIN
    UPDATE epoch_status_counts SET n = n - 1 WHERE status = OLD.status;
END;
