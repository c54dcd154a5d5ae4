//! E-Spiral (seed 002 §4.1, docs/methods.md, multirotor planners §1): rings that follow the field's
//! boundary inwards, one swath apart, so that corners are wide and a multirotor keeps much of
//! its speed through them. Each ring is the field inset by mitred offsets (the "inner
//! side-lines" of the thesis); a ring that splits becomes one spiral per part; what the last
//! ring leaves in the middle is covered by one line along its longest axis.
//!
//! Seed 002 states the method for areas without holes or inner no-fly zones; this planner
//! refuses those instead of flying into them.

use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::orient::{Direction, Orient};
use geo::{Area, Buffer, Coord, MultiPolygon, Polygon, Simplify};

use super::{PlannedPath, Planner, Problem, Progress, connect, no_sweep_lines};
use crate::error::{InputError, PlanError};
use crate::geom::distance;
use crate::path::{FlightPath, PieceKind};
use crate::vehicle::VehicleKind;

pub struct ESpiral;

/// One pass of the spiral: a closed ring, or the line through the middle.
enum Pass {
    Ring(Vec<Coord>),
    Line(Coord, Coord),
}

/// Most rings one plan may have (a guard against absurd spacings; 2 000 km of sweep at 0.5 m).
const MAX_PASSES: usize = 20_000;

/// `area` shrunk by `d` with mitred corners, exteriors counter-clockwise.
fn inset(area: &Polygon, d: f64) -> MultiPolygon {
    let shrunk = area.buffer_with_style(BufferStyle::new(-d).line_join(LineJoin::Miter(4.0)));
    MultiPolygon(shrunk.0.into_iter().filter(|p| p.unsigned_area() > 1e-6).collect()).orient(Direction::Default)
}

/// The two vertices of `area` farthest apart.
fn longest_axis(area: &Polygon) -> (Coord, Coord) {
    let pts: Vec<Coord> = area.exterior().0.clone();
    let mut best = (pts[0], pts[0], 0.0);
    for (i, &a) in pts.iter().enumerate() {
        for &b in &pts[i + 1..] {
            let d = distance(a, b);
            if d > best.2 {
                best = (a, b, d);
            }
        }
    }
    (best.0, best.1)
}

struct Layers {
    step: f64,
    half: f64,
    passes: Vec<Pass>,
}

impl Layers {
    /// The rings inside `flown` (a ring just flown) and their own inner rings, depth first.
    fn inside(&mut self, flown: &Polygon) {
        if self.passes.len() >= MAX_PASSES {
            return;
        }
        let next = inset(flown, self.step);
        if next.0.is_empty() {
            // the middle no ring reaches: one line along it
            for rest in inset(flown, self.half).0 {
                if rest.unsigned_area() > 0.01 * self.step * self.step {
                    let (a, b) = longest_axis(&rest);
                    self.passes.push(Pass::Line(a, b));
                }
            }
            return;
        }
        for part in next.0 {
            self.ring(part);
        }
    }

    fn ring(&mut self, ring: Polygon) {
        // insets come with arcs of sub-millimetre segments: waypoints a flight file should not carry
        let mut pts = ring.exterior().simplify(RING_TOLERANCE_M).0;
        pts.pop(); // the closing point
        self.passes.push(Pass::Ring(pts));
        self.inside(&ring);
    }
}

/// How far a ring may be straightened: a centimetre, nothing next to a swath.
const RING_TOLERANCE_M: f64 = 0.01;

impl Planner for ESpiral {
    fn id(&self) -> &'static str {
        "e_spiral"
    }

    fn description(&self) -> &'static str {
        "Energy-aware spiral (seed 002 §4.1): rings along the boundary inwards, one swath apart, with wide corners \
         a multirotor flies without stopping; each leg at its energy-optimal speed. Multirotors; areas without holes \
         or inner no-fly zones."
    }

    fn direction_rule(&self) -> &'static str {
        "none: the rings follow the boundary"
    }

    fn plan(&self, problem: &Problem<'_>, progress: &dyn Progress) -> Result<PlannedPath, PlanError> {
        if problem.vehicle.kind != VehicleKind::Multirotor {
            return Err(InputError::new("planner_not_applicable", "/vehicle/kind", "e_spiral is a multirotor planner: its corners are flown without a turning radius").into());
        }
        if problem.region.0.iter().any(|p| !p.interiors().is_empty()) {
            return Err(InputError::new(
                "planner_not_applicable",
                "/planner",
                "e_spiral covers areas without holes or no-fly zones inside them (seed 002 §4.1.4); use boustrophedon for this field",
            )
            .into());
        }
        let half = problem.layout.half_swath();
        let mut layers = Layers { step: problem.layout.spacing, half, passes: Vec::new() };
        for field in &problem.region.0 {
            let first = inset(field, half);
            if first.0.is_empty() {
                let (a, b) = longest_axis(field);
                layers.passes.push(Pass::Line(a, b));
            }
            for part in first.0 {
                layers.ring(part);
            }
        }
        if layers.passes.is_empty() {
            return Err(no_sweep_lines());
        }
        if layers.passes.len() >= MAX_PASSES {
            return Err(PlanError::Infeasible(format!("the spiral would need more than {MAX_PASSES} rings: use a wider spacing")));
        }
        if !progress.report(0.5) {
            return Err(PlanError::Cancelled);
        }
        let mut path = FlightPath::default();
        let mut here = problem.start;
        for pass in &layers.passes {
            let points = match pass {
                Pass::Line(a, b) => vec![*a, *b],
                Pass::Ring(ring) => {
                    // enter at the vertex nearest to where the vehicle is, and close the ring
                    let first = here.map_or(0, |h| (0..ring.len()).min_by(|&i, &j| distance(ring[i], h).total_cmp(&distance(ring[j], h))).expect("a ring has vertices"));
                    ring[first..].iter().chain(&ring[..=first]).copied().collect()
                }
            };
            if let Some(h) = here {
                let kind = if path.pieces.is_empty() { PieceKind::Transit } else { PieceKind::Turn };
                connect(&mut path, kind, h, points[0], problem.transit)?;
            }
            for w in points.windows(2).filter(|w| distance(w[0], w[1]) > 1e-9) {
                path.push(PieceKind::Sweep, vec![w[0], w[1]], half);
            }
            here = path.end();
        }
        if let (Some(h), Some(end)) = (here, problem.end) {
            connect(&mut path, PieceKind::Transit, h, end, problem.transit)?;
        }
        Ok(PlannedPath::new(path, 0.0, problem.region.0.len()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    #[test]
    fn rings_are_one_spacing_apart_and_end_in_a_middle_line() {
        let square = polygon![(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)];
        let mut layers = Layers { step: 20.0, half: 10.0, passes: Vec::new() };
        for part in inset(&square, 10.0).0 {
            layers.ring(part);
        }
        let rings: Vec<&Vec<Coord>> = layers.passes.iter().filter_map(|p| if let Pass::Ring(r) = p { Some(r) } else { None }).collect();
        // insets 10, 30 and 50 − ε: rings of side 80, 40 and none (the centre is a point)
        assert_eq!(rings.len(), 2);
        let side = |r: &Vec<Coord>| distance(r[0], r[1]);
        assert!((side(rings[0]) - 80.0).abs() < 1e-6 && (side(rings[1]) - 40.0).abs() < 1e-6);
        assert!(layers.passes.iter().filter(|p| matches!(p, Pass::Line(..))).count() <= 1);
    }
}
