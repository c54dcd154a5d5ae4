//! Turn stage: how the vehicle gets from the end of one line to the start of the next.
//!
//! A multirotor stops and flies straight ([`TurnModel::Straight`]); a fixed-wing aircraft
//! flies the shortest [`dubins`] path for its turning radius; a ground vehicle chooses among
//! [`ground`] manoeuvres (Dubins words, the [`fishtail`] when it may reverse), planned on the
//! [`continuous_curvature`] radius when its steering is slow.

pub mod climb;
pub mod continuous_curvature;
pub mod dubins;
pub mod fishtail;
pub mod ground;

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
