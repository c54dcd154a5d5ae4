//! KML and KMZ for Google Earth (docs/methods.md, interop §5): the fields with their holes, the
//! no-fly zones, home, and the flown path one placemark per piece, styled by kind and carrying
//! the piece's figures as `ExtendedData`, in a folder per sortie. Written with quick-xml: the
//! `kml` crate reads our imports, but its writer has no styles or extended data.

use geo::{LineString, Polygon};
use geojson::GeometryValue;
use serde_json::Value;

use super::geojson::TERRAIN_REFERENCE;
use super::xml::Xml;
use super::{ALL_METHODS, ExportJob, Exporter, Format, number};
use crate::archive;
use crate::error::InputError;
use crate::path::PieceKind;

pub struct Kml;
pub struct Kmz;

/// The outlines' style ids and their line colours (`aabbggrr`), fill colours and widths.
const OUTLINE_STYLES: &[(&str, &str, &str, &str)] = &[("field", "ff00d7ff", "4000d7ff", "2"), ("nfz", "ff0000ff", "600000ff", "2")];

/// The flown pieces' styles (their ids are the kinds' names).
const PIECE_STYLES: &[(PieceKind, &str, &str, &str)] = &[
    (PieceKind::Sweep, "ff00b000", "00000000", "3"),
    (PieceKind::Headland, "ff008000", "00000000", "3"),
    (PieceKind::Turn, "ff0090ff", "00000000", "2"),
    (PieceKind::Transit, "ffff7000", "00000000", "2"),
];

/// A piece kind's name, as the trajectory's `kind` says it.
fn kind_name(kind: PieceKind) -> String {
    serde_json::to_value(kind).ok().and_then(|v| v.as_str().map(str::to_owned)).unwrap_or_default()
}

/// `kind` values that mark a placemark as a no-fly zone, on import too.
pub const NO_FLY_KIND: &str = "nfz";

impl Exporter for Kml {
    fn format(&self) -> &'static Format {
        &Format {
            id: "kml",
            label: "Google Earth (.kml)",
            media_type: "application/vnd.google-earth.kml+xml",
            extension: ".kml",
            one_flight_per_file: false,
            firmware_commands: false,
            plans: ALL_METHODS,
            verbatim: false,
            waypoint_limit: false,
            default_max_waypoints: None,
        }
    }
    fn write(&self, job: &ExportJob<'_>, _sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(vec![document(job)])
    }
}

impl Exporter for Kmz {
    fn format(&self) -> &'static Format {
        &Format {
            id: "kmz",
            label: "Google Earth (.kmz)",
            media_type: "application/vnd.google-earth.kmz",
            extension: ".kmz",
            one_flight_per_file: false,
            firmware_commands: false,
            plans: ALL_METHODS,
            verbatim: false,
            waypoint_limit: false,
            default_max_waypoints: None,
        }
    }
    fn write(&self, job: &ExportJob<'_>, _sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(vec![archive::zip(&[("doc.kml".to_owned(), document(job))])])
    }
}

fn document(job: &ExportJob<'_>) -> Vec<u8> {
    let mut x = Xml::new();
    x.open("kml", &[("xmlns", "http://www.opengis.net/kml/2.2")]).open("Document", &[]).leaf("name", job.name);
    let pieces = PIECE_STYLES.iter().map(|&(kind, line, fill, width)| (kind_name(kind), line, fill, width));
    for (id, line, fill, width) in OUTLINE_STYLES.iter().map(|&(id, line, fill, width)| (id.to_owned(), line, fill, width)).chain(pieces) {
        x.open("Style", &[("id", &id)]).open("LineStyle", &[]).leaf("color", line).leaf("width", width).close("LineStyle");
        x.open("PolyStyle", &[]).leaf("color", fill).close("PolyStyle").close("Style");
    }
    x.open("Folder", &[]).leaf("name", "Fields");
    for (k, field) in job.outlines.fields.0.iter().enumerate() {
        polygon_placemark(&mut x, &format!("Field {}", k + 1), "field", field);
    }
    x.close("Folder");
    if !job.outlines.no_fly_zones.0.is_empty() {
        x.open("Folder", &[]).leaf("name", "No-fly zones");
        for (k, zone) in job.outlines.no_fly_zones.0.iter().enumerate() {
            polygon_placemark(&mut x, &format!("No-fly zone {}", k + 1), NO_FLY_KIND, zone);
        }
        x.close("Folder");
    }
    let sites = job.outlines.landing_sites.iter().enumerate().map(|(k, &site)| (format!("Landing site {}", k + 1), site));
    for (name, [lon, lat]) in job.outlines.home.map(|home| ("Home".to_owned(), home)).into_iter().chain(sites) {
        x.open("Placemark", &[]).leaf("name", &name).open("Point", &[]).leaf("coordinates", &format!("{},{}", number(lon, 7), number(lat, 7))).close("Point").close("Placemark");
    }
    flight_folders(&mut x, job);
    x.close("Document").close("kml");
    x.finish()
}

