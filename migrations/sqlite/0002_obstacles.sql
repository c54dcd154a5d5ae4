-- obstacles with heights (GeoJSON features with a height_m property), flown over, never through
ALTER TABLE missions ADD COLUMN obstacles TEXT;
