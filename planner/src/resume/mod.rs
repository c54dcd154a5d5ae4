//! Resume: what a plan has left once its flight stopped (docs/methods.md, resume). The stored
//! trajectory is read back in flight order; the cut is a piece and how far along it (or the
//! point of the path nearest the aircraft); the route left is the cut line from a few trigger
//! distances before the cut, then every piece after it as planned, less the legs from home and
//! back of the original's sorties (the sorties are split again for what remains), the gaps
//! those leave joined by the vehicle's connections.

mod flown;

use flown::{Redo, cut_from_log};
pub use flown::{Sampling, track_feature};
use geo::Coord;
use geojson::{FeatureCollection, GeometryValue};
use serde::Deserialize;
use serde_json::Value;

use super::error::{InputError, PlanError};
use super::frame::LocalFrame;
use super::geom::{distance, polyline_length};
use super::metrics::ResumeStats;
use super::params::bearing_to_math;
use super::params::resume::{Cut, MAX_CUT_OFF_PATH_M, Resume};
use super::path::{FlightPath, Piece, PieceKind};
use super::planners::{PlannedPath, Problem};
use super::route::headland_route::connect_anywhere;
use super::turn::dubins::Pose;

/// A flown piece of the stored trajectory, in the local frame.
#[derive(Debug, Clone)]
struct Stored {
    kind: PieceKind,
    points: Vec<Coord>,
    sortie: usize,
    seq: usize,
    /// A ground vehicle's swath left as a tramline.
    tramline: bool,
    /// A fleet's drone that flies it.
    vehicle: Option<usize>,
}

/// Most a heading given with the position may differ from a piece's direction for the cut to
/// lie on that piece, degrees.
const HEADING_TOLERANCE_DEG: f64 = 60.0;

/// Pieces within this of the nearest one are as near: the earliest of them is the cut, so that
/// nothing flown over twice (a transit over a finished line) is taken for done.
const SAME_DISTANCE_M: f64 = 1.0;

/// The original plan read back, and where its flight stopped.
pub(crate) struct Remainder {
    /// The pieces of the vehicle that stopped (of a fleet: its drone's), in flight order.
    pieces: Vec<Stored>,
    /// The piece the flight stopped on, and metres along it.
    cut: (usize, f64),
    /// Metres flown again before the cut on its line.
    back_m: f64,
    /// Stretches before the cut flown again: a log shows them not done.
    redo: Vec<Redo>,
}

/// A piece's direction at `along` metres, math radians.
fn direction_at(points: &[Coord], along: f64) -> f64 {
    let mut walked = 0.0;
    for w in points.windows(2) {
        let step = distance(w[0], w[1]);
        if step > 0.0 && (walked + step >= along || w[1] == points[points.len() - 1]) {
            return (w[1].y - w[0].y).atan2(w[1].x - w[0].x);
        }
        walked += step;
    }
    0.0
}

/// The stretch of a polyline from `from` metres along to its end.
fn from_along(points: &[Coord], from: f64) -> Vec<Coord> {
    let mut walked = 0.0;
    for (i, w) in points.windows(2).enumerate() {
        let step = distance(w[0], w[1]);
        if walked + step > from {
            let f = ((from - walked) / step).clamp(0.0, 1.0);
            let mut out = vec![w[0] + (w[1] - w[0]) * f];
            out.extend_from_slice(&points[i + 1..]);
            return out;
        }
        walked += step;
    }
    vec![points[points.len() - 1]; 2]
}

/// The stretch of a polyline from its start to `along` metres along.
fn up_to(points: &[Coord], along: f64) -> Vec<Coord> {
    let mut out = vec![points[0]];
    let mut walked = 0.0;
    for w in points.windows(2) {
        let step = distance(w[0], w[1]);
        if walked + step >= along {
            out.push(w[0] + (w[1] - w[0]) * ((along - walked) / step).clamp(0.0, 1.0));
            return out;
        }
        walked += step;
        out.push(w[1]);
    }
    out
}

/// The point `along` metres along a polyline.
fn point_along(points: &[Coord], along: f64) -> Coord {
    from_along(points, along)[0]
}

