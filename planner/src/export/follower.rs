//! What an autopilot flies from our mission items: a kinematic follower, the check of a flight
//! file's own geometry where no simulator runs (docs/flight-files.md).
//!
//! A fixed wing is steered by L1 guidance (Park, Deyst and How 2004, as ArduPlane uses it with
//! its defaults: period 17 s, damping 0.75, `WP_RADIUS` 90 m), its bank limited to what the
//! vehicle's turning radius allows at its speed and reached with a 0.5 s lag; it takes off on
//! the heading it stands on at the take-off item's pitch, and a waypoint is reached within its
//! acceptance radius or once the line through it across the leg is passed. A multirotor flies
//! straight from waypoint to waypoint at its acceleration, through a corner of less than 45°
//! at speed and stopping at a sharper one, and climbs, descends and lands as ArduCopter does by
//! default. Photos are taken as both autopilots trigger by distance.

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

use geo::Coord;

use super::Firmware;
use super::mission_items::{CAMERA_CHECK_S, DO_CHANGE_SPEED, DO_SET_CAM_TRIGG_DIST, MissionItem, NAV_LAND, NAV_RETURN_TO_LAUNCH, NAV_TAKEOFF, NAV_WAYPOINT, autopilot_distance_m};
use crate::energy::{LAND_SLOW_BELOW_M, LAND_SPEED_MPS, RTL_HOVER_S};
use crate::frame::LocalFrame;
use crate::vehicle::{L1_DAMPING, VehicleKind, l1_distance_m};

const G: f64 = 9.806_65;
/// Integration step, seconds.
const DT: f64 = 0.05;
/// ArduPlane's default `WP_RADIUS`.
const WP_RADIUS_M: f64 = 90.0;
/// Time constant of the roll controller (`RLL2SRV_TCONST`).
const ROLL_LAG_S: f64 = 0.5;
/// The follower gives up after this long (a fixed wing circling home never ends).
const MAX_FLIGHT_S: f64 = 6.0 * 3600.0;

/// The vehicle the follower flies.
#[derive(Debug, Clone, Copy)]
pub struct FollowerSpec {
    pub kind: VehicleKind,
    pub firmware: Firmware,
    pub cruise_speed_mps: f64,
    /// A fixed wing's smallest turn, which bounds its bank: tan φ = v² / (g r).
    pub turn_radius_m: f64,
    /// A multirotor's acceleration and braking.
    pub acceleration_mps2: f64,
    pub climb_mps: f64,
    pub descent_mps: f64,
}

/// One sample of the flown track, in metres east and north of the take-off point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub at: Coord,
    pub z: f64,
    /// The mission item being flown.
    pub item: usize,
}

/// What the follower flew.
#[derive(Debug, Clone)]
pub struct Flown {
    pub frame: LocalFrame,
    pub track: Vec<Sample>,
    /// `[lon, lat]` of every photo taken.
    pub photos: Vec<[f64; 2]>,
    /// From the start of the take-off to touching down, or to reaching home on a return a fixed
    /// wing ends circling.
    pub duration_s: f64,
    pub landed: bool,
    /// The first waypoint after the take-off lay behind the aircraft as its climb ended: it
    /// turned back to it.
    pub turned_back_after_take_off: bool,
}

/// How far from a waypoint ArduPlane starts turning for a turn of `turn_deg` when the waypoint
/// gives no acceptance radius: its L1 distance (at most `WP_RADIUS`), less for a gentle turn.
pub fn turn_distance_m(speed_mps: f64, turn_deg: f64) -> f64 {
    WP_RADIUS_M.min(l1_distance_m(speed_mps)) * turn_deg.abs().min(90.0) / 90.0
}

