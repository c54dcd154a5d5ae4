//! Field stage: parse the mission's GeoJSON, validate it, and normalise it into the local frame.
//!
//! Every refusal names the offending member with a JSON pointer into the mission document.

use geo::{Area, BooleanOps, BoundingRect, Contains, Coord, Intersects, LineString, MultiPolygon, Polygon, Rect, Validation, Winding};
use geojson::{GeoJson, GeometryValue};
use serde_json::Value;

use super::error::InputError;
use super::frame::LocalFrame;
use super::mesh::{MAX_TRIANGLES, MeshObject, Up, read_obj};

mod corridor;
pub use corridor::Corridor;

/// Limits that protect the service from absurd or oversized missions.
#[derive(Debug, Clone, Copy)]
pub struct FieldLimits {
    pub max_area_ha: f64,
    pub max_vertices: usize,
    pub max_radius_km: f64,
    pub min_area_m2: f64,
}

impl Default for FieldLimits {
    fn default() -> Self {
        Self { max_area_ha: 10_000.0, max_vertices: 20_000, max_radius_km: 50.0, min_area_m2: 10.0 }
    }
}

/// The geometry of a mission as sent by a client (WGS84, GeoJSON).
#[derive(Debug, Clone)]
pub struct MissionGeometry<'a> {
    pub area: &'a Value,
    pub no_fly_zones: Option<&'a Value>,
    /// Polygon features with a `height_m` property: may be overflown, not flown through.
    pub obstacles: Option<&'a Value>,
    /// Polygon features (or Points with `radius_m`) with `height_m`, optional `base_m` and
    /// `name`: structures to inspect, extruded from `base_m` to `base_m + height_m`.
    pub structures: Option<&'a Value>,
    pub home: Option<[f64; 2]>,
    /// The ground's heights, for plans flown at a height above it.
    pub terrain: Option<&'a crate::terrain::ElevationModel>,
}

impl<'a> MissionGeometry<'a> {
    /// The geometry of a mission document as the API writes one (`area`, `no_fly_zones`,
    /// `obstacles`, `structures`, `home`; a member set to null is absent). A home that is not
    /// `[lon, lat]` is no home: validating the document names that error.
    pub fn of(document: &'a Value) -> Self {
        let member = |name: &str| document.get(name).filter(|v| !v.is_null());
        MissionGeometry {
            area: document.get("area").unwrap_or(&Value::Null),
            no_fly_zones: member("no_fly_zones"),
            obstacles: member("obstacles"),
            structures: member("structures"),
            home: member("home").and_then(|h| serde_json::from_value(h.clone()).ok()),
            terrain: None,
        }
    }

    /// A mission of one area and nothing else.
    pub fn area(area: &'a Value) -> Self {
        MissionGeometry { area, no_fly_zones: None, obstacles: None, structures: None, home: None, terrain: None }
    }
}

/// A validated field in its local frame: polygons with holes, no-fly zones, home.
#[derive(Debug, Clone)]
pub struct Field {
    pub frame: LocalFrame,
    /// Exteriors counter-clockwise, holes clockwise; one polygon per field of the mission.
    pub area: MultiPolygon,
    /// No-fly zones as given (not buffered).
    pub no_fly_zones: MultiPolygon,
    /// Obstacle footprints with their height above ground, metres.
    pub obstacles: Vec<(Polygon, f64)>,
    pub structures: Vec<Structure>,
    pub home: Option<Coord>,
    /// The area's corridors (their outlines are part of `area`, after its polygon fields).
    pub corridors: Vec<Corridor>,
    /// How many of `area`'s polygons are fields given as polygons (the first ones).
    pub polygon_fields: usize,
}

/// A structure: its footprint extruded from `base_m` to `base_m + height_m` above ground.
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    pub name: String,
    pub footprint: Polygon,
    pub base_m: f64,
    pub height_m: f64,
    /// Its feature's JSON pointer in the mission.
    pub pointer: String,
    /// A model's object: its triangles in the local frame (the footprint is their hull).
    pub mesh: Option<Vec<[[f64; 3]; 3]>>,
}

/// Sides of the polygon that stands for a cylinder (a Point with `radius_m`).
const CYLINDER_SIDES: usize = 16;

/// A ring as parsed, with where it came from.
struct RawRing {
    pointer: String,
    positions: Vec<[f64; 2]>,
}

struct RawPolygon {
    pointer: String,
    rings: Vec<RawRing>,
}

