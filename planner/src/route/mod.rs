//! Route stage: the order in which cells are flown, and transits between them.
//!
//! [`CellOrder`] implementations: [`nearest_cell::NearestCell`] (greedy, seed 000) and
//! [`cell_tour::CellTour`] (generalised TSP over the cells' entry variants, docs/methods.md, routing §1–§4,
//! solved by [`gtsp`]). A ground vehicle's swaths are ordered and joined in the headland by
//! [`headland_route`].

pub mod cell_tour;
pub mod connect;
pub mod gtsp;
pub mod headland_corners;
pub mod headland_route;
pub mod line_tour;
pub mod nearest_cell;
pub mod refill;
pub mod visibility;

use geo::Coord;

use crate::decompose::Cell;
use visibility::TransitPlanner;

/// How a cell is flown: lines in order or reversed, first line from `a` to `b` or back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellVisit {
    pub cell: usize,
    pub reverse_lines: bool,
    pub first_backwards: bool,
}

impl CellVisit {
    /// The four ways to fly cell `cell`.
    pub fn variants(cell: usize) -> [CellVisit; 4] {
        [(false, false), (false, true), (true, false), (true, true)].map(|(reverse_lines, first_backwards)| CellVisit { cell, reverse_lines, first_backwards })
    }

    /// The directed segments in flight order, as (from, to) local points.
    pub fn legs(&self, cell: &Cell) -> Vec<(Coord, Coord)> {
        cell.legs(self.reverse_lines, self.first_backwards)
    }

    /// Position of this variant in [`CellVisit::variants`].
    pub fn index(&self) -> usize {
        self.reverse_lines as usize * 2 + self.first_backwards as usize
    }

    /// Where the visit enters and leaves the cell.
    pub fn entry_exit(&self, cell: &Cell) -> (Coord, Coord) {
        let legs = self.legs(cell);
        (legs[0].0, legs[legs.len() - 1].1)
    }

    /// The same legs flown backwards: it enters where this one leaves.
    pub fn reversed(&self, cell: &Cell) -> CellVisit {
        let last_backwards = self.first_backwards != ((cell.segments.len() - 1) % 2 == 1);
        CellVisit { cell: self.cell, reverse_lines: !self.reverse_lines, first_backwards: !last_backwards }
    }
}

/// Where the flight starts and ends, and how it gets around no-fly zones.
pub struct RouteContext<'a> {
    pub transit: &'a TransitPlanner,
    pub start: Option<Coord>,
    pub end: Option<Coord>,
}

/// A way to order cells and choose how each is entered.
pub trait CellOrder: Sync {
    fn order(&self, cells: &[Cell], ctx: &RouteContext<'_>) -> Vec<CellVisit>;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::SweepSegment;

    #[test]
    fn a_reversed_visit_enters_where_the_visit_leaves() {
        for lines in 1..5 {
            let segments = (0..lines).map(|i| SweepSegment { line: i, offset: i as f64 * 10.0, a: 0.0, b: 50.0 + i as f64, lo: 0.0, hi: 0.0 }).collect();
            let cell = Cell { angle: 0.3, segments };
            for v in CellVisit::variants(0) {
                let (entry, exit) = v.entry_exit(&cell);
                let (r_entry, r_exit) = v.reversed(&cell).entry_exit(&cell);
                assert_eq!((r_entry, r_exit), (exit, entry), "{lines} lines, {v:?}");
            }
        }
    }
}