impl Remainder {
    /// Reads `trajectory` (a coverage plan's, one vehicle's) and finds the cut; `sampling` says how
    /// the lines are sampled against a log (and the trigger distance flown again before a cut).
    pub fn new(trajectory: &FeatureCollection, frame: &LocalFrame, resume: &Resume, sampling: &Sampling) -> Result<Remainder, InputError> {
        let mut pieces = read(trajectory, frame)?;
        let back_m = resume.photos_back as f64 * sampling.trigger_m;
        let mut redo = Vec::new();
        // a fleet's log is its drone's: the drone whose path the track keeps nearest
        if let Cut::Flown(flown) = &resume.cut
            && pieces.iter().any(|p| p.vehicle.is_some())
            && let Some(v) = nearest_vehicle(&pieces, &flown.track.iter().map(|&[lon, lat]| frame.to_local(lon, lat)).collect::<Vec<_>>())
        {
            pieces.retain(|p| p.vehicle == Some(v));
        }
        let cut = match &resume.cut {
            Cut::At(at) => {
                if at.vehicle.is_none() && pieces.iter().any(|p| p.vehicle.is_some()) {
                    return Err(InputError::new(
                        "vehicle_missing",
                        "/at/vehicle",
                        "this plan is a fleet's: say which drone stopped (`vehicle`, as the trajectory numbers them from 0)",
                    ));
                }
                let k = pieces.iter().position(|p| p.seq == at.seq && p.vehicle == at.vehicle).ok_or_else(|| {
                    let seqs: Vec<String> = pieces.iter().map(|p| p.seq.to_string()).collect();
                    let (first, last) = (seqs.first().cloned().unwrap_or_default(), seqs.last().cloned().unwrap_or_default());
                    InputError::new("unknown_seq", "/at/seq", format!("the plan has no flown piece with seq {}; its pieces run from seq {first} to {last}", at.seq))
                })?;
                (k, at.fraction * polyline_length(&pieces[k].points))
            }
            &Cut::Position([lon, lat], heading_deg) => nearest(&pieces, frame.to_local(lon, lat), heading_deg.map(bearing_to_math))?,
            Cut::Flown(flown) => {
                let (cut, stretches) = cut_from_log(&pieces, frame, flown, sampling, back_m)?;
                redo = stretches;
                cut
            }
        };
        // of a fleet, what the drone that stopped had left
        let cut = match pieces[cut.0].vehicle {
            Some(v) => {
                let k = pieces[..cut.0].iter().filter(|p| p.vehicle == Some(v)).count();
                pieces.retain(|p| p.vehicle == Some(v));
                (k, cut.1)
            }
            None => cut,
        };
        let remainder = Remainder { pieces, cut, back_m, redo };
        if remainder.left().0.is_empty() {
            let (pointer, why) = match resume.cut {
                Cut::At(_) => ("/at", "the flight stopped after the plan's last line: nothing is left to fly"),
                Cut::Position(..) => ("/position", "the flight stopped after the plan's last line: nothing is left to fly"),
                Cut::Flown(_) => ("/flown", "the log shows every line done: nothing is left to fly"),
            };
            return Err(InputError::new("nothing_left", pointer, why));
        }
        Ok(remainder)
    }

    /// A fleet's drone that stopped (its number in the fleet).
    pub fn vehicle(&self) -> Option<usize> {
        // of a fleet, only the drone that stopped has pieces left here
        self.pieces[self.cut.0].vehicle
    }

    /// Where the flight stopped, in the local frame.
    pub fn cut_point(&self) -> Coord {
        let (k, along) = self.cut;
        point_along(&self.pieces[k].points, along)
    }

    /// The first and last working piece of each sortie (by its number), for the legs home
    /// and back outside them.
    fn spans(&self) -> Vec<(usize, usize)> {
        let mut spans: Vec<(usize, usize)> = Vec::new();
        let sorties = self.pieces.iter().map(|p| p.sortie).max().unwrap_or(0);
        for s in 1..=sorties {
            let working = || self.pieces.iter().enumerate().filter(|(_, p)| p.sortie == s && p.kind.works()).map(|(i, _)| i);
            if let (Some(first), Some(last)) = (working().next(), working().next_back()) {
                spans.push((first, last));
            }
        }
        spans
    }

