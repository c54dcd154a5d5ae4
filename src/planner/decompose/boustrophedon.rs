//! Boustrophedon cellular decomposition (Choset), computed on the sweep lines themselves.
//!
//! The slice that sweeps across the region is sampled at each coverage line: a cell goes on
//! while its segment on one line overlaps exactly one segment on the next and that segment
//! overlaps nothing else; where segments split (a hole or a concavity begins) or merge (they
//! end), cells close and new ones open — the SPLIT/MERGE events of the continuous algorithm.
//! Working at line resolution gives exactly the cells that lawnmower lines can fill, with
//! holes and no-fly zones of any shape, and no degenerate zero-width cells.

use super::{Cell, Decomposition};
use crate::planner::sweep::{SweepPattern, SweepSegment};

pub struct Boustrophedon;

fn overlaps(p: &SweepSegment, q: &SweepSegment) -> bool {
    p.a < q.b && q.a < p.b
}

impl Decomposition for Boustrophedon {
    fn cells(&self, pattern: &SweepPattern) -> Vec<Cell> {
        let mut done: Vec<Cell> = Vec::new();
        // open cells, each with the index of its segment on the previous line
        let mut open: Vec<(Cell, usize)> = Vec::new();
        let mut prev: &[SweepSegment] = &[];
        for line in &pattern.lines {
            let degree_prev: Vec<usize> = prev.iter().map(|p| line.iter().filter(|q| overlaps(p, q)).count()).collect();
            let degree_next: Vec<usize> = line.iter().map(|q| prev.iter().filter(|p| overlaps(p, q)).count()).collect();
            let mut next_open: Vec<(Cell, usize)> = Vec::new();
            let mut continued = vec![false; line.len()];
            for (mut cell, pi) in open.drain(..) {
                let successor = (degree_prev[pi] == 1)
                    .then(|| line.iter().position(|q| overlaps(&prev[pi], q)))
                    .flatten()
                    .filter(|&qi| degree_next[qi] == 1);
                match successor {
                    Some(qi) => {
                        cell.segments.push(line[qi]);
                        continued[qi] = true;
                        next_open.push((cell, qi));
                    }
                    None => done.push(cell),
                }
            }
            for (qi, seg) in line.iter().enumerate() {
                if !continued[qi] {
                    next_open.push((Cell { segments: vec![*seg] }, qi));
                }
            }
            next_open.sort_by_key(|(_, qi)| *qi);
            open = next_open;
            prev = line;
        }
        done.extend(open.into_iter().map(|(c, _)| c));
        done.extend(pattern.gap_fills.iter().map(|s| Cell { segments: vec![*s] }));
        // deterministic order: by first line, then position along it
        done.sort_by(|x, y| {
            let (a, b) = (x.segments[0], y.segments[0]);
            a.line.cmp(&b.line).then(a.a.total_cmp(&b.a))
        });
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::sweep::sweep;
    use geo::{MultiPolygon, polygon};

    #[test]
    fn square_with_a_hole_gives_four_cells() {
        // the decomposition spec's test case: [0,100]² with the hole [30,70]²
        let region = MultiPolygon(vec![polygon!(
            exterior: [(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)],
            interiors: [[(x: 30., y: 30.), (x: 30., y: 70.), (x: 70., y: 70.), (x: 70., y: 30.)]],
        )]);
        let pattern = sweep(&region, &MultiPolygon(vec![]), 0.0, 10.0);
        let cells = Boustrophedon.cells(&pattern);
        let sizes: Vec<usize> = cells.iter().map(|c| c.segments.len()).collect();
        // below the hole (3 lines), left and right of it (4 lines each), above it (3 lines)
        assert_eq!(sizes, vec![3, 4, 4, 3]);
        let lines: usize = pattern.lines.iter().map(Vec::len).sum();
        assert_eq!(sizes.iter().sum::<usize>(), lines);
    }

    #[test]
    fn convex_field_is_one_cell() {
        let region = MultiPolygon(vec![polygon![(x: 0., y: 0.), (x: 300., y: 20.), (x: 250., y: 200.), (x: 10., y: 150.)]]);
        let pattern = sweep(&region, &MultiPolygon(vec![]), 0.3, 15.0);
        assert_eq!(Boustrophedon.cells(&pattern).len(), 1);
    }
}
