-- The claim takes single plans before farms' fields (WHERE status = 'queued' ORDER BY
-- farm_plan_id IS NOT NULL, created_at, rowid): the queue's index in that order (rowid ends
-- every index), so that a claim reads one entry instead of sorting every queued plan.
DROP INDEX plans_queue;
CREATE INDEX plans_queue ON plans (status, farm_plan_id IS NOT NULL, created_at);
