//! The flown path as exporters read it: the trajectory's pieces in WGS84, sortie by sortie.

use geojson::{FeatureCollection, GeometryValue};
use serde::Deserialize;
use serde_json::Value;

use crate::error::InputError;
use crate::path::PieceKind;

/// One flown piece: its kind, its points `[lon, lat, altitude]` and its speed. The altitude
/// is above home, or above mean sea level where `ground_m` (a plan over terrain) gives the
/// ground's height under each point.
#[derive(Debug, Clone, PartialEq)]
pub struct FlownPiece {
    pub kind: PieceKind,
    pub points: Vec<[f64; 3]>,
    pub speed_mps: f64,
    pub ground_m: Option<Vec<f64>>,
    /// A ground plan's swath left as a tramline.
    pub tramline: bool,
    /// On a pass of an oblique plan, where the camera points.
    pub camera: Option<CameraPose>,
}

/// The camera on a pass of an oblique plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPose {
    pub pass: usize,
    pub gimbal_pitch_deg: f64,
    /// Compass bearing the vehicle faces on the pass; `None`: the way it flies.
    pub heading_deg: Option<f64>,
}

/// What the camera does at an inspection's viewpoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewAction {
    /// `[lon, lat, altitude above home]`, as the leg that reaches it ends.
    pub position: [f64; 3],
    /// Compass bearing the vehicle faces.
    pub yaw_deg: f64,
    pub gimbal_pitch_deg: f64,
}

/// The pieces of each sortie in flight order, an inspection's viewpoints, and the photos the
/// plan shows on its sweeps.
#[derive(Debug, Clone, PartialEq)]
pub struct Flight {
    pub sorties: Vec<Vec<FlownPiece>>,
    pub views: Vec<ViewAction>,
    /// Every photo (the MultiPoints of kind `photos`).
    pub photos: Vec<PlanPhoto>,
}

/// A photo of the plan: `[lon, lat]`, and the pass of an oblique plan it is taken on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanPhoto {
    pub at: [f64; 2],
    pub pass: Option<usize>,
}

/// The photos of each pass (`None`: a plan without passes), indexed for looking up those near
/// a line: a line's camera takes the photos of its own pass only (two passes' lines may lie on
/// one another).
pub fn photos_by_pass(photos: &[PlanPhoto]) -> std::collections::BTreeMap<Option<usize>, rstar::RTree<[f64; 2]>> {
    let mut passes: std::collections::BTreeMap<Option<usize>, Vec<[f64; 2]>> = std::collections::BTreeMap::new();
    for photo in photos {
        passes.entry(photo.pass).or_default().push(photo.at);
    }
    passes.into_iter().map(|(pass, at)| (pass, rstar::RTree::bulk_load(at))).collect()
}

