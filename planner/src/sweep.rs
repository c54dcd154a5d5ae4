//! Sweep stage: parallel lines across a region, clipped to it and prolonged so that each
//! line's whole swath reaches the boundary (docs/methods.md, decomposition §10.1, docs/methods.md, camera §5);
//! [`ends`] ends them sooner at slanted edges when asked.

pub mod ends;
pub mod offset;

use geo::{BooleanOps, BoundingRect, ConvexHull, Coord, MultiPolygon, Rect};

// Spacing and band edges are in the sweep frame: u along the lines, v across them.

/// One coverage segment in the sweep frame: the line `v = offset`, flown from `u = a` to `u = b`,
/// imaging the band `lo ≤ v ≤ hi` between those ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepSegment {
    pub line: usize,
    pub offset: f64,
    pub a: f64,
    pub b: f64,
    pub lo: f64,
    pub hi: f64,
}

/// The ground one photo images, and the largest step between photos along a line (from the
/// camera's figures and the front overlap).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    pub across_m: f64,
    pub along_m: f64,
    pub photo_spacing_m: f64,
}

/// How lines are laid across a width (docs/methods.md, camera §4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineLayout {
    /// Largest distance between neighbouring lines.
    pub spacing: f64,
    /// A camera's footprint. `Some`: as few lines as cover the width with the outer
    /// footprints flush with its edges, spacing re-fitted (layout `footprint`). `None`: lines
    /// `spacing` apart, centred on the width (layout `centered`).
    pub footprint: Option<Footprint>,
    /// Where lines end at a slanted edge of the area ([`ends::end_lines`]; the sweep itself
    /// always runs them full width).
    pub ends: ends::SwathEnds,
    /// `Some(p)`: lines at offsets `p + k · spacing` only (a guidance line's own, whole
    /// spacings from it), as many as cover the width; without a footprint.
    pub phase: Option<f64>,
}

impl LineLayout {
    pub fn centered(spacing: f64) -> Self {
        Self { spacing, footprint: None, ends: ends::SwathEnds::FullWidth, phase: None }
    }

    /// Number of lines across width `d`.
    pub fn count(&self, d: f64) -> usize {
        match self.footprint.map(|f| f.across_m) {
            None => line_count(d, self.spacing),
            Some(f) => (((d - (f - self.spacing)) / self.spacing) - WIDTH_TOLERANCE).ceil().max(1.0) as usize,
        }
    }

    /// Each line across `[lo, hi]`: its offset and the band it images, `(offset, lo, hi)`.
    pub fn lines(&self, lo: f64, hi: f64) -> Vec<(f64, f64, f64)> {
        if let (Some(phase), None) = (self.phase, self.footprint) {
            return phased_lines(lo, hi, self.spacing, phase);
        }
        let n = self.count(hi - lo);
        if n == 1 {
            let mid = (lo + hi) / 2.0;
            let half = self.spacing.max(hi - lo) / 2.0;
            return vec![(mid, mid - half, mid + half)];
        }
        let (first, step) = match self.footprint.map(|f| f.across_m) {
            None => (lo + ((hi - lo) - (n - 1) as f64 * self.spacing) / 2.0, self.spacing),
            Some(f) => (lo + f / 2.0, ((hi - lo) - f) / (n - 1) as f64),
        };
        (0..n)
            .map(|j| {
                let o = first + j as f64 * step;
                let band_lo = if j == 0 { lo.min(o - step / 2.0) } else { o - step / 2.0 };
                let band_hi = if j == n - 1 { hi.max(o + step / 2.0) } else { o + step / 2.0 };
                (o, band_lo, band_hi)
            })
            .collect()
    }

    /// A camera plan's footprint (lines laid by it): its coverage is what the photos image
    /// ([`crate::metrics::covered`]), not the swath the vehicle sweeps.
    pub fn photographed(&self) -> Option<Footprint> {
        self.footprint
    }

    /// Half the width a sweep images, for the coverage measure.
    pub fn half_swath(&self) -> f64 {
        self.footprint.map_or(self.spacing, |f| f.across_m) / 2.0
    }
}

