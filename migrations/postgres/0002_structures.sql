-- structures to inspect: GeoJSON features (Polygons, or Points with radius_m) with height_m, base_m and name
ALTER TABLE missions ADD COLUMN structures JSONB;
