//! The ground a camera's photos image.

use geo::{Coord, LineString, Polygon};

use crate::camera::photo_offsets_through_bends;
use crate::geom::polyline_length;
use crate::path::{FlightPath, Look, PieceKind};
use crate::sweep::Footprint;

/// A photo: where it is taken, the direction of flight (math radians), and on an oblique
/// plan's pass, where the camera looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Photo {
    pub at: Coord,
    pub heading: f64,
    pub look: Option<Look>,
}

/// Photo positions on every sweep of `path` (docs/methods.md, camera §6, fitted mode), with the
/// line's direction; through a bend between two sweeps, one photo at the bend
/// ([`photo_offsets_through_bends`]). A sweep of no length (a grid of one cell) is one photo,
/// facing `still_heading`, or none without it. A sweep of an oblique plan's pass spaces its
/// photos for what that pass's camera images.
pub fn photo_positions(path: &FlightPath, footprint: &Footprint, still_heading: Option<f64>) -> Vec<Photo> {
    let mut out = Vec::new();
    for (k, p) in path.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep) {
        let (a, b) = (p.start(), p.end());
        let len = polyline_length(&p.points);
        let look = p.look;
        if len == 0.0 {
            out.extend(still_heading.map(|heading| Photo { at: a, heading, look }));
            continue;
        }
        let heading = (b.y - a.y).atan2(b.x - a.x);
        let (along, spacing) = look.map_or((footprint.along_m, footprint.photo_spacing_m), |l| (l.along_m, l.photo_spacing_m));
        let offsets = photo_offsets_through_bends(len, along, spacing, path.bends_into(k), path.bends_into(k + 1));
        out.extend(offsets.into_iter().map(|t| Photo { at: a + (b - a) * (t / len), heading, look }));
    }
    out
}

/// The ground the photos of each pass of an oblique plan surely image, as strips, pass by
/// pass (1 to 5); photos outside a pass are left out.
pub fn pass_strips(photos: &[Photo], pass: usize) -> Vec<Polygon> {
    let on_pass: Vec<Photo> =
        photos.iter().filter(|p| p.look.is_some_and(|l| l.pass == pass)).map(|p| Photo { at: p.at + p.look.map_or(Coord { x: 0.0, y: 0.0 }, |l| l.centre_offset), ..*p }).collect();
    let Some(look) = on_pass.first().and_then(|p| p.look) else { return Vec::new() };
    photo_strips(&on_pass, look.across_m, look.along_m)
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

    /// A ring flown round a square field half a footprint in, entered mid-side: the photo at
    /// each corner, taken as the ring turns, images the field's corner, which photos flush with
    /// the sides' ends leave out.
    #[test]
    fn a_rings_corner_photos_image_the_fields_corners() {
        use crate::path::{FlightPath, PieceKind};
        use geo::{Contains, Point};
        let footprint = Footprint { across_m: 20.0, along_m: 20.0, photo_spacing_m: 20.0 };
        let at = |x: f64, y: f64| Coord { x, y };
        let ring_points = [at(50.0, 10.0), at(90.0, 10.0), at(90.0, 90.0), at(10.0, 90.0), at(10.0, 10.0), at(50.0, 10.0)];
        let mut ring = FlightPath::default();
        for side in ring_points.windows(2) {
            ring.push(PieceKind::Sweep, side.to_vec(), 10.0);
        }
        let photos = photo_positions(&ring, &footprint, None);
        for corner in &ring_points[1..5] {
            assert_eq!(photos.iter().filter(|p| p.at == *corner).count(), 1, "one photo at {corner:?}");
        }
        let imaged = union_of(&photo_strips(&photos, footprint.across_m, footprint.along_m));
        for (x, y) in [(1.0, 1.0), (99.0, 1.0), (99.0, 99.0), (1.0, 99.0)] {
            assert!(imaged.contains(&Point::new(x, y)), "the field's corner near ({x}, {y}) is imaged");
        }
    }

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
                photos.extend((0..count).map(|k| Photo { at: Coord { x: x + c * k as f64 * step * along, y: y + s * k as f64 * step * along }, heading, look: None }));
            }
            let one_by_one: Vec<Polygon> = photos.iter().map(|p| photo_footprint(p, p, across, along)).collect();
            let strips = photo_strips(&photos, across, along);
            prop_assert!(strips.len() <= photos.len());
            let (a, b) = (union_of(&one_by_one).unsigned_area(), union_of(&strips).unsigned_area());
            prop_assert!((a - b).abs() <= 1e-6 * a.max(1.0), "{a} m² one by one, {b} m² as strips");
        }
    }
}