    /// The pieces left to fly in order (the cut line from `back_m` before the cut, the way from
    /// the last line to the end as it was), each with the original's sortie it was flown in;
    /// and the stretch flown again.
    fn left(&self) -> (Vec<Left>, f64) {
        let (c, along) = self.cut;
        let spans = self.spans();
        let in_span = |k: usize| spans.iter().any(|&(a, b)| a <= k && k <= b);
        // the stretches before the cut a log shows not done, first
        let mut left: Vec<Left> = self
            .redo
            .iter()
            .map(|r| {
                let p = &self.pieces[r.index];
                let points = up_to(&from_along(&p.points, r.from_m), r.to_m - r.from_m);
                Left { piece: piece_of(p, points), sortie: p.sortie, index: r.index, from_m: r.from_m }
            })
            .collect();
        let redone = left.len();
        let mut overlap = 0.0;
        let cut_piece = &self.pieces[c];
        let len = polyline_length(&cut_piece.points);
        if cut_piece.kind.works() && along < len - 0.01 {
            let from = (along - self.back_m).max(0.0);
            overlap = along - from;
            left.push(Left { piece: piece_of(cut_piece, from_along(&cut_piece.points, from)), sortie: cut_piece.sortie, index: c, from_m: from });
        }
        for (k, p) in self.pieces.iter().enumerate().skip(c + 1).filter(|&(k, _)| in_span(k)) {
            // what is left starts at a line: the rest of a turn or transit is flown to it anew
            if left.len() == redone && !p.kind.works() {
                continue;
            }
            left.push(Left { piece: piece_of(p, p.points.clone()), sortie: p.sortie, index: k, from_m: 0.0 });
        }
        // the original's way from its last line to its end, as it was
        if let (Some(&(_, last)), false) = (spans.last(), left.is_empty()) {
            let tail = self.pieces.iter().enumerate().skip(last.max(c) + 1).take_while(|(_, p)| p.sortie == self.pieces[last].sortie);
            left.extend(tail.map(|(k, p)| Left { piece: piece_of(p, p.points.clone()), sortie: p.sortie, index: k, from_m: 0.0 }));
        }
        (left, overlap)
    }

    /// What the original had left after the cut: its whole flight, and its working pieces.
    fn original_left_m(&self) -> (f64, f64) {
        let (c, along) = self.cut;
        let rest = |k: usize, p: &Stored| if k == c { (polyline_length(&p.points) - along).max(0.0) } else { polyline_length(&p.points) };
        let all = self.pieces.iter().enumerate().skip(c).map(|(k, p)| rest(k, p)).sum();
        let working = self.pieces.iter().enumerate().skip(c).filter(|(_, p)| p.kind.works()).map(|(k, p)| rest(k, p)).sum();
        (all, working)
    }

