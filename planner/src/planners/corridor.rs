//! Planner `corridor`: a road, river, pipeline or power line flown along its centre line. As
//! many lines as the width needs run parallel to the centre line (round outside its bends, so
//! that their swaths cover the bends' outsides; a fixed wing's mitred, and cut where they bend
//! more than it can follow), flown back and forth with a turn at each end. A corridor longer
//! than one battery flies is cut into sections, each flown whole before the next (an odd
//! number of lines, so that each ends where the next begins), and the battery stage cuts the
//! flight into sorties at their ends.

use geo::{BoundingRect, Contains, Coord, Intersects, MultiPolygon, Polygon, Rect};

use super::{PlannedPath, Planner, Problem, Progress};
use crate::error::{InputError, PlanError};
use crate::field::Corridor;
use crate::geom::{distance, heading, polyline_length, segment_crossing, unit};
use crate::path::{FlightPath, PieceKind};
use crate::sweep::offset::{Outside, offset};
use crate::turn::dubins::Pose;
use crate::turn::{TurnModel, half_circles};

pub struct CorridorPlanner;

/// Share of a battery one section's sweeps may use: the rest is for its turns and the legs
/// from and to home.
const SECTION_BATTERY_SHARE: f64 = 0.8;

/// Shortest piece of a line kept between no-fly zones, metres.
const SHORTEST_PIECE_M: f64 = 0.5;

impl Planner for CorridorPlanner {
    fn id(&self) -> &'static str {
        "corridor"
    }

    fn name(&self) -> &'static str {
        "Corridor scan"
    }

    fn description(&self) -> &'static str {
        "Roads, rivers, pipelines and power lines: lines parallel to each corridor's centre line (a LineString of \
         the area with width_m), as many as its width needs, round outside the bends, flown back and forth with a \
         turn at each end; a corridor longer than a battery flies is flown in sections, each ending where the next \
         begins. Covers the corridors only."
    }

    fn direction_rule(&self) -> &'static str {
        "along each corridor's centre line"
    }

    /// Its lines follow the centre line: no line ends to place.
    fn lays_parallel_lines(&self) -> bool {
        false
    }

    fn plans_fleet_parts(&self) -> bool {
        false
    }

    fn follows_corridors(&self) -> bool {
        true
    }

    fn coverage_target(&self) -> Option<f64> {
        Some(0.995)
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        if problem.corridors.is_empty() {
            return Err(InputError::new("no_corridor", "/area", "planner corridor flies corridors: give the area a LineString feature with its width as width_m").into());
        }
        let half = problem.layout.half_swath();
        let mut path = FlightPath::default();
        let mut left: Vec<&Corridor> = problem.corridors.iter().collect();
        let mut first_heading = None;
        let mut unreached = None;
        while !left.is_empty() {
            // the corridor with an end nearest where the vehicle is, flown from that end
            let here = path.end().or(problem.start).unwrap_or(left[0].centre[0]);
            let gap = |c: &Corridor| distance(here, c.centre[0]).min(distance(here, c.centre[c.centre.len() - 1]));
            let k = (0..left.len()).min_by(|&a, &b| gap(left[a]).total_cmp(&gap(left[b]))).expect("a corridor left");
            let corridor = left.swap_remove(k);
            let mut centre = corridor.centre.clone();
            if distance(here, centre[0]) > distance(here, centre[centre.len() - 1]) {
                centre.reverse();
            }
            first_heading.get_or_insert_with(|| heading(centre[0], centre[1]));
            for (pass, joined_by) in passes(&centre, corridor.width_m, problem) {
                // a pass no clear way reaches (a fixed wing's, boxed in by zones) is left out:
                // the coverage measure shows what that loses
                match join(&mut path, problem, &pass, joined_by) {
                    Ok(()) => path.push(PieceKind::Sweep, pass, half),
                    Err(PlanError::Infeasible(why)) => unreached = Some(why),
                    Err(e) => return Err(e),
                }
            }
            if !progress.report(1.0 - left.len() as f64 / problem.corridors.len() as f64) {
                return Err(PlanError::Cancelled);
            }
        }
        if path.pieces.is_empty() {
            return Err(unreached.map_or_else(super::no_sweep_lines, PlanError::Infeasible));
        }
        if let (Some(end), Some(last)) = (problem.end, path.pieces.last()) {
            let [.., a, b] = last.points[..] else { unreachable!("a sweep has two points") };
            let to = Pose::at(end, problem.end_heading.unwrap_or_else(|| heading(b, end)));
            let points = problem.connector.path(Pose::at(b, heading(a, b)), to).ok_or_else(|| no_way("the last line", "the end"))?;
            path.push(PieceKind::Transit, points, 0.0);
        }
        Ok(PlannedPath::new(path, first_heading.unwrap_or(0.0), problem.corridors.len()))
    }
}

