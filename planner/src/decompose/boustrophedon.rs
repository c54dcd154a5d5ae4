//! Boustrophedon cellular decomposition (Choset), computed on the sweep lines themselves.
//!
//! The slice that sweeps across the region is sampled at each coverage line: a cell goes on
//! while its segment on one line overlaps exactly one segment on the next and that segment
//! overlaps nothing else; where segments split (a hole or a concavity begins) or merge (they
//! end), cells close and new ones open — the SPLIT/MERGE events of the continuous algorithm.
//! Working at line resolution gives exactly the cells that lawnmower lines can fill, with
//! holes and no-fly zones of any shape, and no degenerate zero-width cells.
//!
//! Each cell is then swept in its own best direction where that shortens it (docs/methods.md,
//! decomposition §8): the cell's area is re-swept in the direction of its fewest lines and the result
//! kept when it is one cell again and shorter.

use geo::{BooleanOps, MultiPolygon};

use super::{Cell, CoverageArea, Decomposition, legs_length, sort_cells, swept_cells};
use crate::sweep::{SweepPattern, SweepSegment, fewest_lines_direction};

pub struct Boustrophedon;

impl Decomposition for Boustrophedon {
    fn cells(&self, area: &CoverageArea<'_>) -> Vec<Cell> {
        use rayon::prelude::*;
        let angle = area.angle.unwrap_or_else(|| fewest_lines_direction(area.region, area.layout));
        let cells = cells_of(&area.sweep(area.region, angle));
        if area.angle.is_some() {
            return cells;
        }
        let mut cells: Vec<Cell> = cells.into_par_iter().flat_map_iter(|c| best_direction(c, area)).collect();
        sort_cells(&mut cells);
        cells
    }
}

/// Length of a cell flown back and forth: its lines and the straight turns between them.
pub fn flown_length(cell: &Cell) -> f64 {
    legs_length(&cell.legs(false, false))
}

/// The cell, or the same area re-swept in its own fewest-lines direction when that is one
/// cell again and at least 1 % shorter.
fn best_direction(cell: Cell, area: &CoverageArea<'_>) -> Vec<Cell> {
    if cell.segments.len() < 3 {
        return vec![cell];
    }
    let own = MultiPolygon(vec![cell.footprint()]).intersection(area.region);
    let angle = fewest_lines_direction(&own, area.layout);
    let alternative = swept_cells(&own, area, angle);
    match alternative.as_slice() {
        [one] if flown_length(one) < 0.99 * flown_length(&cell) => alternative,
        _ => vec![cell],
    }
}

fn overlaps(p: &SweepSegment, q: &SweepSegment) -> bool {
    p.a < q.b && q.a < p.b
}

/// The boustrophedon cells of a sweep pattern, gap fills as cells of their own.
pub fn cells_of(pattern: &SweepPattern) -> Vec<Cell> {
    let cell = |segments: Vec<SweepSegment>| Cell { angle: pattern.angle, segments };
    let mut done: Vec<Cell> = Vec::new();
    // open cells, each with the index of its segment on the previous line
    let mut open: Vec<(Cell, usize)> = Vec::new();
    let mut prev: &[SweepSegment] = &[];
    for line in &pattern.lines {
        let degree_prev: Vec<usize> = prev.iter().map(|p| line.iter().filter(|q| overlaps(p, q)).count()).collect();
        let degree_next: Vec<usize> = line.iter().map(|q| prev.iter().filter(|p| overlaps(p, q)).count()).collect();
        let mut next_open: Vec<(Cell, usize)> = Vec::new();
        let mut continued = vec![false; line.len()];
        for (mut c, pi) in open.drain(..) {
            let successor = (degree_prev[pi] == 1).then(|| line.iter().position(|q| overlaps(&prev[pi], q))).flatten().filter(|&qi| degree_next[qi] == 1);
            match successor {
                Some(qi) => {
                    c.segments.push(line[qi]);
                    continued[qi] = true;
                    next_open.push((c, qi));
                }
                None => done.push(c),
            }
        }
        for (qi, seg) in line.iter().enumerate() {
            if !continued[qi] {
                next_open.push((cell(vec![*seg]), qi));
            }
        }
        next_open.sort_by_key(|(_, qi)| *qi);
        open = next_open;
        prev = line;
    }
    done.extend(open.into_iter().map(|(c, _)| c));
    done.extend(pattern.gap_fills.iter().map(|s| cell(vec![*s])));
    // deterministic order: by first line, then position along it
    done.sort_by(|x, y| {
        let (a, b) = (x.segments[0], y.segments[0]);
        a.line.cmp(&b.line).then(a.a.total_cmp(&b.a))
    });
    done
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{LineLayout, sweep};
    use geo::polygon;

    #[test]
    fn square_with_a_hole_gives_four_cells() {
        // the docs/methods.md, decomposition's test case: [0,100]² with the hole [30,70]²
        let region = MultiPolygon(vec![polygon!(
            exterior: [(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)],
            interiors: [[(x: 30., y: 30.), (x: 30., y: 70.), (x: 70., y: 70.), (x: 70., y: 30.)]],
        )]);
        let pattern = sweep(&region, &MultiPolygon(vec![]), 0.0, LineLayout::centered(10.0));
        let cells = cells_of(&pattern);
        let sizes: Vec<usize> = cells.iter().map(|c| c.segments.len()).collect();
        // below the hole (3 lines), left and right of it (4 lines each), above it (3 lines)
        assert_eq!(sizes, vec![3, 4, 4, 3]);
        let lines: usize = pattern.lines.iter().map(Vec::len).sum();
        assert_eq!(sizes.iter().sum::<usize>(), lines);
    }

    #[test]
    fn convex_field_is_one_cell() {
        let region = MultiPolygon(vec![polygon![(x: 0., y: 0.), (x: 300., y: 20.), (x: 250., y: 200.), (x: 10., y: 150.)]]);
        let pattern = sweep(&region, &MultiPolygon(vec![]), 0.3, LineLayout::centered(15.0));
        assert_eq!(cells_of(&pattern).len(), 1);
    }
}
