//! Shortest paths of a Dubins vehicle (forward only, turning radius at least `r`) between two
//! poses: the six words LSL, RSR, LSR, RSL, RLR, LRL in closed form (docs/methods.md, dubins §3), their
//! sampling into polylines (§8), and the turn-pattern closed forms used as test references (§5).
//!
//! Angles here are math headings: radians counter-clockwise from east (local +x). The API
//! speaks compass bearings, which the parameters stage converts at the boundary.
//!
//! `u_turns_between_parallel_lines` below checks the words against the turn patterns.

use std::f64::consts::{PI, TAU};

use geo::Coord;

/// A position and a math heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

impl Pose {
    pub fn new(x: f64, y: f64, theta: f64) -> Self {
        Self { x, y, theta }
    }

    pub fn at(c: Coord, theta: f64) -> Self {
        Self { x: c.x, y: c.y, theta }
    }

    pub fn coord(&self) -> Coord {
        Coord { x: self.x, y: self.y }
    }

    /// The same place facing the other way.
    pub fn reversed(&self) -> Self {
        Self { theta: self.theta + PI, ..*self }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Word {
    Lsl,
    Rsr,
    Lsr,
    Rsl,
    Rlr,
    Lrl,
}

/// One part of a word: left arc, straight, right arc.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    L,
    S,
    R,
}

impl Word {
    pub const ALL: [Word; 6] = [Word::Lsl, Word::Rsr, Word::Lsr, Word::Rsl, Word::Rlr, Word::Lrl];

    pub fn parts(self) -> [Part; 3] {
        use Part::*;
        match self {
            Word::Lsl => [L, S, L],
            Word::Rsr => [R, S, R],
            Word::Lsr => [L, S, R],
            Word::Rsl => [R, S, L],
            Word::Rlr => [R, L, R],
            Word::Lrl => [L, R, L],
        }
    }
}

/// A Dubins path: `start`, radius, word and the three normalised parameters (arc angles in
/// radians, straight length divided by `radius`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DubinsPath {
    pub start: Pose,
    pub radius: f64,
    pub word: Word,
    pub params: [f64; 3],
}

/// `a` in [0, 2π). Arguments here are sums of a few angles, so a turn or two of 2π brings
/// them in without `floor` (a library call on the baseline x86-64 target).
fn mod2pi(a: f64) -> f64 {
    if (0.0..TAU).contains(&a) {
        a
    } else if (-TAU..0.0).contains(&a) {
        a + TAU
    } else if (TAU..2.0 * TAU).contains(&a) {
        a - TAU
    } else {
        a - TAU * (a / TAU).floor()
    }
}

/// A normalised configuration with its sines and cosines, computed once for all six words.
struct Normalised {
    alpha: f64,
    beta: f64,
    d: f64,
    sa: f64,
    ca: f64,
    sb: f64,
    cb: f64,
    cab: f64,
}

impl Normalised {
    /// The arc tangent LSL and LRL share.
    fn tau_lsl(&self) -> f64 {
        (self.cb - self.ca).atan2(self.d + self.sa - self.sb)
    }

    /// The arc tangent RSR and RLR share.
    fn tau_rsr(&self) -> f64 {
        (self.ca - self.cb).atan2(self.d - self.sa + self.sb)
    }

    /// The square of the straight part of a CSC word (negative: the word does not exist), or
    /// the cosine of a CCC word's middle arc over its half (beyond ±1: it does not exist).
    fn shape(&self, word: Word) -> f64 {
        let Normalised { d, sa, sb, cab, .. } = *self;
        match word {
            Word::Lsl => 2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb),
            Word::Rsr => 2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa),
            Word::Lsr => -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb),
            Word::Rsl => -2.0 + d * d + 2.0 * cab - 2.0 * d * (sa + sb),
            Word::Rlr => (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0,
            Word::Lrl => (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0,
        }
    }

    /// A lower bound of `word`'s normalised length without arc tangents (+∞ where it does not
    /// exist). A CSC word's arcs turn by t and q in [0, 2π): LSL's sum to β − α modulo 2π,
    /// RSR's to α − β, and LSR's and RSL's differ by β − α modulo 2π, so their sum is at least
    /// that difference's distance from a whole turn. A CCC word's middle arc is at least π.
    fn floor(&self, word: Word) -> f64 {
        let shape = self.shape(word);
        let turned = mod2pi(self.beta - self.alpha);
        match word {
            Word::Lsl | Word::Rsr | Word::Lsr | Word::Rsl if shape < 0.0 => f64::INFINITY,
            Word::Lsl => shape.sqrt() + turned,
            Word::Rsr => shape.sqrt() + mod2pi(self.alpha - self.beta),
            Word::Lsr | Word::Rsl => shape.sqrt() + turned.min(TAU - turned),
            Word::Rlr | Word::Lrl if shape.abs() > 1.0 => f64::INFINITY,
            Word::Rlr | Word::Lrl => PI,
        }
    }
}

