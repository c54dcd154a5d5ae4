//! What a flight log shows done (docs/methods.md, resume §4): each sweep line is sampled where
//! the plan takes its photos (without a camera, every trigger distance), and a sample is done
//! where the log has a photo beside it (within the tolerance across the line and a little over
//! half a trigger distance along it), or, without photos, where the track passes along the line
//! within the tolerance; samples are matched in flight order (each by a mark no earlier in the
//! log than the last sample's), so that the way out over lines not yet flown is not their work.
//! The cut is the last sample done in flight order; before it, the runs of samples not done
//! that leave ground unimaged (with a track only: runs of two samples or more) are flown again.
//! A track's heading is judged over a step's neighbours too (a receiver's noise on a short
//! step), and slivers shorter than half a trigger distance are not matched against a track.

use std::collections::HashMap;

use geo::Coord;

use super::{MAX_CUT_OFF_PATH_M, Stored};
use crate::camera::photo_offsets_through_bends;
use crate::error::InputError;
use crate::frame::LocalFrame;
use crate::geom::{distance, polyline_length};
use crate::params::resume::Flown;
use crate::path::{FlightPath, Piece, PieceKind};

/// How a line's work is sampled and matched.
#[derive(Debug, Clone, Copy)]
pub struct Sampling {
    /// The distance between two photos (without a camera, what stands for it).
    pub trigger_m: f64,
    /// The camera's footprint along the line, where the plan has a camera.
    pub footprint_along_m: Option<f64>,
    /// Farthest across a line a photo or the track counts as the line's, unless the log says.
    pub tolerance_m: f64,
}

/// A stretch of a line flown again: the piece, and metres along it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Redo {
    pub index: usize,
    pub from_m: f64,
    pub to_m: f64,
}

/// A sweep (its piece), its samples (metres along, done) and its length.
type SampledLine = (usize, Vec<(f64, bool)>, f64);

/// The track heads less than this off a piece's direction to count as flying it.
const ALONG_LINE_DEG: f64 = 30.0;

/// The track may fly this many times the plan's length between two samples it matches, and
/// [`TRACK_REACH_SLACK_M`] more (GPS noise, a wider turn, a detour round a bird).
const TRACK_REACH_FACTOR: f64 = 3.0;
const TRACK_REACH_SLACK_M: f64 = 200.0;

/// A track segment longer than this is a gap in the log (a lost link, a GPS jump), not work.
const LONGEST_TRACK_STEP_M: f64 = 100.0;

/// What the log matches samples against: photos, or the track's segments.
enum Marks {
    Photos(Vec<Coord>),
    Track(Vec<(Coord, Coord)>),
}

/// Marks bucketed on a square grid.
struct Grid {
    cell: f64,
    buckets: HashMap<(i64, i64), Vec<usize>>,
}

impl Grid {
    fn key(&self, p: Coord) -> (i64, i64) {
        ((p.x / self.cell).floor() as i64, (p.y / self.cell).floor() as i64)
    }

    fn new(cell: f64, boxes: impl Iterator<Item = (Coord, Coord)>) -> Grid {
        let mut grid = Grid { cell, buckets: HashMap::new() };
        for (k, (lo, hi)) in boxes.enumerate() {
            let (a, b) = (grid.key(lo), grid.key(hi));
            for i in a.0..=b.0 {
                for j in a.1..=b.1 {
                    grid.buckets.entry((i, j)).or_default().push(k);
                }
            }
        }
        grid
    }

    /// The marks in the cells within `reach` of `p`.
    fn near(&self, p: Coord, reach: f64) -> impl Iterator<Item = usize> + '_ {
        let lo = self.key(p - Coord { x: reach, y: reach });
        let hi = self.key(p + Coord { x: reach, y: reach });
        (lo.0..=hi.0).flat_map(move |i| (lo.1..=hi.1).flat_map(move |j| self.buckets.get(&(i, j)).into_iter().flatten().copied()))
    }
}

