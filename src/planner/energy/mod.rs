//! Energy/time stage: speed, duration and energy of every piece of a flight path.

pub mod constant_power;

use super::path::FlightPath;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PieceEstimate {
    pub speed_mps: f64,
    pub duration_s: f64,
    pub energy_j: f64,
}

pub trait EnergyModel {
    /// One estimate per piece of `path`, in order.
    fn estimate(&self, path: &FlightPath) -> Vec<PieceEstimate>;
}

/// Heading change in radians (0..π) at the joint of `a→b` and `b→c`.
pub fn heading_change(a: geo::Coord, b: geo::Coord, c: geo::Coord) -> f64 {
    let (u, v) = (b - a, c - b);
    let cross = u.x * v.y - u.y * v.x;
    let dot = u.x * v.x + u.y * v.y;
    cross.atan2(dot).abs()
}