/// The parameters `(t, p, q)` of `word` between the normalised configuration, if feasible.
fn word_params(word: Word, n: &Normalised) -> Option<[f64; 3]> {
    let Normalised { alpha, beta, d, sa, ca, sb, cb, .. } = *n;
    let shape = n.shape(word);
    match word {
        Word::Lsl => (shape >= 0.0).then(|| {
            let tau = n.tau_lsl();
            [mod2pi(tau - alpha), shape.sqrt(), mod2pi(beta - tau)]
        }),
        Word::Rsr => (shape >= 0.0).then(|| {
            let tau = n.tau_rsr();
            [mod2pi(alpha - tau), shape.sqrt(), mod2pi(tau - beta)]
        }),
        Word::Lsr => (shape >= 0.0).then(|| {
            let p = shape.sqrt();
            // atan2(y, x) − atan2(−2, p) in one arc tangent (equal modulo 2π)
            let (y, x) = (-ca - cb, d + sa + sb);
            let tau = (y * p + 2.0 * x).atan2(x * p - 2.0 * y);
            [mod2pi(tau - alpha), p, mod2pi(tau - beta)]
        }),
        Word::Rsl => (shape >= 0.0).then(|| {
            let p = shape.sqrt();
            // atan2(y, x) − atan2(2, p) in one arc tangent (equal modulo 2π)
            let (y, x) = (ca + cb, d - sa - sb);
            let tau = (y * p - 2.0 * x).atan2(x * p + 2.0 * y);
            [mod2pi(alpha - tau), p, mod2pi(beta - tau)]
        }),
        Word::Rlr => (shape.abs() <= 1.0).then(|| {
            let p = mod2pi(TAU - shape.acos());
            let t = mod2pi(alpha - n.tau_rsr() + p / 2.0);
            [t, p, mod2pi(alpha - beta - t + p)]
        }),
        Word::Lrl => (shape.abs() <= 1.0).then(|| {
            let p = mod2pi(TAU - shape.acos());
            let t = mod2pi(-alpha + n.tau_lsl() + p / 2.0);
            [t, p, mod2pi(beta - alpha - t + p)]
        }),
    }
}

fn normalise(q0: Pose, q1: Pose, r: f64) -> Normalised {
    let line = Between::new(q0.coord(), q1.coord(), r);
    line.normalised(line.angle(q0.theta), line.angle(q1.theta))
}

/// The straight line between two places, what every word between them shares: its length
/// over `r` and its direction.
struct Between {
    d: f64,
    phi: f64,
}

/// A heading relative to a [`Between`], with its sine and cosine.
#[derive(Clone, Copy)]
struct Angle {
    at: f64,
    sin: f64,
    cos: f64,
}

impl Between {
    fn new(a: Coord, b: Coord, r: f64) -> Self {
        debug_assert!(r > 0.0);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let dist = (dx * dx + dy * dy).sqrt();
        Between { d: dist / r, phi: if dist > 0.0 { dy.atan2(dx) } else { 0.0 } }
    }

    fn angle(&self, theta: f64) -> Angle {
        let at = mod2pi(theta - self.phi);
        let (sin, cos) = at.sin_cos();
        Angle { at, sin, cos }
    }

    fn normalised(&self, a: Angle, b: Angle) -> Normalised {
        Normalised { alpha: a.at, beta: b.at, d: self.d, sa: a.sin, ca: a.cos, sb: b.sin, cb: b.cos, cab: a.cos * b.cos + a.sin * b.sin }
    }
}