impl Field {
    pub fn parse(mission: &MissionGeometry<'_>, limits: &FieldLimits) -> Result<Field, InputError> {
        let (area, raw_corridors) = parse_area(mission.area)?;
        if area.is_empty() && raw_corridors.is_empty() {
            return Err(InputError::new("empty_area", "/area", "the area holds no polygon"));
        }
        let nfz = match mission.no_fly_zones {
            None | Some(Value::Null) => Vec::new(),
            Some(v) => parse_polygons(v, "/no_fly_zones")?,
        };
        let obstacles = match mission.obstacles {
            None | Some(Value::Null) => Vec::new(),
            Some(v) => parse_obstacles(v, "/obstacles")?,
        };
        let structures = match mission.structures {
            None | Some(Value::Null) => Vec::new(),
            Some(v) => parse_structures(v, "/structures")?,
        };
        if let Some(h) = mission.home {
            check_position(&h, "/home")?;
        }
        let structure_polygons = structures.iter().filter_map(|s| if let RawShape::Polygon(p) = &s.shape { Some(p) } else { None });
        let corridor_vertices: usize = raw_corridors.iter().map(|c| c.positions().len()).sum();
        let vertices: usize = corridor_vertices
            + area.iter().chain(&nfz).chain(obstacles.iter().map(|o| &o.0)).chain(structure_polygons).flat_map(|p| &p.rings).map(|r| r.positions.len()).sum::<usize>();
        if vertices > limits.max_vertices {
            return Err(InputError::new("too_many_vertices", "/area", format!("the mission has {vertices} vertices; the limit is {}", limits.max_vertices)));
        }
        let all_points = area
            .iter()
            .chain(&nfz)
            .flat_map(|p| &p.rings)
            .flat_map(|r| r.positions.iter().copied())
            .chain(raw_corridors.iter().flat_map(|c| c.positions().iter().copied()))
            .chain(mission.home);
        let frame = LocalFrame::centred_on(all_points);
        let to_local = |raw: &RawPolygon| local_polygon(&frame, raw, limits);
        let area_polys = area.iter().map(to_local).collect::<Result<Vec<_>, _>>()?;
        let nfz_polys = nfz.iter().map(to_local).collect::<Result<Vec<_>, _>>()?;
        let obstacles = obstacles.iter().map(|(raw, h)| to_local(raw).map(|p| (p, *h))).collect::<Result<Vec<_>, _>>()?;
        let mut placed = Vec::new();
        for s in structures {
            let footprint = match s.shape {
                RawShape::Polygon(raw) => to_local(&raw)?,
                RawShape::Circle { centre, radius_m } => {
                    let c = frame.to_local(centre[0], centre[1]);
                    let ring = (0..CYLINDER_SIDES).map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / CYLINDER_SIDES as f64;
                        Coord { x: c.x + radius_m * a.cos(), y: c.y + radius_m * a.sin() }
                    });
                    Polygon::new(LineString::from_iter(ring), Vec::new())
                }
                RawShape::Model { anchor, rotation_deg, objects } => {
                    placed.extend(place_model(&frame, (anchor, rotation_deg, s.base_m), objects, (&s.name, &s.pointer))?);
                    continue;
                }
            };
            placed.push(Structure { name: s.name, footprint, base_m: s.base_m, height_m: s.height_m, pointer: s.pointer, mesh: None });
        }
        let structures = placed;

        let corridors = raw_corridors.iter().map(|c| corridor::local(&frame, c, limits)).collect::<Result<Vec<_>, _>>()?;
        let mut area_mp = MultiPolygon(area_polys);
        // boxes first: overlaying every pair of thousands of fields would take minutes
        let boxes: Vec<Option<Rect>> = area_mp.0.iter().map(BoundingRect::bounding_rect).collect();
        for (i, a) in area_mp.0.iter().enumerate() {
            for (j, b) in area_mp.0.iter().enumerate().skip(i + 1) {
                let near = matches!((boxes[i], boxes[j]), (Some(x), Some(y)) if x.intersects(&y));
                if near && a.intersection(b).unsigned_area() > 1e-6 * a.unsigned_area().max(1.0) {
                    return Err(InputError::new("overlapping_fields", area[i].pointer.clone(), "this field overlaps another field of the same mission"));
                }
            }
        }
        let polygon_fields = area_mp.0.len();
        if !corridors.is_empty() {
            let outlines: Vec<MultiPolygon> = corridors.iter().map(Corridor::outline).collect();
            for (c, outline) in corridors.iter().zip(&outlines) {
                if !area_mp.0.is_empty() && outline.intersection(&area_mp).unsigned_area() > 1e-6 * c.width_m * c.width_m {
                    return Err(InputError::new("overlapping_fields", c.pointer.clone(), "this corridor overlaps a field of the same mission"));
                }
            }
            // corridors that cross share their crossing
            let joined = outlines.into_iter().reduce(|a, b| a.union(&b)).unwrap_or_else(|| MultiPolygon(Vec::new()));
            area_mp.0.extend(joined.0);
        }
        let total = area_mp.unsigned_area();
        if total < limits.min_area_m2 {
            return Err(InputError::new("area_too_small", "/area", format!("the area to cover is {total:.1} m²; at least {} m² is needed", limits.min_area_m2)));
        }
        if total > limits.max_area_ha * 10_000.0 {
            return Err(InputError::new("area_too_large", "/area", format!("the area is {:.0} ha; the limit is {} ha", total / 10_000.0, limits.max_area_ha)));
        }
        let home = mission.home.map(|h| frame.to_local(h[0], h[1]));
        let nfz_mp = MultiPolygon(nfz_polys);
        if let Some(h) = home
            && nfz_mp.contains(&h)
        {
            return Err(InputError::new("home_in_no_fly_zone", "/home", "the home point lies inside a no-fly zone"));
        }
        Ok(Field { frame, area: area_mp, no_fly_zones: nfz_mp, obstacles, structures, home, corridors, polygon_fields })
    }
}

