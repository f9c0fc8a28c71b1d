-- 0001_central: the central database of many tlsmon sites (docs/central.md). Each site's
-- daemon forwards its outbox here through tlsmon.forward(), as its own login role, a member
-- of tlsmon_site; row-level security lets a site insert and read its own rows only. Analysts
-- read everything as members of tlsmon_reader. Time-series tables are partitioned by month
-- (tlsmon.ensure_month creates a month's partitions when a row first needs them).
-- Rows are keyed by what they are at the site (an epoch's sha256, a zone and quantity, an
-- event's id in the site's database), so a batch sent twice changes nothing.

DO $$
BEGIN
    IF NOT EXISTS (SELECT FROM pg_roles WHERE rolname = 'tlsmon_site') THEN
        CREATE ROLE tlsmon_site NOLOGIN;
    END IF;
    IF NOT EXISTS (SELECT FROM pg_roles WHERE rolname = 'tlsmon_reader') THEN
        CREATE ROLE tlsmon_reader NOLOGIN;
    END IF;
END $$;

CREATE TABLE tlsmon.sites (
    id        serial PRIMARY KEY,
    name      text NOT NULL UNIQUE CHECK (name ~ '^[a-z0-9][a-z0-9_-]{0,39}$'),
    location  text NOT NULL DEFAULT '',
    role_name name NOT NULL UNIQUE,
    created   timestamptz NOT NULL DEFAULT now()
);

-- The highest outbox seq each site database has had committed here. `source` is the site
-- database's own identity (central_forward.database_id), so a rebuilt site database counts
-- afresh.
CREATE TABLE tlsmon.site_cursors (
    site_id       integer NOT NULL REFERENCES tlsmon.sites (id),
    source        text NOT NULL,
    forwarded_seq bigint NOT NULL,
    forwarded_at  timestamptz NOT NULL,
    entries       bigint NOT NULL,
    PRIMARY KEY (site_id, source)
);

CREATE TABLE tlsmon.epochs (
    site_id   integer NOT NULL REFERENCES tlsmon.sites (id),
    sha256    text NOT NULL CHECK (length(sha256) = 64),
    acquired  timestamptz NOT NULL,
    status    text NOT NULL,
    reason    text NOT NULL,
    file      text NOT NULL,
    file_size bigint,
    points    bigint,
    total_ms  double precision,
    site_seq  bigint NOT NULL,
    PRIMARY KEY (site_id, sha256, acquired)
) PARTITION BY RANGE (acquired);
CREATE INDEX epochs_by_time ON tlsmon.epochs (site_id, acquired);

CREATE TABLE tlsmon.registrations (
    site_id         integer NOT NULL REFERENCES tlsmon.sites (id),
    sha256          text NOT NULL,
    acquired        timestamptz NOT NULL,
    method          text NOT NULL,
    accepted        boolean NOT NULL,
    status          text NOT NULL,
    reason          text NOT NULL,
    target_count    bigint NOT NULL,
    rms_m           double precision NOT NULL,
    max_residual_m  double precision NOT NULL,
    sigma0          double precision,
    parameters      double precision[],  -- ω, φ, κ (rad), tx, ty, tz (m)
    sigmas          double precision[],
    variance_factor double precision,
    redundancy      bigint,
    PRIMARY KEY (site_id, sha256, acquired)
) PARTITION BY RANGE (acquired);

-- One zone's series over a window is one range of the primary key, whose index also holds
-- the values (INCLUDE): the series is read from the index alone, without visiting the table,
-- where a zone's rows lie scattered among every other zone's and site's (one page each).
CREATE TABLE tlsmon.zone_results (
    site_id     integer NOT NULL REFERENCES tlsmon.sites (id),
    zone        text NOT NULL,
    quantity    text NOT NULL,
    acquired    timestamptz NOT NULL,
    sha256      text NOT NULL,
    value       double precision NOT NULL,
    uncertainty double precision,
    n           bigint NOT NULL,
    significant boolean NOT NULL,
    PRIMARY KEY (site_id, zone, quantity, acquired, sha256)
        INCLUDE (value, uncertainty, n, significant)
) PARTITION BY RANGE (acquired);

-- The newest value of every zone quantity of every site, kept by tlsmon.forward(): the
-- fleet's overview reads this small table instead of every partition.
CREATE TABLE tlsmon.zone_latest (
    site_id     integer NOT NULL REFERENCES tlsmon.sites (id),
    zone        text NOT NULL,
    quantity    text NOT NULL,
    acquired    timestamptz NOT NULL,
    sha256      text NOT NULL,
    value       double precision NOT NULL,
    uncertainty double precision,
    n           bigint NOT NULL,
    significant boolean NOT NULL,
    PRIMARY KEY (site_id, zone, quantity)
);

CREATE TABLE tlsmon.alarm_events (
    site_id       integer NOT NULL REFERENCES tlsmon.sites (id),
    source        text NOT NULL,
    site_event_id bigint NOT NULL,
    time          timestamptz NOT NULL,
    rule          text NOT NULL,
    zone          text,
    quantity      text,
    kind          text NOT NULL,
    level         text NOT NULL,
    value         double precision,
    sha256        text,
    message       text NOT NULL,
    actor         text NOT NULL,
    PRIMARY KEY (site_id, source, site_event_id, time)
) PARTITION BY RANGE (time);
CREATE INDEX alarm_events_by_time ON tlsmon.alarm_events (time);

CREATE TABLE tlsmon.system_events (
    site_id       integer NOT NULL REFERENCES tlsmon.sites (id),
    source        text NOT NULL,
    site_event_id bigint NOT NULL,
    time          timestamptz NOT NULL,
    level         text NOT NULL,
    kind          text NOT NULL,
    message       text NOT NULL,
    sha256        text,
    PRIMARY KEY (site_id, source, site_event_id, time)
) PARTITION BY RANGE (time);

-- The site of the connected role (NULL for any other role). SECURITY DEFINER: site roles
-- cannot read tlsmon.sites; session_user is the role that logged in.
CREATE FUNCTION tlsmon.current_site() RETURNS integer
LANGUAGE sql STABLE SECURITY DEFINER SET search_path = pg_catalog, tlsmon AS $$
    SELECT id FROM tlsmon.sites WHERE role_name = session_user
$$;

-- The month of `t` (UTC) as partitions of every partitioned table. Serialised by an advisory
-- lock, so two sites needing a new month at once create it once.
CREATE FUNCTION tlsmon.ensure_month(t timestamptz) RETURNS void
LANGUAGE plpgsql SECURITY DEFINER SET search_path = pg_catalog, tlsmon AS $$
DECLARE
    first timestamptz := date_trunc('month', t, 'UTC');
    suffix text := to_char(first AT TIME ZONE 'UTC', 'YYYY_MM');
    parent text;
BEGIN
    IF to_regclass('tlsmon.system_events_' || suffix) IS NOT NULL THEN RETURN; END IF;
    PERFORM pg_advisory_xact_lock(hashtext('tlsmon.ensure_month'));
    FOREACH parent IN ARRAY ARRAY['epochs', 'registrations', 'zone_results', 'alarm_events',
                                  'system_events'] LOOP
        IF to_regclass('tlsmon.' || parent || '_' || suffix) IS NULL THEN
            EXECUTE format('CREATE TABLE tlsmon.%I PARTITION OF tlsmon.%I'
                           ' FOR VALUES FROM (%L) TO (%L)', parent || '_' || suffix, parent,
                           first, first + interval '1 month');
        END IF;
    END LOOP;
END $$;
REVOKE ALL ON FUNCTION tlsmon.ensure_month(timestamptz) FROM PUBLIC;
GRANT EXECUTE ON FUNCTION tlsmon.ensure_month(timestamptz) TO tlsmon_site;

-- One batch of a site's outbox (a JSON array of {seq, kind, p}, p the entry's payload,
-- schema/0020_central_outbox.sql of the site) in the caller's transaction, as the caller:
-- row-level security checks every row. Returns the highest seq now committed for `source`.
CREATE FUNCTION tlsmon.forward(source text, entries jsonb) RETURNS bigint
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
REVOKE ALL ON FUNCTION tlsmon.forward(text, jsonb) FROM PUBLIC;
GRANT EXECUTE ON FUNCTION tlsmon.forward(text, jsonb) TO tlsmon_site;

