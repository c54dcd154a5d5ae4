//! Where a swath ends at a slanted edge of the area it works (docs/methods.md, ground §4, and
//! decomposition §10.3): run on until its whole width has worked the area, stop with its centre
//! line, or stop between the two where a quarter of its width is left.

use geo::MultiPolygon;
use serde::{Deserialize, Serialize};

use super::{SweepPattern, SweepSegment, rotate, scanlines_intervals};

/// Where a line ends at a slanted edge of the area it covers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum SwathEnds {
    #[default]
    Balanced,
    FullWidth,
    CentreLine,
}

/// Lines across a swath's band that measure how much of its width the area fills.
const BAND_SAMPLES: usize = 8;
/// Past the centre line's end and `slack`, a full-width swath runs on while the area still
/// fills this many of its [`BAND_SAMPLES`] (a quarter of its width): a strip beside an edge
/// almost parallel to the swaths is worked, a slanted end's thin tip is not.
const SAMPLES_WORTH_WORKING: usize = 2;

/// How far a centre-line end runs past the area's edge, so that a turn does not start on it.
pub const CENTRE_LINE_PAST_M: f64 = 0.01;

/// Shares of its width a balanced end may leave to work beyond it, tried largest first: the
/// first whose unworked ends stay under [`BALANCED_LEFT`] of the area is kept, else full-width
/// ends. The samples measure what an end leaves exactly at a straight edge, but see nothing
/// beyond the outermost one: no share below an eighth is trusted.
const BALANCED_SHARES: [f64; 3] = [0.25, 0.1875, 0.125];
/// The share of the area balanced ends may leave unworked, all ends together: at a quarter of
/// the width that is 0.1–0.4 % on the real fields, more on a small field worked by a wide
/// implement (1.45 % on 1.6 ha with 10 m).
const BALANCED_LEFT: f64 = 0.005;

/// Where a swath ends.
#[derive(Debug, Clone, Copy)]
enum Cut {
    /// Its centre line's end.
    Centre,
    /// Where this share of its width still has area to work.
    Share(f64),
    /// Its whole width, at most this far past its centre line's end.
    Slack(f64),
}

/// How far a swath's band reaches into the area, in the sweep frame: its own extent, its
/// centre line's interval and its samples' starts and ends, furthest first.
struct Band {
    a: f64,
    b: f64,
    lo: f64,
    hi: f64,
    starts: Vec<f64>,
    ends: Vec<f64>,
    width: f64,
}

impl Band {
    /// The band of `segment` over `at`: the area's intervals on its centre line, then on each
    /// of its samples (sweep frame).
    fn new(s: &SweepSegment, at: &[Vec<(f64, f64)>]) -> Self {
        let within = |line: &Vec<(f64, f64)>| -> Option<(f64, f64)> {
            line.iter()
                .copied()
                .filter(|&(lo, hi)| lo <= s.b && hi >= s.a)
                .fold(None, |acc: Option<(f64, f64)>, (lo, hi)| Some(acc.map_or((lo, hi), |(l, h)| (l.min(lo), h.max(hi)))))
        };
        // where the centre line misses the area (a band grazing a tip or a pond's headland)
        // the swath still works the band's part of it, end to end
        let (lo, hi) = within(&at[0]).unwrap_or((s.a, s.b));
        // clamped to the segment: a sample beside a no-fly zone that cut the segment runs on
        // past the zone, where the line's next segment (or a gap fill) works it, not this end
        let samples: Vec<(f64, f64)> = at[1..].iter().filter_map(within).map(|(lo, hi)| (lo.max(s.a), hi.min(s.b))).collect();
        let mut starts: Vec<f64> = samples.iter().map(|p| p.0).collect();
        let mut ends: Vec<f64> = samples.iter().map(|p| p.1).collect();
        starts.sort_by(f64::total_cmp);
        ends.sort_by(|x, y| y.total_cmp(x));
        Band { a: s.a, b: s.b, lo, hi, starts, ends, width: s.hi - s.lo }
    }

    /// The swath's ends (sweep frame) by `cut`, within the band's own extent.
    fn cut(&self, cut: Cut) -> (f64, f64) {
        let (a, b) = (self.a, self.b);
        let (lo, hi) = (self.lo - CENTRE_LINE_PAST_M, self.hi + CENTRE_LINE_PAST_M);
        match cut {
            Cut::Centre => (a.max(lo), b.min(hi)),
            Cut::Share(share) => (a.max(lo.min(at_share(&self.starts, share).unwrap_or(lo))), b.min(hi.max(at_share(&self.ends, share).unwrap_or(hi)))),
            Cut::Slack(slack) => {
                let worth = |sorted: &[f64], cap: f64| sorted.get(SAMPLES_WORTH_WORKING - 1).copied().unwrap_or(cap);
                let (lo, hi) = (self.lo - slack, self.hi + slack);
                (a.max(lo.min(worth(&self.starts, lo))), b.min(hi.max(worth(&self.ends, hi))))
            }
        }
    }

    /// The area the samples find beyond a swath from `a` to `b` (m²).
    fn left_unworked(&self, a: f64, b: f64) -> f64 {
        let beyond: f64 = self.starts.iter().map(|s| (a - s).max(0.0)).chain(self.ends.iter().map(|e| (e - b).max(0.0))).sum();
        beyond * self.width / BAND_SAMPLES as f64
    }
}