/// The mission's area: its fields as raw rings, and its corridors (LineString features).
fn parse_area(value: &Value) -> Result<(Vec<RawPolygon>, Vec<corridor::RawCorridor>), InputError> {
    let pointer = "/area";
    let geojson = read_geojson(value, pointer)?;
    let features = match geojson {
        GeoJson::Geometry(g) => {
            if matches!(g.value, GeometryValue::LineString { .. } | GeometryValue::MultiLineString { .. }) {
                return Err(corridor::bare_line(pointer));
            }
            let mut out = Vec::new();
            push_geometry(&g.value, pointer, &mut out)?;
            return Ok((out, Vec::new()));
        }
        GeoJson::Feature(f) => vec![(f, pointer.to_owned())],
        GeoJson::FeatureCollection(fc) => fc.features.into_iter().enumerate().map(|(i, f)| (f, format!("{pointer}/features/{i}"))).collect(),
    };
    let (mut polygons, mut corridors) = (Vec::new(), Vec::new());
    for (f, fp) in features {
        match corridor::of_feature(&f, &fp)? {
            Some(lines) => corridors.extend(lines),
            None => push_feature(&f, &fp, &mut polygons)?,
        }
    }
    Ok((polygons, corridors))
}

/// The GeoJSON at `pointer`, in WGS84 (RFC 7946: no `crs` member).
fn read_geojson(value: &Value, pointer: &str) -> Result<GeoJson, InputError> {
    if value.get("crs").is_some() {
        return Err(InputError::new("crs_not_supported", format!("{pointer}/crs"), "a `crs` member is not allowed (RFC 7946): send WGS84 longitude/latitude"));
    }
    serde_json::from_value(value.clone()).map_err(|e| InputError::new("invalid_geojson", pointer, format!("not valid GeoJSON: {e}")))
}

/// Polygon, MultiPolygon, Feature or FeatureCollection of those, as raw rings.
fn parse_polygons(value: &Value, pointer: &str) -> Result<Vec<RawPolygon>, InputError> {
    let geojson = read_geojson(value, pointer)?;
    let mut out = Vec::new();
    match geojson {
        GeoJson::Geometry(g) => push_geometry(&g.value, pointer, &mut out)?,
        GeoJson::Feature(f) => push_feature(&f, pointer, &mut out)?,
        GeoJson::FeatureCollection(fc) => {
            for (i, f) in fc.features.iter().enumerate() {
                push_feature(f, &format!("{pointer}/features/{i}"), &mut out)?;
            }
        }
    }
    Ok(out)
}

/// Tallest obstacle accepted, metres.
const MAX_OBSTACLE_HEIGHT_M: f64 = 1_000.0;

/// A Feature or FeatureCollection of polygons, each feature with a `height_m` property.
fn parse_obstacles(value: &Value, pointer: &str) -> Result<Vec<(RawPolygon, f64)>, InputError> {
    let geojson = read_geojson(value, pointer)?;
    let features: Vec<(geojson::Feature, String)> = match geojson {
        GeoJson::Feature(f) => vec![(f, pointer.to_owned())],
        GeoJson::FeatureCollection(fc) => fc.features.into_iter().enumerate().map(|(i, f)| (f, format!("{pointer}/features/{i}"))).collect(),
        GeoJson::Geometry(_) => {
            return Err(InputError::new("obstacle_height_missing", pointer, "obstacles are features with a `height_m` property; a bare geometry has none"));
        }
    };
    let mut out = Vec::new();
    for (f, fp) in features {
        let hp = format!("{fp}/properties/height_m");
        let height = f
            .property("height_m")
            .and_then(Value::as_f64)
            .ok_or_else(|| InputError::new("obstacle_height_missing", hp.clone(), "each obstacle needs its height above ground in metres as `height_m`"))?;
        if !(height > 0.0 && height <= MAX_OBSTACLE_HEIGHT_M) {
            return Err(InputError::new("parameter_out_of_range", hp, format!("{height} is outside the accepted range (0, {MAX_OBSTACLE_HEIGHT_M}] m")));
        }
        let mut polys = Vec::new();
        push_feature(&f, &fp, &mut polys)?;
        out.extend(polys.into_iter().map(|p| (p, height)));
    }
    Ok(out)
}

