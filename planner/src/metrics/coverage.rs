//! The ground a plan covers: its swaths as flown, their union, what lies under it.

use geo::algorithm::buffer::{BufferStyle, LineCap};
use geo::{Area, BooleanOps, Buffer, Coord, Euclidean, Length, LineString, MultiLineString, MultiPolygon, Polygon, Simplify};

use super::photos::{photo_positions, photo_strips};
use crate::geom::distance;
use crate::path::{FlightPath, PieceKind};
use crate::sweep::Footprint;

/// The swath of a sweep piece as a polygon.
fn swath(points: &[Coord], half: f64) -> Option<Polygon> {
    let (a, b) = (points[0], *points.last()?);
    let d = b - a;
    let len = d.x.hypot(d.y);
    if len == 0.0 || half <= 0.0 {
        return None;
    }
    let n = Coord { x: -d.y / len * half, y: d.x / len * half };
    Some(Polygon::new(LineString::from(vec![a - n, b - n, b + n, a + n, a - n]), vec![]))
}

/// How far a swath's centreline may be straightened before it is measured.
const SWATH_TOLERANCE_M: f64 = 0.01;

/// The swath of a polyline flown without stopping to turn: a sensor or boom `half` to either
/// side, across the direction of travel, turns with the vehicle at each bend, so its footprint
/// is a rectangle per straight stretch and, at each bend, the fan the swath sweeps on the
/// outside as the vehicle turns (seed 002's continuous footprint). (A buffer with round joins
/// is the same ground, but `geo`'s leaves out the middle of a loop tighter than the swath.)
fn footprint(line: &[Coord], half: f64) -> Vec<Polygon> {
    let mut shapes: Vec<Polygon> = line.windows(2).filter_map(|w| swath(w, half)).collect();
    let closed = line.len() > 3 && line.first() == line.last();
    let bends = line.windows(3).map(|w| (w[0], w[1], w[2]));
    let closing = closed.then(|| (line[line.len() - 2], line[0], line[1]));
    for (a, v, b) in bends.chain(closing) {
        let (d_in, d_out) = (v - a, b - v);
        let turn = (d_in.x * d_out.y - d_in.y * d_out.x).atan2(d_in.x * d_out.x + d_in.y * d_out.y);
        if turn.abs() < 1e-6 {
            continue;
        }
        // the outside of a left turn is on the right: the fan starts across the way in, there
        let start = d_in.y.atan2(d_in.x) - turn.signum() * std::f64::consts::FRAC_PI_2;
        let steps = (turn.abs() / FAN_STEP_RAD).ceil() as usize;
        // counter-clockwise, as the union wants its shapes: a right turn's fan is drawn backwards
        let (from, sweep) = if turn > 0.0 { (start, turn) } else { (start + turn, -turn) };
        let arc = (0..=steps).map(|k| {
            let angle = from + sweep * k as f64 / steps as f64;
            v + Coord { x: half * angle.cos(), y: half * angle.sin() }
        });
        shapes.push(Polygon::new(LineString::from(std::iter::once(v).chain(arc).collect::<Vec<_>>()), vec![]));
    }
    shapes
}

/// The angle of one straight piece of a fan's arc (5°).
const FAN_STEP_RAD: f64 = std::f64::consts::PI / 36.0;

/// What one strip of swept ground is drawn from.
enum Strip {
    /// A ground vehicle's headland pass: a closed ring.
    Pass(Vec<Coord>, f64),
    /// Sweeps flown one after another.
    Line(Vec<Coord>, f64),
}

impl Strip {
    /// A pass, a closed ring from its first point in canonical form: the same ring driven from
    /// anywhere, either way round, gives the same strip.
    fn pass(ring: &[Coord], half: f64) -> Strip {
        if ring.len() < 4 || ring.first() != ring.last() {
            return Strip::Pass(ring.to_vec(), half);
        }
        let n = ring.len() - 1;
        let forward: Vec<Coord> = ring[..n].to_vec();
        let backward: Vec<Coord> = forward.iter().rev().copied().collect();
        let lowest = forward.iter().copied().min_by(|a, b| compare_points(&[*a], &[*b])).unwrap_or_default();
        // every rotation that starts at the lowest point, either way round: the least
        let starts = |seq: &[Coord]| (0..n).filter(|&i| seq[i] == lowest).map(|i| seq[i..].iter().chain(&seq[..=i]).copied().collect::<Vec<Coord>>()).collect::<Vec<_>>();
        let first = starts(&forward).into_iter().chain(starts(&backward)).min_by(|a, b| compare_points(a, b)).unwrap_or_else(|| ring.to_vec());
        Strip::Pass(first, half)
    }

