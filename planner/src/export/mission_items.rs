//! MAVLink mission items of one sortie, shared by the QGroundControl `.plan` and the
//! `QGC WPL 110` file (docs/methods.md, interop §4): take-off, a speed change wherever the speed
//! changes, a waypoint at every line end and turn point, the camera triggered by distance on
//! sweeps only (from the plan's first photo of a line to its last, at the line's own step), and
//! a return to launch (or a landing, without a home) at the end. At an
//! inspection's viewpoint the vehicle holds, turns to the viewpoint's yaw, points the gimbal
//! and takes one picture. On an oblique plan's pass the gimbal is pitched where the pass begins
//! and the vehicle holds the pass's heading; past a controller's waypoint limit the items are
//! cut into missions ([`limited_items`]).

use super::flight::{FlownPiece, PlanPhoto, ViewAction, Waypoint, photos_by_pass, waypoints};
use super::follower;
use super::{AltitudeFrame, Bases, ExportJob, Firmware, FlightSettings};
use crate::error::InputError;
use crate::params::Landing;
use rstar::{AABB, RTree};

use crate::frame::LocalFrame;
use crate::path::PieceKind;
use crate::vehicle::{TAKEOFF_PITCH_DEG, VehicleKind, climb_out_m};

pub const NAV_WAYPOINT: u16 = 16;
pub const NAV_RETURN_TO_LAUNCH: u16 = 20;
pub const NAV_LAND: u16 = 21;
pub const NAV_TAKEOFF: u16 = 22;
pub const DO_LAND_START: u16 = 189;
pub const DO_CHANGE_SPEED: u16 = 178;
pub const DO_SET_CAM_TRIGG_DIST: u16 = 206;
pub const CONDITION_YAW: u16 = 115;
pub const DO_GIMBAL_MANAGER_PITCHYAW: u16 = 1000;
pub const IMAGE_START_CAPTURE: u16 = 2000;

/// Waypoints lower than this above home are the take-off and the landing, not places to fly to.
const GROUND_M: f64 = 0.5;

/// `MAV_FRAME_MISSION`: a command without a position.
pub const FRAME_MISSION: u8 = 2;
/// `MAV_FRAME_GLOBAL_RELATIVE_ALT`: altitude above home.
pub const FRAME_RELATIVE: u8 = 3;
/// `MAV_FRAME_GLOBAL`: altitude above mean sea level.
pub const FRAME_GLOBAL: u8 = 0;
/// `MAV_FRAME_GLOBAL_TERRAIN_ALT`: altitude above the ground under the waypoint.
pub const FRAME_TERRAIN: u8 = 10;

/// Most heading change a fixed wing's arc corner stands for: an autopilot following
/// waypoints flies a turn from corners this far apart within about 10 m of the arc (15° steps,
/// in software-in-the-loop and in our follower alike, swung 20 to 28 m wide).
pub const ARC_CORNER_DEG: f64 = 90.0;

#[derive(Debug, Clone, PartialEq)]
pub struct MissionItem {
    pub command: u16,
    pub frame: u8,
    /// p1 to p4; `None` is "no change" (NaN).
    pub params: [Option<f64>; 4],
    /// `[lat, lon, altitude]` for commands that have a position, in `frame`.
    pub position: Option<[f64; 3]>,
}

impl MissionItem {
    fn command(command: u16, params: [f64; 4]) -> Self {
        MissionItem { command, frame: FRAME_MISSION, params: params.map(Some), position: None }
    }

    fn at(command: u16, params: [Option<f64>; 4], lon_lat_alt: [f64; 3]) -> Self {
        Self::in_frame(FRAME_RELATIVE, command, params, lon_lat_alt)
    }

    fn in_frame(frame: u8, command: u16, params: [Option<f64>; 4], lon_lat_alt: [f64; 3]) -> Self {
        MissionItem { command, frame, params, position: Some([lon_lat_alt[1], lon_lat_alt[0], lon_lat_alt[2]]) }
    }
}

/// `MAV_TYPE` of the vehicle.
pub fn mav_type(kind: VehicleKind) -> u8 {
    match kind {
        VehicleKind::FixedWing => 1,
        VehicleKind::Multirotor => 2,
        // MAV_TYPE_GROUND_ROVER: ArduPilot Rover and PX4 rover missions
        VehicleKind::Ground => 10,
    }
}

/// `MAV_AUTOPILOT` of the firmware.
pub fn mav_autopilot(firmware: Firmware) -> u8 {
    match firmware {
        Firmware::Ardupilot => 3,
        Firmware::Px4 => 12,
    }
}

/// Where the sortie takes off: home, or the start of its first piece.
pub fn launch(pieces: &[FlownPiece], home: Option<[f64; 2]>) -> [f64; 2] {
    home.unwrap_or_else(|| {
        let p = pieces[0].points[0];
        [p[0], p[1]]
    })
}