/// Flies `items` (written for `spec.firmware`); the first item must be the take-off.
pub fn fly(items: &[MissionItem], spec: &FollowerSpec) -> Flown {
    let origin = items.iter().find_map(|i| i.position).map_or([0.0, 0.0], |p| [p[1], p[0]]);
    let frame = LocalFrame::new(origin[0], origin[1]);
    let mut state = State {
        spec: *spec,
        frame,
        at: Coord { x: 0.0, y: 0.0 },
        z: 0.0,
        heading: 0.0,
        bank: 0.0,
        speed: 0.0,
        target_speed: spec.cruise_speed_mps,
        t: 0.0,
        item: 0,
        track: Vec::new(),
        camera: Camera { distance: 0.0, last: None, photos: Vec::new() },
    };
    let places: Vec<Option<(Coord, f64)>> = items.iter().map(|i| i.position.map(|p| (frame.to_local(p[1], p[0]), p[2]))).collect();
    let next_place = |from: usize| (from..items.len()).find(|&k| items[k].command == NAV_WAYPOINT || items[k].command == NAV_LAND).and_then(|k| places[k]);
    let home = state.at;
    let mut previous: Option<Coord> = None;
    let (mut landed, mut turned_back) = (false, false);
    for (index, item) in items.iter().enumerate() {
        state.item = index;
        match item.command {
            NAV_TAKEOFF => {
                let altitude = places[index].map_or(0.0, |p| p.1);
                let towards = next_place(index + 1).map(|p| p.0).unwrap_or(Coord { x: 1.0, y: 0.0 });
                state.heading = towards.y.atan2(towards.x);
                state.take_off(altitude, item.params[0].unwrap_or(0.0));
                let ahead = Coord { x: state.heading.cos(), y: state.heading.sin() };
                // behind by more than the last step's overshoot
                turned_back = spec.kind == VehicleKind::FixedWing && next_place(index + 1).is_some_and(|(p, _)| (p - state.at).x * ahead.x + (p - state.at).y * ahead.y < -2.0);
                previous = None;
            }
            DO_CHANGE_SPEED => state.target_speed = item.params[1].filter(|v| *v > 0.0).unwrap_or(state.target_speed),
            DO_SET_CAM_TRIGG_DIST => {
                state.camera.distance = item.params[0].unwrap_or(0.0);
                if item.params[2] == Some(1.0) {
                    let here = frame.to_wgs84(state.at);
                    state.camera.shoot(here);
                }
            }
            NAV_WAYPOINT | NAV_LAND => {
                let Some((to, z)) = places[index] else { continue };
                let landing = item.command == NAV_LAND;
                let after = if landing { None } else { next_place(index + 1) };
                let hold_s = if landing { 0.0 } else { item.params[0].unwrap_or(0.0) };
                match spec.kind {
                    VehicleKind::FixedWing => {
                        let acceptance = item.params[1].filter(|a| *a > 0.0);
                        state.fly_l1(previous, to, z, after.map(|a| a.0), acceptance, landing);
                    }
                    _ => {
                        let corner_mps = match after {
                            Some((next, _)) if hold_s == 0.0 && !landing => corner_speed(state.at, to, next, spec.acceleration_mps2),
                            _ => 0.0,
                        };
                        // a landing flies there at its height, then descends
                        state.fly_straight(to, if landing { state.z } else { z }, corner_mps);
                        state.hover(hold_s);
                    }
                }
                if landing {
                    if spec.kind != VehicleKind::FixedWing {
                        state.descend_and_land();
                    }
                    landed = true;
                    break;
                }
                previous = Some(to);
            }
            NAV_RETURN_TO_LAUNCH => {
                match spec.kind {
                    VehicleKind::FixedWing => state.fly_l1(None, home, state.z, None, Some(spec.turn_radius_m), false),
                    _ => {
                        state.fly_straight(home, state.z, 0.0);
                        state.hover(RTL_HOVER_S);
                        state.descend_and_land();
                        landed = true;
                    }
                }
                break;
            }
            _ => {}
        }
        if state.t > MAX_FLIGHT_S {
            break;
        }
    }
    let duration_s = state.t;
    Flown { frame, track: state.track, photos: state.camera.photos, duration_s, landed, turned_back_after_take_off: turned_back }
}

/// The speed a multirotor passes the corner at `at` with: on the widest arc that fits the
/// corner within half of each leg, at its acceleration sideways (ArduCopter rounds corners
/// since 4.1); a straight on at any speed, a reversal stopped.
fn corner_speed(from: Coord, at: Coord, to: Coord, acceleration_mps2: f64) -> f64 {
    let turn = corner_deg(from, at, to);
    if turn < 0.5 {
        return f64::INFINITY;
    }
    let length = |a: Coord, b: Coord| (b - a).x.hypot((b - a).y);
    let half_leg = length(from, at).min(length(at, to)) / 2.0;
    let radius = half_leg * ((180.0 - turn) / 2.0).to_radians().tan();
    (acceleration_mps2 * radius.max(0.0)).sqrt()
}

/// Heading change at `at` between the legs `from → at` and `at → to`, degrees.
fn corner_deg(from: Coord, at: Coord, to: Coord) -> f64 {
    let (a, b) = (at - from, to - at);
    if a.x.hypot(a.y) < 1e-6 || b.x.hypot(b.y) < 1e-6 {
        return 0.0;
    }
    angle_between(a, b).abs().to_degrees()
}

