-- why a failed plan failed, for programs: time_limit, infeasible, internal, interrupted, or the
-- code of the input error
ALTER TABLE plans ADD COLUMN error_code TEXT;
