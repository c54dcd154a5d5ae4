//! The flight path as an RFC 7946 FeatureCollection in flight order: the trajectory every
//! other format is written from.

use std::collections::BTreeMap;

use geo::{Area, Coord, MultiPolygon};
use geojson::{Feature, FeatureCollection, Geometry, GeometryValue, JsonObject, Position};
use serde_json::json;

use super::{ALL_METHODS, ExportJob, Exporter, Format};
use crate::energy::PathEstimate;
use crate::error::InputError;
use crate::frame::LocalFrame;
use crate::inspection::InspectionPlan;
use crate::metrics::Photo;
use crate::params::math_to_bearing;
use crate::path::{FlightPath, Look};

fn round(v: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    (v * f).round() / f
}

fn position(frame: &LocalFrame, c: Coord, altitude_m: Option<f64>) -> Position {
    let [lon, lat] = frame.to_wgs84(c);
    let (lon, lat) = (round(lon, 7), round(lat, 7));
    match altitude_m {
        Some(z) => Position::from([lon, lat, round(z, 2)]),
        None => Position::from([lon, lat]),
    }
}

pub(crate) fn feature(value: GeometryValue, properties: serde_json::Value) -> Feature {
    let properties: JsonObject = match properties {
        serde_json::Value::Object(o) => o,
        _ => JsonObject::new(),
    };
    Feature { geometry: Some(Geometry::new(value)), properties: Some(properties), ..Default::default() }
}

/// The `altitude_reference` of a flown piece whose heights are above mean sea level, laid
/// over the ground (without it: above home); such a piece's `ground_m` gives the ground's
/// height under each of its points.
pub const TERRAIN_REFERENCE: &str = "terrain";

/// One vehicle's flight, as the trajectory shows it.
pub struct VehicleFlight<'a> {
    pub sorties: &'a [FlightPath],
    /// One per sortie.
    pub estimates: &'a [PathEstimate],
    /// Energy one battery gives above its reserve.
    pub usable_j: f64,
    /// Without a home: where each battery runs out (ends of pieces, in flight order).
    pub battery_swaps: &'a [Coord],
    /// Fleet: the drone's index, written on each of its features.
    pub vehicle: Option<usize>,
    /// Over terrain: how each sortie lies over the ground (empty: flown at one altitude above
    /// home).
    pub laid: &'a [crate::terrain::profile::Laid],
}

/// What the trajectory shows besides the flown pieces.
pub struct Marks<'a> {
    pub photos: Option<&'a [Photo]>,
    /// The part of the field (outside the no-fly zones) no swath covers.
    pub uncovered: &'a MultiPolygon,
}