enum RawShape {
    Polygon(RawPolygon),
    Circle {
        centre: [f64; 2],
        radius_m: f64,
    },
    /// An OBJ model whose origin stands at `anchor`, turned clockwise by `rotation_deg`.
    Model {
        anchor: [f64; 2],
        rotation_deg: f64,
        objects: Vec<MeshObject>,
    },
}

/// A model's objects in the local frame: each a structure (named `<name>/<object>` when the
/// model has several) whose footprint is the hull of its vertices.
/// `at`: the anchor, the clockwise turn and the height of the model's origin above the ground;
/// `named`: the feature's name and pointer.
fn place_model(frame: &LocalFrame, at: ([f64; 2], f64, f64), objects: Vec<MeshObject>, named: (&str, &str)) -> Result<Vec<Structure>, InputError> {
    let (anchor, rotation_deg, base_m) = at;
    let (feature, pointer) = named;
    let origin = frame.to_local(anchor[0], anchor[1]);
    // a compass turn is clockwise: the math angle is its negative
    let (sin, cos) = (-rotation_deg.to_radians()).sin_cos();
    let place = |p: [f64; 3]| [origin.x + cos * p[0] - sin * p[1], origin.y + sin * p[0] + cos * p[1], base_m + p[2]];
    let several = objects.len() > 1;
    objects
        .into_iter()
        .map(|o| {
            let triangles: Vec<[[f64; 3]; 3]> = o.triangles.iter().map(|t| t.map(place)).collect();
            let corners = || triangles.iter().flatten();
            let (low, high) = corners().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[2]), hi.max(p[2])));
            if low < -0.01 {
                return Err(InputError::new(
                    "model_below_ground",
                    format!("{pointer}/properties/base_m"),
                    format!("object `{}` reaches {:.2} m below the ground: raise base_m", o.name, -low),
                ));
            }
            let hull = geo::ConvexHull::convex_hull(&geo::MultiPoint::from(corners().map(|p| Coord { x: p[0], y: p[1] }).collect::<Vec<_>>()));
            if geo::Area::unsigned_area(&hull) < 1e-6 {
                return Err(InputError::new("invalid_model", format!("{pointer}/properties/obj"), format!("object `{}` has no extent seen from above", o.name)));
            }
            let name = if several { format!("{feature}/{}", o.name) } else { feature.to_owned() };
            Ok(Structure { name, footprint: hull, base_m: low, height_m: (high - low).max(0.01), pointer: pointer.to_owned(), mesh: Some(triangles) })
        })
        .collect()
}

struct RawStructure {
    name: String,
    shape: RawShape,
    base_m: f64,
    height_m: f64,
    pointer: String,
}