/// How a pass is joined to what was flown before it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Join {
    /// From the line beside it at a section's end, or (a fixed wing) from the leg before a
    /// bend it turns at on its own.
    Turn,
    /// Across a no-fly zone, or from another corridor.
    Transit,
}

fn no_way(from: &str, to: &str) -> PlanError {
    PlanError::Infeasible(format!("no clear way outside the no-fly zones joins {from} to {to} of a corridor"))
}

/// Flies to the start of `pass` from where the path ends (or the problem's start).
fn join(path: &mut FlightPath, problem: &Problem<'_>, pass: &[Coord], joined_by: Join) -> Result<(), PlanError> {
    let to = Pose::at(pass[0], heading(pass[0], pass[1]));
    let from = match path.pieces.last() {
        Some(last) => {
            let [.., a, b] = last.points[..] else { unreachable!("a piece has two points") };
            Pose::at(b, heading(a, b))
        }
        None => match problem.start {
            Some(start) => Pose::at(start, problem.start_heading.unwrap_or_else(|| heading(start, pass[0]))),
            None => return Ok(()),
        },
    };
    let points = problem.connector.path(from, to).or_else(|| turned_about(problem, from, to)).ok_or_else(|| no_way("a line", "the next"))?;
    let kind = if joined_by == Join::Turn && !path.pieces.is_empty() { PieceKind::Turn } else { PieceKind::Transit };
    // (a pass that begins where the last ended needs no connection)
    if points.len() >= 2 {
        path.push(kind, points, 0.0);
    }
    Ok(())
}

/// A fixed wing's way from `from` to `to` that turns about on a clear half circle first, or
/// arrives on one, or both: where a line ends facing a zone, or begins just past one, its end
/// is pulled back only as far as one half circle clears the zone, and every way the search
/// tries turns into the zone there. The shortest of these.
fn turned_about(problem: &Problem<'_>, from: Pose, to: Pose) -> Option<Vec<Coord>> {
    let TurnModel::Dubins(r) = problem.vehicle.turn_model() else { return None };
    let r = problem.connector.wind().map_or(r, |d| d.safe_radius(r));
    let clear_arcs = |pose: Pose, out: f64| -> Vec<Vec<Coord>> {
        let mut arcs: Vec<Vec<Coord>> =
            half_circles(pose.coord(), Coord { x: out.cos(), y: out.sin() }, r).into_iter().filter(|arc| problem.transit.is_polyline_clear(arc)).collect();
        // the circle's first point is the pose's but for rounding: pieces join exactly
        for arc in &mut arcs {
            arc[0] = pose.coord();
        }
        arcs
    };
    let turn_about: Vec<Option<Vec<Coord>>> = std::iter::once(None).chain(clear_arcs(from, from.theta).into_iter().map(Some)).collect();
    // an arrival half circle, flown backwards from `to`, then reversed
    let arrive_on: Vec<Option<Vec<Coord>>> = std::iter::once(None)
        .chain(clear_arcs(to, to.theta + std::f64::consts::PI).into_iter().map(|mut arc| {
            arc.reverse();
            Some(arc)
        }))
        .collect();
    let mut best: Option<Vec<Coord>> = None;
    for first in &turn_about {
        for last in &arrive_on {
            if first.is_none() && last.is_none() {
                continue;
            }
            let a = first.as_ref().map_or(from, |arc| Pose::at(arc[arc.len() - 1], from.theta + std::f64::consts::PI));
            let b = last.as_ref().map_or(to, |arc| Pose::at(arc[0], to.theta + std::f64::consts::PI));
            let Some(middle) = problem.connector.path(a, b) else { continue };
            let way: Vec<Coord> =
                first.iter().flatten().copied().chain(middle.into_iter().skip(usize::from(first.is_some()))).chain(last.iter().flatten().skip(1).copied()).collect();
            if best.as_ref().is_none_or(|b| polyline_length(&way) < polyline_length(b)) {
                best = Some(way);
            }
        }
    }
    best
}

