//! Fields that come in as files: GeoJSON, KML and KMZ, shapefile zips, ISOXML TaskData and
//! QGroundControl `.plan`, one format per file. Each reads polygons in WGS84 and says what it
//! took as fields, holes, no-fly zones and obstacles, and what it dropped and why; the result is
//! a mission document the field stage then validates like any other.
//!
//! Archives and XML are read through [`crate::archive`], which refuses zip bombs and XML
//! entities before a parser sees them.

pub mod flight_log;
mod geojson;
mod isoxml;
mod kml;
mod qgc_plan;
mod shapefile;

use geo::{LineString, Polygon, Winding};
use serde::Serialize;
use serde_json::{Value, json};

use super::archive;
use super::error::InputError;
use super::field::check_position;
use super::params::guidance::Guidance;

/// What a file held, in WGS84 (x = longitude, y = latitude).
#[derive(Debug, Default)]
pub struct Collected {
    pub name: Option<String>,
    pub fields: Vec<Polygon>,
    /// Each field's name in the file (its feature's, placemark's, partfield's or record's), in
    /// the order of `fields`.
    pub field_names: Vec<Option<String>>,
    pub no_fly_zones: Vec<Polygon>,
    /// Footprints with their height above ground, metres.
    pub obstacles: Vec<(Polygon, f64)>,
    pub home: Option<[f64; 2]>,
    pub guidance: Vec<ImportedGuidance>,
    pub warnings: Vec<String>,
}

/// A guidance line a file holds, by its name: a plan's `guidance` as it is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct ImportedGuidance {
    pub name: String,
    pub guidance: Guidance,
}

/// A mission document made from a file, as `POST /api/v1/missions` takes it, and what was left
/// out of the file.
#[derive(Debug, Clone, Serialize)]
pub struct ImportedMission {
    pub name: Option<String>,
    /// The fields, exteriors counter-clockwise: a GeoJSON MultiPolygon, or where the file names
    /// its fields a FeatureCollection of Polygons, each with its `name` (a farm plan's fields
    /// keep those names).
    pub area: Value,
    pub no_fly_zones: Option<Value>,
    pub obstacles: Option<Value>,
    pub home: Option<[f64; 2]>,
    /// The farm's guidance lines (ISOXML AB and A+ patterns), each ready as a plan's `guidance`.
    pub guidance: Vec<ImportedGuidance>,
    pub warnings: Vec<String>,
}

/// What [`sniff`] sees of a file: the names in a zip (lower case), the start of an XML text, or
/// a JSON document.
pub enum Glimpse<'a> {
    Zip(Vec<String>),
    Xml(&'a str),
    Json(Value),
}

impl Glimpse<'_> {
    /// A zip holding a file whose name ends with `end` (lower case).
    fn zip_holds(&self, end: &str) -> bool {
        matches!(self, Glimpse::Zip(names) if names.iter().any(|n| n.ends_with(end)))
    }
}

/// One file format.
pub trait Importer: Sync {
    /// The `format` query value.
    fn id(&self) -> &'static str;
    /// Whether a file that looks like this is in this format ([`IMPORTERS`] are asked in order).
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool;
    /// Reads the file; refusals name the part of the file that is wrong.
    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError>;
}

/// Every import format, in the order [`sniff`] asks them (the more particular first).
pub static IMPORTERS: &[&dyn Importer] = &[&shapefile::ShapefileZip, &isoxml::TaskData, &kml::Kmz, &kml::Kml, &qgc_plan::QgcPlan, &geojson::GeoJsonFile];

pub fn format_ids() -> Vec<&'static str> {
    IMPORTERS.iter().map(|i| i.id()).collect()
}

