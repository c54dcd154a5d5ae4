//! Lines parallel to a polyline (a corridor's centre line): each point of the centre line
//! moved sideways by the same distance, round or mitred on the outside of every bend (so that
//! a swath along it covers the bend's outside), and on the inside cut near the crossing where
//! the moved segments would fold back on themselves, each running on past it by as much as
//! its swath needs to reach the corner's neighbour line (a small notch).

use geo::Coord;

use crate::geom::{distance, segment_crossing, unit};

/// Angle between the points of an outside bend's arc (radians): 5°.
const ARC_STEP_RAD: f64 = 0.087;

/// Points nearer than this are one: a segment shorter has no direction worth following.
const POINT_TOLERANCE_M: f64 = 0.01;

/// Inner angles of 160° and more (bends under 20°) get no notch: cos 160°.
const NOTCHED_BEND_COS: f64 = -0.94;

/// Mitres longer than this many offsets are cut square (bends sharper than about 150°).
const MITRE_LIMIT: f64 = 4.0;

/// How the outside of a bend is joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outside {
    /// An arc round the bend's vertex: the line stays its offset from the centre line.
    Round,
    /// The two moved segments prolonged to their crossing: one corner, for a vehicle that
    /// leaves the line there and turns on its own.
    Mitre,
}

/// The polyline `d` metres to the left of `line` (to the right for negative `d`), for a swath
/// `half` metres to each side of it.
pub fn offset(line: &[Coord], d: f64, half: f64, outside: Outside) -> Vec<Coord> {
    if line.len() < 2 || d == 0.0 {
        return line.to_vec();
    }
    let normals: Vec<Coord> = line.windows(2).map(|w| left_normal(w[0], w[1])).collect();
    // each raw point with the centre line's distance along at which it was made, and how far
    // the centre line has turned there (radians, left positive)
    let mut raw: Vec<(Coord, f64, f64)> = vec![(line[0] + normals[0] * d, 0.0, 0.0)];
    let (mut station, mut turned) = (0.0, 0.0);
    for k in 1..line.len() - 1 {
        station += distance(line[k - 1], line[k]);
        let (n0, n1, p) = (normals[k - 1], normals[k], line[k]);
        let bend = (n0.x * n1.y - n0.y * n1.x).atan2(n0.x * n1.x + n0.y * n1.y);
        let before = turned;
        turned += bend;
        // the outside of a bend: left turns have it on the right (d < 0)
        let outer = bend * d < 0.0;
        // a slight bend's arc would be one chord: its mitre is as good
        if outer && (outside == Outside::Mitre || bend.abs() < ARC_STEP_RAD) {
            let cos = n0.x * n1.x + n0.y * n1.y;
            if 1.0 + cos > 2.0 / (MITRE_LIMIT * MITRE_LIMIT) {
                raw.push((p + (n0 + n1) * (d / (1.0 + cos)), station, turned));
            } else {
                // square: each segment prolonged by the limit
                let (u0, u1) = (Coord { x: n0.y, y: -n0.x }, Coord { x: n1.y, y: -n1.x });
                raw.push((p + n0 * d + u0 * (MITRE_LIMIT * d.abs()), station, before));
                raw.push((p + n1 * d - u1 * (MITRE_LIMIT * d.abs()), station, turned));
            }
            continue;
        }
        raw.push((p + n0 * d, station, before));
        if outer {
            let a0 = n0.y.atan2(n0.x);
            let steps = (bend.abs() / ARC_STEP_RAD).ceil() as usize;
            for s in 1..steps {
                let a = bend * s as f64 / steps as f64;
                raw.push((p + Coord { x: (a0 + a).cos(), y: (a0 + a).sin() } * d, station, before + a));
            }
        }
        raw.push((p + n1 * d, station, turned));
    }
    station += distance(line[line.len() - 2], line[line.len() - 1]);
    raw.push((*line.last().expect("two points") + *normals.last().expect("a segment") * d, station, turned));
    without_folds(raw, d, half)
}

fn left_normal(a: Coord, b: Coord) -> Coord {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len = dx.hypot(dy);
    Coord { x: -dy / len, y: dx / len }
}

