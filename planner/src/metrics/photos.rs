//! The ground a camera's photos image.

use geo::{Coord, LineString, Polygon};

/// A photo: where it is taken, and the direction of flight (math radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Photo {
    pub at: Coord,
    pub heading: f64,
}

pub fn photo_points(photos: &[Photo]) -> Vec<Coord> {
    photos.iter().map(|p| p.at).collect()
}

/// The ground the photos from `first` to `last` (taken along one line) image: `across` wide,
/// from half a footprint (`along`) behind the first to half a footprint past the last.
fn photo_footprint(first: &Photo, last: &Photo, across: f64, along: f64) -> Polygon {
    let (s, c) = first.heading.sin_cos();
    let u = Coord { x: c * along / 2.0, y: s * along / 2.0 };
    let n = Coord { x: -s * across / 2.0, y: c * across / 2.0 };
    let (a, b) = (first.at, last.at);
    Polygon::new(LineString::from(vec![a - u - n, b + u - n, b + u + n, a - u + n, a - u - n]), vec![])
}

/// True when `next` is taken on `photo`'s line, ahead of it and no further than a footprint
/// (`along`): their footprints overlap or touch along the line.
fn continues(photo: &Photo, next: &Photo, along: f64) -> bool {
    let d = next.at - photo.at;
    let (s, c) = photo.heading.sin_cos();
    let (ahead, aside) = (d.x * c + d.y * s, d.y * c - d.x * s);
    (next.heading - photo.heading).abs() < 1e-9 && (0.0..=along + 1e-6).contains(&ahead) && aside.abs() < 1e-6
}

/// The ground the photos image, in as few shapes as it takes: a run of photos along one line
/// overlap one another (the front overlap is never negative), so the run images one strip. The
/// union of thousands of overlapping footprints is the same ground, but slow to compute.
pub(super) fn photo_strips(photos: &[Photo], across: f64, along: f64) -> Vec<Polygon> {
    let mut strips = Vec::new();
    let mut first = 0;
    for i in 0..photos.len() {
        if photos.get(i + 1).is_none_or(|next| !continues(&photos[i], next, along)) {
            strips.push(photo_footprint(&photos[first], &photos[i], across, along));
            first = i + 1;
        }
    }
    strips
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::coverage::union_of;
    use geo::Area;
    use proptest::prelude::*;

    proptest! {
        /// Runs of photos along lines image the same ground as their footprints one by one.
        #[test]
        fn photo_strips_image_what_the_photos_do(
            lines in prop::collection::vec((0.0..std::f64::consts::TAU, -200.0..200.0f64, -200.0..200.0f64, 1usize..12, 0.2..1.0f64), 1..6),
            across in 5.0..60.0f64,
            along in 5.0..60.0f64,
        ) {
            let mut photos = Vec::new();
            for (heading, x, y, count, step) in lines {
                let (s, c) = heading.sin_cos();
                photos.extend((0..count).map(|k| Photo { at: Coord { x: x + c * k as f64 * step * along, y: y + s * k as f64 * step * along }, heading }));
            }
            let one_by_one: Vec<Polygon> = photos.iter().map(|p| photo_footprint(p, p, across, along)).collect();
            let strips = photo_strips(&photos, across, along);
            prop_assert!(strips.len() <= photos.len());
            let (a, b) = (union_of(&one_by_one).unsigned_area(), union_of(&strips).unsigned_area());
            prop_assert!((a - b).abs() <= 1e-6 * a.max(1.0), "{a} m² one by one, {b} m² as strips");
        }
    }
}
