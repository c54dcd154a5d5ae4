//! Headlands (docs/methods.md, ground §1): a ground vehicle works a band along the field's
//! edge and around every hole in passes that follow the boundary, and fills the mainland
//! inside the band with straight swaths, turning at their ends in the band.
//!
//! The mainland is the area inset by the headland width. Pass `k` of `n` runs at
//! `width · (k + ½) / n` from the boundary, on a ring whose corners are rounded to the turning
//! radius (so that the vehicle can follow it): each boundary of the inset area opened and
//! closed by the radius, three buffers.

use geo::{Area, BooleanOps, Buffer, Contains, Coord, LineString, MultiPolygon, Polygon, SimplifyVwPreserve};
use rayon::prelude::*;

use crate::geom::EdgeIndex;

/// Steps by which a pond too small to round is grown, up to the turning radius, until a
/// rounded ring fits round it.
const POND_STEPS: usize = 8;
/// Parts of inset areas smaller than this are slivers, not room to work.
const SLIVER_M2: f64 = 1.0;
/// A piece the rounding cuts off a pass's ring larger than this many squared turning radii is
/// a strip too narrow to round, not a corner (a right angle's is 0.21, a 30° tip's 2.4).
const NECK_R2: f64 = 4.0;
/// Vertices that bend a boundary by less than this (the triangle with their neighbours) are
/// dropped before a ring is grown back: centimetres that no vehicle follows, which made `geo`'s
/// buffer ten times slower on some rings (10 ms against 0.6 ms for a 229-point ring).
const DETAIL_M2: f64 = 0.025;

#[derive(Debug, Clone)]
pub struct Headland {
    /// What the swaths cover: the area inset by the headland width.
    pub mainland: MultiPolygon,
    /// The passes, outermost first: each a set of closed rings (first point repeated last),
    /// one per boundary that still has room at that offset.
    pub passes: Vec<Vec<Vec<Coord>>>,
    /// The band the passes cover: the area less the mainland.
    pub band: MultiPolygon,
}

/// The headland of `region` (the field less its holes and zones): `passes` passes spread over
/// `width_m`, rings rounded to `turn_radius_m`.
pub fn headland(region: &MultiPolygon, width_m: f64, passes: usize, turn_radius_m: f64) -> Headland {
    let index = EdgeIndex::new(region);
    let mainland_and_band = || {
        let mainland = without_slivers(inset(region, width_m));
        let band = if mainland.0.is_empty() { region.clone() } else { region.difference(&mainland) };
        (mainland, band)
    };
    // each pass and each of its rings on its own: the buffers are most of a plan's set-up
    let rings_of_passes = || {
        (0..passes)
            .into_par_iter()
            .map(|k| {
                let offset = width_m * (k as f64 + 0.5) / passes as f64;
                let at_offset = without_slivers(inset(region, offset));
                let edges = at_offset.iter().map(|p| (p.exterior(), false));
                let holes = at_offset.iter().flat_map(|p| p.interiors().iter().map(|ring| (ring, true)));
                let rings: Vec<(&LineString, bool)> = edges.chain(holes).collect();
                rings.into_par_iter().flat_map_iter(|(ring, around_hole)| drivable(ring, around_hole, region, &index, turn_radius_m, offset)).collect()
            })
            .collect()
    };
    let ((mainland, band), passes) = rayon::join(mainland_and_band, rings_of_passes);
    Headland { mainland, passes, band }
}

/// The rings a vehicle turning no tighter than `r` drives along `ring` (a boundary of the area
/// inset by `offset`): the ring's shape opened and closed by `r` (convex corners rounded
/// inwards, concave ones outwards), each ring on its own so that a narrow neck between a hole
/// and the edge does not merge their passes. A hole too small to round is driven round by the
/// closest rounded ring clear of it (at most `r` from it); a strip too narrow to round, or a
/// rounded ring that would leave `region`, is driven as it is, corners and all.
fn drivable(ring: &LineString, around_hole: bool, region: &MultiPolygon, edges: &EdgeIndex, r: f64, offset: f64) -> Vec<Vec<Coord>> {
    let shape = MultiPolygon(vec![Polygon::new(ring.clone(), vec![])]);
    let round = |shape: &MultiPolygon| without_slivers(inset(&inset(shape, r).simplify_vw_preserve(DETAIL_M2).buffer(2.0 * r), r));
    let mut rounded = round(&shape);
    if rounded.0.is_empty() && around_hole {
        // a pond too small to round at this offset is driven round as close as a ring rounded
        // on the turning radius keeps clear of it: the pond grown a little further each time,
        // at most to the radius (where one circle of it fits round any pond)
        let clear = |ring: &MultiPolygon| ring.iter().all(|p| !edges.crossed(&p.exterior().0));
        let further = (r - offset).max(0.0);
        rounded = (1..=POND_STEPS)
            .map(|k| shape.buffer(further * k as f64 / POND_STEPS as f64))
            .map(|grown| round(&grown))
            .find(|ring| !ring.0.is_empty() && clear(ring))
            .unwrap_or_else(|| shape.buffer(further));
    } else if rounded.0.is_empty() {
        // a strip narrower than the turning circle (between the edge and a pond's passes) is
        // driven round as it is: it is left unworked otherwise
        rounded = shape;
    } else {
        // so is such a strip where it joins a wider part, which the rounding cuts off (a pass
        // between ponds close to the edge: a quarter of a small field's headland was left)
        let necks = shape.difference(&rounded).0.into_iter().filter(|p| p.unsigned_area() >= NECK_R2 * r * r);
        rounded.0.extend(necks);
    }
    let rings: Vec<Vec<Coord>> = rounded.iter().map(|p| p.exterior().0.clone()).filter(|ring| ring.len() >= 4).collect();
    // inside the area: its first point is, and it crosses none of the area's edges
    let inside = rings.iter().all(|ring| !edges.crossed(ring) && region.contains(&ring[0]));
    if inside { rings } else { vec![ring.0.clone()] }
}