/// A FeatureCollection of structures, each a Polygon (or a Point with `radius_m`, a cylinder
/// such as a silo or a tree) with `height_m`, optional `base_m` (default 0) and a unique
/// `name` (default `structure-<n>`, counted from 1); or a Point with `obj`, a Wavefront OBJ
/// model whose origin stands there, `base_m` above the ground, turned by `rotation_deg`
/// (clockwise), with `up` `z` (default) or `y`.
fn parse_structures(value: &Value, pointer: &str) -> Result<Vec<RawStructure>, InputError> {
    let geojson = read_geojson(value, pointer)?;
    let GeoJson::FeatureCollection(fc) = geojson else {
        return Err(InputError::new("structures_not_a_collection", pointer, "structures are a FeatureCollection of Polygon or Point features"));
    };
    let mut out: Vec<RawStructure> = Vec::new();
    let mut triangles = 0;
    for (i, f) in fc.features.iter().enumerate() {
        let fp = format!("{pointer}/features/{i}");
        let number = |key: &str, required: bool, lo: f64, hi: f64| -> Result<Option<f64>, InputError> {
            let at = format!("{fp}/properties/{key}");
            match f.property(key) {
                None | Some(Value::Null) if !required => Ok(None),
                Some(v) => match v.as_f64() {
                    Some(x) if x >= lo && x <= hi => Ok(Some(x)),
                    _ => Err(InputError::new("parameter_out_of_range", at, format!("{v} is not a number in [{lo}, {hi}]"))),
                },
                None => Err(InputError::new("structure_height_missing", at, format!("each structure needs `{key}` in metres"))),
            }
        };
        let obj = match f.property("obj") {
            None | Some(Value::Null) => None,
            Some(Value::String(text)) => Some(text.as_str()),
            Some(_) => return Err(InputError::new("invalid_model", format!("{fp}/properties/obj"), "`obj` is the text of a Wavefront OBJ file")),
        };
        // a model's height is its own
        let height_m = if obj.is_some() { 0.0 } else { number("height_m", true, 0.1, MAX_OBSTACLE_HEIGHT_M)?.expect("required") };
        let base_m = number("base_m", false, 0.0, MAX_OBSTACLE_HEIGHT_M)?.unwrap_or(0.0);
        let name = match f.property("name") {
            None | Some(Value::Null) => format!("structure-{}", i + 1),
            Some(Value::String(s)) if !s.trim().is_empty() && s.len() <= 200 => s.trim().to_owned(),
            Some(_) => return Err(InputError::new("invalid_name", format!("{fp}/properties/name"), "a structure's name is a text of 1 to 200 characters")),
        };
        if out.iter().any(|s| s.name == name) {
            return Err(InputError::new("structure_name_twice", format!("{fp}/properties/name"), format!("two structures are named `{name}`")));
        }
        let shape = match f.geometry.as_ref().map(|g| &g.value) {
            Some(GeometryValue::Point { coordinates }) => {
                let centre = raw_position(coordinates, &format!("{fp}/geometry/coordinates"))?;
                if let Some(text) = obj {
                    let up = match f.property("up").and_then(Value::as_str) {
                        None | Some("z") => Up::Z,
                        Some("y") => Up::Y,
                        Some(other) => return Err(InputError::new("invalid_model", format!("{fp}/properties/up"), format!("`{other}`: the model's up axis is z or y"))),
                    };
                    let rotation_deg = number("rotation_deg", false, -360.0, 360.0)?.unwrap_or(0.0);
                    let objects = read_obj(text, up).map_err(|e| InputError::new("invalid_model", format!("{fp}/properties/obj"), e))?;
                    triangles += objects.iter().map(|o| o.triangles.len()).sum::<usize>();
                    if triangles > MAX_TRIANGLES {
                        return Err(InputError::new("invalid_model", format!("{fp}/properties/obj"), format!("the mission's models have more than {MAX_TRIANGLES} triangles")));
                    }
                    out.push(RawStructure { name, shape: RawShape::Model { anchor: centre, rotation_deg, objects }, base_m, height_m, pointer: fp });
                    continue;
                }
                let radius_m = number("radius_m", true, 0.1, 500.0)
                    .map_err(|e| {
                        if e.code == "structure_height_missing" { InputError::new("radius_missing", e.pointer, "a Point structure is a cylinder: give its `radius_m`") } else { e }
                    })?
                    .expect("required");
                RawShape::Circle { centre, radius_m }
            }
            _ if obj.is_some() => {
                return Err(InputError::new("model_needs_anchor", format!("{fp}/geometry"), "a model's feature is a Point: where the model's origin stands"));
            }
            _ => {
                let mut polys = Vec::new();
                push_feature(f, &fp, &mut polys)?;
                if polys.len() != 1 {
                    return Err(InputError::new(
                        "structure_not_one_polygon",
                        format!("{fp}/geometry"),
                        "a structure is one Polygon (give each part of a MultiPolygon its own feature)",
                    ));
                }
                RawShape::Polygon(polys.remove(0))
            }
        };
        out.push(RawStructure { name, shape, base_m, height_m, pointer: fp });
    }
    Ok(out)
}

fn push_feature(f: &geojson::Feature, pointer: &str, out: &mut Vec<RawPolygon>) -> Result<(), InputError> {
    match &f.geometry {
        Some(g) => push_geometry(&g.value, &format!("{pointer}/geometry"), out),
        None => Err(InputError::new("missing_geometry", pointer, "this feature has no geometry")),
    }
}

fn push_geometry(g: &GeometryValue, pointer: &str, out: &mut Vec<RawPolygon>) -> Result<(), InputError> {
    match g {
        GeometryValue::Polygon { coordinates } => {
            out.push(raw_polygon(coordinates, &format!("{pointer}/coordinates"))?);
        }
        GeometryValue::MultiPolygon { coordinates } => {
            for (i, p) in coordinates.iter().enumerate() {
                out.push(raw_polygon(p, &format!("{pointer}/coordinates/{i}"))?);
            }
        }
        other => {
            return Err(InputError::new("unsupported_geometry", pointer, format!("expected a Polygon or MultiPolygon, found a {}", other.type_name())));
        }
    }
    Ok(())
}