    /// A single straight sweep from its lower end: flown either way, the same strip.
    fn line(mut points: Vec<Coord>, half: f64) -> Strip {
        if points.len() == 2 && compare_points(&points[1..], &points[..1]).is_lt() {
            points.reverse();
        }
        Strip::Line(points, half)
    }

    fn points(&self) -> &[Coord] {
        match self {
            Strip::Pass(p, _) | Strip::Line(p, _) => p,
        }
    }

    fn half(&self) -> f64 {
        match self {
            Strip::Pass(_, h) | Strip::Line(_, h) => *h,
        }
    }

    fn draw(&self) -> Vec<Polygon> {
        match self {
            Strip::Pass(ring, half) => {
                // the same ground as [`footprint`], faster on passes of thousands of short
                // segments (and the passes turn no tighter than the swath is wide, where `geo`'s
                // buffer errs)
                let style = BufferStyle::new(*half).line_cap(LineCap::Butt);
                LineString::from(ring.clone()).buffer_with_style(style).0
            }
            Strip::Line(line, half) => {
                let mut line = LineString::from(line.clone()).simplify(SWATH_TOLERANCE_M);
                line.0.dedup_by(|a, b| distance(*a, *b) < SWATH_TOLERANCE_M);
                if *half > 0.0 { footprint(&line.0, *half) } else { Vec::new() }
            }
        }
    }
}

/// Point sequences in lexicographic order of their coordinates.
fn compare_points(a: &[Coord], b: &[Coord]) -> std::cmp::Ordering {
    a.iter().zip(b).map(|(p, q)| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))).find(|o| o.is_ne()).unwrap_or(a.len().cmp(&b.len()))
}

/// The swaths of `path`. Sweeps flown one after another (a spiral's rings, a grid path's runs)
/// are one polyline, straightened to within [`SWATH_TOLERANCE_M`] (offset curves come as
/// thousands of sub-millimetre segments) and measured by [`footprint`]; a ground vehicle's
/// headland passes cover the same ground, measured by their buffer.
fn sweep_strips(path: &FlightPath) -> Vec<Strip> {
    let mut strips = Vec::new();
    let pieces = &path.pieces;
    let mut i = 0;
    while i < pieces.len() {
        if pieces[i].kind == PieceKind::Headland {
            strips.push(Strip::pass(&pieces[i].points, pieces[i].half_swath_m));
            i += 1;
            continue;
        }
        if pieces[i].kind != PieceKind::Sweep {
            i += 1;
            continue;
        }
        let half = pieces[i].half_swath_m;
        let mut line = pieces[i].points.clone();
        i += 1;
        // joined sweeps only: a fleet's path runs one drone's flight after another's
        while let Some(next) = pieces.get(i).filter(|p| p.kind == PieceKind::Sweep && p.half_swath_m == half && line.last() == p.points.first()) {
            line.extend_from_slice(&next.points[1..]);
            i += 1;
        }
        strips.push(Strip::line(line, half));
    }
    strips
}

/// The union of the strips and their areas summed, whatever order they come in: drawn side
/// by side (a headland pass's buffer takes a millisecond) and joined in a canonical order, so
/// that the same strips always give the same polygons.
fn cover(mut strips: Vec<Strip>) -> (MultiPolygon, f64) {
    use rayon::prelude::*;
    strips.sort_by(|a, b| compare_points(a.points(), b.points()).then(a.half().total_cmp(&b.half())));
    let shapes: Vec<Polygon> = strips.par_iter().flat_map_iter(Strip::draw).collect();
    (union_of(&shapes), shapes.iter().map(|s| s.unsigned_area()).sum())
}

/// What [`swept_and_strip_area`] gives for a ground vehicle's path whose sweeps are `swaths`
/// and whose headland passes are `passes` (rings), in any order, direction and first point: for a
/// planner to measure beside its search for the order.
pub fn ground_swept(swaths: &[(Coord, Coord)], passes: &[Vec<Coord>], half: f64) -> (MultiPolygon, f64) {
    let lines = swaths.iter().map(|&(a, b)| Strip::line(vec![a, b], half));
    cover(passes.iter().map(|ring| Strip::pass(ring, half)).chain(lines).collect())
}

/// The union of `shapes` (empty without shapes).
pub(super) fn union_of(shapes: &[Polygon]) -> MultiPolygon {
    if shapes.is_empty() { MultiPolygon(vec![]) } else { geo::unary_union(shapes) }
}

/// The area of `region` inside `union`, and the area of `union`.
pub(super) fn under(union: &MultiPolygon, region: &MultiPolygon) -> (f64, f64) {
    if union.0.is_empty() {
        return (0.0, 0.0);
    }
    (region.intersection(union).unsigned_area(), union.unsigned_area())
}

/// The area of `region` inside the union of `shapes`, and the area of that union.
pub(super) fn covered_by(shapes: &[Polygon], region: &MultiPolygon) -> (f64, f64) {
    under(&union_of(shapes), region)
}

