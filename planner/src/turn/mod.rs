//! Turn stage: how the vehicle gets from the end of one line to the start of the next.
//!
//! A multirotor stops and flies straight ([`TurnModel::Straight`]); a fixed-wing aircraft
//! flies the shortest [`dubins`] path for its turning radius; a ground vehicle chooses among
//! [`ground`] manoeuvres: Dubins words, with reversing the [`reeds_shepp`] words and the
//! [`fishtail`], and with slow steering [`continuous_curvature`] turns in place of arcs.

pub mod climb;
pub mod continuous_curvature;
pub mod dubins;
pub mod fishtail;
pub mod ground;
pub mod reeds_shepp;
pub mod trochoid;

use geo::Coord;

use dubins::{Pose, shortest};

/// Chord tolerance of sampled arcs in the output (docs/methods.md, dubins §8).
pub const CHORD_TOLERANCE_M: f64 = 0.2;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TurnModel {
    /// Stop, turn on the spot, fly straight.
    Straight,
    /// Forward only, turning radius at least this many metres.
    Dubins(f64),
}

impl TurnModel {
    /// Length of the free-space connection between two poses.
    pub fn length(&self, from: Pose, to: Pose) -> f64 {
        match *self {
            TurnModel::Straight => (to.x - from.x).hypot(to.y - from.y),
            TurnModel::Dubins(r) => shortest(from, to, r).length(),
        }
    }

    /// The free-space connection as points, first and last exactly the two positions.
    pub fn points(&self, from: Pose, to: Pose) -> Vec<Coord> {
        match *self {
            TurnModel::Straight => vec![from.coord(), to.coord()],
            TurnModel::Dubins(r) => {
                let mut pts = shortest(from, to, r).sample(CHORD_TOLERANCE_M);
                *pts.last_mut().expect("a sampled path has points") = to.coord();
                pts
            }
        }
    }
}

/// The stretch of the line `a → b` whose ends a vehicle of turning radius `r` can turn at:
/// each end pulled back in steps of `r / 8` until `can_turn(at, out)` holds (`out`: the unit
/// direction of leaving the line there); `None` when no more than `min_left` metres are left.
pub fn turnable_stretch(a: Coord, b: Coord, r: f64, min_left: f64, can_turn: impl Fn(Coord, Coord) -> bool) -> Option<(Coord, Coord)> {
    let length = crate::geom::distance(a, b);
    if length == 0.0 {
        return None;
    }
    let dir = (b - a) / length;
    let step = r / 8.0;
    let mut from_a = 0.0;
    while from_a <= length && !can_turn(a + dir * from_a, -dir) {
        from_a += step;
    }
    let mut from_b = 0.0;
    while length - from_b > from_a && !can_turn(b - dir * from_b, dir) {
        from_b += step;
    }
    (length - from_b - from_a > min_left).then(|| (a + dir * from_a, b - dir * from_b))
}

/// The two half circles of radius `r` from `at`, leaving in the unit direction `out`: turning
/// left, then right, each 17 points.
pub fn half_circles(at: Coord, out: Coord, r: f64) -> [Vec<Coord>; 2] {
    [1.0, -1.0].map(|side: f64| {
        let centre = at + Coord { x: -out.y, y: out.x } * (side * r);
        let phase = (at.y - centre.y).atan2(at.x - centre.x);
        (0..=16)
            .map(|k| {
                let phi = phase + side * std::f64::consts::PI * k as f64 / 16.0;
                centre + Coord { x: phi.cos(), y: phi.sin() } * r
            })
            .collect()
    })
}
