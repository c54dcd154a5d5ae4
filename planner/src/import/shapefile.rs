//! Shapefiles, as the zip farm software sends them: `.shp`, `.shx`, `.dbf` and `.prj` of each
//! layer (read with the `shapefile` crate). The `.prj` must say WGS84 longitude/latitude or a
//! WGS84 UTM zone (reprojected with `proj4rs`); anything else is refused rather than guessed. A
//! record whose `kind`, `type`, `class` or `name` attribute says no-fly zone or obstacle becomes
//! one (obstacles take `height_m` or `height`).

use std::io::Cursor;

use geo::{Contains, LineString, Polygon};
use shapefile::dbase::{self, FieldValue};
use shapefile::{PolygonRing, Shape, ShapeReader};

use super::{Collected, Glimpse, Importer, Kind, kind_of_label, ring};
use crate::archive;
use crate::error::InputError;

pub struct ShapefileZip;

impl Importer for ShapefileZip {
    fn id(&self) -> &'static str {
        "shapefile"
    }
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        glimpse.zip_holds(".shp")
    }

    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        if !archive::is_zip(bytes) {
            return Err(InputError::new("invalid_zip", "/", "send a shapefile as a zip of its .shp, .shx, .dbf and .prj files"));
        }
        let files = archive::unzip(bytes)?;
        let find = |name: &str| files.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, c)| c.as_slice());
        let layers: Vec<&str> = files.iter().filter_map(|(n, _)| n.len().checked_sub(4).filter(|&i| n[i..].eq_ignore_ascii_case(".shp")).map(|i| &n[..i])).collect();
        if layers.is_empty() {
            return Err(InputError::new("missing_file_part", "/*.shp", "the zip holds no .shp file"));
        }
        let mut out = Collected::default();
        for layer in layers {
            let part = |ext: &str| -> Result<&[u8], InputError> {
                let name = format!("{layer}.{ext}");
                find(&name).ok_or_else(|| {
                    let why = if ext == "prj" { "without it the coordinates' reference system is unknown" } else { "a shapefile needs its .shp, .shx, .dbf and .prj" };
                    InputError::new("missing_file_part", format!("/{name}"), format!("{name} is missing: {why}"))
                })
            };
            let projection = Projection::from_prj(part("prj")?, &format!("/{layer}.prj"))?;
            read_layer(layer, part("shp")?, part("shx")?, part("dbf")?, &projection, &mut out)?;
        }
        Ok(out)
    }
}

fn read_layer(layer: &str, shp: &[u8], shx: &[u8], dbf: &[u8], projection: &Projection, out: &mut Collected) -> Result<(), InputError> {
    let broken = |ext: &str, e: &dyn std::fmt::Display| InputError::new("invalid_shapefile", format!("/{layer}.{ext}"), format!("not a readable {ext} file: {e}"));
    let shapes = ShapeReader::with_shx(Cursor::new(shp), Cursor::new(shx)).map_err(|e| broken("shp", &e))?;
    let records = dbase::Reader::new(Cursor::new(dbf)).map_err(|e| broken("dbf", &e))?;
    let mut reader = shapefile::Reader::new(shapes, records);
    for (i, item) in reader.iter_shapes_and_records().enumerate() {
        let (shape, record) = item.map_err(|e| broken("shp", &e))?;
        let at = format!("/{layer}.shp/records/{i}");
        let rings: Vec<(bool, Vec<[f64; 2]>)> = match shape {
            Shape::Polygon(p) => p.rings().iter().map(|r| ring_points(r, |q| [q.x, q.y])).collect(),
            Shape::PolygonM(p) => p.rings().iter().map(|r| ring_points(r, |q| [q.x, q.y])).collect(),
            Shape::PolygonZ(p) => p.rings().iter().map(|r| ring_points(r, |q| [q.x, q.y])).collect(),
            Shape::NullShape => continue,
            other => {
                out.warnings.push(format!("{at}: a {} shape was dropped (only polygons are read)", other.shapetype()));
                continue;
            }
        };
        let text = |key: &str| match record.get(key) {
            Some(FieldValue::Character(Some(s))) => Some(s.clone()),
            _ => None,
        };
        let number = |key: &str| match record.get(key) {
            Some(FieldValue::Numeric(Some(v)) | FieldValue::Double(v) | FieldValue::Currency(v)) => Some(*v),
            Some(FieldValue::Float(Some(v))) => Some(f64::from(*v)),
            Some(FieldValue::Integer(v)) => Some(f64::from(*v)),
            _ => None,
        };
        let label: Vec<String> = ["kind", "KIND", "type", "TYPE", "class", "CLASS", "name", "NAME", "Name"].iter().filter_map(|k| text(k)).collect();
        let kind = kind_of_label(&label.join(" ")).unwrap_or(Kind::Field);
        let height = ["height_m", "HEIGHT_M", "height", "HEIGHT"].iter().find_map(|k| number(k));
        let name = ["name", "NAME", "Name"].iter().find_map(|k| text(k));
        for polygon in polygons(rings, projection, &at)? {
            out.add(kind, polygon, height, name.as_deref(), &at);
        }
    }
    Ok(())
}