/// The corridor's sweeps in flight order, each with how it is joined to the one before.
fn passes(centre: &[Coord], width: f64, problem: &Problem<'_>) -> Vec<(Vec<Coord>, Join)> {
    let layout = &problem.layout;
    let length = polyline_length(centre);
    let mut offsets: Vec<f64> = layout.lines(-width / 2.0, width / 2.0).into_iter().map(|(o, _, _)| o).collect();
    let sections = section_count(length, offsets.len(), problem);
    if sections > 1 && offsets.len().is_multiple_of(2) {
        // an odd count ends each section where the next begins
        offsets = odd_count(width, offsets.len() + 1, layout.photographed().map(|f| f.across_m));
    }
    let (reach, half) = (width / 2.0, layout.half_swath());
    // a fixed wing turns on its own where the line bends more than it can follow
    let sharpest = match problem.vehicle.turn_model() {
        TurnModel::Dubins(r) => Some(sharpest_bend(r, half)),
        TurnModel::Straight => None,
    };
    let bends = if sharpest.is_some() { Outside::Mitre } else { Outside::Round };
    let mut out = Vec::new();
    for j in 0..sections {
        let part = slice(centre, length * j as f64 / sections as f64, length * (j + 1) as f64 / sections as f64);
        let order: Vec<f64> = if j % 2 == 0 { offsets.clone() } else { offsets.iter().rev().copied().collect() };
        for (i, &d) in order.iter().enumerate() {
            let mut line = offset(&part, d, half, bends);
            // past the corridor's ends, as far as its round end reaches beside the line
            let beyond = (reach * reach - (d.abs() - half).max(0.0).powi(2)).max(0.0).sqrt();
            if j == 0 && beyond > 0.0 {
                line.insert(0, line[0] + unit(part[1], part[0]) * beyond);
            }
            if j == sections - 1 && beyond > 0.0 {
                let n = part.len();
                line.push(line[line.len() - 1] + unit(part[n - 2], part[n - 1]) * beyond);
            }
            if i % 2 == 1 {
                line.reverse();
            }
            // a fixed wing's legs (cut at the bends it cannot follow), then what lies outside
            // the zones
            let legs = match sharpest {
                Some(angle) => at_sharp_bends(line, angle, (if i % 2 == 1 { -d } else { d }, beyond.max(half)), half),
                None => vec![line],
            };
            for (m, leg) in legs.into_iter().enumerate() {
                let (first, last) = (leg[0], leg[leg.len() - 1]);
                let mut pieces = outside(leg, problem.keep_out);
                if sharpest.is_none() {
                    into_the_margin(&mut pieces, (first, last), half, problem);
                } else {
                    // a fixed wing's lines end where it can turn clear of the zones
                    pieces = pieces.into_iter().filter_map(|p| turnable(p, problem)).collect();
                }
                for (k, piece) in pieces.into_iter().enumerate() {
                    out.push((piece, if k == 0 && (i > 0 || m > 0) { Join::Turn } else { Join::Transit }));
                }
            }
        }
    }
    out
}

/// The sharpest bend (radians) a fixed wing of turning radius `r` flies along a line without
/// leaving its swath's middle half: cutting a bend of θ misses its corner by r (1/cos(θ/2) − 1).
fn sharpest_bend(r: f64, half: f64) -> f64 {
    2.0 * (1.0 / (1.0 + half / (2.0 * r))).acos()
}

