-- What a queued job plans: a coverage plan (or inspection), or a patrol. Patrols used to be told
-- apart by a `kind` member injected into their stored parameters: moved to this column.
ALTER TABLE plans ADD COLUMN kind TEXT NOT NULL DEFAULT 'plan' CHECK (kind IN ('plan', 'patrol'));
UPDATE plans SET kind = 'patrol', params = params - 'kind' WHERE params->>'kind' = 'patrol';
CREATE INDEX plans_by_mission_and_kind ON plans (tenant, mission_id, kind);
