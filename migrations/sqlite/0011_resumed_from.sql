-- a resumed plan: the plan whose flight it finishes
ALTER TABLE plans ADD COLUMN resumed_from TEXT;