/// The cut (piece, metres along) and the stretches before it to fly again, from what `flown`
/// shows done on `pieces`; `back_m` is flown again before each stretch, as before a cut.
pub fn cut_from_log(pieces: &[Stored], frame: &LocalFrame, flown: &Flown, sampling: &Sampling, back_m: f64) -> Result<((usize, f64), Vec<Redo>), InputError> {
    let track: Vec<Coord> = flown.track.iter().map(|&[lon, lat]| frame.to_local(lon, lat)).collect();
    check_near(pieces, &track)?;
    let tolerance = flown.tolerance_m.unwrap_or(sampling.tolerance_m);
    let with_photos = !flown.photos.is_empty() && sampling.footprint_along_m.is_some();
    let along_tolerance = 0.6 * sampling.trigger_m;
    let marks = if with_photos {
        Marks::Photos(flown.photos.iter().map(|&[lon, lat]| frame.to_local(lon, lat)).collect())
    } else {
        Marks::Track(track.windows(2).map(|w| (w[0], w[1])).filter(|(a, b)| distance(*a, *b) <= LONGEST_TRACK_STEP_M).collect())
    };
    let cell = tolerance.max(along_tolerance).max(5.0);
    let grid = match &marks {
        Marks::Photos(p) => Grid::new(cell, p.iter().map(|&c| (c, c))),
        Marks::Track(s) => Grid::new(cell, s.iter().map(|(a, b)| (Coord { x: a.x.min(b.x), y: a.y.min(b.y) }, Coord { x: a.x.max(b.x), y: a.y.max(b.y) }))),
    };
    let cos_along = ALONG_LINE_DEG.to_radians().cos();
    // the track's length up to each of its segments: the track may not have flown much more
    // than the plan between two samples it matches (a later pass over the same ground is not
    // this one)
    let track_at: Vec<f64> = match &marks {
        Marks::Track(segments) => segments
            .iter()
            .scan(0.0, |walked, (a, b)| {
                let at = *walked;
                *walked += distance(*a, *b);
                Some(at)
            })
            .collect(),
        Marks::Photos(_) => Vec::new(),
    };
    // the first mark at or after `floor` (in log order) beside `p` on a line going `u`, within
    // `reach_m` of track flown since the floor
    let done = |p: Coord, u: Coord, floor: usize, reach_m: f64| -> Option<usize> {
        let beside = |k: &usize| match &marks {
            Marks::Photos(photos) => {
                let d = photos[*k] - p;
                (d.x * u.x + d.y * u.y).abs() <= along_tolerance && (d.y * u.x - d.x * u.y).abs() <= tolerance
            }
            Marks::Track(segments) => {
                let (a, b) = segments[*k];
                let heads_along = |d: Coord| {
                    let len = d.x.hypot(d.y);
                    len > 0.0 && (d.x * u.x + d.y * u.y) / len >= cos_along
                };
                // a short step's own heading is mostly the receiver's noise: the chord over
                // its neighbours in the log says where the vehicle was going
                let chord = || {
                    let before = k.checked_sub(1).map(|j| segments[j]).filter(|s| s.1 == a).map_or(a, |s| s.0);
                    let after = segments.get(k + 1).filter(|s| s.0 == b).map_or(b, |s| s.1);
                    after - before
                };
                point_to_segment(p, a, b) <= tolerance && (heads_along(b - a) || heads_along(chord()))
            }
        };
        let within = |k: &usize| track_at.get(*k).is_none_or(|at| at - track_at.get(floor).copied().unwrap_or(0.0) <= reach_m);
        grid.near(p, cell).filter(|&k| k >= floor).filter(within).filter(beside).min()
    };
    let path = FlightPath { pieces: pieces.iter().map(|p| Piece::new(p.kind, p.points.clone(), 0.0)).collect() };
    // the samples of every sweep, and whether each is done: matched in flight order, so that
    // the way to the first line or home over lines not yet flown is not taken for their work
    let mut floor = 0;
    let mut lines: Vec<SampledLine> = Vec::new();
    // where along the plan the last matched sample lies, and the plan walked since
    let (mut walked, mut matched_at) = (0.0, 0.0);
    let reach = |plan_at: f64, matched_at: f64| TRACK_REACH_FACTOR * (plan_at - matched_at) + TRACK_REACH_SLACK_M;
    for (k, p) in pieces.iter().enumerate() {
        let len = polyline_length(&p.points);
        let evenly = |len: f64| -> Vec<f64> {
            let n = (len / sampling.trigger_m).ceil().max(1.0) as usize;
            (0..=n).map(|i| len * i as f64 / n as f64).collect()
        };
        if p.kind != PieceKind::Sweep {
            // the track flying a transit or turn moves the floor on (no work, and no photos
            // are taken there): a way out along a later line is the way out
            if matches!(marks, Marks::Track(_)) && len > 0.0 {
                for t in evenly(len) {
                    if let Some(m) = done(point_at(&p.points, t), direction_at(&p.points, t), floor, reach(walked + t, matched_at)) {
                        (floor, matched_at) = (m, walked + t);
                    }
                }
            }
            walked += len;
            continue;
        }
        if matches!(marks, Marks::Track(_)) && len < sampling.trigger_m / 2.0 {
            // a sliver at a field's tip, shorter than its track's noise tells a heading by: not
            // worth a flight again, and a later pass beside it must not move the floor past the
            // lines that follow it
            walked += len;
            continue;
        }
        let offsets = match sampling.footprint_along_m {
            Some(along) => photo_offsets_through_bends(len, along, sampling.trigger_m, path.bends_into(k), path.bends_into(k + 1)),
            None => evenly(len),
        };
        let samples = offsets
            .into_iter()
            .map(|t| {
                let matched = done(point_at(&p.points, t), direction_at(&p.points, t), floor, reach(walked + t, matched_at));
                if let Some(m) = matched {
                    (floor, matched_at) = (m, walked + t);
                }
                (t, matched.is_some())
            })
            .collect();
        lines.push((k, samples, len));
        walked += len;
    }
    let last_done = lines.iter().enumerate().rev().find_map(|(l, (_, samples, _))| samples.iter().rposition(|s| s.1).map(|i| (l, i)));
    let Some((l_cut, i_cut)) = last_done else {
        let first = lines.first().map_or(0, |l| l.0);
        return Ok(((first, 0.0), Vec::new()));
    };
    let (k_cut, samples, len) = &lines[l_cut];
    let cut_along = if i_cut + 1 == samples.len() { *len } else { samples[i_cut].0 };
    let mut redo = Vec::new();
    for (l, (k, samples, len)) in lines.iter().enumerate().take(l_cut + 1) {
        let before_cut = if l == l_cut { i_cut } else { samples.len() };
        let mut i = 0;
        while i < before_cut {
            if samples[i].1 {
                i += 1;
                continue;
            }
            let first = i;
            while i < before_cut && !samples[i].1 {
                i += 1;
            }
            let last = i - 1;
            let (at_start, at_end) = (first == 0, last + 1 == samples.len());
            // a photo or two missed inside a line whose neighbours' footprints still meet
            let unimaged = match sampling.footprint_along_m.filter(|_| with_photos) {
                Some(along) if !at_start && !at_end => samples[last + 1].0 - samples[first - 1].0 > along,
                Some(_) => true,
                // the track: one sample missed beside done ones is the track's noise (a turn
                // begun a little early), and a sliver of a line shorter than half a trigger
                // distance is not worth a flight; neither is a stretch left
                None => {
                    let before = if at_start { 0.0 } else { samples[first - 1].0 };
                    let after = if at_end { *len } else { samples[last + 1].0 };
                    last > first && after - before > sampling.trigger_m / 2.0
                }
            };
            if unimaged {
                let from_m = if at_start { 0.0 } else { (samples[first].0 - back_m).max(0.0) };
                let to_m = if at_end { *len } else { (samples[last].0 + sampling.trigger_m / 2.0).min(*len) };
                redo.push(Redo { index: *k, from_m, to_m });
            }
        }
    }
    Ok(((*k_cut, cut_along), redo))
}