struct Camera {
    distance: f64,
    last: Option<[f64; 2]>,
    photos: Vec<[f64; 2]>,
}

impl Camera {
    fn shoot(&mut self, at: [f64; 2]) {
        self.photos.push(at);
        self.last = Some(at);
    }
}

struct State {
    spec: FollowerSpec,
    frame: LocalFrame,
    at: Coord,
    z: f64,
    /// Math heading of the track, radians.
    heading: f64,
    bank: f64,
    speed: f64,
    target_speed: f64,
    t: f64,
    item: usize,
    track: Vec<Sample>,
    camera: Camera,
}

impl State {
    /// Advances the clock one step: the position moves by `velocity`, the camera triggers.
    fn step(&mut self, velocity: Coord, climb: f64, dt: f64) {
        // the camera fires once the distance is flown, on average half a check late
        let lag_m = velocity.x.hypot(velocity.y) * CAMERA_CHECK_S / 2.0;
        let place = |s: f64| self.frame.to_wgs84(self.at + velocity * (dt * s));
        let mut from = 0.0;
        while self.camera.distance > 0.0 {
            let Some(last) = self.camera.last else {
                self.camera.shoot(place(0.0));
                continue;
            };
            let short = |s: f64| autopilot_distance_m(self.spec.firmware, last, place(s)) < self.camera.distance + lag_m;
            if short(1.0) {
                break;
            }
            let (mut lo, mut hi) = (from, 1.0);
            for _ in 0..50 {
                let mid = (lo + hi) / 2.0;
                if short(mid) { lo = mid } else { hi = mid }
            }
            self.camera.shoot(place(hi));
            from = hi;
        }
        self.at = self.at + velocity * dt;
        self.z += climb * dt;
        self.t += dt;
        self.track.push(Sample { t: self.t, at: self.at, z: self.z, item: self.item });
    }

    fn hover(&mut self, seconds: f64) {
        let steps = (seconds / DT).round() as usize;
        for _ in 0..steps {
            self.step(Coord { x: 0.0, y: 0.0 }, 0.0, DT);
        }
    }

    fn take_off(&mut self, altitude: f64, pitch_deg: f64) {
        match self.spec.kind {
            VehicleKind::FixedWing => {
                // rolls and climbs straight ahead at the take-off pitch, at cruise speed
                let pitch = pitch_deg.max(4.0).to_radians();
                self.speed = self.target_speed;
                let (horizontal, climb) = (self.speed * pitch.cos(), self.speed * pitch.sin());
                while self.z < altitude && self.t < MAX_FLIGHT_S {
                    let v = Coord { x: self.heading.cos(), y: self.heading.sin() } * horizontal;
                    self.step(v, climb, DT);
                }
            }
            _ => {
                while self.z < altitude && self.t < MAX_FLIGHT_S {
                    let dt = DT.min((altitude - self.z) / self.spec.climb_mps).max(1e-6);
                    self.step(Coord { x: 0.0, y: 0.0 }, self.spec.climb_mps, dt);
                }
            }
        }
    }

    /// ArduCopter's landing from where it hovers: down at its descent speed, the last
    /// [`LAND_SLOW_BELOW_M`] at [`LAND_SPEED_MPS`].
    fn descend_and_land(&mut self) {
        while self.z > 0.0 && self.t < MAX_FLIGHT_S {
            let rate = if self.z > LAND_SLOW_BELOW_M { self.spec.descent_mps } else { LAND_SPEED_MPS };
            let floor = if self.z > LAND_SLOW_BELOW_M { LAND_SLOW_BELOW_M } else { 0.0 };
            let dt = DT.min((self.z - floor) / rate).max(1e-6);
            self.step(Coord { x: 0.0, y: 0.0 }, -rate, dt);
        }
    }

    /// A multirotor's straight leg to `to`, arriving there at `corner_mps` at most.
    fn fly_straight(&mut self, to: Coord, z: f64, corner_mps: f64) {
        let a = self.spec.acceleration_mps2;
        let start_z = self.z;
        let length = (to - self.at).x.hypot((to - self.at).y);
        if length < 1e-6 {
            return;
        }
        let dir = (to - self.at) / length;
        let mut left = length;
        while left > 1e-3 && self.t < MAX_FLIGHT_S {
            let brake_to = corner_mps.min(self.target_speed);
            let allowed = (brake_to * brake_to + 2.0 * a * left).sqrt();
            let wanted = self.target_speed.min(allowed);
            self.speed = if wanted > self.speed { (self.speed + a * DT).min(wanted) } else { wanted };
            let v = self.speed.max(0.05);
            let dt = DT.min(left / v);
            left -= v * dt;
            let climb = (z - start_z) * (v * dt) / length / dt;
            self.step(dir * v, climb, dt);
        }
        self.at = to;
        self.z = z;
        self.speed = self.speed.min(corner_mps);
    }

