//! The altitude profile over terrain (docs/methods.md, terrain): the path is sampled every
//! metre, each sample gets a band of allowed altitudes (survey height above ground ± the
//! tolerance on sweeps, at least the height minus the tolerance elsewhere, obstacles' climbs
//! kept), the band is narrowed to what the vehicle's climb and descent limits can fly (so that
//! climbs start before the slope), and the fewest straight vertical pieces that stay inside it
//! are laid through it (a cone of feasible slopes carried from each vertical vertex).

use geo::Coord;

use super::ElevationModel;
use crate::error::InputError;
use crate::frame::LocalFrame;
use crate::geom::distance;
use crate::path::{FlightPath, PieceKind};

/// Horizontal distance between the samples of the ground, metres.
pub const SAMPLE_M: f64 = 1.0;
/// Side of the lookup cells that map local metres to the model's cells, metres.
const LOOKUP_M: f64 = 50.0;

/// Ground heights in a plan's local frame. The map from local metres to the model's cells is
/// smooth: it is computed exactly on a 50 m lattice over `bounds` and interpolated between
/// (centimetre-exact), so sampling a long path costs no projection per sample.
pub struct Ground<'a> {
    model: &'a ElevationModel,
    frame: LocalFrame,
    origin: Coord,
    nx: usize,
    ny: usize,
    lattice: Vec<Option<[f64; 2]>>,
}

impl<'a> Ground<'a> {
    /// The ground under `bounds` (local metres, min and max corner).
    pub fn new(model: &'a ElevationModel, frame: LocalFrame, bounds: [Coord; 2]) -> Ground<'a> {
        let origin = bounds[0] - Coord { x: LOOKUP_M, y: LOOKUP_M };
        let span = bounds[1] - origin + Coord { x: LOOKUP_M, y: LOOKUP_M };
        let (nx, ny) = ((span.x / LOOKUP_M).ceil() as usize + 1, (span.y / LOOKUP_M).ceil() as usize + 1);
        let (nx, ny) = if nx.saturating_mul(ny) > 4_000_000 { (0, 0) } else { (nx, ny) };
        let lattice = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i, j)))
            .map(|(i, j)| {
                let [lon, lat] = frame.to_wgs84(origin + Coord { x: i as f64 * LOOKUP_M, y: j as f64 * LOOKUP_M });
                model.pixel_of(lon, lat)
            })
            .collect();
        Ground { model, frame, origin, nx, ny, lattice }
    }

    /// Height of the ground at `c`, metres above mean sea level.
    pub fn at(&self, c: Coord) -> Option<f64> {
        let (fx, fy) = ((c.x - self.origin.x) / LOOKUP_M, (c.y - self.origin.y) / LOOKUP_M);
        let (i, j) = (fx.floor(), fy.floor());
        if i >= 0.0 && j >= 0.0 && (i as usize) + 1 < self.nx && (j as usize) + 1 < self.ny {
            let (i, j) = (i as usize, j as usize);
            let (tx, ty) = (fx - i as f64, fy - j as f64);
            let corner = |di: usize, dj: usize| self.lattice[(j + dj) * self.nx + i + di];
            if let (Some(a), Some(b), Some(c), Some(d)) = (corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)) {
                let mix = |k: usize| (a[k] * (1.0 - tx) + b[k] * tx) * (1.0 - ty) + (c[k] * (1.0 - tx) + d[k] * tx) * ty;
                return self.model.height_at_pixel([mix(0), mix(1)]);
            }
        }
        let [lon, lat] = self.frame.to_wgs84(c);
        self.model.height_at(lon, lat)
    }

    fn missing(&self, c: Coord) -> InputError {
        let [lon, lat] = self.frame.to_wgs84(c);
        InputError::new(
            "terrain_not_covering",
            "/",
            format!(
                "the planned path passes [{lon:.6}, {lat:.6}], where the elevation model {} the ground: give a model reaching further around the fields",
                if self.model.missing(lon, lat) == "does not reach" { "does not reach" } else { "has no data for" }
            ),
        )
    }
}