    /// The route left, from `problem.start` (home, or the aircraft in the air) to
    /// `problem.end`, its gaps joined by `problem.connector`.
    pub fn route(&self, problem: &Problem<'_>) -> Result<PlannedPath, PlanError> {
        let (left, _) = self.left();
        if left.is_empty() {
            return Err(PlanError::Infeasible("the flight stopped after the plan's last line: nothing is left to fly".into()));
        }
        let half_swath = problem.layout.half_swath();
        let mut path = FlightPath::default();
        // a ground vehicle drives to its swaths along the headland, as its plan did
        let headland = problem.ground.map(|setup| setup.routes(problem.region, problem.vehicle));
        let join = |path: &mut FlightPath, from: Pose, to: Pose| -> Result<(), PlanError> {
            let way = match &headland {
                Some(routes) => Some(connect_anywhere(routes, from, to).0.points),
                None => problem.connector.path(from, to),
            };
            let points = way.ok_or_else(|| {
                if problem.connector.stopped() {
                    return PlanError::Cancelled;
                }
                PlanError::Infeasible(format!("no clear path joins ({:.1}, {:.1}) to ({:.1}, {:.1}) in the local frame", from.x, from.y, to.x, to.y))
            })?;
            path.push(PieceKind::Transit, points, 0.0);
            Ok(())
        };
        let start_pose = |p: &Piece| Pose::at(p.start(), direction_at(&p.points, 0.0));
        let end_pose = |p: &Piece| Pose::at(p.end(), direction_at(&p.points, f64::INFINITY));
        // where the vehicle finds no connection of its own (a fixed wing beside a zone), it
        // flies the original's way there, its camera off
        let as_flown = |path: &mut FlightPath, pieces: &[Stored]| {
            for p in pieces.iter().filter(|p| p.points.len() >= 2) {
                path.pieces.push(Piece::new(if p.kind.works() { PieceKind::Transit } else { p.kind }, p.points.clone(), 0.0));
            }
        };
        let first = &left[0];
        if let Some(start) = problem.start {
            let entry = start_pose(&first.piece);
            if join(&mut path, Pose::at(start, (entry.y - start.y).atan2(entry.x - start.x)), entry).is_err() {
                // the original's own way from its sortie's start, if it started there
                let opened = self.pieces.iter().position(|p| p.sortie == first.sortie).unwrap_or(first.index);
                if distance(self.pieces[opened].points[0], start) >= STORED_ROUNDING_M {
                    join(&mut path, Pose::at(start, (entry.y - start.y).atan2(entry.x - start.x)), entry)?;
                }
                as_flown(&mut path, &self.pieces[opened..first.index]);
                if first.from_m > 0.0 {
                    let cut = &self.pieces[first.index];
                    let flown = up_to(&cut.points, first.from_m);
                    as_flown(&mut path, &[Stored { points: flown, ..cut.clone() }]);
                }
                if let Some(p) = path.pieces.first_mut() {
                    p.points[0] = start;
                }
            }
        }
        let mut breaks = Vec::new();
        let mut sortie = first.sortie;
        let mut previous: Option<usize> = None;
        for Left { piece: mut p, sortie: of, index, .. } in left {
            if of != sortie {
                breaks.push(path.pieces.len());
                sortie = of;
            }
            if let Some(last) = path.pieces.last().filter(|last| last.end() != p.start()) {
                let from = end_pose(last);
                let joined = join(&mut path, from, start_pose(&p));
                match (joined, previous) {
                    (Ok(()), _) => {}
                    // the original's way between them (home and back)
                    (Err(_), Some(k)) if k < index => as_flown(&mut path, &self.pieces[k + 1..index]),
                    (Err(e), _) => return Err(e),
                }
            }
            previous = Some(index);
            if p.kind.works() {
                p.half_swath_m = half_swath;
            }
            path.pieces.push(p);
        }
        if let (Some(end), Some(last)) = (problem.end, path.pieces.last_mut()) {
            if distance(last.end(), end) < STORED_ROUNDING_M {
                // the original's way to the end, its end read back a few millimetres off
                *last.points.last_mut().expect("a piece has points") = end;
            } else {
                let from = end_pose(last);
                join(&mut path, from, Pose::at(end, (end.y - from.y).atan2(end.x - from.x)))?;
            }
        }
        let longest = path.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).max_by(|a, b| a.length().total_cmp(&b.length()));
        let sweep_angle = longest.map_or(0.0, |p| direction_at(&p.points, 0.0).rem_euclid(std::f64::consts::PI));
        Ok(PlannedPath { sortie_breaks: breaks, ..PlannedPath::new(path, sweep_angle, 1) })
    }

    /// The statistics' account of the cut.
    pub fn stats(&self, frame: &LocalFrame) -> ResumeStats {
        let (c, along) = self.cut;
        let len = polyline_length(&self.pieces[c].points);
        let (original_left_m, original_sweep_left_m) = self.original_left_m();
        let round = |v: f64| (v * 100.0).round() / 100.0;
        ResumeStats {
            seq: self.pieces[c].seq,
            fraction: if len > 0.0 { (along / len).clamp(0.0, 1.0) } else { 1.0 },
            position: frame.to_wgs84(self.cut_point()),
            original_left_m: round(original_left_m),
            original_sweep_left_m: round(original_sweep_left_m),
            overlap_m: round(self.left().1),
            redone_m: (!self.redo.is_empty()).then(|| round(self.redo.iter().map(|r| r.to_m - r.from_m).sum())),
        }
    }
}

/// A piece left to fly.
struct Left {
    piece: Piece,
    /// The original's sortie it was flown in.
    sortie: usize,
    /// The original's piece it is, from `from_m` metres along.
    index: usize,
    from_m: f64,
}

/// Farther than this, a point read back from the stored trajectory is another point (its
/// coordinates have 7 decimals: about a centimetre).
const STORED_ROUNDING_M: f64 = 0.05;

