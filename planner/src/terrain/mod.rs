//! Terrain stage: the user's elevation model (GeoTIFF or SRTM `.hgt`), sampled bilinearly,
//! and the altitude profile that keeps a plan at its height above that ground ([`profile`]).
//!
//! Heights are metres above mean sea level as the model gives them. A model is read from
//! bytes (the service stores them, the CLI reads a file): nothing here touches a file.

mod geotiff;
mod hgt;
pub mod profile;

use serde::Serialize;

use super::archive;
use super::error::InputError;

/// Largest elevation model accepted, in bytes (a 1″ SRTM tile is 26 MB).
pub const MAX_MODEL_BYTES: usize = 64 * 1024 * 1024;
/// Most cells a model may hold once read.
pub const MAX_CELLS: usize = 16_000_000;
/// Metres of ground the model must reach beyond the fields, home, start and end.
pub const COVER_MARGIN_M: f64 = 100.0;

/// The coordinate systems read: geographic WGS84 and the WGS84 UTM zones.
#[derive(Clone)]
pub enum Crs {
    /// EPSG:4326, x = longitude, y = latitude in degrees.
    LonLat,
    /// EPSG:326zz (north) or 327zz (south), metres.
    Utm { zone: u8, south: bool, proj: Box<proj4rs::Proj>, wgs84: Box<proj4rs::Proj> },
}

impl Crs {
    /// The EPSG code of a supported system, or an error naming the one given.
    pub fn from_epsg(code: u32, part: &str) -> Result<Crs, InputError> {
        match code {
            4326 => Ok(Crs::LonLat),
            32601..=32660 | 32701..=32760 => {
                let (zone, south) = ((code % 100) as u8, code >= 32700);
                let hemisphere = if south { " +south" } else { "" };
                let proj = proj4rs::Proj::from_proj_string(&format!("+proj=utm +zone={zone}{hemisphere} +datum=WGS84 +units=m +no_defs"))
                    .map_err(|e| InputError::new("unsupported_crs", part, format!("UTM zone {zone}: {e}")))?;
                let wgs84 = proj4rs::Proj::from_proj_string("+proj=longlat +datum=WGS84 +no_defs").expect("WGS84 definition");
                Ok(Crs::Utm { zone, south, proj: Box::new(proj), wgs84: Box::new(wgs84) })
            }
            other => Err(unsupported(&format!("EPSG:{other}"), part)),
        }
    }

    pub fn epsg(&self) -> u32 {
        match self {
            Crs::LonLat => 4326,
            Crs::Utm { zone, south, .. } => u32::from(*zone) + if *south { 32700 } else { 32600 },
        }
    }

    /// `[lon, lat]` in degrees to this system's coordinates.
    fn project(&self, lon: f64, lat: f64) -> Option<[f64; 2]> {
        match self {
            Crs::LonLat => Some([lon, lat]),
            Crs::Utm { proj, wgs84, .. } => {
                let mut c = geo::Coord { x: lon.to_radians(), y: lat.to_radians() };
                proj4rs::transform::transform(wgs84, proj, &mut c).ok()?;
                Some([c.x, c.y])
            }
        }
    }

    fn to_wgs84(&self, x: f64, y: f64) -> Option<[f64; 2]> {
        match self {
            Crs::LonLat => Some([x, y]),
            Crs::Utm { proj, wgs84, .. } => {
                let mut c = geo::Coord { x, y };
                proj4rs::transform::transform(proj, wgs84, &mut c).ok()?;
                Some([c.x.to_degrees(), c.y.to_degrees()])
            }
        }
    }
}

fn unsupported(what: &str, part: &str) -> InputError {
    InputError::new(
        "unsupported_crs",
        part,
        format!(
            "the elevation model's coordinate system is {what}; coverplan reads geographic WGS84 (EPSG:4326) and the WGS84 UTM zones (EPSG:326xx, 327xx): reproject it, for example with gdalwarp -t_srs EPSG:4326"
        ),
    )
}

/// A grid of heights: cell centres at `origin + (col, row) · step` in the model's system.
#[derive(Clone)]
pub struct ElevationModel {
    cols: usize,
    rows: usize,
    /// Row-major; NaN where the model has no data.
    heights: Vec<f32>,
    origin: [f64; 2],
    /// Signed: a top-down raster has a negative y step, a bottom-up one a positive.
    step: [f64; 2],
    crs: Crs,
}