/// [`shortest`]'s lengths from `q0` to the place `to` arriving in each of `headings`, and
/// from `to` leaving in each of `headings` to `q1`, the same to the bit: the line's arc tangent
/// and the fixed pose's sine and cosine are found once for all (a detour corner is looked at
/// in 16 headings, each from or to one pose).
pub fn lengths_arriving<const N: usize>(q0: Pose, to: Coord, headings: &[f64; N], r: f64) -> [f64; N] {
    let line = Between::new(q0.coord(), to, r);
    let leaving = line.angle(q0.theta);
    std::array::from_fn(|k| shortest_of(&line.normalised(leaving, line.angle(headings[k])), q0, r).length())
}

/// See [`lengths_arriving`].
pub fn lengths_leaving<const N: usize>(from: Coord, headings: &[f64; N], q1: Pose, r: f64) -> [f64; N] {
    let line = Between::new(from, q1.coord(), r);
    let arriving = line.angle(q1.theta);
    std::array::from_fn(|k| shortest_of(&line.normalised(line.angle(headings[k]), arriving), Pose::at(from, headings[k]), r).length())
}

/// Every feasible word from `q0` to `q1` with radius `r > 0`, in the order of [`Word::ALL`].
pub fn all_words(q0: Pose, q1: Pose, r: f64) -> Vec<DubinsPath> {
    let n = normalise(q0, q1, r);
    Word::ALL.iter().filter_map(|&word| word_params(word, &n).map(|params| DubinsPath { start: q0, radius: r, word, params })).collect()
}

/// Each word's path from `q0` to `q1` with radius `r > 0` where it exists, in the order of
/// [`Word::ALL`]: the configuration normalised once for all six.
pub fn each_word(q0: Pose, q1: Pose, r: f64) -> [Option<DubinsPath>; 6] {
    let n = normalise(q0, q1, r);
    Word::ALL.map(|word| word_params(word, &n).map(|params| DubinsPath { start: q0, radius: r, word, params }))
}

/// The path of `word` from `q0` to `q1` with radius `r > 0`, where it exists.
pub fn word_path(q0: Pose, q1: Pose, r: f64, word: Word) -> Option<DubinsPath> {
    word_params(word, &normalise(q0, q1, r)).map(|params| DubinsPath { start: q0, radius: r, word, params })
}

/// The shortest path from `q0` to `q1` with radius `r > 0`; ties go to the first word of
/// [`Word::ALL`]. It is called millions of times by the route search, so the words are
/// priced in place, without a list, and a word whose [`Normalised::floor`] is above the
/// best so far is not priced at all (its arc tangents were most of the time).
pub fn shortest(q0: Pose, q1: Pose, r: f64) -> DubinsPath {
    shortest_of(&normalise(q0, q1, r), q0, r)
}

/// [`shortest`] from `q0` in the normalised configuration `n`.
fn shortest_of(n: &Normalised, q0: Pose, r: f64) -> DubinsPath {
    let mut best: Option<DubinsPath> = None;
    for word in Word::ALL {
        // floors are normalised lengths; rounding may put a length a hair below its floor
        if best.is_some_and(|b| n.floor(word) * (1.0 - 1e-12) > b.params.iter().sum::<f64>()) {
            continue;
        }
        if let Some(params) = word_params(word, n) {
            let path = DubinsPath { start: q0, radius: r, word, params };
            if best.is_none_or(|b| path.length() < b.length()) {
                best = Some(path);
            }
        }
    }
    best.expect("LSL or RSR is always feasible")
}

/// A lower bound of the shortest path from `q0` to the point `p` arriving in any heading
/// (so of every [`shortest`] path from `q0` to a pose at `p`). Such a path is a turn then a
/// straight line (tangent from a turning circle) when `p` lies outside that circle, or two
/// turns, never shorter than the straight distance, when it lies inside one (Bui, Souères,
/// Boissonnat and Laumond 1994): the least of the tangent paths that exist and, when `p`
/// is inside a circle, the straight distance.
pub fn to_point_lower_bound(q0: Pose, p: Coord, r: f64) -> f64 {
    let (sin0, cos0) = q0.theta.sin_cos();
    let mut best = f64::INFINITY;
    for sigma in [1.0, -1.0] {
        let centre = Coord { x: q0.x - sigma * r * sin0, y: q0.y + sigma * r * cos0 };
        let (dx, dy) = (p.x - centre.x, p.y - centre.y);
        let d = dx.hypot(dy);
        if d <= r {
            best = best.min((p.x - q0.x).hypot(p.y - q0.y));
            continue;
        }
        // the tangent point's angle on the circle, and the arc turned to reach it
        let tangent = dy.atan2(dx) - sigma * (r / d).acos();
        let start = (q0.y - centre.y).atan2(q0.x - centre.x);
        let arc = mod2pi(sigma * (tangent - start));
        let arc = if arc > TAU - 1e-9 { 0.0 } else { arc };
        best = best.min(r * arc + (d * d - r * r).sqrt());
    }
    best
}