/// Of a fleet's drones, the one whose pieces lie nearest `track` on average (up to 500 of its
/// positions); `None` for one vehicle's plan.
fn nearest_vehicle(pieces: &[Stored], track: &[Coord]) -> Option<usize> {
    let drones = pieces.iter().filter_map(|p| p.vehicle).max()?;
    let step = (track.len() / 500).max(1);
    let mean_to = |v: usize| -> f64 {
        let own: Vec<&Stored> = pieces.iter().filter(|p| p.vehicle == Some(v)).collect();
        let near = |t: Coord| own.iter().flat_map(|p| p.points.windows(2)).map(|w| flown::point_to_segment(t, w[0], w[1])).fold(f64::INFINITY, f64::min);
        track.iter().step_by(step).map(|&t| near(t)).sum::<f64>()
    };
    (0..=drones).min_by(|&a, &b| mean_to(a).total_cmp(&mean_to(b)))
}

/// The stored piece `p` as a piece of the route left, along `points` (all or part of its own).
fn piece_of(p: &Stored, points: Vec<Coord>) -> Piece {
    Piece { tramline: p.tramline, ..Piece::new(p.kind, points, 0.0) }
}

/// The flown pieces of a coverage plan's trajectory, in flight order.
fn read(trajectory: &FeatureCollection, frame: &LocalFrame) -> Result<Vec<Stored>, InputError> {
    let mut pieces = Vec::new();
    for (i, feature) in trajectory.features.iter().enumerate() {
        let property = |key: &str| feature.properties.as_ref().and_then(|p| p.get(key));
        let Some(kind) = property("kind").and_then(|k| PieceKind::deserialize(k).ok()) else { continue };
        let Some(GeometryValue::LineString { coordinates }) = feature.geometry.as_ref().map(|g| &g.value) else { continue };
        let points: Vec<Coord> = coordinates.iter().filter(|p| p.len() >= 2).map(|p| frame.to_local(p[0], p[1])).collect();
        if points.len() < 2 {
            continue;
        }
        let number = |key: &str| property(key).and_then(Value::as_u64).map(|n| n as usize);
        let tramline = property("tramline").and_then(Value::as_bool).unwrap_or(false);
        pieces.push(Stored { kind, points, sortie: number("sortie").unwrap_or(1), seq: number("seq").unwrap_or(i), tramline, vehicle: number("vehicle") });
    }
    if !pieces.iter().any(|p| p.kind == PieceKind::Sweep) {
        return Err(InputError::new("not_resumable", "/at", "only a coverage plan's sweep lines are resumed; this plan has none"));
    }
    if trajectory.features.iter().any(|f| f.properties.as_ref().is_some_and(|p| p.contains_key("pass"))) {
        return Err(InputError::new(
            "not_resumable",
            "/at",
            "an oblique plan's passes each hold their own camera pose, which a resumed plan does not carry yet: plan the mission again",
        ));
    }
    Ok(pieces)
}