fn polygon_placemark(x: &mut Xml, name: &str, kind: &str, polygon: &Polygon) {
    x.open("Placemark", &[]).leaf("name", name).leaf("styleUrl", &format!("#{kind}"));
    x.open("ExtendedData", &[]).open("Data", &[("name", "kind")]).leaf("value", kind).close("Data").close("ExtendedData");
    x.open("Polygon", &[]).leaf("altitudeMode", "clampToGround");
    ring(x, "outerBoundaryIs", polygon.exterior());
    for hole in polygon.interiors() {
        ring(x, "innerBoundaryIs", hole);
    }
    x.close("Polygon").close("Placemark");
}

fn ring(x: &mut Xml, boundary: &str, ring: &LineString) {
    let coordinates: Vec<String> = ring.coords().map(|c| format!("{},{}", number(c.x, 7), number(c.y, 7))).collect();
    x.open(boundary, &[]).open("LinearRing", &[]).leaf("coordinates", &coordinates.join(" ")).close("LinearRing").close(boundary);
}

/// The trajectory's flown pieces, a folder per sortie, each with its properties.
fn flight_folders(x: &mut Xml, job: &ExportJob<'_>) {
    let mut sortie = 0;
    let altitude = job.settings.altitude_m;
    for feature in &job.trajectory.features {
        let properties = feature.properties.clone().unwrap_or_default();
        let kind = properties.get("kind").and_then(Value::as_str).unwrap_or_default();
        let Some(GeometryValue::LineString { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) else { continue };
        if !PIECE_STYLES.iter().any(|&(k, ..)| kind_name(k) == kind) {
            continue;
        }
        let this = properties.get("sortie").and_then(Value::as_u64).unwrap_or(1);
        if this != sortie {
            if sortie != 0 {
                x.close("Folder");
            }
            sortie = this;
            x.open("Folder", &[]).leaf("name", &format!("Sortie {sortie}"));
        }
        let seq = properties.get("seq").map(Value::to_string).unwrap_or_default();
        x.open("Placemark", &[]).leaf("name", &format!("{kind} {seq}")).leaf("styleUrl", &format!("#{kind}"));
        x.open("ExtendedData", &[]);
        for (key, value) in &properties {
            let text = value.as_str().map_or_else(|| value.to_string(), str::to_owned);
            x.open("Data", &[("name", key)]).leaf("value", &text).close("Data");
        }
        x.close("ExtendedData");
        let points: Vec<String> =
            coordinates.iter().map(|p| format!("{},{},{}", number(p[0], 7), number(p[1], 7), number(p.as_slice().get(2).copied().unwrap_or(altitude), 2))).collect();
        // over terrain the heights are above mean sea level
        let mode = if properties.get("altitude_reference").and_then(Value::as_str) == Some(TERRAIN_REFERENCE) { "absolute" } else { "relativeToGround" };
        x.open("LineString", &[]).leaf("altitudeMode", mode).leaf("coordinates", &points.join(" ")).close("LineString");
        x.close("Placemark");
    }
    if sortie != 0 {
        x.close("Folder");
    }
}
