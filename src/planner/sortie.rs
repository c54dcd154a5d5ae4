//! Battery stage: a plan that needs more energy than one battery gives (minus its reserve) is
//! split into sorties (docs/methods.md, energy §9, seed 000 §5.3). Each leaves home, flies a contiguous
//! run of the route's sweep lines and returns home; the next resumes where it stopped.
//!
//! The cut is greedy: each sortie takes as many lines as its battery allows, which gives the
//! fewest sorties for the route's order when connections obey the triangle inequality. Each
//! candidate sortie is priced by the energy model on its real path (home legs included),
//! because a multirotor's energy is not additive over legs.

use geo::Coord;
use serde::{Deserialize, Serialize};

use super::error::{InputError, PlanError};
use super::path::{FlightPath, PieceKind};
use super::turn::dubins::Pose;

/// The figures of one sortie.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct SortieTotals {
    /// 1-based, in flight order.
    pub sortie: usize,
    pub sweep_lines: usize,
    pub length_m: f64,
    pub duration_s: f64,
    pub energy_j: f64,
    /// Share of the usable battery energy this sortie needs.
    pub battery_used: f64,
}

/// What splitting needs from the rest of the planner.
pub struct Budget<'a> {
    pub home: Option<Coord>,
    /// Energy one sortie may use, J.
    pub usable_j: f64,
    pub max_sorties: usize,
    /// A clear connection between two poses (turn arcs included for a fixed-wing aircraft).
    pub connect: &'a dyn Fn(Pose, Pose) -> Option<Vec<Coord>>,
    /// Energy of a whole sortie, take-off and landing included.
    pub energy: &'a dyn Fn(&FlightPath) -> f64,
}

fn heading(a: Coord, b: Coord) -> f64 {
    (b.y - a.y).atan2(b.x - a.x)
}

impl Budget<'_> {
    /// The route split into sorties; the route itself when one battery suffices.
    pub fn split(&self, route: &FlightPath) -> Result<Vec<FlightPath>, PlanError> {
        let needed = (self.energy)(route);
        if needed <= self.usable_j {
            return Ok(vec![route.clone()]);
        }
        let Some(home) = self.home else {
            return Err(InputError::new(
                "home_missing",
                "/home",
                format!(
                    "this plan needs {:.0} kJ but one battery gives {:.0} kJ above its reserve; give the mission a home so that the plan can be split into sorties",
                    needed / 1000.0,
                    self.usable_j / 1000.0
                ),
            )
            .into());
        };
        let sweeps: Vec<usize> = route.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep).map(|(i, _)| i).collect();
        let m = sweeps.len();
        let mut sorties = Vec::new();
        let mut i = 0;
        while i < m {
            let block = |j: usize| self.sortie(route, home, sweeps[i], sweeps[j - 1]);
            let fits = |j: usize| -> Result<bool, PlanError> { Ok((self.energy)(&block(j)?) <= self.usable_j) };
            if !fits(i + 1)? {
                return Err(PlanError::Infeasible(format!(
                    "sweep line {} alone, flown from home and back, needs more than one battery's {:.0} kJ above its reserve: use a vehicle with a larger battery or a smaller field",
                    i + 1,
                    self.usable_j / 1000.0
                )));
            }
            // the last block end that fits: gallop, then bisect
            let (mut good, mut step) = (i + 1, 1);
            while good + step <= m && fits(good + step)? {
                good += step;
                step *= 2;
            }
            let mut bad = (good + step).min(m + 1);
            while bad - good > 1 {
                let mid = (good + bad) / 2;
                if fits(mid)? { good = mid } else { bad = mid }
            }
            if sorties.len() == self.max_sorties {
                return Err(PlanError::Infeasible(format!(
                    "the plan needs more than max_sorties = {} sorties ({:.0} kJ in all, {:.0} kJ per battery)",
                    self.max_sorties,
                    needed / 1000.0,
                    self.usable_j / 1000.0
                )));
            }
            sorties.push(block(good)?);
            i = good;
        }
        Ok(sorties)
    }

    /// Home → the route's pieces `first..=last` → home.
    fn sortie(&self, route: &FlightPath, home: Coord, first: usize, last: usize) -> Result<FlightPath, PlanError> {
        let (a, b) = (&route.pieces[first], &route.pieces[last]);
        let entry = Pose::at(a.start(), heading(a.points[0], a.points[1]));
        let exit_dir = heading(b.points[b.points.len() - 2], b.end());
        let unreachable = || PlanError::Infeasible(format!("no clear path joins home to sweep line at ({:.1}, {:.1}) in the local frame", a.start().x, a.start().y));
        let out = (self.connect)(Pose::at(home, heading(home, entry.coord())), entry).ok_or_else(unreachable)?;
        let back = (self.connect)(Pose::at(b.end(), exit_dir), Pose::at(home, heading(b.end(), home))).ok_or_else(unreachable)?;
        let mut path = FlightPath::default();
        path.push(PieceKind::Transit, out, 0.0);
        path.pieces.extend_from_slice(&route.pieces[first..=last]);
        path.push(PieceKind::Transit, back, 0.0);
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(n: usize, length: f64) -> FlightPath {
        let c = |x, y| Coord { x, y };
        let mut p = FlightPath::default();
        for k in 0..n {
            let y = k as f64 * 10.0;
            let (a, b) = if k % 2 == 0 { (c(0.0, y), c(length, y)) } else { (c(length, y), c(0.0, y)) };
            if k > 0 {
                p.push(PieceKind::Turn, vec![p.end().unwrap(), a], 0.0);
            }
            p.push(PieceKind::Sweep, vec![a, b], 5.0);
        }
        p
    }

    #[test]
    fn sorties_stay_within_the_battery_and_fly_every_line_once_in_order() {
        let route = lines(40, 300.0);
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0; // 10 J/m
        let budget = Budget { home: Some(Coord { x: -50.0, y: 0.0 }), usable_j: 30_000.0, max_sorties: 20, connect: &connect, energy: &energy };
        let sorties = budget.split(&route).unwrap();
        assert!(sorties.len() > 1);
        for s in &sorties {
            assert!(energy(s) <= 30_000.0);
            assert_eq!(s.pieces.first().unwrap().start(), Coord { x: -50.0, y: 0.0 });
            assert_eq!(s.end(), Some(Coord { x: -50.0, y: 0.0 }));
        }
        let flown: Vec<Coord> = sorties.iter().flat_map(|s| s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).map(|p| p.start())).collect();
        let planned: Vec<Coord> = route.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).map(|p| p.start()).collect();
        assert_eq!(flown, planned);
        // greedy: no sortie could have taken the next line too
        let sweeps: Vec<usize> = route.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep).map(|(i, _)| i).collect();
        let mut first = 0;
        for s in &sorties[..sorties.len() - 1] {
            let n = s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count();
            let longer = budget.sortie(&route, Coord { x: -50.0, y: 0.0 }, sweeps[first], sweeps[first + n]).unwrap();
            assert!(energy(&longer) > 30_000.0);
            first += n;
        }
        let no_home = Budget { home: None, ..budget };
        assert!(matches!(no_home.split(&route), Err(PlanError::Input(e)) if e.code == "home_missing"));
        let tiny = Budget { usable_j: 1_000.0, ..no_home };
        assert!(tiny.split(&lines(1, 10.0)).is_ok(), "a plan that fits needs no home");
    }
}