/// The items of one sortie, in order; `views` are the inspection's viewpoints (empty for a
/// coverage plan), `photos` the plan's photos (`[lon, lat]`), which the camera triggers take.
pub fn mission_items(pieces: &[FlownPiece], views: &[ViewAction], photos: &[PlanPhoto], settings: &FlightSettings, bases: Bases) -> Vec<MissionItem> {
    let home = bases.home;
    let fixed_wing = settings.kind == VehicleKind::FixedWing;
    // ArduPilot ignores a waypoint's yaw; PX4 reads 0 as "face north", NaN as "keep"
    let keep_yaw = match settings.firmware {
        Firmware::Ardupilot => Some(0.0),
        Firmware::Px4 => None,
    };
    let [lon, lat] = launch(pieces, home);
    let pitch = if fixed_wing { TAKEOFF_PITCH_DEG } else { 0.0 };
    let mut points = waypoints(pieces, fixed_wing.then_some(ARC_CORNER_DEG));
    // each line looks up the photos near it: indexed once, not scanned per line
    let photos = photos_by_pass(if settings.trigger_distance_m.is_some() { photos } else { &[] });
    if fixed_wing {
        // a fixed wing climbs out straight ahead (the plan's first transit begins so): a
        // waypoint it passes while climbing (home itself, first of all) would turn it back
        // once it is up, so the first transit's points within the climb-out are left out
        let climb_out = climb_out_m(settings.altitude_m);
        let frame = LocalFrame::new(lon, lat);
        let mut along = 0.0;
        let mut previous = geo::Coord { x: 0.0, y: 0.0 };
        let behind = points
            .iter()
            .take_while(|w| {
                let c = frame.to_local(w.position[0], w.position[1]);
                along += (c - previous).x.hypot((c - previous).y);
                previous = c;
                pieces[w.piece].kind == PieceKind::Transit && along < climb_out - 0.5
            })
            .count();
        points.drain(..behind.min(points.len().saturating_sub(1)));
    }
    // over terrain: each waypoint in the frame asked; the take-off climbs to the first one
    let over_terrain = pieces.first().is_some_and(|p| p.ground_m.is_some());
    let (frame, height_of): (u8, &dyn Fn(&Waypoint) -> f64) = match (over_terrain, settings.altitude_frame) {
        (false, _) => (FRAME_RELATIVE, &|w| w.position[2]),
        (true, AltitudeFrame::Amsl) => (FRAME_GLOBAL, &|w| w.position[2]),
        (true, AltitudeFrame::Terrain) => (FRAME_TERRAIN, &|w| w.position[2] - w.ground_m.unwrap_or(0.0)),
    };
    let place = |command, params, w: &Waypoint| MissionItem::in_frame(frame, command, params, [w.position[0], w.position[1], height_of(w)]);
    let takeoff_params = [Some(pitch), Some(0.0), Some(0.0), keep_yaw];
    let mut items = match points.first() {
        Some(first) if over_terrain => vec![place(NAV_TAKEOFF, takeoff_params, &Waypoint { position: [lon, lat, first.position[2]], ..*first })],
        _ => vec![MissionItem::at(NAV_TAKEOFF, takeoff_params, [lon, lat, settings.altitude_m])],
    };
    // airspeed for fixed wings, ground speed for multirotors
    let speed_type = if fixed_wing { 0.0 } else { 1.0 };
    let mut speed: Option<f64> = None;
    // a piece's speed, written where it changes
    let change_speed = |items: &mut Vec<MissionItem>, speed: &mut Option<f64>, mps: f64| {
        if mps > 0.0 && speed.is_none_or(|s| (mps - s).abs() > 0.05) {
            *speed = Some(mps);
            items.push(MissionItem::command(DO_CHANGE_SPEED, [speed_type, mps, -1.0, 0.0]));
        }
    };
    // landing `auto` with a home, or at another landing site: the last waypoint is where the
    // vehicle lands
    let lands = (settings.landing == Landing::Auto || bases.lands_at.is_some()) && home.is_some();
    let last_sweep = pieces.iter().rposition(|p| p.kind == PieceKind::Sweep);
    let landing_at = if lands { points.pop() } else { None };
    let mut land_start_written = false;
    let mut pass = None;
    for w in &points {
        let piece = &pieces[w.piece];
        // an oblique plan's pass: the gimbal pitched as it asks, before its first leg's photos
        if let Some(camera) = piece.camera.filter(|c| pass != Some(c.pass)) {
            pass = Some(camera.pass);
            items.push(gimbal_pitch(camera.gimbal_pitch_deg));
        }
        if fixed_wing && lands && !land_start_written && last_sweep.is_some_and(|k| w.piece > k) {
            // the landing sequence: from the return's first point to touch-down; an autopilot's
            // own return jumps here when told to land
            items.push(MissionItem::command(DO_LAND_START, [0.0; 4]));
            land_start_written = true;
        }
        change_speed(&mut items, &mut speed, piece.speed_mps);
        let on_sweep = piece.kind == PieceKind::Sweep;
        let sweep_end = on_sweep && w.index + 1 == piece.points.len();
        let mut stopped = false;
        if let (Some(distance), true) = (settings.trigger_distance_m, on_sweep && w.index == 1) {
            match line_triggers(piece, w.piece, photos.get(&piece.camera.map(|c| c.pass)), Some(settings.firmware)) {
                // a straight line: fly to its first photo, trigger there and every step, stop
                // half a step past its last photo
                Triggers::Line(line) => {
                    let line = if settings.compact_lines { LineTriggers { start: None, stop: None, ..line } } else { line };
                    if let Some(start) = &line.start {
                        items.push(place(NAV_WAYPOINT, [Some(0.0), Some(0.0), Some(0.0), keep_yaw], start));
                    }
                    items.push(MissionItem::command(DO_SET_CAM_TRIGG_DIST, [line.step_m, 0.0, 1.0, 0.0]));
                    if let Some(stop) = &line.stop {
                        items.push(place(NAV_WAYPOINT, [Some(0.0), Some(0.0), Some(0.0), keep_yaw], stop));
                        items.push(MissionItem::command(DO_SET_CAM_TRIGG_DIST, [0.0, 0.0, 0.0, 0.0]));
                        stopped = true;
                    }
                }
                Triggers::None => stopped = true,
                // a sweep laid over terrain bends: trigger from its start at the camera's step
                Triggers::Bent => items.push(MissionItem::command(DO_SET_CAM_TRIGG_DIST, [distance, 0.0, 1.0, 0.0])),
            }
        }
        if w.position[2] - w.ground_m.unwrap_or(0.0) < GROUND_M {
            continue;
        }
        // an arc's corner: the autopilot's own turn distance, unless the arc begins sooner
        let acceptance = match w.arc_begins_m {
            Some(m) if m > follower::turn_distance_m(piece.speed_mps.max(settings.cruise_speed_mps), 90.0) => m.round().clamp(1.0, 255.0),
            _ => 0.0,
        };
        // on an oblique pass the vehicle faces the camera's heading on every leg: PX4 reads
        // it from the waypoint, ArduCopter is told after each one (it resets its yaw at each)
        let facing = piece.camera.and_then(|c| c.heading_deg);
        match views.iter().find(|v| v.position == w.position) {
            Some(view) => items.extend(view_items(view, w.position, settings)),
            None => match (facing, settings.firmware) {
                (Some(heading), Firmware::Px4) => items.push(place(NAV_WAYPOINT, [Some(0.0), Some(acceptance), Some(0.0), Some(heading)], w)),
                (Some(heading), Firmware::Ardupilot) => {
                    items.push(place(NAV_WAYPOINT, [Some(0.0), Some(acceptance), Some(0.0), keep_yaw], w));
                    items.push(MissionItem::command(CONDITION_YAW, [heading, 0.0, 0.0, 0.0]));
                }
                (None, _) => items.push(place(NAV_WAYPOINT, [Some(0.0), Some(acceptance), Some(0.0), keep_yaw], w)),
            },
        }
        if settings.trigger_distance_m.is_some() && sweep_end && !stopped {
            items.push(MissionItem::command(DO_SET_CAM_TRIGG_DIST, [0.0, 0.0, 0.0, 0.0]));
        }
    }
    match (home, landing_at) {
        (Some(_), Some(at)) => {
            if fixed_wing && !land_start_written {
                items.push(MissionItem::command(DO_LAND_START, [0.0; 4]));
            }
            // the way to the landing point at its own speed, not the last piece's
            change_speed(&mut items, &mut speed, pieces[at.piece].speed_mps);
            let ground = Waypoint { position: [at.position[0], at.position[1], at.ground_m.unwrap_or(0.0)], ..at };
            items.push(place(NAV_LAND, [Some(0.0), Some(0.0), Some(0.0), keep_yaw], &ground));
        }
        (Some(_), None) => items.push(MissionItem::command(NAV_RETURN_TO_LAUNCH, [0.0; 4])),
        (None, _) => {
            let last = points.last().map_or([lon, lat, 0.0], |w| w.position);
            items.push(MissionItem::at(NAV_LAND, [Some(0.0), Some(0.0), Some(0.0), keep_yaw], [last[0], last[1], 0.0]));
        }
    }
    items
}

