//! Decompose stage: split the area to cover into cells that can each be flown back and forth,
//! every cell with its own sweep direction and lines (docs/methods.md, decomposition §6–§9);
//! for a ground vehicle, the [`headland`] band and the mainland inside it.

pub mod boustrophedon;
pub mod eecd;
pub mod energy_aware;
pub mod headland;
pub mod naive;
pub mod polygon;

use geo::{Area, BooleanOps, Coord, LineString, MultiPolygon, Polygon};

use super::geom::distance;
use super::sweep::ends::end_lines;
use super::sweep::{LineLayout, SweepPattern, SweepSegment, from_sweep_frame, sweep};

/// A cell: one segment on each of a run of consecutive lines of direction `angle`.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Sweep direction, math radians.
    pub angle: f64,
    pub segments: Vec<SweepSegment>,
}

impl Cell {
    /// The ends of a segment of this cell in local coordinates, from `a` to `b`.
    pub fn ends(&self, seg: &SweepSegment) -> (Coord, Coord) {
        (from_sweep_frame(self.angle, seg.a, seg.offset), from_sweep_frame(self.angle, seg.b, seg.offset))
    }

    /// The area the cell's lines image: the staircase of their bands, in local coordinates.
    pub fn footprint(&self) -> Polygon {
        // counter-clockwise: up the right ends, down the left ends
        let right = self.segments.iter().flat_map(|s| [(s.b, s.lo), (s.b, s.hi)]);
        let left = self.segments.iter().rev().flat_map(|s| [(s.a, s.hi), (s.a, s.lo)]);
        let mut ring: Vec<Coord> = right.chain(left).map(|(u, v)| from_sweep_frame(self.angle, u, v)).collect();
        ring.push(ring[0]);
        Polygon::new(LineString::from(ring), vec![])
    }

    /// The segments in flight order as (from, to) local points: lines in order or reversed,
    /// the first flown from `a` to `b` or back, then alternating.
    pub fn legs(&self, reverse_lines: bool, first_backwards: bool) -> Vec<(Coord, Coord)> {
        let n = self.segments.len();
        (0..n)
            .map(|k| {
                let (a, b) = self.ends(&self.segments[if reverse_lines { n - 1 - k } else { k }]);
                if (k % 2 == 1) != first_backwards { (b, a) } else { (a, b) }
            })
            .collect()
    }

    /// Summed length of the lines.
    pub fn sweep_length(&self) -> f64 {
        self.segments.iter().map(|s| s.b - s.a).sum()
    }
}

/// Length of legs flown one after the other: the legs and the straight joins between them.
pub fn legs_length(legs: &[(Coord, Coord)]) -> f64 {
    legs.iter().map(|(a, b)| distance(*a, *b)).sum::<f64>() + legs.windows(2).map(|w| distance(w[0].1, w[1].0)).sum::<f64>()
}

/// What a decomposition works on.
pub struct CoverageArea<'a> {
    /// The area to cover (fields minus holes and grown no-fly zones).
    pub region: &'a MultiPolygon,
    /// No-fly zones grown by the margin: lines stop at their edge.
    pub keep_out: &'a MultiPolygon,
    pub layout: LineLayout,
    /// A sweep direction fixed by the user (math radians), for every cell.
    pub angle: Option<f64>,
}

impl CoverageArea<'_> {
    /// Lines at `angle` across `piece` (the region or a part of it), ended by the layout's rule
    /// where the region itself ends.
    pub fn sweep(&self, piece: &MultiPolygon, angle: f64) -> SweepPattern {
        let mut pattern = sweep(piece, self.keep_out, angle, self.layout);
        end_lines(&mut pattern, self.region, self.layout.ends, piece.unsigned_area());
        pattern
    }
}

/// A decomposition method: the area in, swept cells out. Together the cells' footprints
/// cover the area.
pub trait Decomposition: Sync {
    fn cells(&self, area: &CoverageArea<'_>) -> Vec<Cell>;
}

/// The cells of lines at `angle` across `piece`: one per run of lines that overlap one to
/// one (see [`boustrophedon::cells_of`]), plus the gap fills beside no-fly zones.
pub fn swept_cells(piece: &MultiPolygon, area: &CoverageArea<'_>, angle: f64) -> Vec<Cell> {
    boustrophedon::cells_of(&area.sweep(piece, angle))
}

/// Sweeps each convex piece in its own direction (the user's, or its narrowest), keeping
/// holes and no-fly zones out of the lines.
pub fn sweep_pieces(pieces: &[Polygon], area: &CoverageArea<'_>) -> Vec<Cell> {
    use rayon::prelude::*;
    let per_piece: Vec<Vec<Cell>> = pieces
        .par_iter()
        .map(|p| {
            let clipped = MultiPolygon(vec![p.clone()]).intersection(area.region);
            let angle = area.angle.unwrap_or_else(|| polygon::min_width(p.exterior()).1);
            swept_cells(&clipped, area, angle)
        })
        .collect();
    per_piece.into_iter().flatten().collect()
}

/// Orders cells deterministically: by their first segment's position.
pub(crate) fn sort_cells(cells: &mut [Cell]) {
    cells.sort_by(|x, y| {
        let (a, b) = (x.ends(&x.segments[0]).0, y.ends(&y.segments[0]).0);
        a.y.total_cmp(&b.y).then(a.x.total_cmp(&b.x))
    });
}
