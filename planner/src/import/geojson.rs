//! GeoJSON (RFC 7946): a mission document (`area`, `no_fly_zones`, `obstacles`, `home`) or
//! any Polygon, MultiPolygon, Feature or FeatureCollection. Features whose `kind`, `type` or
//! `name` says no-fly zone or obstacle (with `height_m`) become those; a Point named home
//! becomes home.

use geo::{Polygon, Validation};
use geojson::{GeoJson, GeometryValue, JsonObject};
use serde_json::Value;

use super::{Collected, Glimpse, Importer, Kind, kind_of_label, ring};
use crate::error::InputError;

pub struct GeoJsonFile;

impl Importer for GeoJsonFile {
    fn id(&self) -> &'static str {
        "geojson"
    }
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        matches!(glimpse, Glimpse::Json(_))
    }

    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        let value: Value = serde_json::from_slice(bytes).map_err(|e| InputError::new("invalid_geojson", "/", format!("not valid JSON: {e}")))?;
        let mut out = Collected::default();
        if value.get("area").is_some() {
            out.name = value.get("name").and_then(Value::as_str).map(str::to_owned);
            walk(&value["area"], "/area", Kind::Field, &mut out)?;
            for (key, kind) in [("no_fly_zones", Kind::NoFlyZone), ("obstacles", Kind::Obstacle)] {
                if let Some(v) = value.get(key).filter(|v| !v.is_null()) {
                    walk(v, &format!("/{key}"), kind, &mut out)?;
                }
            }
            if let Some(h) = value.get("home").filter(|h| !h.is_null()) {
                out.home = Some(serde_json::from_value(h.clone()).map_err(|_| InputError::new("invalid_position", "/home", "home must be [longitude, latitude]"))?);
            }
        } else {
            walk(&value, "", Kind::Field, &mut out)?;
        }
        Ok(out)
    }
}

fn walk(value: &Value, pointer: &str, default: Kind, out: &mut Collected) -> Result<(), InputError> {
    if value.get("crs").is_some() {
        return Err(InputError::new("crs_not_supported", format!("{pointer}/crs"), "a `crs` member is not allowed (RFC 7946): send WGS84 longitude/latitude"));
    }
    let geojson = serde_json::from_value::<GeoJson>(value.clone()).map_err(|e| InputError::new("invalid_geojson", pointer, format!("not valid GeoJSON: {e}")))?;
    match geojson {
        GeoJson::Geometry(g) => geometry(&g.value, &JsonObject::new(), pointer, default, out),
        GeoJson::Feature(f) => feature(&f, pointer, default, out),
        GeoJson::FeatureCollection(fc) => {
            for (i, f) in fc.features.iter().enumerate() {
                feature(f, &format!("{pointer}/features/{i}"), default, out)?;
            }
            Ok(())
        }
    }
}

fn feature(f: &geojson::Feature, pointer: &str, default: Kind, out: &mut Collected) -> Result<(), InputError> {
    let properties = f.properties.clone().unwrap_or_default();
    match &f.geometry {
        Some(g) => geometry(&g.value, &properties, &format!("{pointer}/geometry"), default, out),
        None => {
            out.warnings.push(format!("{pointer}: a feature without geometry was dropped"));
            Ok(())
        }
    }
}

fn label(properties: &JsonObject) -> String {
    ["kind", "type", "hole_kind", "name"].iter().filter_map(|k| properties.get(*k).and_then(Value::as_str)).collect::<Vec<_>>().join(" ")
}

fn geometry(value: &GeometryValue, properties: &JsonObject, pointer: &str, default: Kind, out: &mut Collected) -> Result<(), InputError> {
    let label = label(properties);
    let kind = if default == Kind::Field { kind_of_label(&label).unwrap_or(Kind::Field) } else { default };
    let height = properties.get("height_m").and_then(Value::as_f64);
    let name = properties.get("name").and_then(Value::as_str);
    match value {
        GeometryValue::Polygon { coordinates } => out.add(kind, polygon(coordinates, pointer)?, height, name, pointer),
        GeometryValue::MultiPolygon { coordinates } => {
            for (i, p) in coordinates.iter().enumerate() {
                let at = format!("{pointer}/coordinates/{i}");
                out.add(kind, polygon(p, &at)?, height, name, &at);
            }
        }
        GeometryValue::GeometryCollection { geometries } => {
            for (i, g) in geometries.iter().enumerate() {
                geometry(&g.value, properties, &format!("{pointer}/geometries/{i}"), default, out)?;
            }
        }
        GeometryValue::Point { coordinates } if label.to_ascii_lowercase().contains("home") => {
            out.home = Some([coordinates[0], coordinates[1]]);
        }
        other => out.warnings.push(format!("{pointer}: a {} was dropped (only polygons and a home point are read)", other.type_name())),
    }
    Ok(())
}

fn polygon(rings: &[Vec<geojson::Position>], pointer: &str) -> Result<Polygon, InputError> {
    let mut rings = rings.iter().enumerate().map(|(i, r)| ring(r.iter().map(|p| [p[0], p[1]]).collect(), &format!("{pointer}/coordinates/{i}")));
    let exterior = rings.next().ok_or_else(|| InputError::new("empty_geometry", pointer, "a polygon without rings"))??;
    let polygon = Polygon::new(exterior, rings.collect::<Result<_, _>>()?);
    if !polygon.is_valid() {
        return Err(InputError::new("invalid_polygon", pointer, "the polygon is not valid (self-intersecting, or a hole outside its exterior)"));
    }
    Ok(polygon)
}