/// Lines at `angle` (math radians, counter-clockwise from east).
#[derive(Debug, Clone)]
pub struct SweepPattern {
    pub angle: f64,
    /// Segments of each line, sorted by `a`.
    pub lines: Vec<Vec<SweepSegment>>,
    /// Short extra segments over what the lines leave uncovered beside no-fly zones.
    pub gap_fills: Vec<SweepSegment>,
}

impl SweepPattern {
    /// Segments to fly, gap fills included.
    pub fn segment_count(&self) -> usize {
        self.lines.iter().map(Vec::len).sum::<usize>() + self.gap_fills.len()
    }
}

/// Lines at `phase + k · spacing` whose bands (a spacing wide, centred on them) cover
/// `[lo, hi]`: the first band holds `lo`, the last `hi`.
fn phased_lines(lo: f64, hi: f64, spacing: f64, phase: f64) -> Vec<(f64, f64, f64)> {
    let first = ((lo - phase) / spacing + 0.5).floor() as i64;
    let last = (((hi - phase) / spacing - 0.5).ceil() as i64).max(first);
    (first..=last)
        .map(|k| {
            let o = phase + k as f64 * spacing;
            (o, o - spacing / 2.0, o + spacing / 2.0)
        })
        .collect()
}

/// Local coordinates of the point `(u, v)` of the sweep frame at `angle`.
pub fn from_sweep_frame(angle: f64, u: f64, v: f64) -> Coord {
    let (s, c) = angle.sin_cos();
    Coord { x: u * c - v * s, y: u * s + v * c }
}

/// Rotates local coordinates into the sweep frame (lines become horizontal).
pub fn to_sweep_frame(angle: f64, c: Coord) -> Coord {
    let (s, co) = angle.sin_cos();
    Coord { x: c.x * co + c.y * s, y: -c.x * s + c.y * co }
}

pub fn rotate(mp: &MultiPolygon, angle: f64) -> MultiPolygon {
    use geo::MapCoords;
    mp.map_coords(|c| to_sweep_frame(angle, c))
}

/// Extent of the points across lines of direction `angle` (the width function).
pub fn width_across(points: &[Coord], angle: f64) -> f64 {
    let (s, c) = angle.sin_cos();
    let (lo, hi) = points.iter().map(|p| -p.x * s + p.y * c).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    hi - lo
}

/// Share of a spacing by which a width may exceed a whole number of spacings and still take
/// that many lines: widths measured after clipping (a fleet's bands, whole spacings wide) carry
/// rounding of about 1e-8 of a spacing.
const WIDTH_TOLERANCE: f64 = 1e-6;

/// Number of lines of spacing `s` needed to span width `w`.
pub fn line_count(w: f64, s: f64) -> usize {
    ((w / s) - WIDTH_TOLERANCE).ceil().max(1.0) as usize
}

/// Directions of the hull's edges (mod π) and a 1° grid: where the width function's minima
/// and the line counts' steps lie.
pub fn candidate_directions(hull: &[Coord]) -> Vec<f64> {
    let mut candidates: Vec<f64> = hull.windows(2).map(|w| (w[1].y - w[0].y).atan2(w[1].x - w[0].x).rem_euclid(std::f64::consts::PI)).collect();
    candidates.extend((0..180).map(|d| (d as f64).to_radians()));
    candidates
}

/// The direction that needs the fewest lines; ties go to the smaller width, then the smaller
/// angle.
pub fn fewest_lines_direction(region: &MultiPolygon, layout: LineLayout) -> f64 {
    fewest_lines_directions(region, layout, 1).first().copied().unwrap_or(0.0)
}

/// Up to `most` directions with the fewest lines, fewest first (ties: the smaller width, then
/// the smaller angle), each at least [`DISTINCT_DIRECTIONS_DEG`] from those before it.
pub fn fewest_lines_directions(region: &MultiPolygon, layout: LineLayout, most: usize) -> Vec<f64> {
    let hull: Vec<Coord> = region.convex_hull().exterior().0.clone();
    let key = |a: f64| {
        let w = width_across(&hull, a);
        (layout.count(w), w)
    };
    let mut ranked: Vec<((usize, f64), f64)> = candidate_directions(&hull).into_iter().map(|a| (key(a), a)).collect();
    ranked.sort_by(|(ka, aa), (kb, ab)| ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then(aa.total_cmp(ab)));
    let apart = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(std::f64::consts::PI);
        d.min(std::f64::consts::PI - d) >= DISTINCT_DIRECTIONS_DEG.to_radians()
    };
    let mut chosen: Vec<f64> = Vec::new();
    for (_, a) in ranked {
        if chosen.len() == most {
            break;
        }
        if chosen.iter().all(|&c| apart(a, c)) {
            chosen.push(a);
        }
    }
    chosen
}