    /// A fixed wing's leg to `to` by L1 guidance along `from → to` (directly from where it is
    /// when `from` is `None`), reached within `acceptance` (default: ArduPlane's turn
    /// distance) or on passing the line through `to` across the leg; `landing` glides down to
    /// touch `to`.
    fn fly_l1(&mut self, from: Option<Coord>, to: Coord, z: f64, after: Option<Coord>, acceptance: Option<f64>, landing: bool) {
        let v = self.target_speed;
        self.speed = v;
        let l1 = l1_distance_m(v);
        let gain = 4.0 * L1_DAMPING * L1_DAMPING;
        let max_lateral = v * v / self.spec.turn_radius_m.max(1.0);
        let a = from.unwrap_or(self.at);
        let ab = to - a;
        let ab_len = ab.x.hypot(ab.y);
        let unit = if ab_len > 1e-6 { ab / ab_len } else { Coord { x: self.heading.cos(), y: self.heading.sin() } };
        let turn = after.map_or(0.0, |next| corner_deg(a, to, next));
        let accept = acceptance.unwrap_or(turn_distance_m(v, turn));
        let (start_z, start_left) = (self.z, (to - self.at).x.hypot((to - self.at).y).max(1e-6));
        loop {
            let rel = to - self.at;
            let dist = rel.x.hypot(rel.y);
            let along = (self.at - a).x * unit.x + (self.at - a).y * unit.y;
            if dist <= accept.max(0.5) || along >= ab_len || self.t > MAX_FLIGHT_S {
                break;
            }
            let velocity = Coord { x: self.heading.cos(), y: self.heading.sin() } * v;
            let from_a = self.at - a;
            // left of the leg, positive; the L1 point lies ahead on the leg, captured at 45° at most
            let left_of_leg = from_a.y * unit.x - from_a.x * unit.y;
            let nu = if from_a.x.hypot(from_a.y) > l1 && along / from_a.x.hypot(from_a.y).max(1.0) < -FRAC_1_SQRT_2 {
                // far behind the leg's start: head for it
                angle_between(velocity, a - self.at)
            } else {
                angle_between(velocity, unit) - (left_of_leg / l1).clamp(-FRAC_1_SQRT_2, FRAC_1_SQRT_2).asin()
            };
            let lateral = (gain * v * v / l1 * nu.clamp(-FRAC_PI_2, FRAC_PI_2).sin()).clamp(-max_lateral, max_lateral);
            let wanted_bank = (lateral / G).atan();
            self.bank += (wanted_bank - self.bank) * (DT / ROLL_LAG_S).min(1.0);
            self.heading += G * self.bank.tan() / v * DT;
            let goal_z = if landing { z + (start_z - z) * (dist / start_left).min(1.0) } else { z };
            let climb = ((goal_z - self.z) / DT).clamp(-self.spec.descent_mps, self.spec.climb_mps);
            let climb = if landing { (goal_z - self.z) / DT } else { climb };
            self.step(velocity, climb, DT);
        }
        if landing {
            self.z = z;
        }
    }
}