/// The pose reached after `s` metres of `part`, from `from` (backwards when `s` is negative).
pub(crate) fn advance(from: Pose, part: Part, s: f64, r: f64) -> Pose {
    match part {
        Part::S => Pose { x: from.x + s * from.theta.cos(), y: from.y + s * from.theta.sin(), theta: from.theta },
        Part::L | Part::R => {
            let sigma = turn_sign(part);
            let c = arc_centre(from, part, r);
            let theta = from.theta + sigma * s / r;
            Pose { x: c.x + sigma * r * theta.sin(), y: c.y - sigma * r * theta.cos(), theta }
        }
    }
}

/// +1 for a left arc, -1 for a right one.
fn turn_sign(part: Part) -> f64 {
    if part == Part::L { 1.0 } else { -1.0 }
}

/// Centre of the circle an arc of `part` (L or R) flies from `from`.
fn arc_centre(from: Pose, part: Part, r: f64) -> Coord {
    let sigma = turn_sign(part);
    let (sin0, cos0) = from.theta.sin_cos();
    Coord { x: from.x - sigma * r * sin0, y: from.y + sigma * r * cos0 }
}

/// The angle between samples of an arc of radius `r` whose chords stray at most
/// `chord_tolerance_m` from it, and at most 10°.
pub fn arc_step(r: f64, chord_tolerance_m: f64) -> f64 {
    let max_step = 10f64.to_radians();
    if chord_tolerance_m < r { (2.0 * (1.0 - chord_tolerance_m / r).acos()).min(max_step) } else { max_step }
}

impl DubinsPath {
    pub fn length(&self) -> f64 {
        self.radius * (self.params[0] + self.params[1] + self.params[2])
    }

    /// The three parts with their lengths in metres.
    pub fn segments(&self) -> [(Part, f64); 3] {
        let parts = self.word.parts();
        [0, 1, 2].map(|i| (parts[i], self.params[i] * self.radius))
    }

    /// A box that holds the whole path: each arc's circle and each straight's ends. Cheap
    /// next to [`Self::sample`], so a path far from every obstacle is cleared without points.
    pub fn bounds(&self) -> geo::Rect {
        let r = self.radius;
        let (mut lo, mut hi) = (self.start.coord(), self.start.coord());
        let mut q = self.start;
        for (part, s) in self.segments() {
            let next = advance(q, part, s, r);
            let (a, b) = match part {
                Part::S => (q.coord(), next.coord()),
                Part::L | Part::R => {
                    let centre = arc_centre(q, part, r);
                    (centre - Coord { x: r, y: r }, centre + Coord { x: r, y: r })
                }
            };
            lo = Coord { x: lo.x.min(a.x).min(b.x), y: lo.y.min(a.y).min(b.y) };
            hi = Coord { x: hi.x.max(a.x).max(b.x), y: hi.y.max(a.y).max(b.y) };
            q = next;
        }
        geo::Rect::new(lo, hi)
    }

    /// The straight part's two ends, as [`Self::sample`] puts them, when there is one: a far
    /// turn over an area is found crossing its edge here, before any arc is drawn.
    pub fn straight(&self) -> Option<[Coord; 2]> {
        let [(p0, s0), (p1, s1), _] = self.segments();
        (p1 == Part::S && s1 > 0.0).then(|| {
            let q = if s0 > 0.0 { advance(self.start, p0, s0, self.radius) } else { self.start };
            [q.coord(), advance(q, p1, s1, self.radius).coord()]
        })
    }