/// The sortie's items within `job.max_waypoints` (docs/flight-files.md, controller limits): as
/// planned; else with every line its two ends (the camera triggered from one to the other);
/// else that cut into missions, each within the limit, each ending at a waypoint with the
/// camera off and the next starting there.
pub fn limited_items(job: &ExportJob<'_>, sortie: usize) -> Result<Vec<Vec<MissionItem>>, InputError> {
    let pieces = &job.flight.sorties[sortie];
    let items = |settings: &FlightSettings| mission_items(pieces, &job.flight.views, &job.flight.photos, settings, job.bases(sortie));
    let planned = items(&job.settings);
    let Some(max) = job.max_waypoints.filter(|&max| planned.len() > max) else { return Ok(vec![planned]) };
    let compact = items(&FlightSettings { compact_lines: true, ..job.settings });
    if compact.len() <= max {
        return Ok(vec![compact]);
    }
    in_missions(&compact, max)
}

/// `items` cut into missions of at most `max` items: each begins with the take-off (passed at
/// once when airborne), the speed and gimbal in force, and the waypoint the last ended at; each
/// but the last ends at a waypoint with the camera off, where the vehicle holds.
fn in_missions(items: &[MissionItem], max: usize) -> Result<Vec<Vec<MissionItem>>, InputError> {
    let last_of = |command: u16, before: usize| items[..before].iter().rposition(|i| i.command == command);
    // the return and landing stay together in the last mission
    let tail = items.iter().position(|i| i.command == DO_LAND_START).unwrap_or(items.len() - 1);
    let camera_off = |before: usize| last_of(DO_SET_CAM_TRIGG_DIST, before).is_none_or(|k| items[k].params[0].unwrap_or(0.0) == 0.0);
    let cut_before = |k: usize| items[k - 1].command == NAV_WAYPOINT && camera_off(k);
    let prefix = |from: usize| -> Vec<MissionItem> {
        let mut out = vec![items[0].clone()];
        if from > 1 {
            out.extend([DO_CHANGE_SPEED, DO_GIMBAL_MANAGER_PITCHYAW].iter().filter_map(|&c| last_of(c, from)).map(|k| items[k].clone()));
            out.push(items[from - 1].clone());
        }
        out
    };
    let mut missions = Vec::new();
    let mut from = 1;
    loop {
        let head = prefix(from);
        if head.len() + items.len() - from <= max {
            missions.push([head, items[from..].to_vec()].concat());
            return Ok(missions);
        }
        let room = max - head.len();
        let Some(to) = (from + 1..=(from + room).min(tail)).rev().find(|&k| cut_before(k)) else {
            return Err(InputError::new(
                "max_waypoints_too_few",
                "/max_waypoints",
                format!("a stretch of this flight that cannot be cut (a line with the camera on, or the landing) takes more than {room} items: give a larger max_waypoints"),
            ));
        };
        missions.push([head, items[from..to].to_vec()].concat());
        from = to;
    }
}