impl std::fmt::Debug for ElevationModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ElevationModel").field("crs", &self.crs.epsg()).field("cols", &self.cols).field("rows", &self.rows).finish_non_exhaustive()
    }
}

/// A plan flown over terrain, as its statistics show it.
#[derive(Debug, Clone, PartialEq, Default, Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TerrainStats {
    /// Always `terrain`: the trajectory's third coordinate is metres above mean sea level.
    pub altitude_reference: String,
    /// Least and greatest height above ground along the whole path, sampled every metre.
    pub height_above_ground_m: [f64; 2],
    /// The same on sweeps only.
    pub sweep_height_above_ground_m: [f64; 2],
    /// Metres of sweep whose height above ground leaves the tolerance because the ground
    /// rises or falls faster than the vehicle may climb or descend (0 on gentle ground).
    pub sweep_outside_tolerance_m: f64,
    /// Height gained and lost along the path, metres (take-offs and landings not counted).
    pub climb_m: f64,
    pub descent_m: f64,
    /// Waypoints of the laid path per kilometre of sweep.
    pub waypoints_per_sweep_km: f64,
}

/// Heights on a regular longitude/latitude grid over a model, for drawing it (relief shading).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TerrainGrid {
    /// `[west, south, east, north]` in degrees: the first sample is the north-west corner.
    pub bounds: [f64; 4],
    pub columns: usize,
    pub rows: usize,
    /// Row by row from the north, metres above mean sea level; null where the model has none.
    pub heights: Vec<Option<f32>>,
}

/// What a stored model is, as `GET …/terrain` shows it.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TerrainSummary {
    /// `EPSG:4326`, or `EPSG:326zz` / `EPSG:327zz`.
    pub crs: String,
    pub columns: usize,
    pub rows: usize,
    /// Cell size in the model's units (degrees or metres), x then y.
    pub cell_size: [f64; 2],
    /// Cell size on the ground, metres, x then y (at the model's centre).
    pub cell_size_m: [f64; 2],
    /// `[west, south, east, north]` in degrees: the extent of the cell centres.
    pub bounds: [f64; 4],
    /// Lowest and highest height, metres above mean sea level.
    pub min_m: f64,
    pub max_m: f64,
    /// Cells without data.
    pub nodata_cells: usize,
}

impl ElevationModel {
    /// Reads a GeoTIFF, an SRTM `.hgt` tile (its name gives its place), or a zip holding one.
    pub fn read(bytes: &[u8], file_name: &str) -> Result<ElevationModel, InputError> {
        if bytes.len() > MAX_MODEL_BYTES {
            return Err(InputError::new(
                "terrain_too_large",
                "/",
                format!("the elevation model is {:.1} MB; the limit is {} MB: crop it to the fields", bytes.len() as f64 / 1e6, MAX_MODEL_BYTES / 1024 / 1024),
            ));
        }
        if archive::is_zip(bytes) {
            let files = archive::unzip(bytes)?;
            let inner = files
                .iter()
                .find(|(name, _)| is_model_name(name))
                .ok_or_else(|| InputError::new("invalid_terrain", "/", "the zip holds no elevation model: a .tif, .tiff or .hgt file was expected"))?;
            return Self::read(&inner.1, &inner.0);
        }
        if geotiff::is_tiff(bytes) {
            return geotiff::read(bytes);
        }
        if file_name.to_ascii_lowercase().ends_with(".hgt") || hgt::side(bytes.len()).is_some() {
            return hgt::read(bytes, file_name);
        }
        Err(InputError::new("invalid_terrain", "/", "not an elevation model: coverplan reads GeoTIFF (.tif) and SRTM (.hgt, or zipped) files"))
    }

    /// A model from a grid already read: `heights` row by row (NaN: no data), the centre of
    /// cell (0, 0) at `origin` and the next column and row `step` away, in system `epsg`.
    pub fn from_grid(cols: usize, rows: usize, heights: Vec<f32>, origin: [f64; 2], step: [f64; 2], epsg: u32) -> Result<ElevationModel, InputError> {
        Self::new(cols, rows, heights, origin, step, Crs::from_epsg(epsg, "/")?)
    }