    /// Points along the path: arcs with a chord error of at most `chord_tolerance_m` (and at
    /// most 10° per step), straights by their ends. Starts at the start position; the last
    /// point is the end position.
    pub fn sample(&self, chord_tolerance_m: f64) -> Vec<Coord> {
        let r = self.radius;
        let step = arc_step(r, chord_tolerance_m);
        // room for every point at once: a route search samples millions of words
        let arcs: f64 = self.segments().iter().filter(|(part, _)| *part != Part::S).map(|(_, s)| (s / r / step).ceil() + 1.0).sum();
        let mut out = Vec::with_capacity(4 + arcs as usize);
        out.push(self.start.coord());
        let mut q = self.start;
        for (part, s) in self.segments() {
            if s <= 0.0 {
                continue;
            }
            if part != Part::S {
                // k equal steps round the arc's centre, the direction turned by rotation
                // rather than a sine and cosine per point
                let k = ((s / r) / step).ceil().max(1.0) as usize;
                let sigma = turn_sign(part);
                let centre = arc_centre(q, part, r);
                let (sin_d, cos_d) = (sigma * s / r / k as f64).sin_cos();
                let (mut sin_t, mut cos_t) = q.theta.sin_cos();
                for _ in 1..k {
                    (sin_t, cos_t) = (sin_t * cos_d + cos_t * sin_d, cos_t * cos_d - sin_t * sin_d);
                    out.push(Coord { x: centre.x + sigma * r * sin_t, y: centre.y - sigma * r * cos_t });
                }
            }
            q = advance(q, part, s, r);
            out.push(q.coord());
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Length of the shortest path, without building it.
    fn shortest_length(q0: Pose, q1: Pose, r: f64) -> f64 {
        shortest(q0, q1, r).length()
    }

    impl DubinsPath {
        /// The pose where the path ends (by following its parts).
        fn end_pose(&self) -> Pose {
            self.segments().iter().fold(self.start, |q, &(part, s)| advance(q, part, s, self.radius))
        }
    }

    proptest! {
        /// The point bound is a bound: below the shortest path to the point in every heading
        /// tried, and within a metre of the best of 360 headings (it is the exact minimum).
        #[test]
        fn the_point_bound_is_below_every_heading_and_tight(
            x in -300.0..300.0f64, y in -300.0..300.0f64, theta in 0.0..TAU, r in 5.0..90.0f64,
        ) {
            let q0 = Pose::new(0.0, 0.0, theta);
            let p = Coord { x, y };
            let bound = to_point_lower_bound(q0, p, r);
            let best = (0..360).map(|k| shortest(q0, Pose::at(p, (k as f64).to_radians()), r).length()).fold(f64::INFINITY, f64::min);
            prop_assert!(bound <= best + 1e-6, "bound {bound} above {best}");
            prop_assert!(bound >= x.hypot(y) - 1e-9);
            // outside both circles the bound is the exact tangent path
            let outside = [1.0, -1.0].iter().all(|s: &f64| (x + s * r * theta.sin()).hypot(y - s * r * theta.cos()) > r + 1.0);
            if outside {
                // (the headings tried are a degree apart)
                prop_assert!(best - bound < 1.0 + 0.02 * r, "bound {bound} far below {best}");
            }
        }
    }

    proptest! {
        /// The lengths to and from a place in several headings are [`shortest`]'s, to the bit,
        /// the place itself (no line between) included.
        #[test]
        fn fanned_lengths_are_the_shortest_words(
            x in -300.0..300.0f64, y in -300.0..300.0f64, theta in 0.0..TAU, r in 5.0..90.0f64, same_place in any::<bool>(),
        ) {
            let q = Pose::new(0.0, 0.0, theta);
            let at = if same_place { q.coord() } else { Coord { x, y } };
            let headings: [f64; 16] = std::array::from_fn(|k| k as f64 * TAU / 16.0);
            let (arriving, leaving) = (lengths_arriving(q, at, &headings, r), lengths_leaving(at, &headings, q, r));
            for (k, &h) in headings.iter().enumerate() {
                prop_assert_eq!(arriving[k].to_bits(), shortest(q, Pose::at(at, h), r).length().to_bits());
                prop_assert_eq!(leaving[k].to_bits(), shortest(Pose::at(at, h), q, r).length().to_bits());
            }
        }
    }

    /// Turn between antiparallel lines `d` apart with aligned ends in closed form, the
    /// reference the words are checked against: U-turn when `d ≥ 2r`, Ω-turn ("bulb") below.
    fn parallel_turn_length(d: f64, r: f64) -> f64 {
        if d >= 2.0 * r {
            PI * r + (d - 2.0 * r)
        } else {
            let eta = (d / 2.0 + r).atan2((4.0 * r * r - ((d + 2.0 * r) / 2.0).powi(2)).sqrt());
            r * (3.0 * PI - 4.0 * eta)
        }
    }

    fn deg(p: (f64, f64, f64)) -> Pose {
        Pose::new(p.0, p.1, p.2.to_radians())
    }

    fn angle_gap(a: f64, b: f64) -> f64 {
        let d = mod2pi(a - b);
        d.min(TAU - d)
    }

    #[test]
    fn u_turns_between_parallel_lines() {
        // (r, d, length): U-turns between parallel lines d apart, in closed form
        let cases = [
            (85.0, 0.0, 623.08),
            (85.0, 75.0, 527.53),
            (85.0, 150.0, 384.23),
            (85.0, 170.0, 267.04),
            (85.0, 225.0, 322.04),
            (85.0, 300.0, 397.04),
            (40.0, 28.0, 258.44),
            (40.0, 56.0, 214.43),
            (40.0, 84.0, 129.66),
            (40.0, 0.0, 293.22),
            (60.0, 86.4, 317.02),
            (60.0, 172.8, 241.30),
        ];
        for (r, d, expected) in cases {
            let len = shortest_length(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, d, PI), r);
            assert!((len - expected).abs() < 0.01, "r {r} d {d}: {len} vs {expected}");
            assert!((parallel_turn_length(d, r) - expected).abs() < 0.01, "closed form r {r} d {d}");
        }
    }

    #[test]
    fn general_configurations() {
        let cases = [
            ((0.0, 0.0, 90.0), (200.0, 100.0, -45.0), 50.0, Word::Rsr, 249.424),
            ((10.0, 20.0, 30.0), (-50.0, 60.0, 200.0), 25.0, Word::Lsl, 113.464),
            ((0.0, 0.0, 0.0), (30.0, 10.0, 180.0), 40.0, Word::Rlr, 275.441),
            ((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 40.0, Word::Lsl, 100.000),
        ];
        for (a, b, r, word, expected) in cases {
            let p = shortest(deg(a), deg(b), r);
            assert_eq!(p.word, word, "{a:?} → {b:?}");
            assert!((p.length() - expected).abs() < 1e-3, "{a:?} → {b:?}: {}", p.length());
        }
        // every feasible word of the first case
        let lengths: Vec<(Word, f64)> = all_words(deg((0.0, 0.0, 90.0)), deg((200.0, 100.0, -45.0)), 50.0).iter().map(|p| (p.word, p.length())).collect();
        for (word, expected) in [(Word::Lsl, 826.339), (Word::Lsr, 551.009), (Word::Rlr, 602.477), (Word::Rsl, 542.022), (Word::Rsr, 249.424)] {
            let got = lengths.iter().find(|(w, _)| *w == word).map(|x| x.1);
            assert!(got.is_some_and(|l| (l - expected).abs() < 1e-3), "{word:?}: {got:?}");
        }
    }

    #[test]
    fn samples_keep_the_chord_error_small() {
        let p = shortest(Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 75.0, PI), 85.0);
        let pts = p.sample(0.2);
        assert_eq!(pts[0], Coord { x: 0.0, y: 0.0 });
        let last = *pts.last().unwrap();
        assert!((last.x).abs() < 1e-6 && (last.y - 75.0).abs() < 1e-6);
        // each chord spans at most 7.9° of an 85 m arc
        let max_chord = 2.0 * 85.0 * (7.9f64.to_radians() / 2.0).sin();
        assert!(pts.windows(2).all(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y) <= max_chord + 1e-6));
        let sampled: f64 = pts.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum();
        assert!(sampled <= p.length() && sampled > p.length() * 0.999);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]
        /// Arc points found by rotation lie where the closed form puts them.
        #[test]
        fn samples_lie_on_the_path(q0 in pose(), q1 in pose(), r in prop::sample::select(vec![1.0, 10.0, 85.0])) {
            let path = shortest(q0, q1, r);
            let pts = path.sample(0.2);
            let mut expected = vec![q0.coord()];
            let mut q = q0;
            for (part, s) in path.segments().into_iter().filter(|&(_, s)| s > 0.0) {
                let k = if part == Part::S { 1 } else { ((s / r) / (2.0 * (1.0 - 0.2 / r).acos()).min(10f64.to_radians())).ceil().max(1.0) as usize };
                expected.extend((1..=k).map(|i| advance(q, part, s * i as f64 / k as f64, r).coord()));
                q = advance(q, part, s, r);
            }
            prop_assert_eq!(pts.len(), expected.len());
            for (p, e) in pts.iter().zip(&expected) {
                prop_assert!((p.x - e.x).hypot(p.y - e.y) < 1e-9, "{:?} instead of {:?}", p, e);
            }
        }

