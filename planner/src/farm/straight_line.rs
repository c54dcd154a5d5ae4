//! Transits in a straight line (the great circle), for farms whose roads the request leaves out.

use geo::{Distance, Haversine, Point};
use rayon::prelude::*;

use super::{LonLat, Transit};

/// Between any two places, the great-circle distance.
///
/// ```
/// use coverplan_planner::farm::{StraightLine, Transit};
///
/// let d = StraightLine.distances(&[[0.0, 0.0], [0.0, 0.01]]);
/// assert!((d[1] - 1_112.0).abs() < 2.0 && d[0] == 0.0);
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct StraightLine;

impl Transit for StraightLine {
    fn distances(&self, places: &[LonLat]) -> Vec<f64> {
        let n = places.len();
        (0..n * n).into_par_iter().map(|k| Haversine.distance(Point::from(places[k / n]), Point::from(places[k % n]))).collect()
    }
}