/// The format of a file, from its content: zips by the files they hold, XML by its root, JSON
/// by its members.
pub fn sniff(bytes: &[u8]) -> Option<&'static str> {
    let glimpse = if archive::is_zip(bytes) {
        Glimpse::Zip(archive::unzip(bytes).ok()?.into_iter().map(|(name, _)| name.to_ascii_lowercase()).collect())
    } else {
        let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
        let head = head.trim_start_matches('\u{feff}').trim_start();
        if head.starts_with('<') {
            return IMPORTERS.iter().find(|i| i.recognises(&Glimpse::Xml(head))).map(|i| i.id());
        }
        if !head.starts_with('{') {
            return None;
        }
        Glimpse::Json(serde_json::from_slice::<Value>(bytes).unwrap_or(Value::Null))
    };
    IMPORTERS.iter().find(|i| i.recognises(&glimpse)).map(|i| i.id())
}

/// Reads `bytes` as `format` (or the format [`sniff`] finds, when `None`).
pub fn import(format: Option<&str>, bytes: &[u8]) -> Result<ImportedMission, InputError> {
    let known = || format_ids().join(", ");
    if bytes.is_empty() {
        return Err(InputError::new("empty_file", "/", "the file is empty"));
    }
    let format = match format {
        Some(f) => f,
        None => sniff(bytes).ok_or_else(|| InputError::new("unknown_format", "/format", format!("the file's format is not recognised; give `format`, one of {}", known())))?,
    };
    let importer =
        IMPORTERS.iter().find(|i| i.id() == format).ok_or_else(|| InputError::new("unknown_format", "/format", format!("no import format `{format}`; known: {}", known())))?;
    let collected = importer.read(bytes)?;
    if collected.fields.is_empty() {
        return Err(InputError::new("empty_geometry", "/", format!("the file holds no field polygon{}", reasons(&collected.warnings))));
    }
    let polygons = |ps: &[Polygon]| json!({"type": "MultiPolygon", "coordinates": ps.iter().map(polygon_coordinates).collect::<Vec<_>>()});
    let area = if collected.field_names.iter().any(Option::is_some) { named_polygons(&collected.fields, &collected.field_names) } else { polygons(&collected.fields) };
    let obstacles = (!collected.obstacles.is_empty()).then(|| {
        let features: Vec<Value> = collected
            .obstacles
            .iter()
            .map(|(p, h)| json!({"type": "Feature", "properties": {"height_m": h}, "geometry": {"type": "Polygon", "coordinates": polygon_coordinates(p)}}))
            .collect();
        json!({"type": "FeatureCollection", "features": features})
    });
    Ok(ImportedMission {
        name: collected.name,
        area,
        no_fly_zones: (!collected.no_fly_zones.is_empty()).then(|| polygons(&collected.no_fly_zones)),
        obstacles,
        home: collected.home,
        guidance: collected.guidance,
        warnings: collected.warnings,
    })
}

fn reasons(warnings: &[String]) -> String {
    if warnings.is_empty() { String::new() } else { format!(" ({})", warnings.join("; ")) }
}

/// A FeatureCollection of the fields as Polygon features, each with its name where it has one.
fn named_polygons(fields: &[Polygon], names: &[Option<String>]) -> Value {
    let features: Vec<Value> = fields
        .iter()
        .zip(names)
        .map(|(p, name)| {
            let properties = name.as_ref().map_or_else(|| json!({}), |n| json!({"name": n}));
            json!({"type": "Feature", "properties": properties, "geometry": {"type": "Polygon", "coordinates": polygon_coordinates(p)}})
        })
        .collect();
    json!({"type": "FeatureCollection", "features": features})
}

/// GeoJSON rings of a polygon by the right-hand rule.
fn polygon_coordinates(p: &Polygon) -> Value {
    let ring = |r: &LineString, ccw: bool| {
        let mut r = r.clone();
        if ccw {
            r.make_ccw_winding()
        } else {
            r.make_cw_winding()
        }
        r.coords().map(|c| json!([c.x, c.y])).collect::<Vec<_>>()
    };
    let mut rings = vec![ring(p.exterior(), true)];
    rings.extend(p.interiors().iter().map(|h| ring(h, false)));
    json!(rings)
}

