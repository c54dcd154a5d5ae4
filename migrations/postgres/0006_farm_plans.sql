-- A farm plan: many fields, each planned as a job of the queue (plans.farm_plan_id), then
-- scheduled over machines and days once every field's plan has finished.
CREATE TABLE farm_plans (
    seq         BIGSERIAL NOT NULL,
    id          TEXT PRIMARY KEY NOT NULL,
    tenant      TEXT NOT NULL,
    name        TEXT NOT NULL,
    request     JSONB NOT NULL,        -- machines, window, transit as sent
    fields      JSONB NOT NULL,        -- each field: its mission, name and plan, or why it was refused
    schedule    JSONB,                 -- written once, when every field's plan has finished
    cancelled   BOOLEAN NOT NULL DEFAULT FALSE,
    created_at  TEXT NOT NULL,
    finished_at TEXT
);
CREATE INDEX farm_plans_tenant ON farm_plans (tenant, created_at);
ALTER TABLE plans ADD COLUMN farm_plan_id TEXT REFERENCES farm_plans (id) ON DELETE CASCADE;
CREATE INDEX plans_farm ON plans (farm_plan_id) WHERE farm_plan_id IS NOT NULL;