impl Flight {
    /// Reads the LineString features of kind sweep, headland, turn or transit, and the Points of
    /// kind viewpoint; points without a height are flown at `altitude_m`.
    pub fn from_trajectory(trajectory: &FeatureCollection, altitude_m: f64) -> Result<Flight, InputError> {
        let mut sorties: Vec<Vec<FlownPiece>> = Vec::new();
        let mut views = Vec::new();
        let mut photos = Vec::new();
        for (i, feature) in trajectory.features.iter().enumerate() {
            let property = |key: &str| feature.properties.as_ref().and_then(|p| p.get(key));
            let number = |key: &str| property(key).and_then(Value::as_f64);
            if property("kind").and_then(Value::as_str) == Some("viewpoint") {
                let (Some(GeometryValue::Point { coordinates: p }), Some(yaw_deg), Some(gimbal_pitch_deg)) =
                    (feature.geometry.as_ref().map(|g| &g.value), number("yaw_deg"), number("gimbal_pitch_deg"))
                else {
                    return Err(InputError::new("invalid_trajectory", format!("/features/{i}"), "a viewpoint is a Point with yaw_deg and gimbal_pitch_deg"));
                };
                views.push(ViewAction { position: [p[0], p[1], p.as_slice().get(2).copied().unwrap_or(altitude_m)], yaw_deg, gimbal_pitch_deg });
                continue;
            }
            if property("kind").and_then(Value::as_str) == Some("photos") {
                if let Some(GeometryValue::MultiPoint { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) {
                    let pass = property("pass").and_then(Value::as_u64).map(|p| p as usize);
                    photos.extend(coordinates.iter().filter(|p| p.len() >= 2).map(|p| PlanPhoto { at: [p[0], p[1]], pass }));
                }
                continue;
            }
            // the flown pieces; other marks are not flown
            let Some(kind) = property("kind").and_then(|k| PieceKind::deserialize(k).ok()) else { continue };
            let Some(GeometryValue::LineString { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) else {
                return Err(InputError::new("invalid_trajectory", format!("/features/{i}/geometry"), "a flown piece must be a LineString"));
            };
            let points = coordinates.iter().map(|p| [p[0], p[1], p.as_slice().get(2).copied().unwrap_or(altitude_m)]).collect();
            let sortie = property("sortie").and_then(Value::as_u64).unwrap_or(1).max(1) as usize;
            if sortie > sorties.len() {
                sorties.resize(sortie, Vec::new());
            }
            let speed_mps = property("speed_mps").and_then(Value::as_f64).unwrap_or(0.0);
            let ground_m = match property("altitude_reference").and_then(Value::as_str) {
                Some(super::geojson::TERRAIN_REFERENCE) => {
                    let ground: Option<Vec<f64>> = property("ground_m").and_then(Value::as_array).map(|a| a.iter().filter_map(Value::as_f64).collect());
                    match ground {
                        Some(g) if g.len() == coordinates.len() => Some(g),
                        _ => {
                            return Err(InputError::new(
                                "invalid_trajectory",
                                format!("/features/{i}/properties/ground_m"),
                                "a piece over terrain gives the ground under each point",
                            ));
                        }
                    }
                }
                _ => None,
            };
            let tramline = property("tramline").and_then(Value::as_bool).unwrap_or(false);
            let camera = match (property("pass").and_then(Value::as_u64), number("gimbal_pitch_deg")) {
                (Some(pass), Some(gimbal_pitch_deg)) => Some(CameraPose { pass: pass as usize, gimbal_pitch_deg, heading_deg: number("camera_heading_deg") }),
                _ => None,
            };
            sorties[sortie - 1].push(FlownPiece { kind, points, speed_mps, ground_m, tramline, camera });
        }
        sorties.retain(|s| !s.is_empty());
        if sorties.is_empty() {
            return Err(InputError::new("invalid_trajectory", "/features", "the trajectory has no flown piece"));
        }
        Ok(Flight { sorties, views, photos })
    }

    /// Over terrain: the ground's height, above mean sea level, where `sortie` takes off.
    pub fn launch_ground_m(&self, sortie: usize) -> Option<f64> {
        self.sorties.get(sortie)?.first()?.ground_m.as_ref()?.first().copied()
    }
}

/// The points a vehicle is sent to, in order, each with the piece it ends: every point of every
/// piece, once (consecutive pieces share their ends); with `arc_corner_deg` (a fixed wing) the
/// arcs of turns and transits are written as corners round them (docs/flight-files.md).
pub fn waypoints(pieces: &[FlownPiece], arc_corner_deg: Option<f64>) -> Vec<Waypoint> {
    let mut out: Vec<Waypoint> = Vec::new();
    for (index, piece) in pieces.iter().enumerate() {
        let points = match arc_corner_deg {
            Some(max_turn) if matches!(piece.kind, PieceKind::Turn | PieceKind::Transit) => arc_corners(piece, max_turn),
            _ => (0..piece.points.len()).map(|k| (k, piece.points[k], piece.ground_m.as_ref().map(|g| g[k]), None)).collect(),
        };
        for (k, position, ground_m, arc_begins_m) in points {
            if out.last().is_some_and(|w| w.position == position) {
                continue;
            }
            out.push(Waypoint { position, piece: index, index: k, arc_begins_m, ground_m });
        }
    }
    out
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    /// `[lon, lat, altitude]`: above home, or (`ground_m` given) above mean sea level.
    pub position: [f64; 3],
    /// Index of the piece this point belongs to (the first one that has it), and of the point
    /// in that piece.
    pub piece: usize,
    pub index: usize,
    /// A corner written for an arc: the distance from it at which the arc begins.
    pub arc_begins_m: Option<f64>,
    /// Over terrain: the ground's height under it, above mean sea level.
    pub ground_m: Option<f64>,
}

/// The largest heading change between two samples of an arc (`turn::dubins` samples at most
/// 10° a step), with room for rounding.
const ARC_STEP_MAX_RAD: f64 = 10.5 * std::f64::consts::PI / 180.0;

/// A point written for a piece: the index of the piece's point at or before it, its position,
/// the ground under it, and for an arc's corner the distance from it at which the arc begins.
type Written = (usize, [f64; 3], Option<f64>, Option<f64>);

/// A fixed wing's arcs as an autopilot following waypoints flies them: each arc of `piece`
/// (a run of equal chords turning one way) becomes the corners of the polygon drawn round it,
/// one per `max_turn_deg` of heading change at most, each with the distance from it at which
/// the arc begins; straights keep their ends.
fn arc_corners(piece: &FlownPiece, max_turn_deg: f64) -> Vec<Written> {
    let points = &piece.points;
    let n = points.len();
    let ground = |k: usize| piece.ground_m.as_ref().map(|g| g[k]);
    let mut out = vec![(0, points[0], ground(0), None)];
    if n < 2 {
        return out;
    }
    const METRES_PER_DEGREE: f64 = 111_320.0;
    let cos = points[0][1].to_radians().cos();
    let local = |p: &[f64; 3]| geo::Coord { x: p[0] * cos * METRES_PER_DEGREE, y: p[1] * METRES_PER_DEGREE };
    let back = |c: geo::Coord, z: f64| [c.x / cos / METRES_PER_DEGREE, c.y / METRES_PER_DEGREE, z];
    let xy: Vec<geo::Coord> = points.iter().map(local).collect();
    let heading = |i: usize| (xy[i + 1].y - xy[i].y).atan2(xy[i + 1].x - xy[i].x);
    let length = |i: usize| (xy[i + 1] - xy[i]).x.hypot((xy[i + 1] - xy[i]).y);
    let wrap = |a: f64| (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    // the turn at vertex i, between chords i - 1 and i, when it continues an arc: equal chords
    // turning no more than the sampler's step (a corner between two legs is no arc)
    let arc_turn = |i: usize| {
        let turn = wrap(heading(i) - heading(i - 1));
        let equal = (length(i) - length(i - 1)).abs() <= 0.01 * length(i).max(length(i - 1));
        (turn.abs() > 1e-4 && turn.abs() <= ARC_STEP_MAX_RAD && equal).then_some(turn)
    };
    let mut a = 0;
    while a < n - 1 {
        // chords a..=b form one arc
        let mut b = a;
        while b + 1 < n - 1 && arc_turn(b + 1).is_some_and(|t| arc_turn(a + 1).is_some_and(|t0| t * t0 > 0.0)) {
            b += 1;
        }
        if b == a {
            out.push((a + 1, points[a + 1], ground(a + 1), None));
            a += 1;
            continue;
        }
        let beta = (a + 1..=b).map(|i| wrap(heading(i) - heading(i - 1))).sum::<f64>() / (b - a) as f64;
        let total = beta * (b - a + 1) as f64;
        let radius = length(a) / (2.0 * (beta.abs() / 2.0).sin());
        let h0 = heading(a) - beta / 2.0;
        let side = beta.signum();
        let centre = xy[a] + geo::Coord { x: -h0.sin(), y: h0.cos() } * (side * radius);
        let parts = (total.abs().to_degrees() / max_turn_deg).ceil().max(1.0) as usize;
        let step = total / parts as f64;
        let tangent = radius * (step.abs() / 2.0).tan();
        let z = (a..=b + 1).map(|k| points[k][2]).fold(f64::NEG_INFINITY, f64::max);
        let highest = (a..=b + 1).max_by(|&i, &j| points[i][2].total_cmp(&points[j][2])).unwrap_or(a);
        for j in 0..parts {
            let h = h0 + step * j as f64;
            let on_arc = centre + geo::Coord { x: h.sin(), y: -h.cos() } * (side * radius);
            let corner = on_arc + geo::Coord { x: h.cos(), y: h.sin() } * tangent;
            out.push((a, back(corner, z), ground(highest), Some(tangent)));
        }
        out.push((b + 1, points[b + 1], ground(b + 1), None));
        a = b + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(n: usize, degrees: f64) -> Vec<[f64; 3]> {
        (0..=n).map(|k| (k as f64 / n as f64 * degrees).to_radians()).map(|a| [1e-3 * a.cos(), 1e-3 * a.sin(), 50.0]).collect()
    }

    fn turn(points: Vec<[f64; 3]>) -> FlownPiece {
        FlownPiece { kind: PieceKind::Turn, points, speed_mps: 15.0, ground_m: None, tramline: false, camera: None }
    }

    /// A half circle sampled every 5°, then a straight: two corners of the square round it,
    /// each as far from the arc's ends as the radius (tan 45°), and the straight's end.
    #[test]
    fn an_arc_becomes_the_corners_round_it() {
        let mut points = arc(36, 180.0);
        points.push([-1e-3, -1e-3, 50.0]);
        let out = arc_corners(&turn(points.clone()), 90.0);
        let metres = |p: [f64; 3]| (p[0] * 111_320.0, p[1] * 111_320.0);
        let radius = 1e-3 * 111_320.0;
        assert_eq!(out.len(), 5, "{out:?}");
        assert_eq!(out[0].1, points[0]);
        for (corner, expected) in out[1..3].iter().zip([(radius, radius), (-radius, radius)]) {
            let (x, y) = metres(corner.1);
            assert!((x - expected.0).abs() < 0.5 && (y - expected.1).abs() < 0.5, "{corner:?}");
            assert!(corner.3.is_some_and(|d| (d - radius).abs() < 0.5), "{corner:?}");
        }
        assert_eq!(out[3].1, points[36]);
        assert_eq!(out[4].1, points[37]);
    }

    /// 60° of arc is one corner; 300° five, each standing for 60°.
    #[test]
    fn corners_stand_for_at_most_the_step() {
        assert_eq!(arc_corners(&turn(arc(12, 60.0)), 90.0).iter().filter(|c| c.3.is_some()).count(), 1);
        let many = arc_corners(&turn(arc(60, 300.0)), 90.0);
        let corners: Vec<f64> = many.iter().filter_map(|c| c.3).collect();
        assert_eq!(corners.len(), 4);
        let radius = 1e-3 * 111_320.0;
        assert!(corners.iter().all(|d| (d - radius * 37.5f64.to_radians().tan()).abs() < 0.5), "{corners:?}");
    }

    #[test]
    fn shared_ends_appear_once() {
        let a = FlownPiece { kind: PieceKind::Sweep, points: vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0]], speed_mps: 5.0, ground_m: None, tramline: false, camera: None };
        let b = FlownPiece { kind: PieceKind::Turn, points: vec![[1.0, 0.0, 1.0], [1.0, 1.0, 1.0]], speed_mps: 5.0, ground_m: None, tramline: false, camera: None };
        let w = waypoints(&[a, b], None);
        assert_eq!(w.iter().map(|w| w.piece).collect::<Vec<_>>(), vec![0, 0, 1]);
    }
}
