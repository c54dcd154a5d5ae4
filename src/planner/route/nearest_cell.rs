//! Greedy cell order: from where the vehicle is, fly next the cell (in the best of its four
//! entry variants) whose entry is nearest. Without a fixed start, every cell and variant is
//! tried as the first one and the shortest tour kept.

use geo::Coord;

use crate::planner::decompose::Cell;
use crate::planner::path::distance;
use crate::planner::sweep::{SweepPattern, SweepSegment};

/// How a cell is flown: lines in order or reversed, first line from `a` to `b` or back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellVisit {
    pub cell: usize,
    pub reverse_lines: bool,
    pub first_backwards: bool,
}

impl CellVisit {
    /// The directed segments in flight order, as (from, to) local points.
    pub fn legs(&self, cell: &Cell, pattern: &SweepPattern) -> Vec<(Coord, Coord)> {
        let segs: Box<dyn Iterator<Item = &SweepSegment>> =
            if self.reverse_lines { Box::new(cell.segments.iter().rev()) } else { Box::new(cell.segments.iter()) };
        segs.enumerate()
            .map(|(k, s)| {
                let (a, b) = pattern.segment_ends(s);
                if (k % 2 == 1) != self.first_backwards { (b, a) } else { (a, b) }
            })
            .collect()
    }

    fn entry_exit(&self, cell: &Cell, pattern: &SweepPattern) -> (Coord, Coord) {
        let legs = self.legs(cell, pattern);
        (legs[0].0, legs[legs.len() - 1].1)
    }
}

fn variants(cell: usize) -> impl Iterator<Item = CellVisit> {
    [(false, false), (false, true), (true, false), (true, true)]
        .into_iter()
        .map(move |(reverse_lines, first_backwards)| CellVisit { cell, reverse_lines, first_backwards })
}

/// Orders `cells`; the total connection distance (straight lines) decides between tours.
pub fn order(cells: &[Cell], pattern: &SweepPattern, start: Option<Coord>, end: Option<Coord>) -> Vec<CellVisit> {
    let ends: Vec<[(Coord, Coord); 4]> = (0..cells.len())
        .map(|c| {
            let v: Vec<(Coord, Coord)> = variants(c).map(|v| v.entry_exit(&cells[c], pattern)).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect();
    let greedy = |first: Option<CellVisit>| -> (f64, Vec<CellVisit>) {
        let mut done = vec![false; cells.len()];
        let mut tour = Vec::with_capacity(cells.len());
        let mut cost = 0.0;
        let mut here = start;
        if let Some(f) = first {
            let (entry, exit) = ends[f.cell][variant_index(&f)];
            cost += here.map_or(0.0, |h| distance(h, entry));
            done[f.cell] = true;
            tour.push(f);
            here = Some(exit);
        }
        while tour.len() < cells.len() {
            let here_pt = here.unwrap_or(Coord { x: f64::NEG_INFINITY, y: 0.0 });
            let best = (0..cells.len())
                .filter(|&c| !done[c])
                .flat_map(variants)
                .map(|v| {
                    let d = if here.is_some() { distance(here_pt, ends[v.cell][variant_index(&v)].0) } else { 0.0 };
                    (d, v)
                })
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .expect("a cell is left");
            cost += best.0;
            done[best.1.cell] = true;
            here = Some(ends[best.1.cell][variant_index(&best.1)].1);
            tour.push(best.1);
        }
        if let (Some(h), Some(e)) = (here, end) {
            cost += distance(h, e);
        }
        (cost, tour)
    };
    if cells.is_empty() {
        return Vec::new();
    }
    if start.is_some() || cells.len() > 60 {
        return greedy(None).1;
    }
    (0..cells.len())
        .flat_map(variants)
        .map(|v| greedy(Some(v)))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, t)| t)
        .expect("at least one cell")
}

fn variant_index(v: &CellVisit) -> usize {
    (v.reverse_lines as usize) * 2 + v.first_backwards as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::decompose::{Decomposition, boustrophedon::Boustrophedon};
    use crate::planner::sweep::sweep;
    use geo::{MultiPolygon, polygon};

    #[test]
    fn visits_every_cell_once_and_alternates_directions() {
        let region = MultiPolygon(vec![polygon!(
            exterior: [(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)],
            interiors: [[(x: 30., y: 30.), (x: 30., y: 70.), (x: 70., y: 70.), (x: 70., y: 30.)]],
        )]);
        let pattern = sweep(&region, &MultiPolygon(vec![]), 0.0, 10.0);
        let cells = Boustrophedon.cells(&pattern);
        let tour = order(&cells, &pattern, Some(Coord { x: -10.0, y: -10.0 }), None);
        let mut seen: Vec<usize> = tour.iter().map(|v| v.cell).collect();
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        // starts with the cell nearest to the start, at its nearest corner
        let legs = tour[0].legs(&cells[tour[0].cell], &pattern);
        assert_eq!(legs[0].0, Coord { x: 0.0, y: 5.0 });
        for w in legs.windows(2) {
            assert!((w[0].1.x - w[1].0.x).abs() < 1e-9, "a turn joins the same side");
        }
    }
}
