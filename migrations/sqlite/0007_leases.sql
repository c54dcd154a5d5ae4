-- the queue shared by replicas: which replica runs a plan, and until when (seconds since 1970)
-- its claim holds unless renewed by its heartbeat
ALTER TABLE plans ADD COLUMN claimed_by TEXT;
ALTER TABLE plans ADD COLUMN lease_until REAL;

-- every claim of a plan by a replica and how it ended: the record that no plan ran twice at once
CREATE TABLE plan_claims (
    plan_id     TEXT NOT NULL REFERENCES plans (id) ON DELETE CASCADE,
    replica     TEXT NOT NULL,
    claimed_at  REAL NOT NULL,
    ended_at    REAL,
    outcome     TEXT          -- succeeded, failed, cancelled, handed_back, abandoned
);
CREATE INDEX plan_claims_plan ON plan_claims (plan_id, replica);