/// Directions closer than this sweep nearly the same lines.
pub const DISTINCT_DIRECTIONS_DEG: f64 = 3.0;

/// Lines across `region`, each segment covering the connected part of the region within its
/// band, minus the parts of the centre line inside `keep_out`.
pub fn sweep(region: &MultiPolygon, keep_out: &MultiPolygon, angle: f64, layout: LineLayout) -> SweepPattern {
    let rotated = rotate(region, angle);
    let keep_out = rotate(keep_out, angle);
    let Some(bbox) = rotated.bounding_rect() else {
        return SweepPattern { angle, lines: Vec::new(), gap_fills: Vec::new() };
    };
    let (x0, x1) = (bbox.min().x - 1.0, bbox.max().x + 1.0);
    let layout_lines = layout.lines(bbox.min().y, bbox.max().y);
    let n = layout_lines.len();
    // the region's pieces in each band, from one intersection per parity of band: bands of one
    // parity lie a band's width apart, so no piece spans two (one intersection per band cost
    // 45 overlays of the whole region for 45 lines)
    let mut extents: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
    for parity in 0..2 {
        let group: Vec<usize> = (parity..n).step_by(2).collect();
        let bands = MultiPolygon(group.iter().map(|&i| Rect::new(Coord { x: x0, y: layout_lines[i].1 }, Coord { x: x1, y: layout_lines[i].2 }).to_polygon()).collect());
        for r in rotated.intersection(&bands).iter().filter_map(|p| p.bounding_rect()) {
            let middle = (r.min().y + r.max().y) / 2.0;
            let at = group.partition_point(|&i| layout_lines[i].2 < middle).min(group.len() - 1);
            extents[group[at]].push((r.min().x, r.max().x));
        }
    }
    let lines = layout_lines
        .into_iter()
        .zip(extents)
        .enumerate()
        .map(|(i, ((offset, lo, hi), extents))| segments_on(SweepSegment { line: i, offset, a: 0.0, b: 0.0, lo, hi }, extents, &keep_out))
        .collect::<Vec<_>>();
    let gap_fills = if keep_out.0.is_empty() { Vec::new() } else { gap_fills(&rotated, &keep_out, &lines, layout.spacing, n) };
    SweepPattern { angle, lines, gap_fills }
}

/// The parts of the line of `line` spanning `extents`, minus what lies in `keep_out`.
fn segments_on(line: SweepSegment, mut extents: Vec<(f64, f64)>, keep_out: &MultiPolygon) -> Vec<SweepSegment> {
    extents.sort_by(|a, b| a.0.total_cmp(&b.0));
    let blocked = scanline_intervals(keep_out, line.offset);
    let mut segs = Vec::new();
    for (a, b) in merge_overlapping(extents) {
        for (a, b) in subtract_intervals((a, b), &blocked) {
            if b - a > 0.05 {
                segs.push(SweepSegment { a, b, ..line });
            }
        }
    }
    segs
}

/// Where a no-fly zone cuts a line, the part of its band beside the zone is left uncovered;
/// each such piece (1 m² or more) gets short lines of its own, centred on it.
fn gap_fills(rotated: &MultiPolygon, keep_out: &MultiPolygon, lines: &[Vec<SweepSegment>], spacing: f64, first_index: usize) -> Vec<SweepSegment> {
    use geo::{Area, Polygon};
    let half = spacing / 2.0;
    let strips: Vec<Polygon> = lines.iter().flatten().map(|s| Rect::new(Coord { x: s.a, y: s.lo }, Coord { x: s.b, y: s.hi }).to_polygon()).collect();
    let covered = geo::unary_union(&strips);
    let uncovered = rotated.difference(&covered);
    let mut out = Vec::new();
    for piece in uncovered.iter().filter(|p| p.unsigned_area() >= 1.0) {
        let Some(bb) = piece.bounding_rect() else { continue };
        let k = line_count(bb.height(), spacing);
        let step = bb.height() / k as f64;
        for j in 0..k {
            let offset = bb.min().y + step * (j as f64 + 0.5);
            let band = Rect::new(Coord { x: bb.min().x - 1.0, y: offset - half }, Coord { x: bb.max().x + 1.0, y: offset + half });
            let extents = piece.intersection(&band.to_polygon()).iter().filter_map(|p| p.bounding_rect()).map(|r| (r.min().x, r.max().x)).collect();
            let line = SweepSegment { line: first_index + out.len(), offset, a: 0.0, b: 0.0, lo: offset - half, hi: offset + half };
            out.extend(segments_on(line, extents, keep_out));
        }
    }
    out
}

