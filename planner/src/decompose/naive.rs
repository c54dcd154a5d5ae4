//! Naive convex decomposition (seed 000 §3.2.1, docs/methods.md, decomposition §6): cut at each reflex
//! vertex along the extension of one of its edges, the shorter cut of the two, until every
//! piece is convex; each piece is then swept across its width.

use geo::{BooleanOps, Coord, MultiPolygon, Polygon};

use super::polygon::{closed, open_ring, ray_hit, reflex_vertices, split};
use super::{Cell, CoverageArea, Decomposition, boustrophedon, sort_cells, sweep_pieces};
use crate::sweep::{LineLayout, sweep};

pub struct Naive;

impl Decomposition for Naive {
    fn cells(&self, area: &CoverageArea<'_>) -> Vec<Cell> {
        let pieces: Vec<Polygon> =
            simple_parts(area.region, area.layout).into_iter().flat_map(|ring| convex_pieces(ring, naive_cut)).map(|r| Polygon::new(closed(&r), vec![])).collect();
        let mut cells = sweep_pieces(&pieces, area);
        sort_cells(&mut cells);
        cells
    }
}

/// A cut: the chord from vertex `i` to `hit` on edge `j`.
pub type Cut = (usize, usize, Coord);

/// The shorter of the two edge extensions at reflex vertex `i`.
pub fn naive_cut(ring: &[Coord], i: usize) -> Option<Cut> {
    let n = ring.len();
    let (p, v, q) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
    [v - p, v - q].into_iter().filter_map(|d| ray_hit(ring, i, d)).min_by(|x, y| x.0.total_cmp(&y.0)).map(|(_, j, hit)| (i, j, hit))
}

/// Cuts the ring at its reflex vertices with `choose` until the pieces are convex. A piece the
/// rule cannot cut stays whole (its lines are still clipped to it, so nothing is lost).
pub fn convex_pieces(ring: Vec<Coord>, choose: impl Fn(&[Coord], usize) -> Option<Cut>) -> Vec<Vec<Coord>> {
    let mut queue = vec![ring];
    let mut out = Vec::new();
    // each cut removes a reflex vertex; the bound only guards against numerical loops
    let mut budget = 4 * queue[0].len() + 16;
    while let Some(r) = queue.pop() {
        let cut = reflex_vertices(&r).into_iter().find_map(|i| choose(&r, i));
        match cut {
            Some((i, j, hit)) if budget > 0 => {
                budget -= 1;
                let (a, b) = split(&r, i, j, hit);
                queue.extend([a, b].into_iter().filter(|p| p.len() >= 3));
            }
            _ => out.push(r),
        }
    }
    out.reverse();
    out
}

/// Rings without holes that together make up the region: polygons without holes as they are;
/// a polygon with holes split first into its boustrophedon cells (docs/methods.md, decomposition §6), at the
/// direction of its narrowest width.
pub fn simple_parts(region: &MultiPolygon, layout: LineLayout) -> Vec<Vec<Coord>> {
    let mut out = Vec::new();
    for poly in region {
        if poly.interiors().is_empty() {
            out.push(open_ring(poly.exterior()));
            continue;
        }
        let whole = MultiPolygon(vec![poly.clone()]);
        let angle = super::polygon::min_width(poly.exterior()).1;
        let pattern = sweep(&whole, &MultiPolygon(vec![]), angle, layout);
        for cell in boustrophedon::cells_of(&pattern) {
            for part in MultiPolygon(vec![cell.footprint()]).intersection(&whole) {
                out.push(open_ring(part.exterior()));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::polygon::reflex_vertices;
    use crate::geom::signed_area;

    #[test]
    fn pieces_are_convex_and_keep_the_area() {
        // a comb with three teeth
        let pts = [(0., 0.), (70., 0.), (70., 40.), (60., 40.), (60., 10.), (40., 10.), (40., 40.), (30., 40.), (30., 10.), (10., 10.), (10., 40.), (0., 40.)];
        let ring: Vec<Coord> = pts.iter().map(|&(x, y)| Coord { x, y }).collect();
        let pieces = convex_pieces(ring.clone(), naive_cut);
        assert!(pieces.iter().all(|p| reflex_vertices(p).is_empty()));
        let total: f64 = pieces.iter().map(|p| signed_area(p)).sum();
        assert!((total - signed_area(&ring)).abs() < 1e-6);
        assert!(pieces.len() <= reflex_vertices(&ring).len() + 1);
    }
}