/// The distance between two `[lon, lat]` points as the autopilot measures it when it triggers
/// by distance: ArduPilot's `Location::get_distance` (a sphere of 111 318.845 m a degree,
/// longitude scaled at the mean latitude), PX4's haversine on a 6 371 km sphere.
pub fn autopilot_distance_m(firmware: Firmware, a: [f64; 2], b: [f64; 2]) -> f64 {
    match firmware {
        Firmware::Ardupilot => {
            const METRES_PER_DEGREE: f64 = 111_318.845_021_450_34;
            let scale = ((a[1] + b[1]) / 2.0).to_radians().cos().max(0.01);
            METRES_PER_DEGREE * (b[1] - a[1]).hypot((b[0] - a[0]) * scale)
        }
        Firmware::Px4 => {
            const RADIUS_M: f64 = 6_371_000.0;
            let (la, lb) = (a[1].to_radians(), b[1].to_radians());
            let h = ((lb - la) / 2.0).sin().powi(2) + la.cos() * lb.cos() * ((b[0] - a[0]).to_radians() / 2.0).sin().powi(2);
            2.0 * RADIUS_M * h.sqrt().min(1.0).asin()
        }
    }
}

/// How often ArduPilot's camera library (50 Hz) and PX4's trigger check the distance flown: a
/// photo is taken, on average, half this late.
pub const CAMERA_CHECK_S: f64 = 0.02;

/// How far from a line a photo may lie and still be one of its photos (the plan writes them to
/// the centimetre).
const ON_LINE_M: f64 = 0.02;

/// Where a straight sweep's photos start and stop, and their step.
pub(super) struct LineTriggers {
    /// The first photo's place, unless it is the line's start.
    pub start: Option<Waypoint>,
    /// Half a step past the last photo, unless that is past the line's end (or the line has one
    /// photo: a step of 0 takes it and stops).
    pub stop: Option<Waypoint>,
    pub step_m: f64,
}

/// How a sweep's camera is triggered.
pub(super) enum Triggers {
    /// A straight line: from its first photo to its last.
    Line(LineTriggers),
    /// A straight line the plan shows no photo on.
    None,
    /// A line of several segments (laid over terrain).
    Bent,
}

