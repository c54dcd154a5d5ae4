CREATE TABLE missions (
    id           TEXT PRIMARY KEY NOT NULL,
    name         TEXT NOT NULL,
    area         TEXT NOT NULL,          -- GeoJSON as sent (WGS84)
    no_fly_zones TEXT,                   -- GeoJSON or NULL
    home_lon     REAL,
    home_lat     REAL,
    created_at   TEXT NOT NULL,
    updated_at   TEXT NOT NULL
);

CREATE INDEX missions_created ON missions (created_at, id);

CREATE TABLE plans (
    id           TEXT PRIMARY KEY NOT NULL,
    mission_id   TEXT NOT NULL REFERENCES missions (id) ON DELETE CASCADE,
    -- what the job plans: the parameters and a snapshot of the mission's geometry, so that
    -- editing the mission later does not change a queued plan
    params       TEXT NOT NULL,
    mission      TEXT NOT NULL,
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
    progress     REAL NOT NULL DEFAULT 0,
    stats        TEXT,
    trajectory   TEXT,
    error        TEXT,
    attempts     INTEGER NOT NULL DEFAULT 0,
    created_at   TEXT NOT NULL,
    started_at   TEXT,
    finished_at  TEXT
);

CREATE INDEX plans_queue ON plans (status, created_at);
CREATE INDEX plans_mission ON plans (mission_id, created_at);
