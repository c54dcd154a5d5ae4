-- vehicle profiles: the built-ins (inserted at start-up if missing) and the operators' own
CREATE TABLE vehicles (
    id          TEXT PRIMARY KEY NOT NULL,
    builtin     INTEGER NOT NULL DEFAULT 0,
    body        TEXT NOT NULL,          -- the profile as JSON
    created_at  TEXT NOT NULL,
    updated_at  TEXT NOT NULL
);