/// The area of `region` under the swaths of `path`, in m²; with a camera's `photos`, under what
/// its photos image (see [`photographed`]).
pub fn covered_area(path: &FlightPath, region: &MultiPolygon, photos: Option<Footprint>) -> f64 {
    under(&covered(path, photos), region).0
}

/// The ground `path` covers: its swaths, or with a camera's `photos` what its photos image.
pub fn covered(path: &FlightPath, photos: Option<Footprint>) -> MultiPolygon {
    match photos {
        Some(footprint) => photographed(path, &footprint),
        None => swept(path),
    }
}

/// Pieces of uncovered ground smaller than this are rounding between swaths, not gaps.
const UNCOVERED_SLIVER_M2: f64 = 1.0;

/// The ground under the swaths of `path`: computed once per plan, since the union of many
/// strips is the costliest step of measuring it.
pub fn swept(path: &FlightPath) -> MultiPolygon {
    swept_and_strip_area(path).0
}

/// [`swept`], and the swaths' areas summed (ground swept twice counted twice), for
/// [`Stats::overlap_ratio`]: both from the same strips.
pub fn swept_and_strip_area(path: &FlightPath) -> (MultiPolygon, f64) {
    cover(sweep_strips(path))
}

/// The ground the photos on the sweeps of `path` image ([`photo_positions`]; those of sweeps of
/// no length left out).
pub fn photographed(path: &FlightPath, footprint: &Footprint) -> MultiPolygon {
    union_of(&photo_strips(&photo_positions(path, footprint, None), footprint.across_m, footprint.along_m))
}

/// The part of `target` outside `swept` (see [`swept`]): the clearance band around no-fly
/// zones, corners the lines do not reach. Slivers under a square metre are left out.
pub fn uncovered(swept: &MultiPolygon, target: &MultiPolygon) -> MultiPolygon {
    let rest = if swept.0.is_empty() { target.clone() } else { target.difference(swept) };
    MultiPolygon(rest.0.into_iter().filter(|p| p.unsigned_area() >= UNCOVERED_SLIVER_M2).collect())
}