/// Each flight's sorties' pieces in flight order, each with its sortie (1-based), speeds, time
/// and energy, and the battery left at its end (as a share of the usable energy); a fleet's
/// features carry `vehicle`, and `seq` and `sortie` count each drone's own. Without a home, a
/// Point of kind `battery_swap` marks each place a battery runs out (the end of a piece at one
/// of `battery_swaps`, in order); the count of the battery left starts again after it. Then the
/// photos (a MultiPoint) and the uncovered ground (a MultiPolygon).
pub fn feature_collection(frame: &LocalFrame, flights: &[VehicleFlight<'_>], altitude_m: Option<f64>, marks: &Marks<'_>) -> FeatureCollection {
    let mut features = Vec::new();
    for flight in flights {
        features.extend(flight_features(frame, flight, altitude_m));
    }
    let Marks { photos, uncovered } = *marks;
    if let Some(photos) = photos {
        // over terrain the photos' heights differ from point to point: they are given in 2D
        let photo_altitude = if flights.iter().any(|f| !f.laid.is_empty()) { None } else { altitude_m };
        features.extend(photo_features(frame, photos, photo_altitude));
    }
    if !uncovered.0.is_empty() {
        let ring = |r: &geo::LineString| r.coords().map(|&c| position(frame, c, None)).collect::<Vec<_>>();
        let coordinates = uncovered.0.iter().map(|p| std::iter::once(ring(p.exterior())).chain(p.interiors().iter().map(ring)).collect()).collect();
        let area = uncovered.unsigned_area();
        features.push(feature(GeometryValue::MultiPolygon { coordinates }, json!({"kind": "uncovered", "area_m2": round(area, 1)})));
    }
    FeatureCollection { bbox: None, features, foreign_members: None }
}

/// The photos as MultiPoints of kind `photos`: one for all of them, or on an oblique plan one
/// per pass, with the pass, the gimbal's pitch and the camera's heading (a compass bearing;
/// none on the nadir pass, which faces the way it flies).
fn photo_features(frame: &LocalFrame, photos: &[Photo], altitude_m: Option<f64>) -> Vec<Feature> {
    // by pass, the photos of no pass first (a plan without passes: all of them, maybe none)
    let mut passes: BTreeMap<Option<usize>, (Option<Look>, Vec<Position>)> = BTreeMap::new();
    for photo in photos {
        passes.entry(photo.look.map(|l| l.pass)).or_insert((photo.look, Vec::new())).1.push(position(frame, photo.at, altitude_m));
    }
    if passes.is_empty() {
        passes.insert(None, (None, Vec::new()));
    }
    passes
        .into_values()
        .map(|(look, taken)| {
            let mut props = json!({"kind": "photos", "count": taken.len()});
            if let Some(look) = look {
                add_look(&mut props, &look);
            }
            feature(GeometryValue::MultiPoint { coordinates: taken }, props)
        })
        .collect()
}

/// A pass's camera, as the trajectory says it: the pass, the gimbal's pitch, and on an oblique
/// pass the compass bearing the camera faces.
fn add_look(props: &mut serde_json::Value, look: &Look) {
    props["pass"] = json!(look.pass);
    props["gimbal_pitch_deg"] = json!(round(look.gimbal_pitch_deg, 2));
    if let Some(heading) = look.heading {
        props["camera_heading_deg"] = json!(round(math_to_bearing(heading), 2));
    }
}

/// An inspection in flight order: each leg a LineString with heights (kind `transit`), each
/// viewpoint a Point (kind `viewpoint`) with its camera's yaw (compass bearing) and gimbal
/// pitch, what it newly sees, and the time and energy on arrival; with `show_points`, the
/// points of interest seen and unseen as two MultiPoints (kinds `seen` and `unseen`).
pub fn inspection_collection(frame: &LocalFrame, plan: &InspectionPlan, show_points: bool) -> FeatureCollection {
    let at = |p: [f64; 3]| position(frame, Coord { x: p[0], y: p[1] }, Some(p[2]));
    let mut features = Vec::new();
    for (i, leg) in plan.legs.iter().enumerate() {
        let props = json!({
            "seq": features.len(),
            "kind": "transit",
            "length_m": round(leg.length_m, 2),
            // the mean: a leg is flown from rest to rest
            "speed_mps": round(if leg.time_s > 0.0 { leg.length_m / leg.time_s } else { 0.0 }, 2),
            "duration_s": round(leg.time_s, 2),
            "energy_j": round(leg.energy_j, 1),
        });
        features.push(feature(GeometryValue::LineString { coordinates: leg.points.iter().map(|&p| at(p)).collect() }, props));
        if let Some(v) = plan.viewpoints.get(i) {
            let props = json!({
                "seq": features.len(),
                "kind": "viewpoint",
                "order": i + 1,
                "altitude_m": round(v.at[2], 2),
                "yaw_deg": round(v.yaw_deg, 2),
                "gimbal_pitch_deg": round(v.gimbal_pitch_deg, 2),
                "new_pois_seen": v.new_pois,
                "weighted_gain": round(v.weighted_gain, 3),
                "eta_s": round(v.eta_s, 2),
                "energy_j": round(v.energy_j, 1),
            });
            features.push(feature(GeometryValue::Point { coordinates: at(v.at) }, props));
        }
    }
    if show_points {
        for (kind, seen) in [("seen", true), ("unseen", false)] {
            let points: Vec<Position> = plan.pois.iter().zip(&plan.seen).filter(|(_, s)| **s == seen).map(|(p, _)| at(p.at)).collect();
            let count = points.len();
            features.push(feature(GeometryValue::MultiPoint { coordinates: points }, json!({"kind": kind, "count": count})));
        }
    }
    FeatureCollection { bbox: None, features, foreign_members: None }
}

/// The features of one vehicle's flight (see [`feature_collection`]).
fn flight_features(frame: &LocalFrame, flight: &VehicleFlight<'_>, altitude_m: Option<f64>) -> Vec<Feature> {
    let mut features = Vec::new();
    let mut swaps = flight.battery_swaps.iter().peekable();
    let push = |features: &mut Vec<Feature>, geometry: GeometryValue, mut props: serde_json::Value| {
        props["seq"] = json!(features.len());
        if let Some(v) = flight.vehicle {
            props["vehicle"] = json!(v);
        }
        features.push(feature(geometry, props));
    };
    for (k, (sortie, estimate)) in flight.sorties.iter().zip(flight.estimates).enumerate() {
        // take-off is spent before the first piece
        let mut used = estimate.takeoff.energy_j;
        for (j, (piece, e)) in sortie.pieces.iter().zip(&estimate.pieces).enumerate() {
            used += e.energy_j;
            let coords = piece.points.iter().enumerate().map(|(i, &c)| position(frame, c, piece.z.get(i).copied().or(altitude_m))).collect();
            let mut props = json!({
                "sortie": k + 1,
                "kind": piece.kind,
                "length_m": round(piece.length(), 2),
                "duration_s": round(e.duration_s, 2),
                "energy_j": round(e.energy_j, 2),
                "speed_mps": round(e.speed_mps, 2),
                "v_in_mps": round(e.v_in_mps, 2),
                "v_out_mps": round(e.v_out_mps, 2),
                "cumulative_energy_j": round(used, 1),
                "battery_remaining": round(1.0 - used / flight.usable_j, 4),
            });
            if let Some(z) = altitude_m {
                props["altitude_m"] = json!(round(z, 2));
            }
            if let Some(w) = e.wind {
                props["ground_speed_mps"] = json!(round(w.ground_speed_mps, 2));
                props["airspeed_mps"] = json!(round(w.airspeed_mps, 2));
                props["crab_deg"] = json!(round(w.crab_deg, 1));
            }
            if let Some(stop) = piece.refill_s {
                props["refill_s"] = json!(stop);
                props["refill"] = json!(true);
            }
            if piece.tramline {
                props["tramline"] = json!(true);
            }
            if let Some(look) = &piece.look {
                add_look(&mut props, look);
            }
            if let Some(shape) = piece.shape {
                props["turn_type"] = json!(shape);
            }
            if let Some(laid) = flight.laid.get(k) {
                let [lo, hi] = laid.piece_heights[j];
                props["altitude_reference"] = json!(TERRAIN_REFERENCE);
                props["min_height_above_ground_m"] = json!(round(lo, 2));
                props["max_height_above_ground_m"] = json!(round(hi, 2));
                props["ground_m"] = json!(laid.point_ground[j].iter().map(|&g| round(g, 2)).collect::<Vec<_>>());
            }
            push(&mut features, GeometryValue::LineString { coordinates: coords }, props);
            if swaps.peek().is_some_and(|&&c| c == piece.end()) {
                swaps.next();
                let battery = flight.battery_swaps.len() - swaps.len();
                let props = json!({"kind": "battery_swap", "battery": battery, "cumulative_energy_j": round(used, 1)});
                push(&mut features, GeometryValue::Point { coordinates: position(frame, piece.end(), altitude_m) }, props);
                used = estimate.takeoff.energy_j;
            }
        }
    }
    features
}

/// The trajectory as stored.
pub struct GeoJsonFile;

impl Exporter for GeoJsonFile {
    fn format(&self) -> &'static Format {
        &Format {
            id: "geojson",
            label: "GeoJSON",
            media_type: "application/geo+json",
            extension: ".geojson",
            one_flight_per_file: false,
            firmware_commands: false,
            plans: ALL_METHODS,
            verbatim: true,
            waypoint_limit: false,
            default_max_waypoints: None,
        }
    }
    fn write(&self, job: &ExportJob<'_>, _sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(vec![serde_json::to_vec(job.trajectory).expect("JSON")])
    }
}