/// A shapefile ring: outer (clockwise in the file) or hole, and its points.
fn ring_points<P>(r: &PolygonRing<P>, xy: impl Fn(&P) -> [f64; 2]) -> (bool, Vec<[f64; 2]>) {
    match r {
        PolygonRing::Outer(points) => (true, points.iter().map(&xy).collect()),
        PolygonRing::Inner(points) => (false, points.iter().map(&xy).collect()),
    }
}

/// Polygons from a record's rings: each hole joins the outer ring that contains it. A hole
/// outside every outer ring means the rings are wound the wrong way round.
fn polygons(rings: Vec<(bool, Vec<[f64; 2]>)>, projection: &Projection, at: &str) -> Result<Vec<Polygon>, InputError> {
    let mut outers: Vec<Polygon> = Vec::new();
    let mut holes: Vec<LineString> = Vec::new();
    for (k, (outer, points)) in rings.into_iter().enumerate() {
        let points = projection.to_wgs84(points, &format!("{at}/rings/{k}"))?;
        let r = ring(points, &format!("{at}/rings/{k}"))?;
        if outer { outers.push(Polygon::new(r, vec![])) } else { holes.push(r) }
    }
    for (k, hole) in holes.into_iter().enumerate() {
        let inside = Polygon::new(hole.clone(), vec![]);
        let owner = outers.iter_mut().find(|o| o.contains(&inside)).ok_or_else(|| {
            InputError::new(
                "wrong_winding",
                at,
                format!("ring {k} is wound as a hole (counter-clockwise) but lies in no outer ring: shapefiles wind outer rings clockwise and holes counter-clockwise"),
            )
        })?;
        owner.interiors_push(hole);
    }
    Ok(outers)
}

/// The reference systems read from `.prj` files.
enum Projection {
    LonLat,
    Utm(Box<proj4rs::Proj>),
}

impl Projection {
    fn from_prj(bytes: &[u8], part: &str) -> Result<Projection, InputError> {
        let wkt = String::from_utf8_lossy(bytes).to_ascii_uppercase().replace([' ', '_'], "");
        let wgs84 = wkt.contains("WGS1984") || wkt.contains("WGS84");
        let refuse = |why: &str| {
            InputError::new("unsupported_projection", part, format!("{why}; send the shapefile in WGS84 longitude/latitude (EPSG:4326) or a WGS84 UTM zone (EPSG:326xx/327xx)"))
        };
        if !wgs84 {
            return Err(refuse("the .prj names another datum than WGS84"));
        }
        if wkt.starts_with("GEOGCS") {
            return Ok(Projection::LonLat);
        }
        let zone = wkt.find("UTMZONE").map(|i| &wkt[i + 7..]).and_then(|rest| {
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            let hemisphere = rest[digits.len()..].chars().next()?;
            Some((digits.parse::<u8>().ok()?, hemisphere))
        });
        match zone {
            Some((z @ 1..=60, h @ ('N' | 'S'))) => {
                let south = if h == 'S' { " +south" } else { "" };
                let proj =
                    proj4rs::Proj::from_proj_string(&format!("+proj=utm +zone={z}{south} +datum=WGS84 +units=m +no_defs")).map_err(|e| refuse(&format!("UTM zone {z}{h}: {e}")))?;
                Ok(Projection::Utm(Box::new(proj)))
            }
            _ => Err(refuse("the .prj is neither geographic WGS84 nor a WGS84 UTM zone")),
        }
    }

    fn to_wgs84(&self, points: Vec<[f64; 2]>, part: &str) -> Result<Vec<[f64; 2]>, InputError> {
        let Projection::Utm(utm) = self else { return Ok(points) };
        let wgs84 = proj4rs::Proj::from_proj_string("+proj=longlat +datum=WGS84 +no_defs").expect("WGS84 definition");
        points
            .into_iter()
            .map(|[x, y]| {
                let mut c = geo::Coord { x, y };
                proj4rs::transform::transform(utm, &wgs84, &mut c)
                    .map_err(|e| InputError::new("invalid_position", part, format!("({x}, {y}) cannot be reprojected from UTM: {e}")))?;
                Ok([c.x.to_degrees(), c.y.to_degrees()])
            })
            .collect()
    }
}