/// Where the plan's photos lie on a sweep: the file triggers where the plan images. The step is
/// in `firmware`'s metric, less its trigger's average lateness; without one (DJI), in metres.
pub(super) fn line_triggers(piece: &FlownPiece, index: usize, photos: Option<&RTree<[f64; 2]>>, firmware: Option<Firmware>) -> Triggers {
    let [a, b] = piece.points.as_slice() else { return Triggers::Bent };
    let Some(photos) = photos else { return Triggers::None };
    let frame = LocalFrame::new(a[0], a[1]);
    let end = frame.to_local(b[0], b[1]);
    let len = end.x.hypot(end.y);
    if len == 0.0 {
        return Triggers::None;
    }
    let along = geo::Coord { x: end.x / len, y: end.y / len };
    // the photos on this line: within a centimetre of it, between its ends; looked up in the box
    // in degrees of the line as the plan draws it (straight in metres, so a long one bows in
    // degrees), a metre wider, and then tested in metres
    const MARGIN_DEG: f64 = 1e-5;
    let drawn: Vec<[f64; 2]> = (0..=8).map(|k| frame.to_wgs84(geo::Coord { x: end.x * k as f64 / 8.0, y: end.y * k as f64 / 8.0 })).collect();
    let (lo, hi) = drawn.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])]));
    let near = AABB::from_corners([lo[0] - MARGIN_DEG, lo[1] - MARGIN_DEG], [hi[0] + MARGIN_DEG, hi[1] + MARGIN_DEG]);
    let mut offsets: Vec<f64> = photos
        .locate_in_envelope(&near)
        .map(|p| frame.to_local(p[0], p[1]))
        .filter(|p| (p.x * along.y - p.y * along.x).abs() < ON_LINE_M)
        .map(|p| p.x * along.x + p.y * along.y)
        // a photo at the line's end is the next line's first, where the path bends (a ring's
        // corner): the camera keeps triggering through it; on a line of a few centimetres the
        // photo nearer its start is its own
        .filter(|t| *t >= -ON_LINE_M && !(len - t < ON_LINE_M && len - t < *t))
        .collect();
    offsets.sort_by(f64::total_cmp);
    offsets.dedup_by(|x, y| (*x - *y).abs() < ON_LINE_M);
    let (Some(&first), Some(&last)) = (offsets.first(), offsets.last()) else { return Triggers::None };
    let step_m = if offsets.len() > 1 { (last - first) / (offsets.len() - 1) as f64 } else { 0.0 };
    // a waypoint closer than this to another is none: the vehicle is there already
    const NEAR_M: f64 = 0.05;
    let at = |t: f64| {
        let f = t / len;
        let lerp = |u: f64, v: f64| u + (v - u) * f;
        let ground_m = piece.ground_m.as_ref().map(|g| lerp(g[0], g[1]));
        Waypoint { position: [lerp(a[0], b[0]), lerp(a[1], b[1]), lerp(a[2], b[2])], piece: index, index: 0, arc_begins_m: None, ground_m }
    };
    let stop_t = last + step_m / 2.0;
    // the step as the autopilot measures it: its metric and ours differ by up to a few tenths of
    // a per cent, which a long line's photos would add up to a photo more or less
    // and less the distance flown, on average, between the autopilot's checks of the distance
    // and the picture: its photos then lie as far apart as the plan's
    let autopilot_step_m = match firmware {
        Some(firmware) if offsets.len() > 1 => {
            let (p, q) = (at(first).position, at(last).position);
            let latency_m = piece.speed_mps * CAMERA_CHECK_S / 2.0;
            autopilot_distance_m(firmware, [p[0], p[1]], [q[0], q[1]]) / (offsets.len() - 1) as f64 - latency_m
        }
        _ => step_m,
    };
    Triggers::Line(LineTriggers { start: (first > NEAR_M).then(|| at(first)), stop: (step_m > 0.0 && stop_t < len - NEAR_M).then(|| at(stop_t)), step_m: autopilot_step_m })
}

/// The gimbal pitched to `pitch_deg`, its yaw with the vehicle's heading, rates unset.
fn gimbal_pitch(pitch_deg: f64) -> MissionItem {
    MissionItem { command: DO_GIMBAL_MANAGER_PITCHYAW, frame: FRAME_MISSION, params: [Some(pitch_deg), Some(0.0), None, None], position: None }
}