/// `line` (offset `d` to the left of the centre line, in the direction flown) cut at each
/// vertex where it bends by more than `angle`. Each leg runs on past the centre line's vertex
/// by `run_on` (as far as the corridor's round outside reaches beside the line; a mitre's
/// corner is already `d tan(bend / 2)` past it) and the next begins as far before it.
fn at_sharp_bends(line: Vec<Coord>, angle: f64, (d, run_on): (f64, f64), half: f64) -> Vec<Vec<Coord>> {
    let mut legs = Vec::new();
    let mut leg = vec![line[0]];
    for w in line.windows(3) {
        let (a, b) = (heading(w[0], w[1]), heading(w[1], w[2]));
        let turn = (b - a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        if turn.abs() > angle {
            // a left turn has its outside on the right (d < 0)
            let run_on = if turn * d < 0.0 { (run_on - d.abs() * (turn.abs() / 2.0).tan()).max(0.0) } else { run_on };
            leg.push(w[1] + unit(w[0], w[1]) * run_on);
            legs.push(std::mem::replace(&mut leg, vec![w[1] - unit(w[1], w[2]) * run_on]));
        }
        leg.push(w[1]);
    }
    leg.push(line[line.len() - 1]);
    legs.push(leg);
    // a leg cut at both ends that is one short straight is a notch's chord: a way across the
    // inside of a bend, not a swath the corridor needs
    let count = legs.len();
    let mut k = 0;
    legs.retain(|l| {
        k += 1;
        // (its second point and its last, run on: a notch's chord is 2 half sin(bend / 2) long)
        let chord = k > 1 && k < count && l.len() == 3 && distance(l[1], l[2]) <= run_on + 2.0 * half + 1e-6;
        !chord && polyline_length(l) >= SHORTEST_PIECE_M
    });
    legs
}

/// `piece` with each end pulled back until a fixed wing can turn there clear of the zones
/// ([`crate::route::connect::Connector::turnable`]); `None` when nothing is left.
fn turnable(piece: Vec<Coord>, problem: &Problem<'_>) -> Option<Vec<Coord>> {
    let mut piece = turnable_end(piece, problem)?;
    piece.reverse();
    let mut piece = turnable_end(piece, problem)?;
    piece.reverse();
    Some(piece)
}

/// `piece` with its last end pulled back, segment by segment, until the aircraft can turn there.
fn turnable_end(mut piece: Vec<Coord>, problem: &Problem<'_>) -> Option<Vec<Coord>> {
    while piece.len() >= 2 {
        let n = piece.len();
        // only the end is asked about: the segment's start is taken from far behind it
        let (a, b) = (piece[n - 2], piece[n - 1]);
        let behind = b + (a - b) * (1.0 + 1e6 / distance(a, b).max(1e-9));
        if let Some((_, end)) = problem.connector.turnable(behind, b) {
            let along = (end.x - b.x) * (a.x - b.x) + (end.y - b.y) * (a.y - b.y);
            if along <= distance(a, b).powi(2) {
                piece[n - 1] = end;
                return (polyline_length(&piece) >= SHORTEST_PIECE_M).then_some(piece);
            }
        }
        piece.pop();
    }
    None
}

/// Each end where a zone cut a line run on into the zone's margin, up to half a swath (halved
/// until it stays clear of the zone): the swath's corners reach the margin's edge where the
/// edge is slanted to the line, and the run stays within half a swath of the corridor.
fn into_the_margin(pieces: &mut [Vec<Coord>], line_ends: (Coord, Coord), half: f64, problem: &Problem<'_>) {
    let run_on = |end: Coord, towards: Coord| {
        let out = unit(towards, end);
        (0..8).map(|k| end + out * (half / f64::from(1 << k))).find(|&p| problem.transit.is_clear(end, p))
    };
    for piece in pieces.iter_mut() {
        if distance(piece[0], line_ends.0) > 1e-6
            && let Some(p) = run_on(piece[0], piece[1])
        {
            piece.insert(0, p);
        }
        let n = piece.len();
        if distance(piece[n - 1], line_ends.1) > 1e-6
            && let Some(p) = run_on(piece[n - 1], piece[n - 2])
        {
            piece.push(p);
        }
    }
}

/// `n` offsets across `width`, evenly: the outer swaths flush with the edges.
fn odd_count(width: f64, n: usize, footprint: Option<f64>) -> Vec<f64> {
    let across = footprint.unwrap_or(width / n as f64).min(width);
    let step = (width - across) / (n - 1) as f64;
    (0..n).map(|k| -width / 2.0 + across / 2.0 + k as f64 * step).collect()
}

/// How many sections a corridor of `length` flown with `lines` lines is cut into: as many as
/// keep one section's sweeps within a battery's share.
fn section_count(length: f64, lines: usize, problem: &Problem<'_>) -> usize {
    let per_m = sweep_energy_per_m(problem);
    let section = SECTION_BATTERY_SHARE * problem.vehicle.battery.usable_j() / per_m / lines.max(1) as f64;
    if !(section.is_finite() && section > 0.0) {
        return 1;
    }
    (length / section).ceil().clamp(1.0, 10_000.0) as usize
}

/// Energy a metre of straight sweep costs (the energy model's, in the plan's wind).
fn sweep_energy_per_m(problem: &Problem<'_>) -> f64 {
    let model = problem.vehicle.energy_model_in(problem.wind.as_ref());
    let straight = |m: f64| {
        let mut p = FlightPath::default();
        p.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: m, y: 0.0 }], 0.0);
        model.estimate(&p, None).energy_j()
    };
    (straight(2_000.0) - straight(1_000.0)) / 1_000.0
}