/// What the profile keeps.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Height above ground of the survey.
    pub height_m: f64,
    /// How far the height above ground may stray on sweeps (and below it elsewhere).
    pub tolerance_m: f64,
    /// Steepest climb and descent, metres of height per metre flown.
    pub climb: f64,
    pub descent: f64,
}

/// The profile laid over one path.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Laid {
    /// Least and greatest height above ground of each piece, sampled every metre.
    pub piece_heights: Vec<[f64; 2]>,
    /// Metres of sweep where the ground rises or falls faster than the vehicle can climb or
    /// descend, so that the height above ground leaves the tolerance (kept above its floor).
    pub sweep_off_band_m: f64,
    /// The ground's height under each point of each piece of the laid path.
    pub point_ground: Vec<Vec<f64>>,
}

struct Sample {
    s: f64,
    at: Coord,
    piece: usize,
    ground: f64,
    /// The highest ground looked at between the sample before and this one (every quarter
    /// step): the path between samples is straight, the ground under it is not.
    ground_before: f64,
    /// Height wanted above the ground: the survey height, or more where the path was raised
    /// (over obstacles, into a fleet's layer).
    wanted: f64,
    sweep: bool,
}

/// Lays `path` (altitudes in `piece.z` above the survey's flat ground, or none: the survey
/// height) over the ground: every piece gets one altitude above mean sea level per point, with
/// vertices added where the profile bends.
pub fn lay(path: &FlightPath, ground: &Ground<'_>, settings: &Settings) -> Result<(FlightPath, Laid), InputError> {
    let samples = sample(path, ground, settings.height_m)?;
    if samples.is_empty() {
        return Ok((path.clone(), Laid::default()));
    }
    let Settings { height_m, tolerance_m, climb, descent } = *settings;
    // keeps the band a little inside the bounds: the ground bends between samples
    let inset = (0.1 * tolerance_m).min(0.5);
    let target: Vec<f64> = samples.iter().map(|p| p.ground + p.wanted).collect();
    // the floor under a sample: the highest ground on the straight legs to either neighbour
    // (over a cliff's edge the ground between samples stands metres above both)
    let floor = |i: usize| samples[i].ground_before.max(samples.get(i + 1).map_or(f64::NEG_INFINITY, |q| q.ground_before));
    let mut lo: Vec<f64> =
        samples.iter().enumerate().map(|(i, p)| if p.wanted > height_m + 1e-6 { p.ground + p.wanted } else { floor(i) + height_m - tolerance_m + inset }).collect();
    let mut hi: Vec<f64> = samples.iter().zip(&target).map(|(p, t)| if p.sweep { t + tolerance_m - inset } else { t + 3.0 * tolerance_m }).collect();
    let step = |i: usize| samples[i].s - samples[i - 1].s;
    let n = samples.len();
    for i in 1..n {
        lo[i] = lo[i].max(lo[i - 1] - descent * step(i));
        hi[i] = hi[i].min(hi[i - 1] + climb * step(i));
    }
    for i in (1..n).rev() {
        lo[i - 1] = lo[i - 1].max(lo[i] - climb * step(i));
        hi[i - 1] = hi[i - 1].min(hi[i] + descent * step(i));
    }
    // where the limits leave one altitude (a ramp up a cliff), a sliver of band keeps the
    // cone from closing at every rounding
    for i in 0..n {
        hi[i] = hi[i].max(lo[i] + 0.05);
    }
    let vertices = simplify(&samples, &lo, &hi, &target, settings);
    let (laid_path, point_ground) = rebuild(path, &samples, &vertices);
    let mut laid = Laid { piece_heights: vec![[f64::INFINITY, f64::NEG_INFINITY]; path.pieces.len()], sweep_off_band_m: 0.0, point_ground };
    let profile = Profile { s: vertices.iter().map(|v| samples[v.0].s).collect(), z: vertices.iter().map(|v| v.1).collect() };
    for (i, p) in samples.iter().enumerate() {
        let z = profile.at(p.s);
        let above = z - p.ground;
        let h = &mut laid.piece_heights[p.piece];
        *h = [h[0].min(above), h[1].max(above)];
        if p.sweep && i > 0 && (above - height_m).abs() > tolerance_m {
            laid.sweep_off_band_m += step(i);
        }
    }
    for h in &mut laid.piece_heights {
        if !h[0].is_finite() {
            *h = [height_m, height_m];
        }
    }
    Ok((laid_path, laid))
}

