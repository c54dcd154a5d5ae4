//! The energy-aware sweep of Di Franco and Buttazzo (seed 000 §3.2.3; the E-BF baseline of seed
//! 002), in the polygon-difference form of docs/methods.md, decomposition §9.2: lines parallel to the
//! longest edge, starting from it, flown as one main run while each line overlaps the last;
//! what the run leaves uncovered splits into pockets, each swept the same way, recursively.

use geo::{Area, BooleanOps, Coord, MultiPolygon, Polygon};

use super::polygon::{min_width, open_ring};
use super::{Cell, CoverageArea, Decomposition, sort_cells, swept_cells};
use crate::sweep::{SweepSegment, fewest_lines_direction, to_sweep_frame};

pub struct EnergyAware;

/// Pockets deeper than this are swept by plain boustrophedon cells.
const MAX_DEPTH: usize = 4;

impl Decomposition for EnergyAware {
    fn cells(&self, area: &CoverageArea<'_>) -> Vec<Cell> {
        let mut cells = Vec::new();
        for poly in area.region {
            pocket_cells(poly, area, 0, &mut cells);
        }
        sort_cells(&mut cells);
        cells
    }
}

/// The longest exterior edge, as (start, end); ties keep the first in ring order.
fn longest_edge(poly: &Polygon) -> (Coord, Coord) {
    let ring = open_ring(poly.exterior());
    let n = ring.len();
    (0..n)
        .map(|i| (ring[i], ring[(i + 1) % n]))
        .fold(None, |best: Option<(Coord, Coord)>, (a, b)| {
            let len = |(p, q): (Coord, Coord)| (q.x - p.x).hypot(q.y - p.y);
            match best {
                Some(e) if len(e) >= len((a, b)) => Some(e),
                _ => Some((a, b)),
            }
        })
        .expect("a ring has edges")
}

fn overlap(p: &SweepSegment, q: &SweepSegment) -> f64 {
    (p.b.min(q.b) - p.a.max(q.a)).max(0.0)
}

fn pocket_cells(poly: &Polygon, area: &CoverageArea<'_>, depth: usize, out: &mut Vec<Cell>) {
    let piece = MultiPolygon(vec![poly.clone()]);
    if depth >= MAX_DEPTH {
        let angle = area.angle.unwrap_or_else(|| fewest_lines_direction(&piece, area.layout));
        out.extend(swept_cells(&piece, area, angle));
        return;
    }
    let (e0, e1) = longest_edge(poly);
    let angle = area.angle.unwrap_or_else(|| (e1.y - e0.y).atan2(e1.x - e0.x).rem_euclid(std::f64::consts::PI));
    let pattern = area.sweep(&piece, angle);
    // start from the line nearest the longest edge
    let edge_v = to_sweep_frame(angle, e0).y;
    let mut lines: Vec<&Vec<SweepSegment>> = pattern.lines.iter().filter(|l| !l.is_empty()).collect();
    let (Some(first), Some(last)) = (lines.first(), lines.last()) else { return };
    if (last[0].offset - edge_v).abs() < (first[0].offset - edge_v).abs() {
        lines.reverse();
    }
    let mut run: Vec<SweepSegment> = Vec::new();
    for line in lines {
        let next = match run.last() {
            None => line.iter().max_by(|p, q| (p.b - p.a).total_cmp(&(q.b - q.a))),
            Some(prev) => line.iter().filter(|q| overlap(prev, q) > 0.0).max_by(|p, q| overlap(prev, p).total_cmp(&overlap(prev, q))),
        };
        match next {
            Some(s) => run.push(*s),
            None => break,
        }
    }
    if run.is_empty() {
        return;
    }
    run.sort_by(|p, q| p.offset.total_cmp(&q.offset));
    let main = Cell { angle, segments: run };
    let residual = piece.difference(&MultiPolygon(vec![main.footprint()]));
    out.push(main);
    let swath = 2.0 * area.layout.half_swath();
    let min_area = 0.02 * swath * swath;
    for pocket in residual.iter().filter(|p| p.unsigned_area() >= min_area && min_width(p.exterior()).0 >= 0.5) {
        pocket_cells(pocket, area, depth + 1, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::LineLayout;
    use geo::polygon;

    #[test]
    fn a_u_is_one_main_run_and_one_pocket() {
        // docs/methods.md, decomposition §9.2's example
        let u = MultiPolygon(vec![polygon![
            (x: 0., y: 0.), (x: 300., y: 0.), (x: 300., y: 200.), (x: 200., y: 200.),
            (x: 200., y: 80.), (x: 100., y: 80.), (x: 100., y: 200.), (x: 0., y: 200.)
        ]]);
        let none = MultiPolygon(vec![]);
        let area = CoverageArea { region: &u, keep_out: &none, layout: LineLayout::centered(20.0), angle: None };
        let cells = EnergyAware.cells(&area);
        assert_eq!(cells.len(), 2, "{cells:?}");
        let main = cells.iter().max_by_key(|c| c.segments.len()).unwrap();
        assert!(main.angle.abs() < 1e-9, "main run along the 300 m base");
        // the pocket is the other arm, swept along its own longest (vertical) edge
        let pocket = cells.iter().min_by_key(|c| c.segments.len()).unwrap();
        assert!((pocket.angle - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        let covered: f64 = cells.iter().map(|c| MultiPolygon(vec![c.footprint()]).intersection(&u).unsigned_area()).sum();
        assert!(covered >= u.unsigned_area() * 0.999);
    }
}
