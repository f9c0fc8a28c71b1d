-- 0002: per-core-point arrays (a site's [central] forward_arrays, docs/central.md): one row per
-- epoch and quantity, the float32 values (little-endian, in the site's core point order) as
-- the site stores them; partitioned by month like the results, under the same row-level
-- security. tlsmon.ensure_month makes their partitions too (also for the months already
-- there), and tlsmon.forward takes the entries of kind core_point_array.

CREATE TABLE tlsmon.core_point_arrays (
    site_id  integer NOT NULL REFERENCES tlsmon.sites (id),
    sha256   text NOT NULL,
    acquired timestamptz NOT NULL,
    quantity text NOT NULL,
    count    bigint NOT NULL CHECK (count >= 0),
    data     bytea NOT NULL CHECK (length(data) = 4 * count),
    PRIMARY KEY (site_id, sha256, acquired, quantity)
) PARTITION BY RANGE (acquired);

CREATE OR REPLACE FUNCTION tlsmon.ensure_month(t timestamptz) RETURNS void
LANGUAGE plpgsql SECURITY DEFINER SET search_path = pg_catalog, tlsmon AS $$
DECLARE
    first timestamptz := date_trunc('month', t, 'UTC');
    suffix text := to_char(first AT TIME ZONE 'UTC', 'YYYY_MM');
    parent text;
BEGIN
    IF to_regclass('tlsmon.core_point_arrays_' || suffix) IS NOT NULL THEN RETURN; END IF;
    PERFORM pg_advisory_xact_lock(hashtext('tlsmon.ensure_month'));
    FOREACH parent IN ARRAY ARRAY['epochs', 'registrations', 'zone_results', 'alarm_events',
                                  'system_events', 'core_point_arrays'] LOOP
        IF to_regclass('tlsmon.' || parent || '_' || suffix) IS NULL THEN
            EXECUTE format('CREATE TABLE tlsmon.%I PARTITION OF tlsmon.%I'
                           ' FOR VALUES FROM (%L) TO (%L)', parent || '_' || suffix, parent,
                           first, first + interval '1 month');
        END IF;
    END LOOP;
END $$;

-- The months that have partitions already get theirs.
SELECT tlsmon.ensure_month(to_date(right(c.relname, 7), 'YYYY_MM')::timestamp AT TIME ZONE 'UTC')
FROM pg_inherits i JOIN pg_class c ON c.oid = i.inhrelid
WHERE i.inhparent = 'tlsmon.system_events'::regclass;

CREATE OR REPLACE FUNCTION tlsmon.forward(source text, entries jsonb) RETURNS bigint
LANGUAGE plpgsql SECURITY INVOKER SET search_path = pg_catalog, tlsmon AS $$
DECLARE
    site integer := tlsmon.current_site();
    top bigint;
BEGIN
    IF site IS NULL THEN
        RAISE EXCEPTION 'role % is not a registered tlsmon site', session_user
            USING ERRCODE = 'insufficient_privilege';
    END IF;
    CREATE TEMP TABLE IF NOT EXISTS forward_batch (seq bigint, kind text, p jsonb)
        ON COMMIT DELETE ROWS;
    TRUNCATE forward_batch;
    INSERT INTO forward_batch
    SELECT (e ->> 'seq')::bigint, e ->> 'kind', e -> 'p' FROM jsonb_array_elements(entries) e;

    -- The months first, before this transaction holds any lock on the partitioned tables.
    PERFORM tlsmon.ensure_month(m) FROM (
        SELECT DISTINCT date_trunc('month', to_timestamp(
            coalesce(p ->> 'acquired', p ->> 'time')::bigint), 'UTC') AS m
        FROM forward_batch) months;

    -- An epoch's newest state wins (a failed epoch processed again).
    INSERT INTO tlsmon.epochs AS x (site_id, sha256, acquired, status, reason, file, file_size,
                                    points, total_ms, site_seq)
    SELECT DISTINCT ON (p ->> 'sha256') site, p ->> 'sha256', to_timestamp((p ->> 'acquired')::bigint),
           p ->> 'status', p ->> 'reason', p ->> 'file', (p ->> 'file_size')::bigint,
           (p ->> 'points')::bigint, (p ->> 'total_ms')::double precision, seq
    FROM forward_batch WHERE kind = 'epoch' ORDER BY p ->> 'sha256', seq DESC
    ON CONFLICT (site_id, sha256, acquired) DO UPDATE
        SET status = excluded.status, reason = excluded.reason, file = excluded.file,
            file_size = excluded.file_size, points = excluded.points,
            total_ms = excluded.total_ms, site_seq = excluded.site_seq
        WHERE x.site_seq < excluded.site_seq;

    INSERT INTO tlsmon.registrations
    SELECT site, p ->> 'sha256', to_timestamp((p ->> 'acquired')::bigint), p ->> 'method',
           (p ->> 'accepted')::integer <> 0, p ->> 'status', p ->> 'reason',
           (p ->> 'target_count')::bigint, (p ->> 'rms_m')::double precision,
           (p ->> 'max_residual_m')::double precision, (p ->> 'sigma0')::double precision,
           CASE WHEN jsonb_typeof(p -> 'parameters') = 'array' THEN ARRAY(
               SELECT v::double precision FROM jsonb_array_elements_text(p -> 'parameters') v) END,
           CASE WHEN jsonb_typeof(p -> 'sigmas') = 'array' THEN ARRAY(
               SELECT v::double precision FROM jsonb_array_elements_text(p -> 'sigmas') v) END,
           (p ->> 'variance_factor')::double precision, (p ->> 'redundancy')::bigint
    FROM forward_batch WHERE kind = 'registration'
    ON CONFLICT DO NOTHING;

    -- The zone results parsed once, for the series and for the newest values.
    CREATE TEMP TABLE IF NOT EXISTS forward_zone_results (LIKE tlsmon.zone_results, seq bigint)
        ON COMMIT DELETE ROWS;
    TRUNCATE forward_zone_results;
    INSERT INTO forward_zone_results
    SELECT site, p ->> 'zone', p ->> 'quantity', to_timestamp((p ->> 'acquired')::bigint),
           p ->> 'sha256', (p ->> 'value')::double precision,
           (p ->> 'uncertainty')::double precision, (p ->> 'n')::bigint,
           (p ->> 'significant')::integer <> 0, seq
    FROM forward_batch WHERE kind = 'zone_result';

    INSERT INTO tlsmon.zone_results
    SELECT site_id, zone, quantity, acquired, sha256, value, uncertainty, n, significant
    FROM forward_zone_results
    ON CONFLICT DO NOTHING;

    INSERT INTO tlsmon.zone_latest AS x
    SELECT DISTINCT ON (zone, quantity)
           site_id, zone, quantity, acquired, sha256, value, uncertainty, n, significant
    FROM forward_zone_results ORDER BY zone, quantity, acquired DESC, seq DESC
    ON CONFLICT (site_id, zone, quantity) DO UPDATE
        SET acquired = excluded.acquired, sha256 = excluded.sha256, value = excluded.value,
            uncertainty = excluded.uncertainty, n = excluded.n,
            significant = excluded.significant
        WHERE x.acquired <= excluded.acquired;

    INSERT INTO tlsmon.alarm_events
    SELECT site, source, (p ->> 'id')::bigint, to_timestamp((p ->> 'time')::bigint),
           p ->> 'rule', p ->> 'zone', p ->> 'quantity', p ->> 'kind', p ->> 'level',
           (p ->> 'value')::double precision, p ->> 'sha256', p ->> 'message', p ->> 'actor'
    FROM forward_batch WHERE kind = 'alarm_event'
    ON CONFLICT DO NOTHING;

    INSERT INTO tlsmon.system_events
    SELECT site, source, (p ->> 'id')::bigint, to_timestamp((p ->> 'time')::bigint),
           p ->> 'level', p ->> 'kind', p ->> 'message', p ->> 'sha256'
    FROM forward_batch WHERE kind = 'system_event'
    ON CONFLICT DO NOTHING;

    INSERT INTO tlsmon.core_point_arrays
    SELECT site, p ->> 'sha256', to_timestamp((p ->> 'acquired')::bigint), p ->> 'quantity',
           (p ->> 'count')::bigint, decode(p ->> 'data', 'hex')
    FROM forward_batch WHERE kind = 'core_point_array'
    ON CONFLICT DO NOTHING;

    SELECT max(seq) INTO top FROM forward_batch;
    INSERT INTO tlsmon.site_cursors AS x VALUES (site, source, coalesce(top, 0), now(),
                                                 (SELECT count(*) FROM forward_batch))
    ON CONFLICT ON CONSTRAINT site_cursors_pkey DO UPDATE
        SET forwarded_seq = greatest(x.forwarded_seq, excluded.forwarded_seq),
            forwarded_at = excluded.forwarded_at, entries = x.entries + excluded.entries;
    SELECT forwarded_seq INTO top FROM tlsmon.site_cursors
    WHERE site_id = site AND site_cursors.source = forward.source;
    RETURN top;
END $$;

GRANT SELECT, INSERT ON tlsmon.core_point_arrays TO tlsmon_site;
GRANT SELECT ON tlsmon.core_point_arrays TO tlsmon_reader;
ALTER TABLE tlsmon.core_point_arrays ENABLE ROW LEVEL SECURITY;
CREATE POLICY own_rows ON tlsmon.core_point_arrays TO tlsmon_site
    USING (site_id = tlsmon.current_site()) WITH CHECK (site_id = tlsmon.current_site());
CREATE POLICY read_all ON tlsmon.core_point_arrays FOR SELECT TO tlsmon_reader USING (true);