fn raw_polygon(rings: &[Vec<geojson::Position>], pointer: &str) -> Result<RawPolygon, InputError> {
    if rings.is_empty() {
        return Err(InputError::new("empty_polygon", pointer, "a polygon needs an exterior ring"));
    }
    let rings = rings
        .iter()
        .enumerate()
        .map(|(r, ring)| {
            let rp = format!("{pointer}/{r}");
            let positions = raw_positions(ring, &rp)?;
            check_ring(&positions, &rp)?;
            Ok(RawRing { pointer: rp, positions })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RawPolygon { pointer: pointer.to_owned(), rings })
}

/// GeoJSON positions as `[lon, lat]`, each checked; `pointer` names the array.
pub(crate) fn raw_positions(positions: &[geojson::Position], pointer: &str) -> Result<Vec<[f64; 2]>, InputError> {
    positions.iter().enumerate().map(|(k, pos)| raw_position(pos, &format!("{pointer}/{k}"))).collect()
}

/// `[lon, lat]` of a GeoJSON position at `pointer`, checked.
fn raw_position(position: &geojson::Position, pointer: &str) -> Result<[f64; 2], InputError> {
    let s = position.as_slice();
    if s.len() < 2 {
        return Err(InputError::new("invalid_position", pointer, "a position needs a longitude and a latitude"));
    }
    let p = [s[0], s[1]];
    check_position(&p, pointer)?;
    Ok(p)
}

pub fn check_position(p: &[f64; 2], pointer: &str) -> Result<(), InputError> {
    let [lon, lat] = *p;
    if !lon.is_finite() || !lat.is_finite() {
        return Err(InputError::new("invalid_position", pointer, "coordinates must be finite numbers"));
    }
    if lat.abs() > 90.0 && lon.abs() <= 90.0 {
        return Err(InputError::new("coordinates_look_swapped", pointer, format!("latitude {lat} is outside [-90, 90]; positions are [longitude, latitude]: these look swapped")));
    }
    if lat.abs() > 90.0 {
        return Err(InputError::new("coordinate_out_of_range", pointer, format!("latitude {lat} is outside [-90, 90]")));
    }
    if lon.abs() > 180.0 {
        return Err(InputError::new("coordinate_out_of_range", pointer, format!("longitude {lon} is outside [-180, 180]")));
    }
    Ok(())
}

fn check_ring(positions: &[[f64; 2]], pointer: &str) -> Result<(), InputError> {
    if positions.len() < 4 {
        return Err(InputError::new("ring_too_short", pointer, format!("a ring needs at least 4 positions (3 distinct, then the first again); this one has {}", positions.len())));
    }
    if positions.first() != positions.last() {
        return Err(InputError::new("ring_not_closed", pointer, "the ring is not closed: its last position must repeat the first"));
    }
    // all positions on one line in longitude/latitude: zero area (in the local frame such a
    // ring would become a sliver of a few square metres)
    let a = positions[0];
    let far = positions.iter().copied().max_by(|p, q| {
        let d = |r: &[f64; 2]| (r[0] - a[0]).hypot(r[1] - a[1]);
        d(p).total_cmp(&d(q))
    });
    let on_one_line = far.is_none_or(|b| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        positions.iter().all(|p| ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() <= 1e-9 * len * len)
    });
    if on_one_line {
        return Err(InputError::new("degenerate_ring", pointer, "the ring has zero area: its positions lie on one line"));
    }
    Ok(())
}

/// Converts to the local frame, removes repeated and collinear vertices, orients the rings
/// (exterior CCW, holes CW) and validates the result.
fn local_polygon(frame: &LocalFrame, raw: &RawPolygon, limits: &FieldLimits) -> Result<Polygon, InputError> {
    let max_r = limits.max_radius_km * 1000.0;
    let mut rings = Vec::with_capacity(raw.rings.len());
    for ring in &raw.rings {
        let mut coords = Vec::with_capacity(ring.positions.len());
        for (k, p) in ring.positions.iter().enumerate() {
            let c = frame.to_local(p[0], p[1]);
            if c.x.hypot(c.y) > max_r {
                return Err(InputError::new(
                    "mission_too_wide",
                    format!("{}/{k}", ring.pointer),
                    format!("this position is more than {} km from the mission's centre", limits.max_radius_km),
                ));
            }
            coords.push(c);
        }
        let cleaned = clean_ring(coords);
        if cleaned.len() < 3 {
            return Err(InputError::new("degenerate_ring", ring.pointer.clone(), "the ring has fewer than 3 distinct, non-collinear vertices (zero area)"));
        }
        rings.push(cleaned);
    }
    let mut rings = rings.into_iter();
    let exterior = LineString::from(rings.next().expect("at least one ring"));
    let holes: Vec<LineString> = rings.map(LineString::from).collect();
    let mut polygon = Polygon::new(exterior, holes);
    polygon.exterior_mut(|e| e.make_ccw_winding());
    polygon.interiors_mut(|hs| hs.iter_mut().for_each(|h| h.make_cw_winding()));
    validate(&polygon, raw, frame)?;
    Ok(polygon)
}

