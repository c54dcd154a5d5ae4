//! EECD (seed 000 §3.2.2, after Li et al. 2011; docs/methods.md, decomposition §7): repeatedly make the cut,
//! from a reflex vertex along any edge direction, that minimises the summed widths of the two
//! pieces; then merge neighbours with the same sweep direction whose union stays monotone.

use geo::{Area, BooleanOps, Coord, MultiPolygon, Polygon};

use super::naive::{Cut, convex_pieces, naive_cut, simple_parts};
use super::polygon::{closed, is_monotone, min_width_of, open_ring, points_inside, ray_hit, split};
use super::{Cell, CoverageArea, Decomposition, sort_cells, sweep_pieces};
use crate::geom::signed_area;

pub struct Eecd;

/// Pieces larger than this are cut by the naive rule: the search is O(r·n²) per cut.
const MAX_SEARCH_VERTICES: usize = 300;
/// Neighbours whose directions differ by less than this merge (radians, 1°).
const MERGE_TOLERANCE: f64 = std::f64::consts::PI / 180.0;

impl Decomposition for Eecd {
    fn cells(&self, area: &CoverageArea<'_>) -> Vec<Cell> {
        let min_area = area.layout.spacing * area.layout.spacing * 0.01;
        let convex: Vec<Vec<Coord>> = simple_parts(area.region, area.layout).into_iter().flat_map(|ring| convex_pieces(ring, |r, i| min_width_sum_cut(r, i, min_area))).collect();
        let pieces = merge_monotone(convex.into_iter().map(|r| Polygon::new(closed(&r), vec![])).collect());
        let mut cells = sweep_pieces(&pieces, area);
        sort_cells(&mut cells);
        cells
    }
}

/// The cut at reflex vertex `i` (along any edge direction of the ring, both ways) with the
/// least summed width of the two pieces; pieces under `min_area` are not made.
fn min_width_sum_cut(ring: &[Coord], i: usize, min_area: f64) -> Option<Cut> {
    if ring.len() > MAX_SEARCH_VERTICES {
        return naive_cut(ring, i);
    }
    let n = ring.len();
    let mut best: Option<(f64, Cut)> = None;
    for e in 0..n {
        let d = ring[(e + 1) % n] - ring[e];
        for dir in [d, Coord { x: -d.x, y: -d.y }] {
            if !points_inside(ring, i, dir) {
                continue;
            }
            let Some((_, j, hit)) = ray_hit(ring, i, dir) else { continue };
            let (a, b) = split(ring, i, j, hit);
            if a.len() < 3 || b.len() < 3 || signed_area(&a) < min_area || signed_area(&b) < min_area {
                continue;
            }
            let w = min_width_of(&a).0 + min_width_of(&b).0;
            if best.as_ref().is_none_or(|(bw, _)| w < bw - 1e-9) {
                best = Some((w, (i, j, hit)));
            }
        }
    }
    best.map(|(_, c)| c).or_else(|| naive_cut(ring, i))
}

/// Merges neighbouring pieces with the same width direction while their union is one
/// polygon, monotone along that direction.
fn merge_monotone(mut pieces: Vec<Polygon>) -> Vec<Polygon> {
    use geo::BoundingRect;
    let direction = |p: &Polygon| min_width_of(&p.exterior().0).1;
    let touch = |a: &Polygon, b: &Polygon| match (a.bounding_rect(), b.bounding_rect()) {
        (Some(x), Some(y)) => x.min().x <= y.max().x + 1e-6 && y.min().x <= x.max().x + 1e-6 && x.min().y <= y.max().y + 1e-6 && y.min().y <= x.max().y + 1e-6,
        _ => false,
    };
    let mut restart_at = 0;
    'again: loop {
        let first = restart_at;
        for i in first..pieces.len() {
            for j in i + 1..pieces.len() {
                if !touch(&pieces[i], &pieces[j]) {
                    continue;
                }
                let (di, dj) = (direction(&pieces[i]), direction(&pieces[j]));
                if crate::geom::axial_difference(di, dj) >= MERGE_TOLERANCE {
                    continue;
                }
                let union = MultiPolygon(vec![pieces[i].clone()]).union(&MultiPolygon(vec![pieces[j].clone()]));
                let [merged] = union.0.as_slice() else { continue };
                let ring = open_ring(merged.exterior());
                let larger = if pieces[i].unsigned_area() >= pieces[j].unsigned_area() { di } else { dj };
                if merged.interiors().is_empty() && is_monotone(&ring, larger) {
                    pieces[i] = Polygon::new(closed(&super::polygon::clean(ring)), vec![]);
                    pieces.remove(j);
                    // earlier pieces are not retried against the union: a missed merge costs length, never coverage
                    restart_at = i;
                    continue 'again;
                }
            }
        }
        return pieces;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::polygon::reflex_vertices;

    #[test]
    fn an_l_is_cut_into_the_two_slabs_of_least_width() {
        // a long bar with a short stub: the best cut separates the stub along the bar
        let pts = [(0., 0.), (100., 0.), (100., 10.), (10., 10.), (10., 30.), (0., 30.)];
        let ring: Vec<Coord> = pts.iter().map(|&(x, y)| Coord { x, y }).collect();
        let pieces = convex_pieces(ring, |r, i| min_width_sum_cut(r, i, 1.0));
        assert_eq!(pieces.len(), 2);
        assert!(pieces.iter().all(|p| reflex_vertices(p).is_empty()));
        let widths: f64 = pieces.iter().map(|p| min_width_of(p).0).sum();
        assert!((widths - 20.0).abs() < 1e-9, "{widths}");
    }

    #[test]
    fn merge_joins_aligned_neighbours_only_when_monotone() {
        let sq = |x0: f64, y0: f64, w: f64, h: f64| {
            Polygon::new(closed(&[Coord { x: x0, y: y0 }, Coord { x: x0 + w, y: y0 }, Coord { x: x0 + w, y: y0 + h }, Coord { x: x0, y: y0 + h }]), vec![])
        };
        // two 100 × 10 slabs side by side along x merge into one 200 × 10 slab
        assert_eq!(merge_monotone(vec![sq(0., 0., 100., 10.), sq(100., 0., 100., 10.)]).len(), 1);
        // slabs with different directions stay apart
        assert_eq!(merge_monotone(vec![sq(0., 0., 100., 10.), sq(100., 0., 10., 100.)]).len(), 2);
    }
}
