-- coverplan's schema on PostgreSQL: the same tables as SQLite's migrations 0001-0007 end with,
-- JSON in jsonb, and `seq` numbering rows in insertion order (SQLite's rowid).
CREATE TABLE missions (
    seq          BIGSERIAL NOT NULL,
    id           TEXT PRIMARY KEY NOT NULL,
    tenant       TEXT NOT NULL DEFAULT 'default',
    name         TEXT NOT NULL,
    area         JSONB NOT NULL,          -- GeoJSON as sent (WGS84)
    no_fly_zones JSONB,
    obstacles    JSONB,                   -- features with a height_m property, flown over
    home_lon     DOUBLE PRECISION,
    home_lat     DOUBLE PRECISION,
    created_at   TEXT NOT NULL,           -- RFC 3339 UTC with milliseconds, as the API shows it
    updated_at   TEXT NOT NULL
);
CREATE INDEX missions_tenant ON missions (tenant, created_at);

CREATE TABLE plans (
    seq          BIGSERIAL NOT NULL,
    id           TEXT PRIMARY KEY NOT NULL,
    tenant       TEXT NOT NULL DEFAULT 'default',
    mission_id   TEXT NOT NULL REFERENCES missions (id) ON DELETE CASCADE,
    -- the parameters and a snapshot of the mission, so that editing it does not change a queued plan
    params       JSONB NOT NULL,
    mission      JSONB NOT NULL,
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
    progress     DOUBLE PRECISION NOT NULL DEFAULT 0,
    stats        JSONB,
    trajectory   TEXT,                    -- GeoJSON text, served as stored
    error        TEXT,
    error_code   TEXT,
    attempts     BIGINT NOT NULL DEFAULT 0,
    claimed_by   TEXT,                    -- the replica running it
    lease_until  DOUBLE PRECISION,        -- seconds since 1970; renewed by the replica's heartbeat
    created_at   TEXT NOT NULL,
    started_at   TEXT,
    finished_at  TEXT
);
-- the queue: claiming reads the oldest queued plan
CREATE INDEX plans_queue ON plans (created_at, seq) WHERE status = 'queued';
CREATE INDEX plans_running ON plans (lease_until) WHERE status = 'running';
CREATE INDEX plans_mission ON plans (mission_id, created_at);
CREATE INDEX plans_tenant_status ON plans (tenant, status);

CREATE TABLE plan_claims (
    plan_id     TEXT NOT NULL REFERENCES plans (id) ON DELETE CASCADE,
    replica     TEXT NOT NULL,
    claimed_at  DOUBLE PRECISION NOT NULL,
    ended_at    DOUBLE PRECISION,
    outcome     TEXT
);
CREATE INDEX plan_claims_plan ON plan_claims (plan_id, replica);

CREATE TABLE vehicles (
    tenant      TEXT NOT NULL,            -- '' for the built-ins
    id          TEXT NOT NULL,
    builtin     BOOLEAN NOT NULL DEFAULT FALSE,
    body        JSONB NOT NULL,
    created_at  TEXT NOT NULL,
    updated_at  TEXT NOT NULL,
    PRIMARY KEY (tenant, id)
);

CREATE TABLE api_keys (
    id          TEXT PRIMARY KEY NOT NULL,
    tenant      TEXT NOT NULL,
    admin       BOOLEAN NOT NULL DEFAULT FALSE,
    secret_hash TEXT NOT NULL,
    created_at  TEXT NOT NULL,
    revoked_at  TEXT
);

CREATE TABLE idempotency (
    tenant       TEXT NOT NULL,
    key          TEXT NOT NULL,
    fingerprint  TEXT NOT NULL,
    status       BIGINT,
    content_type TEXT,
    body         BYTEA,
    created_at   TEXT NOT NULL,
    PRIMARY KEY (tenant, key)
);
CREATE INDEX idempotency_created ON idempotency (created_at);
