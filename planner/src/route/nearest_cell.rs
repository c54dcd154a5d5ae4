//! Greedy cell order (seed 000's ordering): from where the vehicle is, fly next the cell (in
//! the best of its four entry variants) whose entry is nearest in a straight line. Without a
//! fixed start, every cell and variant is tried as the first one and the shortest tour kept.

use geo::Coord;

use super::{CellOrder, CellVisit, RouteContext};
use crate::decompose::Cell;
use crate::geom::distance;

pub struct NearestCell;

/// Above this many cells, a free start is not searched: the first cell is the westernmost.
const SEARCH_FIRST_CELL_UP_TO: usize = 60;

impl CellOrder for NearestCell {
    fn order(&self, cells: &[Cell], ctx: &RouteContext<'_>) -> Vec<CellVisit> {
        if cells.is_empty() {
            return Vec::new();
        }
        let ends: Vec<[(Coord, Coord); 4]> = cells.iter().enumerate().map(|(c, cell)| CellVisit::variants(c).map(|v| v.entry_exit(cell))).collect();
        let at = |v: &CellVisit| ends[v.cell][v.index()];
        let greedy = |first: Option<CellVisit>| -> (f64, Vec<CellVisit>) {
            let mut done = vec![false; cells.len()];
            let mut tour = Vec::with_capacity(cells.len());
            let mut cost = 0.0;
            let mut here = ctx.start;
            if let Some(f) = first {
                cost += here.map_or(0.0, |h| distance(h, at(&f).0));
                done[f.cell] = true;
                tour.push(f);
                here = Some(at(&f).1);
            }
            while tour.len() < cells.len() {
                let here_pt = here.unwrap_or(Coord { x: f64::NEG_INFINITY, y: 0.0 });
                let best = (0..cells.len())
                    .filter(|&c| !done[c])
                    .flat_map(CellVisit::variants)
                    .map(|v| (if here.is_some() { distance(here_pt, at(&v).0) } else { 0.0 }, v))
                    .min_by(|x, y| x.0.total_cmp(&y.0))
                    .expect("a cell is left");
                cost += best.0;
                done[best.1.cell] = true;
                here = Some(at(&best.1).1);
                tour.push(best.1);
            }
            if let (Some(h), Some(e)) = (here, ctx.end) {
                cost += distance(h, e);
            }
            (cost, tour)
        };
        if ctx.start.is_some() || cells.len() > SEARCH_FIRST_CELL_UP_TO {
            return greedy(None).1;
        }
        (0..cells.len()).flat_map(CellVisit::variants).map(|v| greedy(Some(v))).min_by(|x, y| x.0.total_cmp(&y.0)).map(|(_, t)| t).expect("at least one cell")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::boustrophedon::cells_of;
    use crate::route::visibility::TransitPlanner;
    use crate::sweep::{LineLayout, sweep};
    use geo::{MultiPolygon, polygon};

    #[test]
    fn visits_every_cell_once_and_alternates_directions() {
        let region = MultiPolygon(vec![polygon!(
            exterior: [(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)],
            interiors: [[(x: 30., y: 30.), (x: 30., y: 70.), (x: 70., y: 70.), (x: 70., y: 30.)]],
        )]);
        let cells = cells_of(&sweep(&region, &MultiPolygon(vec![]), 0.0, LineLayout::centered(10.0)));
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let ctx = RouteContext { transit: &transit, start: Some(Coord { x: -10.0, y: -10.0 }), end: None };
        let tour = NearestCell.order(&cells, &ctx);
        let mut seen: Vec<usize> = tour.iter().map(|v| v.cell).collect();
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        // starts with the cell nearest to the start, at its nearest corner
        let legs = tour[0].legs(&cells[tour[0].cell]);
        assert_eq!(legs[0].0, Coord { x: 0.0, y: 5.0 });
        for w in legs.windows(2) {
            assert!((w[0].1.x - w[1].0.x).abs() < 1e-9, "a turn joins the same side");
        }
    }
}