fn validate(polygon: &Polygon, raw: &RawPolygon, frame: &LocalFrame) -> Result<(), InputError> {
    use geo::algorithm::validation::{InvalidPolygon, RingRole};
    let Err(problems) = polygon.check_validation() else { return Ok(()) };
    let ring_pointer = |role: &RingRole| match role {
        RingRole::Exterior => format!("{}/0", raw.pointer),
        RingRole::Interior(i) => format!("{}/{}", raw.pointer, i + 1),
    };
    let first = problems;
    Err(match &first {
        InvalidPolygon::SelfIntersection(role) => {
            let ring = ring_of(polygon, role);
            let at = self_intersection(ring)
                .map(|c| {
                    let ll = frame.to_wgs84(c);
                    format!(" near [{:.7}, {:.7}]", ll[0], ll[1])
                })
                .unwrap_or_default();
            InputError::new("self_intersection", ring_pointer(role), format!("the ring crosses itself{at}"))
        }
        InvalidPolygon::InteriorRingNotContainedInExteriorRing(role) => {
            InputError::new("hole_outside_shell", ring_pointer(role), "this hole is not inside its polygon's exterior ring")
        }
        InvalidPolygon::IntersectingRingsOnALine(a, _) | InvalidPolygon::IntersectingRingsOnAnArea(a, _) => {
            InputError::new("rings_intersect", ring_pointer(a), format!("rings of this polygon cross or overlap: {first}"))
        }
        InvalidPolygon::TooFewPointsInRing(role) | InvalidPolygon::NonFiniteCoord(role, _) => InputError::new("degenerate_ring", ring_pointer(role), first.to_string()),
    })
}

fn ring_of<'a>(polygon: &'a Polygon, role: &geo::algorithm::validation::RingRole) -> &'a LineString {
    match role {
        geo::algorithm::validation::RingRole::Exterior => polygon.exterior(),
        geo::algorithm::validation::RingRole::Interior(i) => &polygon.interiors()[*i],
    }
}

/// Where a ring crosses itself (first pair of non-adjacent edges that intersect).
fn self_intersection(ring: &LineString) -> Option<Coord> {
    use geo::algorithm::line_intersection::{LineIntersection, line_intersection};
    let lines: Vec<geo::Line> = ring.lines().collect();
    let n = lines.len();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            match line_intersection(lines[i], lines[j]) {
                Some(LineIntersection::SinglePoint { intersection, .. }) => return Some(intersection),
                Some(LineIntersection::Collinear { intersection }) => return Some(intersection.start),
                None => {}
            }
        }
    }
    None
}

/// Drops the closing vertex, repeated vertices (< 1 mm apart), spikes and collinear vertices
/// (docs/methods.md, decomposition §3, steps 2–3). Each pass is linear; passes repeat only while a
/// removal makes a new vertex redundant.
fn clean_ring(mut pts: Vec<Coord>) -> Vec<Coord> {
    pts.pop(); // closing vertex
    let close = |a: Coord, b: Coord| (a.x - b.x).hypot(a.y - b.y) < 1e-3;
    let mut out: Vec<Coord> = Vec::with_capacity(pts.len());
    for p in pts {
        if !out.last().is_some_and(|&l| close(l, p)) {
            out.push(p);
        }
    }
    while out.len() > 1 && close(out[0], out[out.len() - 1]) {
        out.pop();
    }
    loop {
        let n = out.len();
        if n < 3 {
            return out;
        }
        let redundant: Vec<bool> = (0..n).map(|i| is_redundant(out[(i + n - 1) % n], out[i], out[(i + 1) % n])).collect();
        if !redundant.contains(&true) {
            return out;
        }
        // never drop two neighbours in one pass: the test of each assumed the other stays
        let mut next = Vec::with_capacity(n);
        let mut dropped_previous = false;
        for i in 0..n {
            if redundant[i] && !dropped_previous && !(i == n - 1 && redundant[0]) {
                dropped_previous = true;
            } else {
                dropped_previous = false;
                next.push(out[i]);
            }
        }
        out = next;
    }
}

