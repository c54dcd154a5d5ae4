-- answers to POST requests sent with an Idempotency-Key, replayed to retries for a day
CREATE TABLE idempotency (
    tenant       TEXT NOT NULL,
    key          TEXT NOT NULL,
    fingerprint  TEXT NOT NULL,     -- SHA-256 of method, path, query, media type and body
    status       INTEGER,           -- NULL while the first request is being answered
    content_type TEXT,
    body         BLOB,
    created_at   TEXT NOT NULL,
    PRIMARY KEY (tenant, key)
);
CREATE INDEX idempotency_created ON idempotency (created_at);