/// A closed ring from `[lon, lat]` points (closed when the file leaves it open), checked: at
/// least three distinct points, each a valid position. `part` names where it came from.
pub(crate) fn ring(points: Vec<[f64; 2]>, part: &str) -> Result<LineString, InputError> {
    for p in &points {
        check_position(p, part)?;
    }
    let mut points = points;
    points.dedup();
    if points.len() > 1 && points.first() == points.last() {
        points.pop();
    }
    if points.len() < 3 {
        return Err(InputError::new("empty_geometry", part, "a ring needs at least three distinct points"));
    }
    let mut ring: LineString = points.into_iter().map(|[x, y]| geo::Coord { x, y }).collect();
    ring.close();
    Ok(ring)
}

/// The kind a name or type attribute gives a polygon: no-fly zone, obstacle, or field.
pub(crate) fn kind_of_label(label: &str) -> Option<Kind> {
    let l = label.to_ascii_lowercase().replace(['-', '_', '#', ':'], " ");
    if l.contains("no fly") || l.contains("nofly") || l.split_whitespace().any(|w| w == "nfz") || l.contains("exclusion") {
        Some(Kind::NoFlyZone)
    } else if l.contains("obstacle") {
        Some(Kind::Obstacle)
    } else {
        None
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Field,
    NoFlyZone,
    Obstacle,
}

impl Collected {
    /// Adds a polygon as `kind` (a field with the file's `name` for it); obstacles without a
    /// height become no-fly zones (a height is what lets a plan climb over them).
    pub(crate) fn add(&mut self, kind: Kind, polygon: Polygon, height_m: Option<f64>, name: Option<&str>, part: &str) {
        match (kind, height_m) {
            (Kind::Field, _) => {
                self.fields.push(polygon);
                self.field_names.push(name.map(str::trim).filter(|n| !n.is_empty()).map(str::to_owned));
            }
            (Kind::NoFlyZone, _) => self.no_fly_zones.push(polygon),
            (Kind::Obstacle, Some(h)) if h.is_finite() && h > 0.0 => self.obstacles.push((polygon, h)),
            (Kind::Obstacle, _) => {
                self.warnings.push(format!("{part}: an obstacle without a height was taken as a no-fly zone"));
                self.no_fly_zones.push(polygon);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_name_zones_and_obstacles() {
        for label in ["No-fly: mast", "#nfz", "NOFLY_ZONE", "exclusion", "kind nfz"] {
            assert_eq!(kind_of_label(label), Some(Kind::NoFlyZone), "{label}");
        }
        assert_eq!(kind_of_label("Obstacle: poplar"), Some(Kind::Obstacle));
        for label in ["North field", "Infield 3", "confzone"] {
            assert_eq!(kind_of_label(label), None, "{label}");
        }
    }

    #[test]
    fn formats_are_told_by_content() {
        assert_eq!(sniff(br#"{"fileType": "Plan", "mission": {}}"#), Some("plan"));
        assert_eq!(sniff(br#"{"type": "Polygon"}"#), Some("geojson"));
        assert_eq!(sniff(b"<?xml version=\"1.0\"?><ISO11783_TaskData/>"), Some("isoxml"));
        assert_eq!(sniff(b"\xef\xbb\xbf<kml/>"), Some("kml"));
        assert_eq!(sniff(&archive::zip(&[("x/TASKDATA.XML".into(), b"<a/>".to_vec())])), Some("isoxml"));
        assert_eq!(sniff(&archive::zip(&[("f.SHP".into(), vec![])])), Some("shapefile"));
        assert_eq!(sniff(&archive::zip(&[("doc.kml".into(), vec![])])), Some("kmz"));
        assert_eq!(sniff(b"GIF89a"), None);
    }
}