/// Altitude against distance along the path: straight between vertices.
struct Profile {
    s: Vec<f64>,
    z: Vec<f64>,
}

impl Profile {
    fn at(&self, s: f64) -> f64 {
        let i = self.s.partition_point(|&v| v <= s);
        if i == 0 {
            return self.z[0];
        }
        if i == self.s.len() {
            return self.z[i - 1];
        }
        let (sa, sb) = (self.s[i - 1], self.s[i]);
        self.z[i - 1] + (self.z[i] - self.z[i - 1]) * (s - sa) / (sb - sa)
    }
}

/// The path every [`SAMPLE_M`] metres, with the vertices among the samples.
fn sample(path: &FlightPath, ground: &Ground<'_>, height_m: f64) -> Result<Vec<Sample>, InputError> {
    let mut out: Vec<Sample> = Vec::new();
    let mut s = 0.0;
    for (index, piece) in path.pieces.iter().enumerate() {
        let sweep = piece.kind == PieceKind::Sweep;
        let wanted = |k: usize| piece.z.get(k).copied().unwrap_or(height_m).max(height_m);
        if let Some(last) = out.last_mut() {
            last.sweep |= sweep;
            last.wanted = last.wanted.max(wanted(0));
        }
        for k in 0..piece.points.len() {
            let b = piece.points[k];
            let (a, wa) = if k == 0 { (b, wanted(0)) } else { (piece.points[k - 1], wanted(k - 1)) };
            let length = distance(a, b);
            if out.is_empty() {
                let g = ground.at(b).ok_or_else(|| ground.missing(b))?;
                out.push(Sample { s, at: b, piece: index, ground: g, ground_before: g, wanted: wa, sweep });
            }
            if length < 1e-6 {
                continue;
            }
            let n = (length / SAMPLE_M).ceil() as usize;
            let ground_at = |f: f64| {
                let at = a + (b - a) * f;
                ground.at(at).ok_or_else(|| ground.missing(at))
            };
            for t in 1..=n {
                let f = t as f64 / n as f64;
                let g = ground_at(f)?;
                let mut ground_before = g;
                for quarter in 1..=3 {
                    ground_before = ground_before.max(ground_at((t as f64 - 1.0 + quarter as f64 / 4.0) / n as f64)?);
                }
                out.push(Sample { s: s + length * f, at: a + (b - a) * f, piece: index, ground: g, ground_before, wanted: wa + (wanted(k) - wa) * f, sweep });
            }
            s += length;
        }
    }
    Ok(out)
}

/// The fewest vertical vertices (sample index, altitude) whose straight pieces stay within
/// `[lo, hi]` at every sample and climb and descend within the limits: from each vertex, the
/// slopes that keep every later sample in its band narrow to a cone; where it closes, a vertex
/// goes at the last sample it held, on the slope nearest the target.
fn simplify(samples: &[Sample], lo: &[f64], hi: &[f64], target: &[f64], settings: &Settings) -> Vec<(usize, f64)> {
    let n = samples.len();
    let mut out = vec![(0, target[0].clamp(lo[0], hi[0]))];
    let (mut a, mut za) = out[0];
    let (mut smin, mut smax) = (-settings.descent, settings.climb);
    let mut j = 1;
    let place = |k: usize, a: usize, za: f64, smin: f64, smax: f64| {
        let d = samples[k].s - samples[a].s;
        if d <= 0.0 {
            return target[k].clamp(lo[k], hi[k]);
        }
        za + ((target[k] - za) / d).max(smin).min(smax) * d
    };
    while j < n {
        let d = samples[j].s - samples[a].s;
        if d <= 1e-9 {
            j += 1;
            continue;
        }
        let low = smin.max((lo[j] - za) / d);
        let high = smax.min((hi[j] - za) / d);
        if low <= high + 1e-12 {
            (smin, smax) = (low, high);
            j += 1;
            continue;
        }
        // the cone closed at j: a vertex at the last sample it held (or at j, when that is a)
        let k = if j - 1 > a { j - 1 } else { j };
        let zk = if k == j { za.max(lo[j]).min(hi[j]) } else { place(k, a, za, smin, smax) };
        out.push((k, zk));
        (a, za) = (k, zk);
        (smin, smax) = (-settings.descent, settings.climb);
        j = k + 1;
    }
    if a != n - 1 {
        out.push((n - 1, place(n - 1, a, za, smin, smax)));
    }
    out
}