        /// The straight leg is one leg of the samples, and there is one exactly when the
        /// middle part is a straight of some length.
        #[test]
        fn the_straight_leg_is_a_leg_of_the_samples(q0 in pose(), q1 in pose(), r in prop::sample::select(vec![1.0, 10.0, 85.0])) {
            for path in all_words(q0, q1, r) {
                let pts = path.sample(0.2);
                let has_straight = path.word.parts()[1] == Part::S && path.params[1] > 0.0;
                match path.straight() {
                    Some([a, b]) => {
                        let close = |p: Coord, q: Coord| (p.x - q.x).hypot(p.y - q.y) < 1e-9;
                        prop_assert!(has_straight);
                        prop_assert!(pts.windows(2).any(|w| close(w[0], a) && close(w[1], b)), "{:?} is not a leg of {:?}", [a, b], pts);
                    }
                    None => prop_assert!(!has_straight),
                }
            }
        }
    }

    fn pose() -> impl Strategy<Value = Pose> {
        (0.0..1000.0f64, 0.0..1000.0f64, -PI..PI).prop_map(|(x, y, t)| Pose::new(x, y, t))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        #[test]
        fn words_reach_the_end_pose_and_the_shortest_is_shortest(q0 in pose(), q1 in pose(), r in prop::sample::select(vec![1.0, 10.0, 85.0, 300.0])) {
            let words = all_words(q0, q1, r);
            prop_assert!(!words.is_empty());
            let best = shortest(q0, q1, r);
            for w in &words {
                let end = w.end_pose();
                prop_assert!((end.x - q1.x).hypot(end.y - q1.y) <= 1e-6 * r.max(1.0), "{:?} misses by {}", w.word, (end.x - q1.x).hypot(end.y - q1.y));
                prop_assert!(angle_gap(end.theta, q1.theta) <= 1e-9, "{:?} heading off by {}", w.word, angle_gap(end.theta, q1.theta));
                prop_assert!(best.length() <= w.length() + 1e-9);
            }
            // the floors that let `shortest` skip words are below the words' lengths, and the
            // skipping picks what pricing every word picks: the first of the shortest
            let n = normalise(q0, q1, r);
            for w in &words {
                prop_assert!(n.floor(w.word) * r <= w.length() + 1e-9 * r, "{:?}: floor {} above {}", w.word, n.floor(w.word) * r, w.length());
            }
            let least = words.iter().map(DubinsPath::length).fold(f64::INFINITY, f64::min);
            prop_assert_eq!(Some(best.word), words.iter().find(|w| w.length() == least).map(|w| w.word));
            let back = shortest_length(q1.reversed(), q0.reversed(), r);
            prop_assert!((back - best.length()).abs() <= 1e-6 * r.max(1.0), "reversal: {} vs {}", back, best.length());
            let d = (q1.x - q0.x).hypot(q1.y - q0.y);
            prop_assert!(best.length() >= d - 1e-9 && best.length() <= d + 4.0 * PI * r + 1e-9);
            // every sampled point of every word lies in its bounding box
            for w in &words {
                let b = w.bounds();
                let inside = |p: &Coord| p.x >= b.min().x - 1e-6 && p.x <= b.max().x + 1e-6 && p.y >= b.min().y - 1e-6 && p.y <= b.max().y + 1e-6;
                prop_assert!(w.sample(0.01 * r).iter().all(inside), "{:?} leaves its bounds", w.word);
            }
        }
    }
}