/// A log whose track never comes near the plan is another flight's.
fn check_near(pieces: &[Stored], track: &[Coord]) -> Result<(), InputError> {
    let step = (track.len() / 500).max(1);
    let mut nearest = f64::INFINITY;
    for &t in track.iter().step_by(step) {
        nearest = nearest.min(pieces.iter().flat_map(|p| p.points.windows(2)).map(|w| point_to_segment(t, w[0], w[1])).fold(f64::INFINITY, f64::min));
        if nearest <= MAX_CUT_OFF_PATH_M {
            return Ok(());
        }
    }
    Err(InputError::new(
        "log_off_path",
        "/flown/track",
        format!("the log's track comes no nearer than {nearest:.0} m to the plan's path (at most {MAX_CUT_OFF_PATH_M} m): is it this plan's flight?"),
    ))
}

pub(super) fn point_to_segment(p: Coord, a: Coord, b: Coord) -> f64 {
    let d = b - a;
    let l2 = d.x * d.x + d.y * d.y;
    let t = if l2 > 0.0 { (((p - a).x * d.x + (p - a).y * d.y) / l2).clamp(0.0, 1.0) } else { 0.0 };
    distance(p, a + d * t)
}

fn point_at(points: &[Coord], along: f64) -> Coord {
    super::from_along(points, along)[0]
}

/// The unit direction of a polyline at `along`.
fn direction_at(points: &[Coord], along: f64) -> Coord {
    let angle = super::direction_at(points, along);
    Coord { x: angle.cos(), y: angle.sin() }
}

/// Most points of the flown track drawn with a resumed plan.
const MOST_TRACK_POINTS_SHOWN: usize = 5_000;

/// The log's track as a feature of the resumed plan (kind `flown`, a MultiLineString broken where
/// the log has a gap), thinned to [`MOST_TRACK_POINTS_SHOWN`] points, so that a map shows what
/// was flown beside what is left; readers of plans skip it as no piece of theirs.
pub fn track_feature(flown: &Flown) -> geojson::Feature {
    let step = flown.track.len().div_ceil(MOST_TRACK_POINTS_SHOWN).max(1);
    let frame = LocalFrame::new(flown.track[0][0], flown.track[0][1]);
    let mut lines: Vec<Vec<geojson::Position>> = vec![Vec::new()];
    let mut last: Option<Coord> = None;
    for (_, p) in flown.track.iter().enumerate().filter(|(k, _)| k % step == 0 || *k + 1 == flown.track.len()) {
        let here = frame.to_local(p[0], p[1]);
        if last.is_some_and(|l| distance(l, here) > LONGEST_TRACK_STEP_M * step as f64) && lines.last().is_some_and(|l| !l.is_empty()) {
            lines.push(Vec::new());
        }
        last = Some(here);
        lines.last_mut().expect("a line").push(geojson::Position::from(*p));
    }
    lines.retain(|l| l.len() >= 2);
    let properties = serde_json::json!({"kind": "flown", "positions": flown.track.len(), "photos": flown.photos.len()});
    crate::export::geojson::feature(geojson::GeometryValue::MultiLineString { coordinates: lines }, properties)
}
