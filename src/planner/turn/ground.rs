//! A ground vehicle's ways from the end of one swath to the start of another, shortest
//! first: every Dubins word and, when it may reverse, the fishtail; each with its shape. The
//! route stage keeps the first that stays where turns are allowed.

use geo::Coord;

use super::CHORD_TOLERANCE_M;
use super::dubins::{DubinsPath, Part, Pose, all_words};
use super::fishtail::fishtail;
use crate::path::TurnShape;

/// One way to turn, its points drawn only when asked for (most candidates are rejected or
/// never looked at).
#[derive(Debug, Clone, PartialEq)]
pub struct Manoeuvre {
    path: Path,
    pub length: f64,
    pub shape: TurnShape,
}

#[derive(Debug, Clone, PartialEq)]
enum Path {
    Dubins(DubinsPath, Coord),
    Drawn(Vec<Coord>),
}

impl Manoeuvre {
    /// The points, first and last exactly the two poses.
    pub fn points(&self) -> Vec<Coord> {
        match &self.path {
            Path::Dubins(word, to) => {
                let mut points = word.sample(CHORD_TOLERANCE_M);
                *points.last_mut().expect("a sampled path has points") = *to;
                points
            }
            Path::Drawn(points) => points.clone(),
        }
    }
}

/// Every turn from `from` to `to` on radius `r`, shortest first.
pub fn manoeuvres(from: Pose, to: Pose, r: f64, reverse_allowed: bool) -> Vec<Manoeuvre> {
    let mut out: Vec<Manoeuvre> = all_words(from, to, r)
        .into_iter()
        .map(|w| {
            let shape = if w.word.parts()[1] == Part::S { TurnShape::U } else { TurnShape::Omega };
            Manoeuvre { length: w.length(), shape, path: Path::Dubins(w, to.coord()) }
        })
        .collect();
    if reverse_allowed && let Some((points, length, reverses)) = fishtail(from, to, r, CHORD_TOLERANCE_M) {
        out.push(Manoeuvre { path: Path::Drawn(points), length, shape: if reverses { TurnShape::Fishtail } else { TurnShape::U } });
    }
    out.sort_by(|a, b| a.length.total_cmp(&b.length));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn close_lines_take_an_omega_forward_and_a_fishtail_in_reverse() {
        let (from, to) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.0, 6.0, PI));
        let forward = manoeuvres(from, to, 7.0, false);
        assert_eq!(forward[0].shape, TurnShape::Omega);
        let reversing = manoeuvres(from, to, 7.0, true);
        assert_eq!(reversing[0].shape, TurnShape::Fishtail);
        assert!(reversing[0].length < forward[0].length);
        // a turning diameter apart or more: a U
        assert_eq!(manoeuvres(from, Pose::new(0.0, 20.0, PI), 7.0, false)[0].shape, TurnShape::U);
    }
}