    fn new(cols: usize, rows: usize, heights: Vec<f32>, origin: [f64; 2], step: [f64; 2], crs: Crs) -> Result<ElevationModel, InputError> {
        if heights.len() != cols * rows {
            return Err(InputError::new("invalid_terrain", "/", format!("{} heights for {cols} × {rows} cells", heights.len())));
        }
        if cols < 2 || rows < 2 {
            return Err(InputError::new("invalid_terrain", "/", format!("the model has {cols} × {rows} cells; at least 2 × 2 are needed to interpolate")));
        }
        if !(step[0].is_finite() && step[1].is_finite() && step[0] > 0.0 && step[1] != 0.0 && origin.iter().all(|v| v.is_finite())) {
            return Err(InputError::new("invalid_terrain", "/", "the model's cell size or origin is not a usable number (a rotated or flipped-x raster?)"));
        }
        if heights.iter().all(|h| h.is_nan()) {
            return Err(InputError::new("invalid_terrain", "/", "every cell of the model is nodata"));
        }
        Ok(ElevationModel { cols, rows, heights, origin, step, crs })
    }

    pub fn crs(&self) -> &Crs {
        &self.crs
    }

    /// Ground height at `[lon, lat]`, bilinear between the four nearest cell centres; `None`
    /// outside the model or beside a nodata cell.
    pub fn height_at(&self, lon: f64, lat: f64) -> Option<f64> {
        self.pixel_of(lon, lat).and_then(|p| self.height_at_pixel(p))
    }

    /// `[lon, lat]` as fractional (column, row) of the cell centres.
    pub(crate) fn pixel_of(&self, lon: f64, lat: f64) -> Option<[f64; 2]> {
        let [x, y] = self.crs.project(lon, lat)?;
        Some([(x - self.origin[0]) / self.step[0], (y - self.origin[1]) / self.step[1]])
    }

    /// Whether fractional (column, row) lies among the cell centres (with `slack` cells).
    fn spans_pixel(&self, [fc, fr]: [f64; 2], slack: f64) -> bool {
        fc >= -slack && fr >= -slack && fc <= (self.cols - 1) as f64 + slack && fr <= (self.rows - 1) as f64 + slack
    }

    pub(crate) fn height_at_pixel(&self, [fc, fr]: [f64; 2]) -> Option<f64> {
        if !self.spans_pixel([fc, fr], 1e-9) {
            return None;
        }
        let (max_c, max_r) = ((self.cols - 1) as f64, (self.rows - 1) as f64);
        let (fc, fr) = (fc.clamp(0.0, max_c), fr.clamp(0.0, max_r));
        let (c0, r0) = ((fc.floor() as usize).min(self.cols - 2), (fr.floor() as usize).min(self.rows - 2));
        let (tx, ty) = (fc - c0 as f64, fr - r0 as f64);
        let at = |c: usize, r: usize| f64::from(self.heights[r * self.cols + c]);
        let (h00, h10, h01, h11) = (at(c0, r0), at(c0 + 1, r0), at(c0, r0 + 1), at(c0 + 1, r0 + 1));
        let h = (h00 * (1.0 - tx) + h10 * tx) * (1.0 - ty) + (h01 * (1.0 - tx) + h11 * tx) * ty;
        h.is_finite().then_some(h)
    }

