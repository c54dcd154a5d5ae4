-- The claim takes single plans before farms' fields (ORDER BY farm_plan_id IS NOT NULL,
-- created_at, seq): the queue's index in that order, so that a claim reads one entry instead
-- of sorting every queued plan.
DROP INDEX plans_queue;
CREATE INDEX plans_queue ON plans ((farm_plan_id IS NOT NULL), created_at, seq) WHERE status = 'queued';