/// Where `share` of a band's width is still in the area, from its samples' reaches sorted
/// furthest first: sample i lies (i + ½) / [`BAND_SAMPLES`] of the width in from the outer edge.
fn at_share(sorted: &[f64], share: f64) -> Option<f64> {
    let p = share * BAND_SAMPLES as f64 - 0.5;
    let (i, f) = (p.floor() as usize, p.fract());
    let x = *sorted.get(i)?;
    match sorted.get(i + 1) {
        Some(y) => Some(x + (y - x) * f),
        None => (f == 0.0).then_some(x),
    }
}

/// The ends `(a, b)` of each of `segments` (sweep frame), ended by `rule` against `area`
/// (already in the sweep frame). The segments are full-width sweeps of the area or of a part
/// of it: an end only moves back, and only where the area itself ends, so a part's edge inside
/// the area keeps its full width. `full_width` stops `slack` past the centre line's end unless
/// a quarter of the band still holds area further on; `balanced` stops where a quarter of the
/// band still holds area, or less when that would leave more than [`BALANCED_LEFT`] of
/// `part_area` (the area of the part the segments sweep) unworked; `centre_line` ends with the
/// centre line. Each part is allowed its own share: a decomposition's parts once each left up
/// to [`BALANCED_LEFT`] of the whole area, 1 % and more together.
pub fn cut(area: &MultiPolygon, segments: &[SweepSegment], rule: SwathEnds, slack: f64, part_area: f64) -> Vec<(f64, f64)> {
    let ys: Vec<f64> =
        segments.iter().flat_map(|s| std::iter::once(s.offset).chain((0..BAND_SAMPLES).map(|j| s.lo + (s.hi - s.lo) * (j as f64 + 0.5) / BAND_SAMPLES as f64))).collect();
    let at = scanlines_intervals(area, &ys);
    let bands: Vec<Band> = segments.iter().zip(at.chunks(BAND_SAMPLES + 1)).map(|(s, at)| Band::new(s, at)).collect();
    let cut = match rule {
        SwathEnds::CentreLine => Cut::Centre,
        SwathEnds::FullWidth => Cut::Slack(slack),
        SwathEnds::Balanced => {
            let allowed = BALANCED_LEFT * part_area;
            let left = |share: f64| -> f64 {
                bands
                    .iter()
                    .map(|band| {
                        let (a, b) = band.cut(Cut::Share(share));
                        band.left_unworked(a, b)
                    })
                    .sum()
            };
            BALANCED_SHARES.into_iter().find(|&share| left(share) <= allowed).map_or(Cut::Slack(slack), Cut::Share)
        }
    };
    bands.iter().map(|band| band.cut(cut)).collect()
}

/// Ends the lines of `pattern` (a sweep of a part of `area` whose area is `part_area`) by
/// `rule` against `area` (the whole area to cover, local frame), dropping what is left shorter
/// than 5 cm. Full-width ends leave the pattern as it is; so do gap fills, which work what the
/// lines leave beside no-fly zones.
pub fn end_lines(pattern: &mut SweepPattern, area: &MultiPolygon, rule: SwathEnds, part_area: f64) {
    if rule == SwathEnds::FullWidth {
        return;
    }
    let rotated = rotate(area, pattern.angle);
    let segments: Vec<SweepSegment> = pattern.lines.iter().flatten().copied().collect();
    let mut ends = cut(&rotated, &segments, rule, f64::INFINITY, part_area).into_iter();
    for line in &mut pattern.lines {
        for s in line.iter_mut() {
            (s.a, s.b) = ends.next().expect("one end pair per segment");
        }
        line.retain(|s| s.b - s.a > 0.05);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{LineLayout, sweep};
    use geo::{Area, BooleanOps, polygon};

    /// A field with a slanted edge and a no-fly zone across some lines: balanced ends stop where
    /// a quarter of the width is left at the slanted edge, on the lines the zone cuts too, and
    /// the ends at the zone stay where the zone stops them.
    #[test]
    fn balanced_ends_move_back_at_a_slanted_edge_and_stay_at_a_zone() {
        // the right edge runs from (100, 0) to (80, 60): x = 100 − y / 3
        let field = MultiPolygon(vec![polygon![(x: 0.0, y: 0.0), (x: 100.0, y: 0.0), (x: 80.0, y: 60.0), (x: 0.0, y: 60.0)]]);
        let zone = MultiPolygon(vec![polygon![(x: 30.0, y: 20.0), (x: 50.0, y: 20.0), (x: 50.0, y: 40.0), (x: 30.0, y: 40.0)]]);
        let region = field.difference(&zone);
        let mut pattern = sweep(&region, &zone, 0.0, LineLayout::centered(6.0));
        let full = pattern.clone();
        end_lines(&mut pattern, &region, SwathEnds::Balanced, region.unsigned_area());
        let mut cut_by_zone = 0;
        for (line, full) in pattern.lines.iter().zip(&full.lines) {
            assert_eq!(line.len(), full.len());
            let y = line[0].offset;
            // full width runs 1 m past the centre line's end (the band's lower edge, 3 m below);
            // a quarter of the width in, 1.5 m below the centre, 0.5 m
            let (last, full_last) = (line.last().unwrap(), full.last().unwrap());
            assert!((full_last.b - (100.0 - y / 3.0) - 1.0).abs() < 1e-6, "{full_last:?}");
            assert!((last.b - (100.0 - y / 3.0) - 0.5).abs() < 1e-6, "{last:?}");
            for (s, f) in line.iter().zip(full).take(line.len() - 1) {
                assert_eq!((s.a, s.b), (f.a, f.b), "an end at the zone moved");
                cut_by_zone += 1;
            }
        }
        assert_eq!(cut_by_zone, 4, "four lines pass the zone");
    }
}