/// The part of `line` between distances `from` and `to` along it.
fn slice(line: &[Coord], from: f64, to: f64) -> Vec<Coord> {
    let mut out = Vec::new();
    let mut at = 0.0;
    for w in line.windows(2) {
        let len = distance(w[0], w[1]);
        let point = |s: f64| w[0] + (w[1] - w[0]) * ((s - at) / len).clamp(0.0, 1.0);
        if at + len >= from && at <= to {
            if out.is_empty() {
                out.push(point(from));
            }
            if at + len < to {
                out.push(w[1]);
            } else {
                out.push(point(to));
                break;
            }
        }
        at += len;
    }
    out.dedup_by(|p, q| distance(*p, *q) < 1e-9);
    out
}

/// The pieces of `line` outside the zones, in its order and direction: each segment cut where
/// it crosses a zone's edge, the stretches whose middle lies in no zone kept. (Walked segment
/// by segment: an overlay would also cut the line where it crosses itself, at a notch.)
fn outside(line: Vec<Coord>, zones: &MultiPolygon) -> Vec<Vec<Coord>> {
    let boxes: Vec<(Rect, &Polygon)> = zones.0.iter().filter_map(|z| Some((z.bounding_rect()?, z))).collect();
    let line_box = geo::LineString::new(line.clone()).bounding_rect();
    if !line_box.is_some_and(|l| boxes.iter().any(|(b, _)| b.intersects(&l))) {
        return vec![line];
    }
    let inside = |p: Coord| boxes.iter().any(|(b, z)| b.intersects(&p) && z.contains(&p));
    let mut pieces: Vec<Vec<Coord>> = Vec::new();
    let mut piece: Vec<Coord> = Vec::new();
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let seg = Rect::new(a, b);
        let mut cuts: Vec<f64> = vec![0.0, 1.0];
        for (bx, z) in &boxes {
            if !bx.intersects(&seg) {
                continue;
            }
            for ring in std::iter::once(z.exterior()).chain(z.interiors()) {
                for e in ring.0.windows(2) {
                    if let Some((t, u)) = segment_crossing(a, b, e[0], e[1])
                        && (0.0..=1.0).contains(&t)
                        && (0.0..=1.0).contains(&u)
                    {
                        cuts.push(t);
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        for c in cuts.windows(2) {
            if c[1] - c[0] < 1e-12 {
                continue;
            }
            let (p, q) = (a + (b - a) * c[0], a + (b - a) * c[1]);
            if inside(p + (q - p) * 0.5) {
                if piece.len() >= 2 {
                    pieces.push(std::mem::take(&mut piece));
                }
                piece.clear();
            } else {
                if piece.last() != Some(&p) {
                    piece.push(p);
                }
                piece.push(q);
            }
        }
    }
    if piece.len() >= 2 {
        pieces.push(piece);
    }
    pieces.retain(|p| polyline_length(p) >= SHORTEST_PIECE_M);
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    fn c(x: f64, y: f64) -> Coord {
        Coord { x, y }
    }

    #[test]
    fn a_slice_runs_between_two_distances_along_the_line() {
        let line = [c(0.0, 0.0), c(100.0, 0.0), c(100.0, 100.0)];
        assert_eq!(slice(&line, 50.0, 150.0), vec![c(50.0, 0.0), c(100.0, 0.0), c(100.0, 50.0)]);
        assert_eq!(slice(&line, 0.0, 200.0), line.to_vec());
        assert_eq!(slice(&line, 120.0, 130.0), vec![c(100.0, 20.0), c(100.0, 30.0)]);
    }

    #[test]
    fn a_line_through_a_zone_is_cut_into_the_pieces_outside_in_its_order() {
        let zone = MultiPolygon(vec![polygon![(x: 40., y: -10.), (x: 60., y: -10.), (x: 60., y: 10.), (x: 40., y: 10.)]]);
        for line in [vec![c(0.0, 0.0), c(100.0, 0.0)], vec![c(100.0, 0.0), c(0.0, 0.0)]] {
            let pieces = outside(line.clone(), &zone);
            assert_eq!(pieces.len(), 2);
            assert_eq!(pieces[0][0], line[0]);
            assert_eq!(pieces[1][pieces[1].len() - 1], line[1]);
            assert!((polyline_length(&pieces[0]) - 40.0).abs() < 1e-9);
        }
    }

    #[test]
    fn an_odd_count_puts_the_outer_swaths_flush_with_the_edges() {
        let offsets = odd_count(60.0, 3, None);
        assert_eq!(offsets, vec![-20.0, 0.0, 20.0]);
        let offsets = odd_count(60.0, 3, Some(40.0));
        assert_eq!(offsets, vec![-10.0, 0.0, 10.0]);
    }
}