-- Privileges: sites insert (and update their epochs' state, latest values and cursors);
-- readers read. Row-level security decides whose rows.
GRANT USAGE ON SCHEMA tlsmon TO tlsmon_site, tlsmon_reader;
GRANT SELECT, INSERT ON tlsmon.site_cursors, tlsmon.epochs, tlsmon.registrations,
    tlsmon.zone_results, tlsmon.zone_latest, tlsmon.alarm_events, tlsmon.system_events
    TO tlsmon_site;
GRANT UPDATE ON tlsmon.site_cursors, tlsmon.epochs, tlsmon.zone_latest TO tlsmon_site;
GRANT SELECT ON ALL TABLES IN SCHEMA tlsmon TO tlsmon_reader;

DO $$
DECLARE
    t text;
BEGIN
    FOREACH t IN ARRAY ARRAY['site_cursors', 'epochs', 'registrations', 'zone_results',
                             'zone_latest', 'alarm_events', 'system_events'] LOOP
        EXECUTE format('ALTER TABLE tlsmon.%I ENABLE ROW LEVEL SECURITY', t);
        EXECUTE format('CREATE POLICY own_rows ON tlsmon.%I TO tlsmon_site'
                       ' USING (site_id = tlsmon.current_site())'
                       ' WITH CHECK (site_id = tlsmon.current_site())', t);
        EXECUTE format('CREATE POLICY read_all ON tlsmon.%I FOR SELECT TO tlsmon_reader'
                       ' USING (true)', t);
    END LOOP;
END $$;
