//! Cutting the area into one band per drone, along the sweep lines, and sizing the bands so
//! that the drones finish together (docs/methods.md, fleets §1–§2).
//!
//! Bands are whole numbers of line spacings wide, so that neighbouring drones' lines neither
//! overlap nor leave a gap, and each band is one compact strip of a convex field: no drone
//! crosses another's part to sweep its own.

use geo::{Area, BooleanOps, BoundingRect, Coord, MultiPolygon, Rect};

use crate::sweep::{from_sweep_frame, rotate};

/// The area cut into strips one line spacing wide, across the direction `angle`.
pub struct Bands {
    angle: f64,
    /// Lowest and highest coordinate across the lines, in the sweep frame.
    low: f64,
    high: f64,
    /// Extent along the lines, in the sweep frame, a metre beyond the region on each side.
    along: (f64, f64),
    spacing: f64,
    /// Area of the region in each strip, lowest first.
    strip_areas: Vec<f64>,
}

impl Bands {
    pub fn new(region: &MultiPolygon, angle: f64, spacing: f64) -> Bands {
        let rotated = rotate(region, angle);
        let Some(bbox) = rotated.bounding_rect() else {
            return Bands { angle, low: 0.0, high: 0.0, along: (0.0, 0.0), spacing, strip_areas: Vec::new() };
        };
        let (low, high) = (bbox.min().y, bbox.max().y);
        let strips = (((high - low) / spacing) - 1e-9).ceil().max(1.0) as usize;
        let (x0, x1) = (bbox.min().x - 1.0, bbox.max().x + 1.0);
        let strip_areas = (0..strips)
            .map(|j| {
                let lo = low + j as f64 * spacing;
                let band = Rect::new(Coord { x: x0, y: lo }, Coord { x: x1, y: lo + spacing });
                rotated.intersection(&band.to_polygon()).unsigned_area()
            })
            .collect();
        Bands { angle, low, high, along: (x0, x1), spacing, strip_areas }
    }

    /// Number of strips.
    pub fn len(&self) -> usize {
        self.strip_areas.len()
    }

    /// Area of strips `from..to`.
    pub fn area(&self, from: usize, to: usize) -> f64 {
        self.strip_areas[from..to].iter().sum()
    }

    /// Where to cut for parts of about `areas` (in order): `areas.len() + 1` strip indices from 0
    /// to [`Bands::len`], each cut at the strip boundary nearest its cumulative target. A part
    /// may be empty (zero strips) when its target is under half a strip.
    pub fn cuts(&self, areas: &[f64]) -> Vec<usize> {
        let total: f64 = areas.iter().sum();
        let scale = if total > 0.0 { self.area(0, self.len()) / total } else { 0.0 };
        let mut cumulative = Vec::with_capacity(self.len() + 1);
        cumulative.push(0.0);
        for a in &self.strip_areas {
            cumulative.push(cumulative.last().copied().unwrap_or(0.0) + a);
        }
        let mut cuts = vec![0];
        let mut target = 0.0;
        for a in &areas[..areas.len().saturating_sub(1)] {
            target += a * scale;
            let from = *cuts.last().expect("first cut");
            // the boundary at or after the last cut whose cumulative area is nearest the target
            let best = (from..=self.len()).min_by(|&i, &j| (cumulative[i] - target).abs().total_cmp(&(cumulative[j] - target).abs())).unwrap_or(from);
            cuts.push(best);
        }
        cuts.push(self.len());
        cuts
    }

    /// The part of `region` in strips `from..to` (the outer strips reach past the region's edge).
    pub fn part(&self, region: &MultiPolygon, from: usize, to: usize) -> MultiPolygon {
        if from >= to {
            return MultiPolygon(Vec::new());
        }
        let margin = self.spacing + (self.high - self.low);
        let lo = if from == 0 { self.low - margin } else { self.low + from as f64 * self.spacing };
        let hi = if to == self.len() { self.high + margin } else { self.low + to as f64 * self.spacing };
        let (x0, x1) = self.along;
        let corners = [(x0, lo), (x1, lo), (x1, hi), (x0, hi), (x0, lo)].map(|(u, v)| from_sweep_frame(self.angle, u, v));
        let band = geo::Polygon::new(geo::LineString::from(corners.to_vec()), Vec::new());
        region.intersection(&band)
    }

    /// Where `c` lies across the lines, as a strip position (for ordering drones by their homes).
    pub fn across(&self, c: Coord) -> f64 {
        (crate::sweep::to_sweep_frame(self.angle, c).y - self.low) / self.spacing
    }
}

/// The areas that make every drone finish at the same time `T`, each drone's duration modelled
/// as `fixed[k] + rate[k] × area` (seconds, seconds per m²): `area[k] = (T − fixed[k]) / rate[k]`,
/// with `T` such that the areas add up to `total`. A drone whose fixed time alone exceeds `T`
/// gets nothing. Rates must be positive.
pub fn equal_finish(fixed: &[f64], rate: &[f64], total: f64) -> Vec<f64> {
    let areas = |t: f64| -> Vec<f64> { fixed.iter().zip(rate).map(|(c, r)| ((t - c) / r).max(0.0)).collect() };
    let covered = |t: f64| areas(t).iter().sum::<f64>();
    let mut lo = fixed.iter().copied().fold(f64::INFINITY, f64::min);
    let mut hi = lo + total * rate.iter().copied().fold(0.0, f64::max) + 1.0;
    while covered(hi) < total {
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = (lo + hi) / 2.0;
        if covered(mid) < total { lo = mid } else { hi = mid }
    }
    areas(hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    fn square(side: f64) -> MultiPolygon {
        MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: side, y: 0.0), (x: side, y: side), (x: 0.0, y: side)]])
    }

    #[test]
    fn parts_tile_the_region_at_whole_strips() {
        let region = square(100.0);
        let bands = Bands::new(&region, 0.3, 10.0);
        let cuts = bands.cuts(&[1.0, 2.0, 1.0]);
        assert_eq!(cuts.first(), Some(&0));
        assert_eq!(cuts.last(), Some(&bands.len()));
        let parts: Vec<MultiPolygon> = cuts.windows(2).map(|w| bands.part(&region, w[0], w[1])).collect();
        let total: f64 = parts.iter().map(|p| p.unsigned_area()).sum();
        assert!((total - 10_000.0).abs() < 1e-3, "{total}");
        // the middle part gets about half the area
        assert!((parts[1].unsigned_area() / 10_000.0 - 0.5).abs() < 0.1);
        // parts do not overlap
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                assert!(parts[i].intersection(&parts[j]).unsigned_area() < 1e-3);
            }
        }
    }

    #[test]
    fn equal_finish_balances_fixed_times() {
        let areas = equal_finish(&[0.0, 100.0], &[1.0, 1.0], 1000.0);
        assert!((areas[0] - 550.0).abs() < 1e-6 && (areas[1] - 450.0).abs() < 1e-6, "{areas:?}");
        // a drone too far away to help gets nothing
        let areas = equal_finish(&[0.0, 5000.0], &[1.0, 1.0], 1000.0);
        assert!(areas[1] == 0.0 && (areas[0] - 1000.0).abs() < 1e-6);
    }
}