/// Signed angle from `a` to `b`, radians, counter-clockwise positive.
fn angle_between(a: Coord, b: Coord) -> f64 {
    (a.x * b.y - a.y * b.x).atan2(a.x * b.x + a.y * b.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::mission_items::{FRAME_MISSION, FRAME_RELATIVE};

    fn at(frame: &LocalFrame, command: u16, x: f64, y: f64, z: f64, params: [f64; 4]) -> MissionItem {
        let [lon, lat] = frame.to_wgs84(Coord { x, y });
        MissionItem { command, frame: FRAME_RELATIVE, params: params.map(Some), position: Some([lat, lon, z]) }
    }

    fn plane() -> FollowerSpec {
        FollowerSpec {
            kind: VehicleKind::FixedWing,
            firmware: Firmware::Ardupilot,
            cruise_speed_mps: 15.0,
            turn_radius_m: 50.0,
            acceleration_mps2: 1.0,
            climb_mps: 2.0,
            descent_mps: 2.0,
        }
    }

    /// Taking off east and climbing 80 m at 15° (about 300 m), an aircraft sent next to a
    /// waypoint 100 m out has passed it: it turns back; one 600 m out lies ahead.
    #[test]
    fn a_waypoint_passed_while_climbing_is_a_turn_back() {
        let frame = LocalFrame::new(8.5, 47.3);
        for (x, back) in [(100.0, true), (600.0, false)] {
            let items = [at(&frame, NAV_TAKEOFF, 0.0, 0.0, 80.0, [15.0, 0.0, 0.0, 0.0]), at(&frame, NAV_WAYPOINT, x, 0.0, 80.0, [0.0; 4])];
            assert_eq!(fly(&items, &plane()).turned_back_after_take_off, back, "a waypoint {x} m out");
        }
    }

    /// Sent onto a line 40 m beside its track, L1 guidance brings the aircraft onto it within a
    /// few L1 distances, turning no faster than its bank allows.
    #[test]
    fn l1_guidance_settles_on_a_line() {
        let frame = LocalFrame::new(8.5, 47.3);
        let items = [
            at(&frame, NAV_TAKEOFF, 0.0, 0.0, 50.0, [15.0, 0.0, 0.0, 0.0]),
            at(&frame, NAV_WAYPOINT, 400.0, 0.0, 50.0, [0.0; 4]),
            at(&frame, NAV_WAYPOINT, 400.0, -40.0, 50.0, [0.0; 4]),
            at(&frame, NAV_WAYPOINT, 1400.0, -40.0, 50.0, [0.0; 4]),
        ];
        let flown = fly(&items, &plane());
        // the follower's frame is the take-off point's, as the test's
        let beside = |x: f64| flown.track.iter().filter(|s| s.item == 3 && s.at.x > x).map(|s| (s.at.y + 40.0).abs()).fold(0.0, f64::max);
        assert!(beside(1000.0) < 0.5, "{} m off after 600 m", beside(1000.0));
        // the track's curvature never exceeds the turning radius's (within the roll lag)
        let headings: Vec<f64> = flown.track.windows(2).map(|w| (w[1].at - w[0].at).y.atan2((w[1].at - w[0].at).x)).collect();
        let rate = headings.windows(2).map(|h| angle_between(Coord { x: h[0].cos(), y: h[0].sin() }, Coord { x: h[1].cos(), y: h[1].sin() }).abs() / DT).fold(0.0, f64::max);
        assert!(rate <= 15.0 / 50.0 * 1.01, "{rate} rad/s");
    }

    /// A multirotor's return from 40 m: to home, a 5 s hover, 30 m at its descent rate, the last
    /// 10 m at 0.5 m/s; its photos by distance along a line are as many as the line holds.
    #[test]
    fn a_multirotor_returns_and_lands_as_arducopter_does() {
        let frame = LocalFrame::new(8.5, 47.3);
        let copter = FollowerSpec {
            kind: VehicleKind::Multirotor,
            cruise_speed_mps: 8.0,
            acceleration_mps2: 2.0,
            climb_mps: 2.5,
            descent_mps: 1.5,
            turn_radius_m: 0.0,
            firmware: Firmware::Px4,
        };
        let command = |c: u16, p: [f64; 4]| MissionItem { command: c, frame: FRAME_MISSION, params: p.map(Some), position: None };
        let items = [
            at(&frame, NAV_TAKEOFF, 0.0, 0.0, 40.0, [0.0; 4]),
            command(DO_SET_CAM_TRIGG_DIST, [10.0, 0.0, 1.0, 0.0]),
            at(&frame, NAV_WAYPOINT, 200.0, 0.0, 40.0, [0.0; 4]),
            command(DO_SET_CAM_TRIGG_DIST, [0.0; 4]),
            command(NAV_RETURN_TO_LAUNCH, [0.0; 4]),
        ];
        let flown = fly(&items, &copter);
        assert!(flown.landed);
        assert_eq!(flown.photos.len(), 20, "one at the start and one every 10 m, the last one 10 cm late");
        // 16 s up, 200 m out and back (8 m/s, 2 m/s²: 29 s each way), 5 s, 20 s, 20 s
        let expected = 16.0 + 2.0 * (200.0 / 8.0 + 8.0 / 2.0) + RTL_HOVER_S + 30.0 / 1.5 + LAND_SLOW_BELOW_M / LAND_SPEED_MPS;
        assert!((flown.duration_s - expected).abs() < 0.5, "{} s, expected {expected} s", flown.duration_s);
    }
}