pub fn merge_overlapping(sorted: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (a, b) in sorted {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// Intervals of the horizontal line `y` inside the polygons (even-odd over all rings; a
/// vertex exactly on the line counts as above it).
pub fn scanline_intervals(mp: &MultiPolygon, y: f64) -> Vec<(f64, f64)> {
    let mut xs: Vec<f64> = Vec::new();
    for poly in mp {
        for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
            for l in ring.lines() {
                let (p, q) = (l.start, l.end);
                if (p.y > y) != (q.y > y) {
                    xs.push(p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y));
                }
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    xs.chunks_exact(2).map(|c| (c[0], c[1])).collect()
}

/// [`scanline_intervals`] at each of `ys`, sweeping the edges once from the lowest line up:
/// each line meets only the edges active at its height.
pub fn scanlines_intervals(mp: &MultiPolygon, ys: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut edges: Vec<(Coord, Coord)> = mp
        .iter()
        .flat_map(|poly| std::iter::once(poly.exterior()).chain(poly.interiors()))
        .flat_map(|ring| ring.lines().map(|l| if l.start.y <= l.end.y { (l.start, l.end) } else { (l.end, l.start) }))
        .filter(|(p, q)| p.y < q.y)
        .collect();
    edges.sort_by(|a, b| a.0.y.total_cmp(&b.0.y));
    let mut order: Vec<usize> = (0..ys.len()).collect();
    order.sort_by(|&i, &j| ys[i].total_cmp(&ys[j]));
    let mut out = vec![Vec::new(); ys.len()];
    let mut next = 0;
    let mut active: Vec<(Coord, Coord)> = Vec::new();
    for i in order {
        let y = ys[i];
        while next < edges.len() && edges[next].0.y <= y {
            active.push(edges[next]);
            next += 1;
        }
        active.retain(|(_, q)| q.y > y);
        let mut xs: Vec<f64> = active.iter().map(|(p, q)| p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y)).collect();
        xs.sort_by(f64::total_cmp);
        out[i] = xs.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    }
    out
}

/// `[a, b]` minus the sorted, disjoint `blocked` intervals.
pub fn subtract_intervals((a, b): (f64, f64), blocked: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start = a;
    for &(ba, bb) in blocked {
        if bb <= start || ba >= b {
            continue;
        }
        if ba > start {
            out.push((start, ba));
        }
        start = start.max(bb);
    }
    if start < b {
        out.push((start, b));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{LineString, Polygon, polygon};
    use proptest::prelude::*;

    proptest! {
        /// Phased lines lie at whole spacings from the phase, a spacing apart, and their bands
        /// cover the width with less than a spacing to spare at each side.
        #[test]
        fn phased_lines_are_whole_spacings_from_the_phase_and_cover_the_width(
            lo in -500.0..500.0f64,
            width in 0.0..300.0f64,
            spacing in 1.0..40.0f64,
            phase in -1e4..1e4f64,
        ) {
            let hi = lo + width;
            let lines = LineLayout { phase: Some(phase), ..LineLayout::centered(spacing) }.lines(lo, hi);
            prop_assert!(!lines.is_empty());
            for &(o, band_lo, band_hi) in &lines {
                let k = (o - phase) / spacing;
                prop_assert!((k - k.round()).abs() * spacing < 1e-6);
                prop_assert!((band_hi - band_lo - spacing).abs() < 1e-9 && (o - (band_lo + band_hi) / 2.0).abs() < 1e-9);
            }
            for w in lines.windows(2) {
                prop_assert!((w[1].0 - w[0].0 - spacing).abs() < 1e-6);
            }
            let (first, last) = (lines[0], lines[lines.len() - 1]);
            prop_assert!(first.1 <= lo + 1e-9 && lo < first.2 + 1e-9, "{:?} for {}", first, lo);
            prop_assert!(last.1 - 1e-9 <= hi && hi <= last.2 + 1e-9, "{:?} for {}", last, hi);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// The lines found from one intersection per parity of band are those found from one
        /// intersection per band, to a tenth of a millimetre (the overlay rounds each input to
        /// its own grid): star-shaped fields with a hole and a zone, any heading, spacing and
        /// layout.
        #[test]
        fn lines_from_two_intersections_are_those_from_one_per_band(
            radii in prop::collection::vec(40.0..200.0f64, 5..24),
            hole in (-30.0..30.0f64, -30.0..30.0f64, 3.0..15.0f64),
            zone in (-120.0..120.0f64, -120.0..120.0f64, 5.0..30.0f64),
            angle in 0.0..std::f64::consts::PI,
            spacing in 3.0..40.0f64,
            footprint in any::<bool>(),
        ) {
            let n = radii.len();
            let mut outer: Vec<Coord> = radii.iter().enumerate().map(|(k, r)| {
                let a = k as f64 * std::f64::consts::TAU / n as f64;
                Coord { x: r * a.cos(), y: r * a.sin() }
            }).collect();
            outer.push(outer[0]);
            let square = |(cx, cy, h): (f64, f64, f64)| LineString::from(vec![(cx - h, cy - h), (cx + h, cy - h), (cx + h, cy + h), (cx - h, cy + h), (cx - h, cy - h)]);
            let region = MultiPolygon(vec![Polygon::new(LineString::from(outer), vec![square(hole)])]);
            let keep_out = MultiPolygon(vec![Polygon::new(square(zone), vec![])]);
            let layout = if footprint { LineLayout { footprint: Some(Footprint { across_m: spacing * 1.4, along_m: spacing, photo_spacing_m: spacing }), ..LineLayout::centered(spacing) } } else { LineLayout::centered(spacing) };
            let pattern = sweep(&region, &keep_out, angle, layout);
            // one intersection per band, as lines were found before
            let rotated = rotate(&region, angle);
            let bbox = rotated.bounding_rect().unwrap();
            let (x0, x1) = (bbox.min().x - 1.0, bbox.max().x + 1.0);
            let rotated_out = rotate(&keep_out, angle);
            let one_by_one: Vec<Vec<SweepSegment>> = layout.lines(bbox.min().y, bbox.max().y).into_iter().enumerate().map(|(i, (offset, lo, hi))| {
                let band = Rect::new(Coord { x: x0, y: lo }, Coord { x: x1, y: hi });
                let extents = rotated.intersection(&band.to_polygon()).iter().filter_map(|p| p.bounding_rect()).map(|r| (r.min().x, r.max().x)).collect();
                segments_on(SweepSegment { line: i, offset, a: 0.0, b: 0.0, lo, hi }, extents, &rotated_out)
            }).collect();
            prop_assert_eq!(pattern.lines.len(), one_by_one.len());
            for (ours, theirs) in pattern.lines.iter().zip(&one_by_one) {
                prop_assert_eq!(ours.len(), theirs.len(), "line {:?} against {:?}", ours, theirs);
                for (s, t) in ours.iter().zip(theirs) {
                    prop_assert!((s.a - t.a).abs() < 1e-4 && (s.b - t.b).abs() < 1e-4, "{:?} against {:?}", s, t);
                }
            }
        }
    }

    fn square_with_hole() -> MultiPolygon {
        MultiPolygon(vec![polygon!(
            exterior: [(x: 0., y: 0.), (x: 100., y: 0.), (x: 100., y: 100.), (x: 0., y: 100.)],
            interiors: [[(x: 30., y: 30.), (x: 30., y: 70.), (x: 70., y: 70.), (x: 70., y: 30.)]],
        )])
    }

    #[test]
    fn scanlines_at_once_match_one_at_a_time() {
        let field = MultiPolygon(vec![geo::Polygon::new(
            geo::LineString::from(vec![(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (50.0, 20.0), (0.0, 60.0), (0.0, 0.0)]),
            vec![geo::LineString::from(vec![(20.0, 5.0), (30.0, 5.0), (30.0, 15.0), (20.0, 15.0), (20.0, 5.0)])],
        )]);
        let ys: Vec<f64> = (0..=62).rev().map(|k| k as f64 - 0.5).collect();
        let together = scanlines_intervals(&field, &ys);
        for (y, got) in ys.iter().zip(&together) {
            let one = scanline_intervals(&field, *y);
            assert_eq!(got.len(), one.len(), "at {y}");
            assert!(got.iter().zip(&one).all(|(a, b)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9), "at {y}");
        }
        assert_eq!(together[52].len(), 2);
    }

    #[test]
    fn lines_span_the_width_and_reach_the_boundary() {
        let p = sweep(&square_with_hole(), &MultiPolygon(vec![]), 0.0, LineLayout::centered(10.0));
        assert_eq!(p.lines.len(), 10);
        assert!((p.lines[0][0].offset - 5.0).abs() < 1e-9);
        assert!((p.lines[0][0].a - 0.0).abs() < 1e-6 && (p.lines[0][0].b - 100.0).abs() < 1e-6);
        // lines through the hole are split in two, others are whole
        assert_eq!(p.lines.iter().map(Vec::len).collect::<Vec<_>>(), vec![1, 1, 1, 2, 2, 2, 2, 1, 1, 1]);
    }

    #[test]
    fn keep_out_cuts_the_centre_line() {
        let ko = MultiPolygon(vec![polygon![(x: 40., y: -10.), (x: 60., y: -10.), (x: 60., y: 110.), (x: 40., y: 110.)]]);
        let p = sweep(&square_with_hole(), &ko, 0.0, LineLayout::centered(10.0));
        assert!(p.lines.iter().all(|l| l.len() == 2));
        assert!((p.lines[0][0].b - 40.0).abs() < 1e-9 && (p.lines[0][1].a - 60.0).abs() < 1e-9);
    }

    #[test]
    fn fewest_lines_follows_the_long_side() {
        let r = MultiPolygon(vec![polygon![(x: 0., y: 0.), (x: 500., y: 200.), (x: 420., y: 400.), (x: -80., y: 200.)]]);
        let a = fewest_lines_direction(&r, LineLayout::centered(20.0));
        assert!((a - (200f64).atan2(500.0)).abs() < 1e-9, "{}", a.to_degrees());
    }

    #[test]
    fn footprint_layout_refits_the_lines() {
        // docs/methods.md, camera §7 E2 and E3: line counts and re-fitted spacing across a cell
        let e2 = LineLayout { footprint: Some(Footprint { across_m: 109.44, along_m: 109.44, photo_spacing_m: 109.44 }), ..LineLayout::centered(109.44 * 0.3) };
        assert_eq!(e2.count(500.0), 13);
        let l = e2.lines(0.0, 500.0);
        assert!((l[1].0 - l[0].0 - 32.5467).abs() < 1e-4);
        assert!((l[0].0 - 109.44 / 2.0).abs() < 1e-9 && (l[12].0 - (500.0 - 109.44 / 2.0)).abs() < 1e-9);
        assert_eq!((l[0].1, l[12].2), (0.0, 500.0));
        let e3 = LineLayout { footprint: Some(Footprint { across_m: 107.99, along_m: 107.99, photo_spacing_m: 107.99 }), ..LineLayout::centered(107.99 * 0.8) };
        assert_eq!((e3.count(500.0), e3.count(450.0), e3.count(100.0)), (6, 5, 1));
        let l = e3.lines(0.0, 500.0);
        assert!((l[1].0 - l[0].0 - 78.402).abs() < 1e-3);
        // bands tile the width
        for w in l.windows(2) {
            assert!((w[0].2 - w[1].1).abs() < 1e-9);
        }
    }

    #[test]
    fn interval_subtraction() {
        assert_eq!(subtract_intervals((0.0, 10.0), &[(2.0, 3.0), (5.0, 12.0)]), vec![(0.0, 2.0), (3.0, 5.0)]);
        assert_eq!(subtract_intervals((0.0, 10.0), &[(-1.0, 11.0)]), vec![]);
    }
}