/// `path` with an altitude at every point, from the profile through `vertices`, and a point
/// added wherever a vertex falls inside a segment; with the ground under each point.
fn rebuild(path: &FlightPath, samples: &[Sample], vertices: &[(usize, f64)]) -> (FlightPath, Vec<Vec<f64>>) {
    let profile = Profile { s: vertices.iter().map(|v| samples[v.0].s).collect(), z: vertices.iter().map(|v| v.1).collect() };
    // every vertex of the path is a sample: its ground is the sample's at its distance
    let ground_at = |s: f64| samples[samples.partition_point(|p| p.s < s - 1e-6).min(samples.len() - 1)].ground;
    let mut out = path.clone();
    let mut grounds = Vec::with_capacity(out.pieces.len());
    let mut v = 0;
    let mut s = 0.0;
    for piece in &mut out.pieces {
        let mut points = Vec::with_capacity(piece.points.len());
        let mut z = Vec::with_capacity(piece.points.len());
        let mut ground = Vec::with_capacity(piece.points.len());
        for k in 0..piece.points.len() {
            let b = piece.points[k];
            if k > 0 {
                let length = distance(piece.points[k - 1], b);
                // profile vertices strictly inside this segment
                while v < vertices.len() && profile.s[v] < s + length - 1e-6 {
                    if profile.s[v] > s + 1e-6 {
                        points.push(samples[vertices[v].0].at);
                        z.push(profile.z[v]);
                        ground.push(samples[vertices[v].0].ground);
                    }
                    v += 1;
                }
                s += length;
            }
            points.push(b);
            z.push(profile.at(s));
            ground.push(ground_at(s));
        }
        piece.points = points;
        piece.z = z;
        grounds.push(ground);
    }
    (out, grounds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::Piece;
    use crate::terrain::tests::synthetic;

    fn frame_at_model_corner(model: &ElevationModel) -> LocalFrame {
        let super::super::Crs::Utm { .. } = model.crs() else { panic!("a UTM model") };
        let [lon, lat] = model.crs().to_wgs84(500_000.0, 5_200_000.0).unwrap();
        LocalFrame::new(lon, lat)
    }

    /// A sweep east along y = 200 m from x = 20 to 980 m, then a transit back.
    fn path() -> FlightPath {
        let mut p = FlightPath::default();
        p.push(PieceKind::Sweep, vec![Coord { x: 20.0, y: 200.0 }, Coord { x: 980.0, y: 200.0 }], 10.0);
        p.push(PieceKind::Transit, vec![Coord { x: 980.0, y: 200.0 }, Coord { x: 20.0, y: 250.0 }], 0.0);
        p
    }

    /// Height above ground of the laid path every metre, from half a metre in (between the
    /// planner's samples), with whether it is on a sweep; and the steepest climb and descent.
    fn check(laid: &FlightPath, ground: &Ground<'_>) -> (Vec<(f64, bool)>, f64, f64) {
        let mut out = Vec::new();
        let (mut up, mut down) = (0.0f64, 0.0f64);
        for piece in &laid.pieces {
            assert_eq!(piece.z.len(), piece.points.len());
            for k in 1..piece.points.len() {
                let (a, b, za, zb) = (piece.points[k - 1], piece.points[k], piece.z[k - 1], piece.z[k]);
                let d = distance(a, b);
                if d < 1e-9 {
                    continue;
                }
                up = up.max((zb - za) / d);
                down = down.max((za - zb) / d);
                let mut t = 0.5;
                while t < d {
                    let f = t / d;
                    out.push((za + (zb - za) * f - ground.at(a + (b - a) * f).unwrap(), piece.kind == PieceKind::Sweep));
                    t += 1.0;
                }
            }
        }
        (out, up, down)
    }

    #[test]
    fn follows_a_gentle_ridge_within_the_tolerance_with_few_vertices() {
        let model = synthetic(120, 60, 10.0, |x, _| 400.0 + 80.0 * (-((x - 500.0) / 150.0).powi(2)).exp());
        let ground = Ground::new(&model, frame_at_model_corner(&model), [Coord { x: 0.0, y: 0.0 }, Coord { x: 1000.0, y: 400.0 }]);
        let settings = Settings { height_m: 60.0, tolerance_m: 5.0, climb: 0.6, descent: 0.6 };
        let (laid, report) = lay(&path(), &ground, &settings).unwrap();
        let (heights, up, down) = check(&laid, &ground);
        for (h, sweep) in &heights {
            assert!(*h >= 55.0 - 1e-6, "below the floor: {h}");
            assert!(!sweep || *h <= 65.0 + 1e-6, "above the band on a sweep: {h}");
        }
        assert!(up <= 0.6 + 1e-9 && down <= 0.6 + 1e-9, "{up} {down}");
        assert_eq!(report.sweep_off_band_m, 0.0);
        let sweep_vertices = laid.pieces[0].points.len();
        assert!((4..=40).contains(&sweep_vertices), "{sweep_vertices} vertices on 960 m over the ridge");
        let [lo, hi] = report.piece_heights[0];
        assert!(lo >= 55.0 && hi <= 65.0, "{lo} {hi}");
    }

    #[test]
    fn climbs_before_a_cliff_it_cannot_follow_and_never_dips_below_the_floor() {
        let model = synthetic(120, 60, 10.0, |x, _| 300.0 + 60.0 / (1.0 + (-(x - 500.0) / 2.0).exp()));
        let ground = Ground::new(&model, frame_at_model_corner(&model), [Coord { x: 0.0, y: 0.0 }, Coord { x: 1000.0, y: 400.0 }]);
        let settings = Settings { height_m: 40.0, tolerance_m: 5.0, climb: 0.3, descent: 0.2 };
        let (laid, report) = lay(&path(), &ground, &settings).unwrap();
        let (heights, up, down) = check(&laid, &ground);
        assert!(heights.iter().all(|(h, _)| *h >= 35.0 - 1e-6), "{:?}", heights.iter().map(|h| h.0).fold(f64::INFINITY, f64::min));
        assert!(up <= 0.3 + 1e-9 && down <= 0.2 + 1e-9, "{up} {down}");
        // the climb of 60 m at 0.3 starts about 180 m before the cliff: the sweep is high there
        assert!(report.sweep_off_band_m > 100.0 && report.sweep_off_band_m < 400.0, "{}", report.sweep_off_band_m);
    }

    #[test]
    fn over_flat_ground_the_path_is_unchanged_at_the_height_above_it() {
        let model = synthetic(120, 60, 10.0, |_, _| 250.0);
        let ground = Ground::new(&model, frame_at_model_corner(&model), [Coord { x: 0.0, y: 0.0 }, Coord { x: 1000.0, y: 400.0 }]);
        let (laid, _) = lay(&path(), &ground, &Settings { height_m: 60.0, tolerance_m: 5.0, climb: 0.5, descent: 0.5 }).unwrap();
        let flat = path();
        for (a, b) in laid.pieces.iter().zip(&flat.pieces) {
            assert_eq!(a.points, b.points);
            assert!(a.z.iter().all(|z| (z - 310.0).abs() < 1e-6), "{:?}", a.z);
        }
        let outside = FlightPath { pieces: vec![Piece::new(PieceKind::Transit, vec![Coord { x: 0.0, y: 0.0 }, Coord { x: -900.0, y: 0.0 }], 0.0)] };
        assert_eq!(lay(&outside, &ground, &Settings { height_m: 60.0, tolerance_m: 5.0, climb: 0.5, descent: 0.5 }).err().unwrap().code, "terrain_not_covering");
    }
}
