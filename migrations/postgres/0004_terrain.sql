-- a mission's elevation model (GeoTIFF or SRTM bytes as uploaded) and what was read from it
CREATE TABLE mission_terrain (
    mission_id  TEXT PRIMARY KEY NOT NULL REFERENCES missions (id) ON DELETE CASCADE,
    file_name   TEXT NOT NULL,
    model       BYTEA NOT NULL,
    summary     JSONB NOT NULL,           -- CRS, cells, bounds, heights
    created_at  TEXT NOT NULL
);