/// Metres of `path` inside `zones`.
pub fn length_inside(path: &FlightPath, zones: &MultiPolygon) -> f64 {
    if zones.0.is_empty() {
        return 0.0;
    }
    let lines = MultiLineString(path.pieces.iter().map(|p| LineString::from(p.points.clone())).collect());
    // + 0.0 turns an empty sum's -0.0 into 0.0
    zones.clip(&lines, false).0.iter().map(|l| Euclidean.length(l)).sum::<f64>() + 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Contains, polygon};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// A ground path's swept ground is the same whatever the order of its swaths and passes,
        /// the way each is driven and where each ring is entered: the ground that
        /// [`ground_swept`] measures without the order.
        #[test]
        fn ground_swept_ground_does_not_depend_on_order_direction_or_entry(
            swaths in prop::collection::vec((0.0..200.0f64, 0.0..200.0f64, 5.0..80.0f64), 1..12),
            rings in prop::collection::vec((20.0..180.0f64, 20.0..180.0f64, 5.0..30.0f64, 3usize..9), 1..4),
            entries in prop::collection::vec((any::<bool>(), 0usize..100), 4),
            reversed in prop::collection::vec(any::<bool>(), 12),
            shuffle in any::<u64>(),
        ) {
            let half = 3.0;
            let lines: Vec<(Coord, Coord)> = swaths.iter().map(|&(x, y, l)| (Coord { x, y }, Coord { x: x + l, y: y + 0.3 * l })).collect();
            let polygons: Vec<Vec<Coord>> = rings
                .iter()
                .map(|&(cx, cy, r, n)| {
                    let mut ring: Vec<Coord> = (0..n).map(|k| k as f64 * std::f64::consts::TAU / n as f64).map(|a| Coord { x: cx + r * a.cos(), y: cy + r * a.sin() }).collect();
                    ring.push(ring[0]);
                    ring
                })
                .collect();
            // the path: rings entered anywhere, either way round; swaths either way; all shuffled
            let mut pieces: Vec<(PieceKind, Vec<Coord>)> = Vec::new();
            for (k, ring) in polygons.iter().enumerate() {
                let (forward, at) = entries[k % entries.len()];
                let n = ring.len() - 1;
                let start = at % n;
                let points: Vec<Coord> = (0..=n).map(|j| if forward { ring[(start + j) % n] } else { ring[(start + n - j % n) % n] }).collect();
                pieces.push((PieceKind::Headland, points));
            }
            for (k, &(a, b)) in lines.iter().enumerate() {
                pieces.push((PieceKind::Sweep, if reversed[k] { vec![b, a] } else { vec![a, b] }));
            }
            let mut rng = crate::route::gtsp::Rng(shuffle | 1);
            for i in (1..pieces.len()).rev() {
                pieces.swap(i, rng.below(i + 1));
            }
            let mut path = FlightPath::default();
            let mut last: Option<Coord> = None;
            for (kind, points) in pieces {
                // a turn between pieces, as a plan has: sweeps are never joined
                if let Some(from) = last {
                    path.push(PieceKind::Turn, vec![from, Coord { x: from.x + 1.0, y: from.y - 1.0 }, points[0]], 0.0);
                }
                last = points.last().copied();
                path.push(kind, points, half);
            }
            let (swept, strips) = swept_and_strip_area(&path);
            let (measured, measured_strips) = ground_swept(&lines, &polygons, half);
            prop_assert!(swept == measured && strips == measured_strips, "{} m² against {} m²", swept.unsigned_area(), measured.unsigned_area());
        }
    }

    /// A ring flown as thousands of sub-millimetre sweeps under a swath wider than its radius
    /// (what an inset of a spiral looks like) is measured on its straightened centreline, and as
    /// flown: the swath turns with the vehicle, so the whole disc out to radius + half is swept.
    #[test]
    fn a_ring_of_tiny_sweeps_is_measured_on_its_straightened_centreline() {
        let (radius, half, steps) = (40.0, 58.0, 200_000);
        let at = |k: usize| {
            let a = k as f64 / steps as f64 * std::f64::consts::TAU;
            Coord { x: radius * a.cos(), y: radius * a.sin() }
        };
        let mut path = FlightPath::default();
        for k in 0..steps {
            path.push(PieceKind::Sweep, vec![at(k), at(k + 1)], half);
        }
        let expected = std::f64::consts::PI * (radius + half).powi(2);
        let swept = swept(&path).unsigned_area();
        assert!((swept - expected).abs() < 0.005 * expected, "{swept} m² swept, {expected} m² expected");
    }

    /// Two sweeps joined at a right angle: two rectangles, less the square where they overlap
    /// inside the bend, plus the quarter disc the swath sweeps outside it as the vehicle turns.
    #[test]
    fn a_bend_sweeps_a_fan_on_its_outside() {
        let half = 10.0;
        let mut path = FlightPath::default();
        path.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        path.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: 100.0 }], half);
        let expected = 2.0 * 100.0 * 2.0 * half - half * half + std::f64::consts::PI * half * half / 4.0;
        let swept = swept(&path);
        assert!((swept.unsigned_area() - expected).abs() < 0.5, "{} m² swept, {expected} m² expected", swept.unsigned_area());
        // the fan lies outside the bend (below and right of the corner), not inside it
        assert!(swept.contains(&Coord { x: 105.0, y: -5.0 }) && !swept.contains(&Coord { x: 109.0, y: -9.0 }));
        // a right turn's fan too, on its own outside (above and right of the corner)
        let mut right = FlightPath::default();
        right.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        right.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: -100.0 }], half);
        let right = super::swept(&right);
        assert!((right.unsigned_area() - expected).abs() < 0.5, "{} m² swept after a right turn", right.unsigned_area());
        assert!(right.contains(&Coord { x: 105.0, y: 5.0 }));
        // sweeps apart (a turn between them) are rectangles only
        let mut apart = FlightPath::default();
        apart.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 100.0, y: 0.0 }], half);
        apart.push(PieceKind::Turn, vec![Coord { x: 100.0, y: 0.0 }, Coord { x: 100.0, y: 0.5 }], 0.0);
        apart.push(PieceKind::Sweep, vec![Coord { x: 100.0, y: 0.5 }, Coord { x: 100.0, y: 100.0 }], half);
        assert!(!super::swept(&apart).contains(&Coord { x: 105.0, y: -5.0 }));
    }

    #[test]
    fn coverage_and_intrusion_are_measured_on_the_geometry() {
        let c = |x, y| Coord { x, y };
        let region = MultiPolygon(vec![polygon![(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 20.), (x: 0., y: 20.)]]);
        let mut path = FlightPath::default();
        path.push(PieceKind::Sweep, vec![c(0.0, 5.0), c(100.0, 5.0)], 5.0);
        assert!((covered_area(&path, &region, None) - 1000.0).abs() < 1e-6);
        path.push(PieceKind::Turn, vec![c(100.0, 5.0), c(100.0, 15.0)], 0.0);
        path.push(PieceKind::Sweep, vec![c(100.0, 15.0), c(50.0, 15.0)], 5.0);
        assert!((covered_area(&path, &region, None) - 1500.0).abs() < 1e-6);
        let zone = MultiPolygon(vec![polygon![(x: 40., y: 0.), (x: 60., y: 0.), (x: 60., y: 10.), (x: 40., y: 10.)]]);
        assert!((length_inside(&path, &zone) - 20.0).abs() < 1e-9);
    }
}