/// The area shrunk by `d` (empty when nothing is left).
fn inset(area: &MultiPolygon, d: f64) -> MultiPolygon {
    if area.0.is_empty() {
        return area.clone();
    }
    area.buffer(-d)
}

fn without_slivers(area: MultiPolygon) -> MultiPolygon {
    MultiPolygon(area.0.into_iter().filter(|p| p.unsigned_area() >= SLIVER_M2).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polyline_length;
    use geo::{Contains, LineString, Polygon, polygon};

    #[test]
    fn a_square_with_a_pond_gets_passes_round_both_and_a_mainland_inside() {
        let pond = LineString::from(vec![(40.0, 40.0), (60.0, 40.0), (60.0, 60.0), (40.0, 60.0), (40.0, 40.0)]);
        let field = Polygon::new(LineString::from(vec![(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0), (0.0, 0.0)]), vec![pond]);
        let h = headland(&MultiPolygon(vec![field.clone()]), 12.0, 2, 7.0);
        // mainland: the square inset by 12 less the pond grown by 12 (rounded corners)
        let expected = 76.0 * 76.0 - (44.0 * 44.0 - (4.0 - std::f64::consts::PI) * 144.0);
        assert!((h.mainland.unsigned_area() - expected).abs() < 5.0, "{}", h.mainland.unsigned_area());
        assert_eq!(h.passes.len(), 2);
        for rings in &h.passes {
            assert_eq!(rings.len(), 2, "one ring round the edge, one round the pond");
            for ring in rings {
                assert!(ring.iter().all(|&p| field.contains(&p)));
            }
        }
        // the outer pass runs 3 m in, its corners rounded on 7 m: 4 × 94 less 4 × (2 − π/2) × 7
        let outer = h.passes[0].iter().map(|r| polyline_length(r)).fold(0.0, f64::max);
        assert!((outer - (4.0 * 94.0 - 4.0 * (2.0 - std::f64::consts::FRAC_PI_2) * 7.0)).abs() < 1.0, "{outer}");
        assert!((h.band.unsigned_area() + h.mainland.unsigned_area() - field.unsigned_area()).abs() < 1.0);
        let narrow = polygon![(x: 0.0, y: 0.0), (x: 100.0, y: 0.0), (x: 100.0, y: 20.0), (x: 0.0, y: 20.0)];
        assert!(headland(&MultiPolygon(vec![narrow]), 12.0, 2, 7.0).mainland.0.is_empty());
    }

    #[test]
    fn a_strip_too_narrow_to_round_between_wider_parts_is_driven_as_it_is() {
        // two 60 m squares joined by a 10 m wide, 40 m long strip; one 4 m pass turning on 7 m
        let field = polygon![
            (x: 0.0, y: 0.0), (x: 60.0, y: 0.0), (x: 60.0, y: 25.0), (x: 100.0, y: 25.0), (x: 100.0, y: 0.0), (x: 160.0, y: 0.0),
            (x: 160.0, y: 60.0), (x: 100.0, y: 60.0), (x: 100.0, y: 35.0), (x: 60.0, y: 35.0), (x: 60.0, y: 60.0), (x: 0.0, y: 60.0)
        ];
        let h = headland(&MultiPolygon(vec![field.clone()]), 4.0, 1, 7.0);
        // a ring along the strip: from one square to the other, within the strip's 10 m
        let along_strip = |ring: &Vec<Coord>| {
            let (lo, hi) = ring.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.x), hi.max(p.x)));
            lo < 65.0 && hi > 95.0 && ring.iter().all(|p| p.y > 25.0 && p.y < 35.0)
        };
        let rings = &h.passes[0];
        assert!(rings.iter().any(along_strip), "no pass works the strip: {rings:?}");
        // the squares' rounded rings stay, and every ring lies in the field
        assert_eq!(rings.iter().filter(|ring| !along_strip(ring)).count(), 2, "{rings:?}");
        assert!(rings.iter().flatten().all(|&p| geo::Intersects::intersects(&field, &p)), "a ring leaves the field");
    }
}