/// The raw offset with its folds cut out: where later segments, made within a few offsets
/// along the centre line after it turned towards the offset's side, cross the current one,
/// the points up to the first crossing's segment go and the line runs on along it.
fn without_folds(raw: Vec<(Coord, f64, f64)>, d: f64, half: f64) -> Vec<Coord> {
    // a fold spans d / tan(α/2) along the centre line each side of a bend of inner angle α:
    // 8 d finds those of bends up to 150° (α ≥ 28°); beyond, a fold is flown, not wrong
    let reach = 8.0 * d.abs();
    let mut out: Vec<Coord> = vec![raw[0].0];
    // the current segment runs from the last point out to raw[i + 1]
    let mut i = 0;
    while i + 1 < raw.len() {
        let (a, b) = (*out.last().expect("a point"), raw[i + 1].0);
        let limit = raw[i + 1].1 + reach;
        // the first later segment that crosses: the bend's own fold, not one the corridor
        // makes where it curls back near itself
        let mut cut: Option<(usize, Coord)> = None;
        let mut j = i + 2;
        while j + 1 < raw.len() && raw[j].1 <= limit {
            // a fold lies where the centre line has turned towards the offset's side; where it
            // turned away, the line comes back near itself only where the corridor does, and
            // both stretches are flown
            let folds = (raw[j].2 - raw[i].2) * d > 0.0;
            if folds && let Some(x) = crossing(a, b, raw[j].0, raw[j + 1].0) {
                cut = Some((j, x));
                break;
            }
            j += 1;
        }
        match cut {
            Some((j, x)) => {
                // on past the crossing until the swath meets the neighbour line's (half over
                // the tangent of half the corner's inner angle), then back onto the next segment
                let (ui, uj) = (unit(a, b), unit(raw[j].0, raw[j + 1].0));
                let cos_inner = -(ui.x * uj.x + ui.y * uj.y);
                let tan_half = ((1.0 - cos_inner) / (1.0 + cos_inner)).max(0.0).sqrt();
                // (no further than the bend's vertex is abreast: a line nearer the centre than
                // its swath is wide has its raw fold flown there)
                let past = if tan_half > 1e-9 { half.min(d.abs()) / tan_half } else { f64::INFINITY }.min(reach);
                // a slight bend leaves a gap of h (1/sin(α/2) − 1) on the bisector: none worth a
                // notch below 20°
                if past > POINT_TOLERANCE_M && cos_inner > NOTCHED_BEND_COS {
                    out.push(x + ui * past);
                    out.push(x - uj * past);
                } else {
                    out.push(x);
                }
                i = j;
            }
            None => {
                out.push(b);
                i += 1;
            }
        }
    }
    out.dedup_by(|p, q| distance(*p, *q) < POINT_TOLERANCE_M);
    out
}