    /// Why there is no height at `[lon, lat]`: outside the model, or nodata.
    fn missing(&self, lon: f64, lat: f64) -> &'static str {
        match self.pixel_of(lon, lat) {
            Some(p) if self.spans_pixel(p, 0.0) => "has no data (nodata cells) at",
            Some(_) => "does not reach",
            None => "cannot be projected to",
        }
    }

    /// `[west, south, east, north]` in degrees: the extent of the cell centres.
    fn bounds(&self) -> [f64; 4] {
        let last = [self.origin[0] + self.step[0] * (self.cols - 1) as f64, self.origin[1] + self.step[1] * (self.rows - 1) as f64];
        let corners: Vec<[f64; 2]> =
            [[self.origin[0], self.origin[1]], [last[0], self.origin[1]], [self.origin[0], last[1]], last].iter().filter_map(|&[x, y]| self.crs.to_wgs84(x, y)).collect();
        corners.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |b, c| [b[0].min(c[0]), b[1].min(c[1]), b[2].max(c[0]), b[3].max(c[1])])
    }

    /// Cell size on the ground, metres, x then y (a geographic model's at its middle latitude).
    fn cell_size_m(&self, bounds: [f64; 4]) -> [f64; 2] {
        match self.crs {
            Crs::LonLat => {
                let lat = (bounds[1] + bounds[3]) / 2.0;
                [self.step[0] * 111_320.0 * lat.to_radians().cos(), self.step[1].abs() * 110_574.0]
            }
            Crs::Utm { .. } => [self.step[0], self.step[1].abs()],
        }
    }

    /// What the model is; reads every cell (for the heights' range).
    pub fn summary(&self) -> TerrainSummary {
        let finite = self.heights.iter().filter(|h| h.is_finite());
        let (min_m, max_m) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| (lo.min(f64::from(h)), hi.max(f64::from(h))));
        let bounds = self.bounds();
        let cell_size_m = self.cell_size_m(bounds);
        TerrainSummary {
            crs: format!("EPSG:{}", self.crs.epsg()),
            columns: self.cols,
            rows: self.rows,
            cell_size: [self.step[0], self.step[1].abs()],
            cell_size_m,
            bounds,
            min_m,
            max_m,
            nodata_cells: self.heights.iter().filter(|h| h.is_nan()).count(),
        }
    }

    /// The model's heights on a grid of at most `size` × `size` samples over its extent,
    /// spaced alike in metres on the ground.
    pub fn grid(&self, size: usize) -> TerrainGrid {
        let bounds = self.bounds();
        let lat = (bounds[1] + bounds[3]) / 2.0;
        let (w, h) = ((bounds[2] - bounds[0]) * lat.to_radians().cos(), bounds[3] - bounds[1]);
        let size = size.max(2);
        let (columns, rows) = if w >= h { (size, ((size as f64 * h / w).round() as usize).max(2)) } else { (((size as f64 * w / h).round() as usize).max(2), size) };
        let heights = (0..rows)
            .flat_map(|r| (0..columns).map(move |c| (c, r)))
            .map(|(c, r)| {
                let lon = bounds[0] + (bounds[2] - bounds[0]) * c as f64 / (columns - 1) as f64;
                let lat = bounds[3] - (bounds[3] - bounds[1]) * r as f64 / (rows - 1) as f64;
                self.height_at(lon, lat).map(|h| h as f32)
            })
            .collect();
        TerrainGrid { bounds, columns, rows, heights }
    }

    /// Checks that the model has a height everywhere within [`COVER_MARGIN_M`] of `places`
    /// (each `(what, pointer, [lon, lat])`) and over the box around them: a place it misses is
    /// named, as is a point of the box without data.
    pub fn check_covers(&self, places: &[(String, String, [f64; 2])]) -> Result<(), InputError> {
        let Some((_, _, [_, lat0])) = places.first() else { return Ok(()) };
        let per_deg = [111_320.0 * lat0.to_radians().cos().max(0.01), 110_574.0];
        let model_bounds = self.bounds();
        let refuse = |what: &str, pointer: &str, p: [f64; 2]| {
            InputError::new(
                "terrain_not_covering",
                pointer,
                format!(
                    "the elevation model {} {what} at [{:.6}, {:.6}]; it must cover the fields, home, start and end and {COVER_MARGIN_M} m around them (the model spans longitude {:.5} to {:.5}, latitude {:.5} to {:.5})",
                    self.missing(p[0], p[1]),
                    p[0],
                    p[1],
                    model_bounds[0],
                    model_bounds[2],
                    model_bounds[1],
                    model_bounds[3]
                ),
            )
        };
        for (what, pointer, p) in places {
            if self.height_at(p[0], p[1]).is_none() {
                return Err(refuse(what, pointer, *p));
            }
        }
        let (dx, dy) = (COVER_MARGIN_M / per_deg[0], COVER_MARGIN_M / per_deg[1]);
        let mut bounds = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for (_, _, [lon, lat]) in places {
            bounds = [bounds[0].min(lon - dx), bounds[1].min(lat - dy), bounds[2].max(lon + dx), bounds[3].max(lat + dy)];
        }
        // a grid over the box at about the model's cell size (at most 400 × 400 points)
        let cell = self.cell_size_m(model_bounds);
        let steps = |span_m: f64, cell_m: f64| ((span_m / cell_m.max(1.0)).ceil() as usize).clamp(1, 400);
        let (nx, ny) = (steps((bounds[2] - bounds[0]) * per_deg[0], cell[0]), steps((bounds[3] - bounds[1]) * per_deg[1], cell[1]));
        for j in 0..=ny {
            for i in 0..=nx {
                let p = [bounds[0] + (bounds[2] - bounds[0]) * i as f64 / nx as f64, bounds[1] + (bounds[3] - bounds[1]) * j as f64 / ny as f64];
                if self.height_at(p[0], p[1]).is_none() {
                    let side = [(p[1] - bounds[1] < dy, "south"), (bounds[3] - p[1] < dy, "north"), (p[0] - bounds[0] < dx, "west"), (bounds[2] - p[0] < dx, "east")]
                        .iter()
                        .filter(|s| s.0)
                        .map(|s| s.1)
                        .collect::<Vec<_>>()
                        .join("-");
                    let what = if side.is_empty() { "the ground between the fields".to_string() } else { format!("the margin {side} of the fields") };
                    return Err(refuse(&what, "/", p));
                }
            }
        }
        Ok(())
    }
}