/// The cut nearest `at` (with a math `heading`: among pieces flown within
/// [`HEADING_TOLERANCE_DEG`] of it): the earliest piece within [`SAME_DISTANCE_M`] of the nearest.
fn nearest(pieces: &[Stored], at: Coord, heading: Option<f64>) -> Result<(usize, f64), InputError> {
    let mut candidates: Vec<(usize, f64, f64)> = Vec::new();
    for (k, p) in pieces.iter().enumerate() {
        let mut walked = 0.0;
        let mut best: Option<(f64, f64)> = None;
        for w in p.points.windows(2) {
            let d = w[1] - w[0];
            let step = d.x.hypot(d.y);
            let aligned = heading.is_none_or(|h| {
                let off = (d.y.atan2(d.x) - h).rem_euclid(std::f64::consts::TAU);
                off.min(std::f64::consts::TAU - off).to_degrees() <= HEADING_TOLERANCE_DEG
            });
            if step > 0.0 && aligned {
                let t = (((at - w[0]).x * d.x + (at - w[0]).y * d.y) / (step * step)).clamp(0.0, 1.0);
                let off = distance(at, w[0] + d * t);
                if best.is_none_or(|(b, _)| off < b) {
                    best = Some((off, walked + t * step));
                }
            }
            walked += step;
        }
        if let Some((off, along)) = best {
            candidates.push((k, off, along));
        }
    }
    let nearest = candidates.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    if nearest > MAX_CUT_OFF_PATH_M {
        let said = if nearest.is_finite() { format!("{nearest:.0} m from the plan's path") } else { "on no piece flown on that heading".to_string() };
        return Err(InputError::new("cut_off_path", "/position", format!("the position is {said}; the most accepted is {MAX_CUT_OFF_PATH_M} m: is it this plan's flight?")));
    }
    let &(k, _, along) = candidates.iter().find(|c| c.1 <= nearest + SAME_DISTANCE_M).expect("the nearest is a candidate");
    Ok((k, along))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(x: f64, y: f64) -> Coord {
        Coord { x, y }
    }

    fn stored(kind: PieceKind, points: &[Coord], sortie: usize, seq: usize) -> Stored {
        Stored { kind, points: points.to_vec(), sortie, seq, tramline: false, vehicle: None }
    }

    /// Two sorties of two lines each from home at (-50, 0): out, line, turn, line, back.
    fn two_sorties() -> Vec<Stored> {
        use PieceKind::*;
        let home = c(-50.0, 0.0);
        vec![
            stored(Transit, &[home, c(0.0, 0.0)], 1, 0),
            stored(Sweep, &[c(0.0, 0.0), c(100.0, 0.0)], 1, 1),
            stored(Turn, &[c(100.0, 0.0), c(100.0, 10.0)], 1, 2),
            stored(Sweep, &[c(100.0, 10.0), c(0.0, 10.0)], 1, 3),
            stored(Transit, &[c(0.0, 10.0), home], 1, 4),
            stored(Transit, &[home, c(0.0, 20.0)], 2, 5),
            stored(Sweep, &[c(0.0, 20.0), c(100.0, 20.0)], 2, 6),
            stored(Turn, &[c(100.0, 20.0), c(100.0, 30.0)], 2, 7),
            stored(Sweep, &[c(100.0, 30.0), c(0.0, 30.0)], 2, 8),
            stored(Transit, &[c(0.0, 30.0), home], 2, 9),
        ]
    }

    #[test]
    fn what_is_left_starts_back_on_the_cut_line_and_skips_the_legs_home() {
        let r = Remainder { pieces: two_sorties(), cut: (3, 60.0), back_m: 15.0, redo: Vec::new() };
        let (left, overlap) = r.left();
        assert_eq!(overlap, 15.0);
        // the cut line from 45 m along (x = 55), then the second sortie's working run
        assert_eq!(left[0].piece.points, vec![c(55.0, 10.0), c(0.0, 10.0)]);
        let kinds: Vec<(PieceKind, usize)> = left.iter().map(|l| (l.piece.kind, l.sortie)).collect();
        use PieceKind::*;
        assert_eq!(kinds, vec![(Sweep, 1), (Sweep, 2), (Turn, 2), (Sweep, 2), (Transit, 2)]);
        // the original had 40 m of its line, its leg home, the second sortie left
        let (all, working) = r.original_left_m();
        let legs_home = 50f64.hypot(10.0) + 50f64.hypot(20.0) + 50f64.hypot(30.0);
        assert!((working - 240.0).abs() < 1e-9 && (all - (40.0 + 210.0 + legs_home)).abs() < 1e-9, "{all} {working}");
    }

    #[test]
    fn a_cut_in_a_turn_or_at_a_lines_end_resumes_at_the_next_line() {
        for cut in [(2, 4.0), (1, 100.0)] {
            let r = Remainder { pieces: two_sorties(), cut, back_m: 15.0, redo: Vec::new() };
            let (left, overlap) = r.left();
            assert_eq!((left[0].piece.points[0], overlap), (c(100.0, 10.0), 0.0), "{cut:?}");
        }
        let done = Remainder { pieces: two_sorties(), cut: (9, 3.0), back_m: 15.0, redo: Vec::new() };
        assert!(done.left().0.is_empty());
    }

    #[test]
    fn the_nearest_piece_on_the_heading_is_the_cut_and_a_far_position_is_refused() {
        let pieces = two_sorties();
        // between lines 3 and 6 (y = 10 and 20, flown west and east): the nearer, or the one
        // flown on the heading given
        assert_eq!(nearest(&pieces, c(30.0, 14.0), None).unwrap(), (3, 70.0));
        let east = Some(0.0);
        assert_eq!(nearest(&pieces, c(30.0, 14.0), east).unwrap(), (6, 30.0));
        // the home legs pass home, the first (out) is the cut
        assert_eq!(nearest(&pieces, c(-50.0, 0.0), None).unwrap(), (0, 0.0));
        let far = nearest(&pieces, c(30.0, 400.0), None).unwrap_err();
        assert_eq!((far.code, far.pointer.as_str()), ("cut_off_path", "/position"));
    }
}
