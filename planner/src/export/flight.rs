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
    /// `[lon, lat]` of every photo (the MultiPoints of kind `photos`).
    pub photos: Vec<[f64; 2]>,
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
                    photos.extend(coordinates.iter().filter(|p| p.len() >= 2).map(|p| [p[0], p[1]]));
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
            sorties[sortie - 1].push(FlownPiece { kind, points, speed_mps, ground_m });
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

/// The points a vehicle is sent to, in order, each with the piece it ends and whether it lies
/// inside a turn's arc: every point of every piece, once (consecutive pieces share their ends),
/// with the arcs of fixed-wing turns thinned to one point per `arc_step_deg` of heading
/// change, keeping the tangent points (docs/methods.md, interop §4).
pub fn waypoints(pieces: &[FlownPiece], arc_step_deg: Option<f64>) -> Vec<Waypoint> {
    let mut out: Vec<Waypoint> = Vec::new();
    for (index, piece) in pieces.iter().enumerate() {
        let keep = match (piece.kind, arc_step_deg) {
            (PieceKind::Turn, Some(step)) => thin_arc(&piece.points, step),
            _ => vec![true; piece.points.len()],
        };
        for (k, (p, kept)) in piece.points.iter().zip(keep).enumerate() {
            if !kept || out.last().is_some_and(|w| w.position == *p) {
                continue;
            }
            let on_arc = piece.kind == PieceKind::Turn && arc_step_deg.is_some() && k > 0 && k + 1 < piece.points.len();
            let ground_m = piece.ground_m.as_ref().map(|g| g[k]);
            out.push(Waypoint { position: *p, piece: index, index: k, on_arc, ground_m });
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
    pub on_arc: bool,
    /// Over terrain: the ground's height under it, above mean sea level.
    pub ground_m: Option<f64>,
}

/// Which points of a densified turn to keep: both ends, every point where one part of the
/// turn meets the next (arc and straight: there the chord length changes, or the turn changes
/// side), and on an arc a point whenever the heading has changed by `step_deg` since the last
/// one kept.
fn thin_arc(points: &[[f64; 3]], step_deg: f64) -> Vec<bool> {
    let n = points.len();
    let mut keep = vec![true; n];
    if n < 3 {
        return keep;
    }
    // a plane scaled by the latitude's cosine: good enough for angles and length ratios
    let cos = points[0][1].to_radians().cos();
    let delta = |i: usize| ((points[i + 1][0] - points[i][0]) * cos, points[i + 1][1] - points[i][1]);
    let mut since = 0.0;
    for (i, kept) in keep.iter_mut().enumerate().take(n - 1).skip(1) {
        let (a, b) = (delta(i - 1), delta(i));
        let turn = (a.0 * b.1 - a.1 * b.0).atan2(a.0 * b.0 + a.1 * b.1).to_degrees();
        let (la, lb) = (a.0.hypot(a.1), b.0.hypot(b.1));
        let next_turn = (i + 2 < n).then(|| {
            let c = delta(i + 1);
            b.0 * c.1 - b.1 * c.0
        });
        let part_ends = (la - lb).abs() > 0.01 * la.max(lb) || next_turn.is_some_and(|t| t * turn < 0.0);
        since += turn.abs();
        *kept = part_ends || since >= step_deg - 1e-9;
        if *kept {
            since = 0.0;
        }
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(n: usize, degrees: f64) -> Vec<[f64; 3]> {
        (0..=n).map(|k| (k as f64 / n as f64 * degrees).to_radians()).map(|a| [1e-3 * a.cos(), 1e-3 * a.sin(), 50.0]).collect()
    }

    #[test]
    fn thinning_keeps_ends_and_steps() {
        // 180° sampled every 5°: 15° steps keep every third point, and both ends
        let points = arc(36, 180.0);
        let keep = thin_arc(&points, 15.0);
        assert!(keep[0] && keep[36]);
        let kept: Vec<usize> = (0..=36).filter(|&i| keep[i]).collect();
        assert!(kept.windows(2).all(|w| w[1] - w[0] <= 3), "{kept:?}");
        assert!(kept.len() <= 14, "{kept:?}");
    }

    #[test]
    fn thinning_keeps_tangent_points() {
        // 20° of arc, then a straight: the tangent point (index 4) stays although only 5° of
        // heading changed since the point kept at 15°
        let mut points = arc(4, 20.0);
        let end = points[4];
        let heading = 110f64.to_radians();
        points.push([end[0] + 1e-3 * heading.cos(), end[1] + 1e-3 * heading.sin(), 50.0]);
        let keep = thin_arc(&points, 15.0);
        assert!(keep[4] && keep[5], "{keep:?}");
        assert!(!keep[1] && !keep[2], "{keep:?}");
    }

    #[test]
    fn shared_ends_appear_once() {
        let a = FlownPiece { kind: PieceKind::Sweep, points: vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0]], speed_mps: 5.0, ground_m: None };
        let b = FlownPiece { kind: PieceKind::Turn, points: vec![[1.0, 0.0, 1.0], [1.0, 1.0, 1.0]], speed_mps: 5.0, ground_m: None };
        let w = waypoints(&[a, b], None);
        assert_eq!(w.iter().map(|w| w.piece).collect::<Vec<_>>(), vec![0, 0, 1]);
    }
}
