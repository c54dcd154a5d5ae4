//! QGroundControl `.plan` (JSON): the sortie as plain `SimpleItem`s, an inclusion fence round
//! the fields and every point the sortie flies (home, turns and transits included) with a
//! margin, and the no-fly zones as exclusion fences (docs/methods.md, interop §3). Written by
//! hand with serde_json: no crate writes this format.

use geo::algorithm::buffer::Buffer;
use geo::{ConvexHull, Coord, LineString, MultiPoint, Point, Simplify, Winding};
use serde_json::{Value, json};

use super::mission_items::{self, FRAME_GLOBAL, FRAME_MISSION, FRAME_TERRAIN, MissionItem, launch, mav_autopilot, mav_type};
use super::{ALL_METHODS, ExportJob, Exporter, Format};
use crate::error::InputError;
use crate::frame::LocalFrame;

/// How far the inclusion fence lies outside the fields and every point flown: an autopilot with
/// its fence enabled arms at home and flies the turns without a breach.
pub const FENCE_MARGIN_M: f64 = 30.0;

pub struct QgcPlan;

/// QGroundControl's `AltitudeMode`s: relative to home, above mean sea level, above the ground
/// under the waypoint (the vehicle's terrain frame).
const ALTITUDE_RELATIVE: u8 = 1;
const ALTITUDE_AMSL: u8 = 2;
const ALTITUDE_TERRAIN_FRAME: u8 = 4;

fn altitude_mode(frame: u8) -> u8 {
    match frame {
        FRAME_GLOBAL => ALTITUDE_AMSL,
        FRAME_TERRAIN => ALTITUDE_TERRAIN_FRAME,
        _ => ALTITUDE_RELATIVE,
    }
}

impl Exporter for QgcPlan {
    fn format(&self) -> &'static Format {
        &Format {
            id: "plan",
            label: "QGroundControl (.plan)",
            media_type: "application/json",
            extension: ".plan",
            one_flight_per_file: true,
            firmware_commands: true,
            plans: ALL_METHODS,
            verbatim: false,
            waypoint_limit: true,
            default_max_waypoints: None,
        }
    }

    fn write(&self, job: &ExportJob<'_>, sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(mission_items::limited_items(job, sortie)?.iter().map(|items| file(job, sortie, items)).collect())
    }
}

/// The `.plan` of `items`, flown in `sortie`.
fn file(job: &ExportJob<'_>, sortie: usize, items: &[MissionItem]) -> Vec<u8> {
    let pieces = &job.flight.sorties[sortie];
    let s = &job.settings;
    let [lon, lat] = launch(pieces, job.bases(sortie).home);
    let plan_mode = items.iter().find(|i| i.frame != FRAME_MISSION).map_or(ALTITUDE_RELATIVE, |i| altitude_mode(i.frame));
    // over terrain, home is where the ground is; otherwise the altitudes are relative to it
    let home_altitude = job.flight.launch_ground_m(sortie).unwrap_or(0.0);
    let items: Vec<Value> = items.iter().enumerate().map(|(k, item)| simple_item(item, k + 1)).collect();
    let mut fences: Vec<Value> = vec![fence(&inclusion_ring(job, sortie), true)];
    fences.extend(job.outlines.no_fly_zones.0.iter().map(|p| fence(p.exterior(), false)));
    let plan = json!({
        "fileType": "Plan",
        "version": 1,
        "groundStation": "coverplan",
        "mission": {
            "version": 2,
            "firmwareType": mav_autopilot(s.firmware),
            "vehicleType": mav_type(s.kind),
            "cruiseSpeed": s.cruise_speed_mps,
            "hoverSpeed": s.cruise_speed_mps,
            "globalPlanAltitudeMode": plan_mode,
            "plannedHomePosition": [lat, lon, home_altitude],
            "items": items,
        },
        "geoFence": {"version": 2, "circles": [], "polygons": fences},
        "rallyPoints": {"version": 2, "points": []},
    });
    (serde_json::to_string_pretty(&plan).expect("JSON") + "\n").into_bytes()
}

fn simple_item(item: &MissionItem, jump_id: usize) -> Value {
    let [lat, lon, alt] = item.position.unwrap_or([0.0; 3]);
    let params: Vec<Value> = item.params.iter().map(|p| p.map_or(Value::Null, |v| json!(v))).chain([json!(lat), json!(lon), json!(alt)]).collect();
    let mut value = json!({
        "type": "SimpleItem",
        "autoContinue": true,
        "command": item.command,
        "doJumpId": jump_id,
        "frame": item.frame,
        "params": params,
    });
    if item.frame != FRAME_MISSION {
        value["Altitude"] = json!(alt);
        value["AltitudeMode"] = json!(altitude_mode(item.frame));
        value["AMSLAltAboveTerrain"] = Value::Null;
    }
    value
}

/// The convex hull of the fields, home and every point of the sortie, grown by
/// [`FENCE_MARGIN_M`], in WGS84.
fn inclusion_ring(job: &ExportJob<'_>, sortie: usize) -> LineString {
    let flown = job.flight.sorties[sortie].iter().flat_map(|p| p.points.iter().map(|q| [q[0], q[1]]));
    let outlines = job.outlines.fields.0.iter().flat_map(|p| p.exterior().0.iter().map(|c| [c.x, c.y]));
    let points: Vec<[f64; 2]> = flown.chain(outlines).chain(job.bases(sortie).home).collect();
    let frame = LocalFrame::centred_on(points.iter().copied());
    let local = MultiPoint(points.iter().map(|&[lon, lat]| Point(frame.to_local(lon, lat))).collect());
    let grown = local.convex_hull().buffer(FENCE_MARGIN_M);
    // a round join's arc in steps of centimetres: a few metres inside it keeps the fence short
    let ring = grown.0.first().map_or_else(|| LineString(vec![]), |p| p.exterior().simplify(1.0));
    LineString(ring.0.iter().map(|&c: &Coord| frame.to_wgs84(c)).map(|[x, y]| Coord { x, y }).collect())
}

/// A fence polygon, clockwise as QGroundControl documents them, `[lat, lon]`, not closed.
fn fence(ring: &LineString, inclusion: bool) -> Value {
    let mut ring = ring.clone();
    ring.make_cw_winding();
    let points: Vec<Value> = ring.0[..ring.0.len() - 1].iter().map(|c| json!([c.y, c.x])).collect();
    json!({"inclusion": inclusion, "polygon": points, "version": 1})
}
