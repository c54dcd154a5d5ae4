//! A ground vehicle's ways from the end of one swath to the start of another, shortest
//! first; the route stage keeps the first that stays where turns are allowed.
//!
//! | steering | forward only | may reverse |
//! |---|---|---|
//! | instant | the Dubins words | the Dubins and Reeds–Shepp words, the fishtail |
//! | at most `σ` per metre | the CC-Dubins words | the CC-Dubins words, the fishtail of CC turns |
//!
//! A turn with a reversing part is a fishtail; one with a straight, or whose middle turn is
//! slight, a U; the rest omegas.

use geo::Coord;

use super::continuous_curvature::{CcPath, CcTurns};
use super::dubins::{self, DubinsPath, Part, Pose, all_words};
use super::fishtail::{QuarterTurn, fishtail};
use super::reeds_shepp::{self, ReedsSheppPath};
use super::{CHORD_TOLERANCE_M, half_circles};
use crate::path::TurnShape;

/// One way to turn, its points drawn only when asked for (most candidates are rejected or
/// never looked at).
#[derive(Debug, Clone, PartialEq)]
pub struct Manoeuvre {
    path: Path,
    to: Coord,
    pub length: f64,
    pub shape: TurnShape,
}

#[derive(Debug, Clone, PartialEq)]
enum Path {
    Dubins(DubinsPath),
    ReedsShepp(ReedsSheppPath),
    Clothoid(CcPath),
    Drawn(Vec<Coord>),
}

impl Manoeuvre {
    /// The points, first and last exactly the two poses.
    pub fn points(&self) -> Vec<Coord> {
        let mut points = match &self.path {
            Path::Dubins(word) => word.sample(CHORD_TOLERANCE_M),
            Path::ReedsShepp(word) => word.sample(CHORD_TOLERANCE_M),
            Path::Clothoid(word) => word.sample(CHORD_TOLERANCE_M),
            Path::Drawn(points) => points.clone(),
        };
        *points.last_mut().expect("a path has points") = self.to;
        points
    }

    /// The straight leg of a Dubins word, one leg of [`Self::points`].
    pub fn straight(&self) -> Option<[Coord; 2]> {
        match &self.path {
            // a straight that ends the word ends on the exact pose, as the points do
            Path::Dubins(word) => word.straight().map(|[a, b]| [a, if word.params[2] > 0.0 { b } else { self.to }]),
            _ => None,
        }
    }
}

/// How a ground vehicle steers: its tightest radius, whether it may reverse, and how fast its
/// curvature may change (continuous-curvature turns) when that is limited.
#[derive(Debug, Clone, PartialEq)]
pub struct Steering {
    radius: f64,
    reverse: bool,
    cc: Option<CcTurns>,
    quarter: QuarterTurn,
    /// Half turns left and right from the origin facing +x.
    half_turns: [Vec<Coord>; 2],
}

impl Steering {
    pub fn new(radius: f64, reverse: bool, curvature_rate: Option<f64>) -> Self {
        let cc = curvature_rate.map(|sigma| CcTurns::new(radius, sigma));
        let quarter = match cc {
            Some(cc) => {
                let (points, length) = cc.quarter_turn(CHORD_TOLERANCE_M);
                QuarterTurn { points, reach: cc.quarter_reach(), length }
            }
            None => QuarterTurn::circle(radius, CHORD_TOLERANCE_M),
        };
        let half_turns = match cc {
            Some(cc) => [1.0, -1.0].map(|side| cc.half_turn(side, CHORD_TOLERANCE_M)),
            None => half_circles(Coord { x: 0.0, y: 0.0 }, Coord { x: 1.0, y: 0.0 }, radius),
        };
        Steering { radius, reverse, cc, quarter, half_turns }
    }

    /// How far beyond a swath's end a turn reaches: the radius, or the continuous-curvature
    /// half turn's reach.
    pub fn reach_ahead(&self) -> f64 {
        self.cc.map_or(self.radius, |cc| cc.reach_ahead())
    }

    /// The half turns to the left and to the right from `at`, leaving in the unit direction
    /// `out`: the room a turn there needs.
    pub fn half_turns(&self, at: Coord, out: Coord) -> [Vec<Coord>; 2] {
        self.half_turns.each_ref().map(|turn| turn.iter().map(|p| Coord { x: at.x + p.x * out.x - p.y * out.y, y: at.y + p.x * out.y + p.y * out.x }).collect())
    }

    /// Whether the vehicle may reverse (and so turn back on the spot, by a fishtail).
    pub fn reverses(&self) -> bool {
        self.reverse
    }

    /// The radius of the circle every turn keeps within: the turning radius, or with slow
    /// steering the circle bounding continuous-curvature turns.
    pub fn bounding_radius(&self) -> f64 {
        self.cc.map_or(self.radius, |cc| cc.outer_radius())
    }