/// A vertex on the straight line through its neighbours (either way: straight or spike).
fn is_redundant(p: Coord, v: Coord, q: Coord) -> bool {
    let (a, b) = (v - p, q - v);
    let cross = a.x * b.y - a.y * b.x;
    cross.abs() <= 1e-9 * a.x.hypot(a.y) * b.x.hypot(b.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Winding;
    use serde_json::json;

    fn parse(area: Value) -> Result<Field, InputError> {
        Field::parse(&MissionGeometry { area: &area, no_fly_zones: None, obstacles: None, structures: None, home: None, terrain: None }, &FieldLimits::default())
    }

    fn square(lon: f64, lat: f64, d: f64) -> Value {
        json!([[lon, lat], [lon + d, lat], [lon + d, lat + d], [lon, lat + d], [lon, lat]])
    }

    #[test]
    fn accepts_a_polygon_with_a_hole_in_either_winding() {
        let f = parse(json!({"type": "Polygon", "coordinates": [square(5.0, 52.0, 0.01), square(5.004, 52.004, 0.001)]})).unwrap();
        let p = &f.area.0[0];
        assert!(p.exterior().is_ccw());
        assert!(p.interiors()[0].is_cw());
        let area = f.area.unsigned_area();
        assert!(area > 700_000.0 && area < 800_000.0, "{area}");
    }

    #[test]
    fn reports_where_the_coordinate_is_wrong() {
        let e = parse(json!({"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.1, 95.0], [5.1, 52.1], [5.0, 52.0]]]})).unwrap_err();
        assert_eq!(e.pointer, "/area/coordinates/0/1");
        assert_eq!(e.code, "coordinates_look_swapped");
        let e = parse(json!({"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[5.0, 52.0], [185.0, 52.0], [5.1, 52.1], [5.0, 52.0]]]}}))
            .unwrap_err();
        assert_eq!(e.pointer, "/area/geometry/coordinates/0/1");
        assert_eq!(e.code, "coordinate_out_of_range");
    }

    #[test]
    fn refuses_bowties_unclosed_rings_and_holes_outside() {
        let bowtie = json!({"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.01, 52.01], [5.01, 52.0], [5.0, 52.01], [5.0, 52.0]]]});
        let e = parse(bowtie).unwrap_err();
        assert_eq!(e.code, "self_intersection");
        assert!(e.detail.contains("near [5.0050000"), "{}", e.detail);
        let open = json!({"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.01, 52.0], [5.01, 52.01], [5.0, 52.01]]]});
        assert_eq!(parse(open).unwrap_err().code, "ring_not_closed");
        let outside = json!({"type": "Polygon", "coordinates": [square(5.0, 52.0, 0.01), square(5.02, 52.0, 0.001)]});
        let e = parse(outside).unwrap_err();
        assert_eq!((e.code, e.pointer.as_str()), ("hole_outside_shell", "/area/coordinates/1"));
    }

    #[test]
    fn refuses_zero_area_and_oversized_fields() {
        let spike = json!({"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.01, 52.0], [5.0, 52.0], [5.0, 52.0]]]});
        assert_eq!(parse(spike).unwrap_err().code, "degenerate_ring");
        let line = json!({"type": "Polygon", "coordinates": [[[5.0, 52.0], [5.01, 52.0], [5.02, 52.0], [5.0, 52.0]]]});
        assert_eq!(parse(line).unwrap_err().code, "degenerate_ring");
        let tiny = json!({"type": "Polygon", "coordinates": [square(5.0, 52.0, 0.00001)]});
        assert_eq!(parse(tiny).unwrap_err().code, "area_too_small");
        let huge = json!({"type": "Polygon", "coordinates": [square(5.0, 52.0, 0.5)]});
        assert_eq!(parse(huge).unwrap_err().code, "area_too_large");
        let point = json!({"type": "Point", "coordinates": [5.0, 52.0]});
        assert_eq!(parse(point).unwrap_err().code, "unsupported_geometry");
    }

    #[test]
    fn removes_collinear_repeated_and_spike_vertices() {
        let c = |x, y| Coord { x, y };
        let ring = vec![c(0.0, 0.0), c(5.0, 0.0), c(10.0, 0.0), c(10.0, 0.0), c(10.0, 10.0), c(10.0, 15.0), c(10.0, 12.0), c(0.0, 10.0), c(0.0, 0.0)];
        assert_eq!(clean_ring(ring), vec![c(0.0, 0.0), c(10.0, 0.0), c(10.0, 12.0), c(0.0, 10.0)]);
    }
}