fn is_model_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    [".tif", ".tiff", ".hgt"].iter().any(|e| lower.ends_with(e))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A model in UTM zone 32N over `cols × rows` cells of `cell` metres from (500 000, 5 200 000)
    /// (top-down), heights from `f(x, y)` in metres from its south-west corner.
    pub fn synthetic(cols: usize, rows: usize, cell: f64, f: impl Fn(f64, f64) -> f64) -> ElevationModel {
        let top = 5_200_000.0 + cell * (rows - 1) as f64;
        let heights = (0..rows).flat_map(|r| (0..cols).map(move |c| (c, r))).map(|(c, r)| f(c as f64 * cell, (rows - 1 - r) as f64 * cell) as f32).collect();
        ElevationModel::new(cols, rows, heights, [500_000.0, top], [cell, -cell], Crs::from_epsg(32632, "/").unwrap()).unwrap()
    }

    #[test]
    fn bilinear_heights_of_a_plane_are_exact() {
        let m = synthetic(50, 40, 10.0, |x, y| 300.0 + 0.2 * x - 0.1 * y);
        let crs = m.crs().clone();
        for (x, y) in [(0.0, 0.0), (123.4, 56.7), (489.9, 389.9), (250.0, 1.0)] {
            let [lon, lat] = crs.to_wgs84(500_000.0 + x, 5_200_000.0 + y).unwrap();
            let h = m.height_at(lon, lat).unwrap();
            assert!((h - (300.0 + 0.2 * x - 0.1 * y)).abs() < 1e-3, "at ({x}, {y}): {h}");
        }
        let [lon, lat] = crs.to_wgs84(500_000.0 - 5.0, 5_200_000.0).unwrap();
        assert_eq!(m.height_at(lon, lat), None);
    }

    #[test]
    fn a_model_must_cover_the_places_and_their_margin_with_data() {
        // 2 km × 2 km; nodata in a 100 m square from (1 300, 1 300) m
        let m = synthetic(201, 201, 10.0, |x, y| if (1300.0..1400.0).contains(&x) && (1300.0..1400.0).contains(&y) { f64::NAN } else { 250.0 });
        let crs = m.crs().clone();
        let place = |x: f64, y: f64| ("the field".to_string(), "/area".to_string(), crs.to_wgs84(500_000.0 + x, 5_200_000.0 + y).unwrap());
        assert_eq!(m.check_covers(&[place(400.0, 400.0), place(900.0, 900.0)]), Ok(()));
        // the nodata square lies in the box between two places
        let e = m.check_covers(&[place(1100.0, 1100.0), place(1600.0, 1600.0)]).unwrap_err();
        assert!(e.code == "terrain_not_covering" && e.detail.contains("has no data"), "{e:?}");
        // within 100 m of the model's edge: the margin is missing, and where is said
        let e = m.check_covers(&[place(1000.0, 1950.0)]).unwrap_err();
        assert!(e.detail.contains("margin") && e.detail.contains("north"), "{}", e.detail);
        let e = m.check_covers(&[place(2500.0, 1000.0)]).unwrap_err();
        assert_eq!(e.pointer, "/area");
    }

    #[test]
    fn refuses_what_is_not_a_model() {
        assert_eq!(ElevationModel::read(b"hello", "x.txt").err().unwrap().code, "invalid_terrain");
        assert_eq!(Crs::from_epsg(27700, "/").err().unwrap().code, "unsupported_crs");
        let big = vec![0u8; MAX_MODEL_BYTES + 1];
        assert_eq!(ElevationModel::read(&big, "x.tif").err().unwrap().code, "terrain_too_large");
    }
}