/// At an inspection's viewpoint: hold, face its yaw (PX4 reads the waypoint's yaw; ArduCopter
/// ignores it and is told with `CONDITION_YAW`), point the gimbal, take one picture.
fn view_items(view: &ViewAction, position: [f64; 3], settings: &FlightSettings) -> Vec<MissionItem> {
    let yaw = match settings.firmware {
        Firmware::Ardupilot => Some(0.0),
        Firmware::Px4 => Some(view.yaw_deg),
    };
    let mut items = vec![MissionItem::at(NAV_WAYPOINT, [Some(settings.hold_s), Some(0.0), Some(0.0), yaw], position)];
    if settings.firmware == Firmware::Ardupilot {
        // absolute bearing, default rate, the shorter way
        items.push(MissionItem::command(CONDITION_YAW, [view.yaw_deg, 0.0, 0.0, 0.0]));
    }
    // the vehicle faces the viewpoint's bearing
    items.push(gimbal_pitch(view.gimbal_pitch_deg));
    // camera 0 (all), no interval, one image
    items.push(MissionItem::command(IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 0.0]));
    items
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::fitted_photo_offsets;

    /// The positions of the `NAV_WAYPOINT` items, `[lat, lon]`, for tests of every flight format.
    fn waypoint_positions(items: &[MissionItem]) -> Vec<[f64; 2]> {
        items.iter().filter(|i| i.command == NAV_WAYPOINT).filter_map(|i| i.position).map(|p| [p[0], p[1]]).collect()
    }

    fn piece(kind: PieceKind, points: &[[f64; 2]], speed: f64) -> FlownPiece {
        FlownPiece { kind, points: points.iter().map(|p| [p[0], p[1], 40.0]).collect(), speed_mps: speed, ground_m: None, tramline: false, camera: None }
    }

    /// The photos a plan shows on the straight sweeps of `pieces` (camera §6's rule), for a
    /// footprint `footprint_m` long and photos at most `spacing_m` apart.
    fn plan_photos_with(pieces: &[FlownPiece], footprint_m: f64, spacing_m: f64) -> Vec<PlanPhoto> {
        let mut out = Vec::new();
        for p in pieces.iter().filter(|p| p.kind == PieceKind::Sweep) {
            let (a, b) = (p.points[0], p.points[1]);
            let frame = LocalFrame::new(a[0], a[1]);
            let end = frame.to_local(b[0], b[1]);
            let len = end.x.hypot(end.y);
            for t in fitted_photo_offsets(len, footprint_m, spacing_m) {
                out.push(PlanPhoto { at: frame.to_wgs84(geo::Coord { x: end.x * t / len, y: end.y * t / len }), pass: None });
            }
        }
        out
    }

    fn plan_photos(pieces: &[FlownPiece], spacing_m: f64) -> Vec<PlanPhoto> {
        plan_photos_with(pieces, 20.0, spacing_m)
    }

    fn settings(trigger: Option<f64>) -> FlightSettings {
        FlightSettings {
            kind: VehicleKind::Multirotor,
            firmware: Firmware::Px4,
            altitude_m: 40.0,
            cruise_speed_mps: 8.0,
            turn_radius_m: 0.0,
            line_spacing_m: 20.0,
            trigger_distance_m: trigger,
            hold_s: 0.0,
            altitude_frame: AltitudeFrame::Amsl,
            landing: Landing::Return,
            compact_lines: false,
            guidance: None,
        }
    }

    #[test]
    fn camera_runs_on_sweeps_only() {
        let pieces = [
            piece(PieceKind::Transit, &[[0.0, 0.0], [1.0, 0.0]], 8.0),
            piece(PieceKind::Sweep, &[[1.0, 0.0], [2.0, 0.0]], 6.0),
            piece(PieceKind::Turn, &[[2.0, 0.0], [2.0, 1.0]], 3.0),
            piece(PieceKind::Sweep, &[[2.0, 1.0], [1.0, 1.0]], 6.0),
        ];
        let items = mission_items(&pieces, &[], &plan_photos(&pieces, 12.0), &settings(Some(12.0)), Bases::home(Some([0.0, 0.0])));
        let commands: Vec<u16> = items.iter().map(|i| i.command).collect();
        // on each sweep: to the first photo, trigger, to half a step past the last, stop, the end
        assert_eq!(commands, vec![22, 178, 16, 16, 178, 16, 206, 16, 206, 16, 178, 16, 178, 16, 206, 16, 206, 16, 20]);
        assert!(items[6].params[0].is_some_and(|step| step > 11.9 && step <= 12.0), "the line's step: {:?}", items[6].params);
        // lat, lon order
        assert_eq!(items[9].position, Some([0.0, 2.0, 40.0]));
        let corners = [[0.0, 0.0], [0.0, 1.0], [0.0, 2.0], [1.0, 2.0], [1.0, 1.0]];
        assert!(corners.iter().all(|c| waypoint_positions(&items).contains(c)));
    }

    #[test]
    fn a_sortie_that_starts_on_a_sweep_triggers_on_it() {
        let pieces = [piece(PieceKind::Sweep, &[[1.0, 0.0], [2.0, 0.0]], 6.0), piece(PieceKind::Turn, &[[2.0, 0.0], [2.0, 1.0]], 6.0)];
        let commands: Vec<u16> = mission_items(&pieces, &[], &plan_photos(&pieces, 12.0), &settings(Some(12.0)), Bases::default()).iter().map(|i| i.command).collect();
        assert_eq!(commands, vec![22, 178, 16, 16, 206, 16, 206, 16, 16, 21]);
    }

    /// Where an autopilot triggering by distance takes photos along `items` (the follower's
    /// multirotor: `[lon, lat]`).
    fn autopilot_photos(items: &[MissionItem], firmware: Firmware) -> Vec<[f64; 2]> {
        let spec =
            follower::FollowerSpec { kind: VehicleKind::Multirotor, firmware, cruise_speed_mps: 6.0, turn_radius_m: 0.0, acceleration_mps2: 2.0, climb_mps: 2.0, descent_mps: 1.5 };
        follower::fly(items, &spec).photos
    }

    /// The flight file triggers where the plan's photos are, line by line: as many, within the
    /// distance flown between two checks of the autopilot along the line, for lines of any
    /// length (a clipped line of a few centimetres too), footprints and steps, in either
    /// autopilot's metric.
    #[test]
    fn an_autopilot_triggering_by_distance_takes_the_plans_photos() {
        let frame = LocalFrame::new(8.5, 47.3);
        let deg = |x: f64, y: f64| frame.to_wgs84(geo::Coord { x, y });
        let mut checked = 0;
        for len in [0.02, 0.035, 9.0, 31.0, 64.5, 120.0, 257.3, 801.0, 1_637.9] {
            for (footprint, spacing) in [(20.0, 4.0), (35.0, 8.4), (60.0, 25.0), (12.0, 12.0)] {
                let firmware = if checked % 2 == 0 { Firmware::Ardupilot } else { Firmware::Px4 };
                let s = FlightSettings { trigger_distance_m: Some(spacing), firmware, ..settings(None) };
                let [a, b, c, d] = [deg(0.0, 0.0), deg(len, 0.0), deg(len, 20.0), deg(0.0, 20.0)];
                let sweep = |p: [f64; 2], q: [f64; 2]| FlownPiece {
                    kind: PieceKind::Sweep,
                    points: vec![[p[0], p[1], 40.0], [q[0], q[1], 40.0]],
                    speed_mps: 6.0,
                    ground_m: None,
                    tramline: false,
                    camera: None,
                };
                let turn =
                    FlownPiece { kind: PieceKind::Turn, points: vec![[b[0], b[1], 40.0], [c[0], c[1], 40.0]], speed_mps: 3.0, ground_m: None, tramline: false, camera: None };
                let pieces = [sweep(a, b), turn, sweep(c, d)];
                let items = mission_items(&pieces, &[], &plan_photos_with(&pieces, footprint, spacing), &s, Bases::default());
                let found: Vec<geo::Coord> = autopilot_photos(&items, s.firmware).iter().map(|p| frame.to_local(p[0], p[1])).collect();
                let offsets = fitted_photo_offsets(len, footprint, spacing);
                let planned: Vec<geo::Coord> = offsets.iter().map(|&t| geo::Coord { x: t, y: 0.0 }).chain(offsets.iter().map(|&t| geo::Coord { x: len - t, y: 20.0 })).collect();
                assert_eq!(found.len(), planned.len(), "{len} m, footprint {footprint} m, step {spacing} m: {found:?}");
                for (f, p) in found.iter().zip(&planned) {
                    // along the line, where triggering decides (across it, a straight line in
                    // degrees and one in metres part by centimetres over a kilometre)
                    // within the distance flown between two of the autopilot's checks
                    assert!(
                        (f.x - p.x).abs() < 6.0 * CAMERA_CHECK_S && (f.y - p.y).abs() < 0.2,
                        "{len} m, footprint {footprint} m, step {spacing} m: a photo at {f:?}, planned at {p:?}"
                    );
                }
                checked += 1;
            }
        }
        assert_eq!(checked, 36);
    }

    #[test]
    fn a_viewpoint_holds_turns_points_the_gimbal_and_takes_a_picture() {
        let view = ViewAction { position: [1.0, 0.0, 12.0], yaw_deg: 135.0, gimbal_pitch_deg: -30.0 };
        let pieces = [
            FlownPiece {
                kind: PieceKind::Transit,
                points: vec![[0.0, 0.0, 0.0], [0.5, 0.0, 6.0], [1.0, 0.0, 12.0]],
                speed_mps: 0.0,
                ground_m: None,
                tramline: false,
                camera: None,
            },
            FlownPiece { kind: PieceKind::Transit, points: vec![[1.0, 0.0, 12.0], [1.0, 1.0, 0.0]], speed_mps: 0.0, ground_m: None, tramline: false, camera: None },
        ];
        let mut s = FlightSettings { hold_s: 2.0, ..settings(None) };
        let px4 = mission_items(&pieces, &[view], &[], &s, Bases::default());
        let commands: Vec<u16> = px4.iter().map(|i| i.command).collect();
        // the points on the ground are the take-off and the landing
        assert_eq!(commands, vec![NAV_TAKEOFF, NAV_WAYPOINT, NAV_WAYPOINT, DO_GIMBAL_MANAGER_PITCHYAW, IMAGE_START_CAPTURE, NAV_LAND]);
        assert_eq!(px4[2].params, [Some(2.0), Some(0.0), Some(0.0), Some(135.0)]);
        assert_eq!(px4[3].params[0], Some(-30.0));
        s.firmware = Firmware::Ardupilot;
        let ardupilot = mission_items(&pieces, &[view], &[], &s, Bases::default());
        assert_eq!(ardupilot[3].command, CONDITION_YAW);
        assert_eq!(ardupilot[3].params[0], Some(135.0));
    }

    /// A fixed wing takes off straight ahead and climbs at its take-off pitch: no waypoint of
    /// the first transit it passes while climbing (home, first of all) is written, so it never
    /// turns back once up. A multirotor, climbing on the spot, keeps them all.
    #[test]
    fn a_fixed_wing_is_not_sent_back_over_home_after_take_off() {
        let frame = LocalFrame::new(8.5, 47.3);
        let at = |x: f64| {
            let [lon, lat] = frame.to_wgs84(geo::Coord { x, y: 0.0 });
            [lon, lat, 80.0]
        };
        let transit =
            FlownPiece { kind: PieceKind::Transit, points: (0..12).map(|k| at(50.0 * k as f64)).collect(), speed_mps: 15.0, ground_m: None, tramline: false, camera: None };
        let sweep = FlownPiece { kind: PieceKind::Sweep, points: vec![at(550.0), at(900.0)], speed_mps: 15.0, ground_m: None, tramline: false, camera: None };
        let plane = FlightSettings { kind: VehicleKind::FixedWing, altitude_m: 80.0, turn_radius_m: 50.0, ..settings(None) };
        let items = mission_items(&[transit.clone(), sweep.clone()], &[], &[], &plane, Bases::home(Some([at(0.0)[0], at(0.0)[1]])));
        let first = items.iter().find(|i| i.command == NAV_WAYPOINT).and_then(|i| i.position).unwrap();
        let ahead = frame.to_local(first[1], first[0]).x;
        let climb_out = climb_out_m(80.0);
        assert!(ahead >= climb_out && ahead < climb_out + 50.0, "the first waypoint {ahead:.0} m ahead; the climb-out takes {climb_out:.0} m");
        let copter = mission_items(&[transit, sweep], &[], &[], &FlightSettings { altitude_m: 80.0, ..settings(None) }, Bases::home(Some([at(0.0)[0], at(0.0)[1]])));
        assert_eq!(copter.iter().filter(|i| i.command == NAV_WAYPOINT).count(), 13, "a multirotor flies every point");
    }

    /// The way to the landing point is flown at its own piece's speed: a slow last piece (a
    /// short line between holes) no longer sets the speed of the whole way home.
    #[test]
    fn the_way_to_the_landing_point_is_flown_at_its_own_speed() {
        let pieces = [
            piece(PieceKind::Transit, &[[0.0, 0.0], [0.001, 0.0]], 8.0),
            piece(PieceKind::Sweep, &[[0.001, 0.0], [0.00101, 0.0]], 1.5),
            piece(PieceKind::Transit, &[[0.00101, 0.0], [0.0, 0.0]], 7.5),
        ];
        let landing = FlightSettings { landing: Landing::Auto, ..settings(None) };
        let items = mission_items(&pieces, &[], &[], &landing, Bases::home(Some([0.0, 0.0])));
        assert_eq!(items.last().unwrap().command, NAV_LAND);
        let speeds: Vec<f64> = items.iter().filter(|i| i.command == DO_CHANGE_SPEED).filter_map(|i| i.params[1]).collect();
        assert_eq!(speeds.last(), Some(&7.5), "{speeds:?}");
        let before_land = &items[items.len() - 2];
        assert_eq!((before_land.command, before_land.params[1]), (DO_CHANGE_SPEED, Some(7.5)));
    }

    #[test]
    fn lands_without_home() {
        let items = mission_items(&[piece(PieceKind::Sweep, &[[1.0, 0.0], [2.0, 0.0]], 6.0)], &[], &[], &settings(None), Bases::default());
        assert_eq!(items.first().unwrap().position, Some([0.0, 1.0, 40.0]));
        assert_eq!(items.last().unwrap().command, NAV_LAND);
        assert_eq!(items.last().unwrap().position, Some([0.0, 2.0, 0.0]));
    }
}