    /// Every turn from `from` to `to`, shortest first.
    pub fn manoeuvres(&self, from: Pose, to: Pose) -> Vec<Manoeuvre> {
        let mut out = self.forward_words(from, to);
        if self.reverse {
            if self.cc.is_none() {
                out.extend(reeds_shepp::all_paths(from, to, self.radius).into_iter().map(|w| {
                    let shape = if w.reverses() {
                        TurnShape::Fishtail
                    } else if w.has_straight() {
                        TurnShape::U
                    } else {
                        TurnShape::Omega
                    };
                    Manoeuvre { length: w.length(), shape, path: Path::ReedsShepp(w), to: to.coord() }
                }));
            }
            if let Some((points, length, reverses)) = fishtail(from, to, &self.quarter) {
                out.push(Manoeuvre { path: Path::Drawn(points), to: to.coord(), length, shape: if reverses { TurnShape::Fishtail } else { TurnShape::U } });
            }
        }
        out.sort_by(|a, b| a.length.total_cmp(&b.length));
        out
    }

    fn forward_words(&self, from: Pose, to: Pose) -> Vec<Manoeuvre> {
        let to_coord = to.coord();
        match &self.cc {
            None => all_words(from, to, self.radius)
                .into_iter()
                .map(|w| {
                    let shape = if w.word.parts()[1] == Part::S { TurnShape::U } else { TurnShape::Omega };
                    Manoeuvre { length: w.length(), shape, path: Path::Dubins(w), to: to_coord }
                })
                .collect(),
            Some(cc) => cc
                .words(from, to)
                .into_iter()
                .map(|w| Manoeuvre { length: w.length, shape: if w.is_omega() { TurnShape::Omega } else { TurnShape::U }, path: Path::Clothoid(w), to: to_coord })
                .collect(),
        }
    }

    /// The shortest forward way from `from` to `to` in open ground (ramps, transits).
    pub fn forward(&self, from: Pose, to: Pose) -> Manoeuvre {
        self.forward_words(from, to).into_iter().min_by(|a, b| a.length.total_cmp(&b.length)).expect("LSL or RSR is always drivable")
    }

    /// No way from `from` to `to` is shorter: the shortest path on the tightest radius,
    /// reversing where allowed (continuous-curvature turns are never shorter).
    pub fn floor(&self, from: Pose, to: Pose) -> f64 {
        if self.reverse { reeds_shepp::shortest(from, to, self.radius).length() } else { dubins::shortest(from, to, self.radius).length() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn close_lines_take_an_omega_forward_and_a_reversing_turn_when_allowed() {
        let (from, to) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 6.0, PI));
        let forward = Steering::new(7.0, false, None).manoeuvres(from, to);
        assert_eq!(forward[0].shape, TurnShape::Omega);
        let reversing = Steering::new(7.0, true, None).manoeuvres(from, to);
        assert_eq!(reversing[0].shape, TurnShape::Fishtail);
        assert!(reversing[0].length < forward[0].length);
        // the Reeds–Shepp words beat the three-point turn here
        let three_point = reversing.iter().find(|m| matches!(m.path, Path::Drawn(_))).unwrap();
        assert!(reversing[0].length < three_point.length - 1.0, "{} vs {}", reversing[0].length, three_point.length);
        // a turning diameter apart or more: a U
        assert_eq!(Steering::new(7.0, false, None).manoeuvres(from, Pose::new(0.0, 20.0, PI))[0].shape, TurnShape::U);
    }

    #[test]
    fn slow_steering_turns_are_longer_and_every_way_ends_on_the_pose() {
        let (from, to) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 20.0, PI));
        for reverse in [false, true] {
            let sharp = Steering::new(7.0, reverse, None);
            let slow = Steering::new(7.0, reverse, Some(0.02));
            assert!(slow.bounding_radius() > sharp.bounding_radius());
            let (a, b) = (sharp.manoeuvres(from, to), slow.manoeuvres(from, to));
            assert!(b[0].length > a[0].length);
            assert!(slow.floor(from, to) <= b[0].length && sharp.floor(from, to) <= a[0].length + 1e-9);
            for m in a.iter().chain(&b) {
                let p = m.points();
                assert_eq!((p[0], *p.last().unwrap()), (from.coord(), to.coord()));
            }
        }
        // with reversing and slow steering the fishtail is made of continuous-curvature turns
        let slow = Steering::new(7.0, true, Some(0.02)).manoeuvres(from, Pose::new(0.0, 6.0, PI));
        assert!(slow.iter().any(|m| m.shape == TurnShape::Fishtail));
    }
}
