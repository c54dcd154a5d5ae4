//! Cell order as a generalised TSP (docs/methods.md, routing §1): each cell is a cluster of its four
//! entry variants; a connection costs the length of the shortest transit around the no-fly
//! zones from one variant's exit to the next one's entry; a variant costs its own lines and
//! turns. Solved by [`super::gtsp`].

use geo::Coord;

use super::gtsp::{Costs, Instance, solve};
use super::{CellOrder, CellVisit, RouteContext};
use crate::decompose::{Cell, legs_length};
use crate::stop::Stop;

pub struct CellTour;

impl CellOrder for CellTour {
    fn order(&self, cells: &[Cell], ctx: &RouteContext<'_>) -> Vec<CellVisit> {
        if cells.is_empty() {
            return Vec::new();
        }
        let visits: Vec<CellVisit> = (0..cells.len()).flat_map(CellVisit::variants).collect();
        let ends: Vec<(Coord, Coord)> = visits.iter().map(|v| v.entry_exit(&cells[v.cell])).collect();
        // points: every cell's four corners, then the start and the end
        let mut points: Vec<Coord> = Vec::with_capacity(visits.len() + 2);
        let mut entry_at = Vec::with_capacity(visits.len());
        let mut exit_at = Vec::with_capacity(visits.len());
        let index = |p: Coord, points: &mut Vec<Coord>| match points.iter().rposition(|&q| q == p) {
            Some(i) => i,
            None => {
                points.push(p);
                points.len() - 1
            }
        };
        for (entry, exit) in &ends {
            entry_at.push(index(*entry, &mut points));
            exit_at.push(index(*exit, &mut points));
        }
        let start_at = ctx.start.map(|s| index(s, &mut points));
        let end_at = ctx.end.map(|e| index(e, &mut points));
        let d = ctx.transit.distance_matrix(&points);
        let n = visits.len();
        let inst = Instance {
            clusters: (0..cells.len()).map(|c| (4 * c..4 * c + 4).collect()).collect(),
            reverse: visits.iter().enumerate().map(|(i, v)| i - i % 4 + v.reversed(&cells[v.cell]).index()).collect(),
            cost: Costs::Dense((0..n * n).map(|k| if k / n / 4 == k % n / 4 { f64::INFINITY } else { d[exit_at[k / n]][entry_at[k % n]] }).collect()),
            node_cost: visits.iter().map(|v| legs_length(&v.legs(&cells[v.cell]))).collect(),
            from_start: start_at.map(|s| entry_at.iter().map(|&e| d[s][e]).collect()),
            to_end: end_at.map(|e| exit_at.iter().map(|&x| d[x][e]).collect()),
            candidates: None,
            stop: Stop::never(),
        };
        solve(&inst).into_iter().map(|v| visits[v]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::boustrophedon::cells_of;
    use crate::geom::distance;
    use crate::route::nearest_cell::NearestCell;
    use crate::route::visibility::TransitPlanner;
    use crate::sweep::{LineLayout, sweep};
    use geo::{MultiPolygon, polygon};

    fn tour_length(cells: &[Cell], tour: &[CellVisit], start: Coord) -> f64 {
        let mut here = start;
        let mut total = 0.0;
        for v in tour {
            let legs = v.legs(&cells[v.cell]);
            total += distance(here, legs[0].0) + legs_length(&legs);
            here = legs[legs.len() - 1].1;
        }
        total
    }

    #[test]
    fn never_longer_than_the_greedy_order() {
        // a comb: many cells between the teeth
        let region = MultiPolygon(vec![polygon![
            (x: 0., y: 0.), (x: 300., y: 0.), (x: 300., y: 200.), (x: 250., y: 200.), (x: 250., y: 50.), (x: 200., y: 50.),
            (x: 200., y: 200.), (x: 150., y: 200.), (x: 150., y: 50.), (x: 100., y: 50.), (x: 100., y: 200.), (x: 50., y: 200.),
            (x: 50., y: 50.), (x: 0., y: 50.)
        ]]);
        let cells = cells_of(&sweep(&region, &MultiPolygon(vec![]), 0.0, LineLayout::centered(10.0)));
        assert_eq!(cells.len(), 4, "the base and three teeth");
        let none = MultiPolygon(vec![]);
        let transit = TransitPlanner::new(&none, &none);
        let start = Coord { x: 320.0, y: 100.0 };
        let ctx = RouteContext { transit: &transit, start: Some(start), end: None };
        let gtsp = CellTour.order(&cells, &ctx);
        let greedy = NearestCell.order(&cells, &ctx);
        assert_eq!(gtsp.len(), cells.len());
        assert!(tour_length(&cells, &gtsp, start) <= tour_length(&cells, &greedy, start) + 1e-6);
    }
}