/// Where segments `a → b` and `c → e` cross, ends excluded.
fn crossing(a: Coord, b: Coord, c: Coord, e: Coord) -> Option<Coord> {
    let (t, u) = segment_crossing(a, b, c, e)?;
    let inside = |v: f64| v > 1e-9 && v < 1.0 - 1e-9;
    (inside(t) && inside(u)).then(|| a + (b - a) * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Distance, Euclidean, LineString, Point};
    use proptest::prelude::*;

    fn c(x: f64, y: f64) -> Coord {
        Coord { x, y }
    }

    fn distance_to(line: &[Coord], p: Coord) -> f64 {
        Euclidean.distance(&Point(p), &LineString::new(line.to_vec()))
    }

    #[test]
    fn a_straight_line_moves_sideways() {
        assert_eq!(offset(&[c(0.0, 0.0), c(100.0, 0.0)], -10.0, 5.0, Outside::Round), vec![c(0.0, -10.0), c(100.0, -10.0)]);
        assert_eq!(offset(&[c(0.0, 0.0), c(50.0, 0.0), c(100.0, 0.0)], 10.0, 5.0, Outside::Mitre), vec![c(0.0, 10.0), c(50.0, 10.0), c(100.0, 10.0)]);
    }

    #[test]
    fn a_bend_is_round_or_mitred_outside_and_notched_at_the_crossing_inside() {
        // a left turn of 90° at (100, 0)
        let line = [c(0.0, 0.0), c(100.0, 0.0), c(100.0, 100.0)];
        // the crossing at (90, 10), each side run on by half the swath over tan 45°
        let inside = offset(&line, 10.0, 5.0, Outside::Round);
        assert_eq!(inside.len(), 4, "{inside:?}");
        assert!(distance(inside[1], c(95.0, 10.0)) < 1e-9 && distance(inside[2], c(90.0, 5.0)) < 1e-9, "{inside:?}");
        assert_eq!(offset(&line, -10.0, 5.0, Outside::Mitre), vec![c(0.0, -10.0), c(110.0, -10.0), c(110.0, 100.0)]);
        let outside = offset(&line, -10.0, 5.0, Outside::Round);
        assert_eq!(outside.first(), Some(&c(0.0, -10.0)));
        assert_eq!(outside.last(), Some(&c(110.0, 100.0)));
        // the arc round the corner: 90° in 5° steps
        assert!(outside.len() >= 19, "{} points", outside.len());
        assert!(outside[1..outside.len() - 1].iter().all(|&p| (distance(p, c(100.0, 0.0)) - 10.0).abs() < 1e-9));
    }

    #[test]
    fn a_sharp_bend_rounded_tighter_than_the_offset_leaves_no_loop_inside() {
        // a 140° turn left round a tip of radius 5 m, offset 20 m towards its inside, with a
        // swath 5 m each side: the notch's tips come no nearer than 2 swaths
        let turn = 140f64.to_radians();
        let tip = (0..=14).map(|k| {
            let a = -std::f64::consts::FRAC_PI_2 + turn * k as f64 / 14.0;
            c(200.0 + 5.0 * a.cos(), 5.0 + 5.0 * a.sin())
        });
        let last = tip.clone().next_back().expect("a tip");
        let back = last + c(turn.cos(), turn.sin()) * 200.0;
        let line: Vec<Coord> = std::iter::once(c(0.0, 0.0)).chain(tip).chain([back]).collect();
        let inside = offset(&line, 20.0, 5.0, Outside::Round);
        for &p in &inside {
            assert!(distance_to(&line, p) > 10.0 - 1e-6, "{p:?} is {} m from the centre line", distance_to(&line, p));
        }
    }

    /// Centre lines that wind but never come back on themselves: headings within 60° of east.
    fn winding() -> impl Strategy<Value = Vec<Coord>> {
        prop::collection::vec((5.0..150.0f64, -1.0..1.0f64), 2..40).prop_map(|steps| {
            let mut at = c(0.0, 0.0);
            let mut points = vec![at];
            for (len, heading) in steps {
                at = at + c(heading.cos(), heading.sin()) * len;
                points.push(at);
            }
            points
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        #[test]
        fn every_point_of_an_offset_lies_its_distance_from_the_centre_line(line in winding(), d in -40.0..40.0f64, half in 1.0..30.0f64) {
            prop_assume!(d.abs() > 0.5);
            let moved = offset(&line, d, half, Outside::Round);
            prop_assert!(moved.len() >= 2);
            // a crossing may fall on an arc's chord, inside the arc by its sagitta
            let eps = d.abs() * (1.0 - (ARC_STEP_RAD / 2.0).cos()) + 1e-6 * d.abs().max(1.0);
            let ends = [line[0], line[line.len() - 1]];
            for &p in &moved {
                // never much further than the offset (arcs outside; a notch's tip may run past a
                // short segment's end) ...
                let gap = distance_to(&line, p);
                prop_assert!(gap < d.abs() + 2.0 * half + eps, "{p:?}: {gap} m from the centre, offset {d}");
                // ... and no nearer than a swath's width (folds cut to notches, whose tips come
                // up to h (1 + cos α) nearer), but where the centre line's ends cut the corner
                // or its segments are shorter than the offset (a fold may be flown there)
                let by_an_end = ends.iter().any(|&e| distance(e, p) < 2.0 * d.abs());
                let short = line.windows(2).any(|w| distance(w[0], w[1]) < d.abs());
                prop_assert!(by_an_end || short || gap > d.abs() - 2.0 * half - eps, "{p:?}: {gap} m from the centre, offset {d}");
            }
        }
    }
}
