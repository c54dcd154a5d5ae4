//! Battery stage: a plan that needs more energy than one battery gives (minus its reserve) is
//! split into sorties (docs/methods.md, energy §9, seed 000 §5.3). Each leaves home, flies a contiguous
//! run of the route's sweep lines and returns home; the next resumes where it stopped. With
//! landing sites, a sortie may land at one instead, and the next takes off there.
//!
//! The cut is greedy: each sortie takes as many lines as its battery allows, which gives the
//! fewest sorties for the route's order when connections obey the triangle inequality. Each
//! candidate sortie is priced by the energy model on its real path (home legs included),
//! because a multirotor's energy is not additive over legs.
//!
//! Without a home there is nowhere to return to: the route is flown as planned and the same
//! greedy cut marks where each battery runs out (the end of the last line it can fly), so that
//! the plan still answers how many batteries it needs.

use geo::Coord;
use serde::{Deserialize, Serialize};

use super::error::PlanError;
use super::geom::{distance, heading};
use super::path::{FlightPath, Piece, PieceKind};
use super::turn::dubins::Pose;

/// Landing places tried for each candidate sortie (the nearest to its way on): a site farther
/// than the third nearest is seldom better, and each try prices a whole sortie.
const LANDING_PLACES_TRIED: usize = 3;

/// The figures of one sortie.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct SortieTotals {
    /// 1-based, in flight order (a fleet's: each drone's in turn).
    pub sortie: usize,
    /// Fleet: the drone that flies it.
    pub vehicle: Option<usize>,
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
    /// More places than home to land and take off again (with a home only): each sortie lands
    /// at the one that serves it and the next best, and the next leaves from there.
    pub landing_sites: &'a [Coord],
    /// Where the first sortie starts when it does not leave home: an aircraft still in the air
    /// (a resumed plan's).
    pub first_from: Option<Coord>,
    /// Energy one sortie may use, J.
    pub usable_j: f64,
    /// Energy the first sortie may use (its battery part spent), J.
    pub first_usable_j: f64,
    pub max_sorties: usize,
    /// A clear connection between two poses (turn arcs included for a fixed-wing aircraft).
    pub connect: &'a dyn Fn(Pose, Pose) -> Option<Vec<Coord>>,
    /// Energy of a whole sortie, take-off and landing included.
    pub energy: &'a dyn Fn(&FlightPath) -> f64,
}

/// The route as it will be flown.
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    /// Flights from home and back; the route alone when one battery suffices or without a home.
    pub sorties: Vec<FlightPath>,
    /// Without a home: where each battery but the last runs out and is changed (the end of a
    /// sweep line), in flight order; empty when one battery suffices.
    pub battery_swaps: Vec<Coord>,
    /// Energy the whole route needs in one flight, J.
    pub needed_j: f64,
}

/// The largest `j` in `from + 1..=last` with `fits(j)`, given `fits(from + 1)`: gallop, then bisect.
fn last_fitting(from: usize, last: usize, fits: impl Fn(usize) -> Result<bool, PlanError>) -> Result<usize, PlanError> {
    let (mut good, mut step) = (from + 1, 1);
    while good + step <= last && fits(good + step)? {
        good += step;
        step *= 2;
    }
    let mut bad = (good + step).min(last + 1);
    while bad - good > 1 {
        let mid = (good + bad) / 2;
        if fits(mid)? { good = mid } else { bad = mid }
    }
    Ok(good)
}

impl Budget<'_> {
    /// The route split into sorties (or, without a home, marked where batteries run out).
    pub fn split(&self, route: &FlightPath) -> Result<Split, PlanError> {
        self.split_between(route, &[])
    }

    /// The route split into sorties that each end before one of `breaks` (piece indices: a
    /// resumed plan keeps its original's sortie ends), each stretch between them split as
    /// [`Budget::split`] splits a route; no breaks: that split.
    pub fn split_between(&self, route: &FlightPath, breaks: &[usize]) -> Result<Split, PlanError> {
        let needed_j = (self.energy)(route);
        if needed_j <= self.first_usable_j {
            return Ok(Split { sorties: vec![route.clone()], battery_swaps: vec![], needed_j });
        }
        let sweeps: Vec<usize> = route.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep).map(|(i, _)| i).collect();
        let Some(home) = self.home else {
            let battery_swaps = self.swaps(route, &sweeps)?.into_iter().map(|k| route.pieces[k].end()).collect();
            return Ok(Split { sorties: vec![route.clone()], battery_swaps, needed_j });
        };
        let mut sorties = Vec::new();
        let (mut first, mut base) = (0, home);
        for end in breaks.iter().copied().chain([route.pieces.len()]) {
            let stretch: Vec<usize> = sweeps.iter().copied().filter(|&k| first <= k && k < end).collect();
            base = self.greedy(route, (home, base), &stretch, needed_j, &mut sorties)?;
            first = end;
        }
        Ok(Split { sorties, battery_swaps: vec![], needed_j })
    }

    /// Adds the sorties that fly the lines `sweeps` (piece indices, in order) to `sorties`, each
    /// with as many lines as its battery allows, the first leaving from `base`; returns where
    /// the last one lands.
    ///
    /// Whether a block fits is not monotone in its length: a block whose last line ends far
    /// from home, or with no clear way home (a fixed wing beside a zone), may not fit where a
    /// longer one does. The block without its way home is monotone (each line adds energy), so
    /// it bounds the search, and the blocks below that bound are tried from the longest down.
    fn greedy(&self, route: &FlightPath, (home, mut base): (Coord, Coord), sweeps: &[usize], needed_j: f64, sorties: &mut Vec<FlightPath>) -> Result<Coord, PlanError> {
        let m = sweeps.len();
        let mut i = 0;
        while i < m {
            let (from, allowed_j) = if sorties.is_empty() { (self.first_from.unwrap_or(home), self.first_usable_j) } else { (base, self.usable_j) };
            // the sortie of lines i..j landing at the best place it reaches on its battery (or,
            // when none, at the first place tried), and whether it fits
            let landed = |j: usize| -> Result<(FlightPath, Coord, bool), PlanError> {
                let next = sweeps.get(j).map(|&k| route.pieces[k].start());
                let mut first = None;
                for place in self.landing_places(home, route.pieces[sweeps[j - 1]].end(), next) {
                    let tried = self.sortie(route, from, place, sweeps[i], sweeps[j - 1]).map(|path| {
                        let fits = (self.energy)(&path) <= allowed_j;
                        (path, place, fits)
                    });
                    if matches!(tried, Ok((_, _, true))) {
                        return tried;
                    }
                    first.get_or_insert(tried);
                }
                first.expect("home is always a place to land")
            };
            let block = |j: usize| landed(j).map(|(path, _, _)| path);
            let fits = |j: usize| landed(j).is_ok_and(|(_, _, fits)| fits);
            let reaches = |j: usize| -> Result<bool, PlanError> { Ok((self.energy)(&self.outbound(route, from, sweeps[i], sweeps[j - 1])?) <= allowed_j) };
            let bound = if reaches(i + 1)? { last_fitting(i, m, reaches)? } else { i };
            let Some(good) = (i + 1..=bound).rev().find(|&j| fits(j)) else {
                let alone = block(i + 1)?;
                let line = route.pieces[..sweeps[i]].iter().filter(|p| p.kind == PieceKind::Sweep).count() + 1;
                return Err(PlanError::Infeasible(if sorties.is_empty() && allowed_j < self.usable_j && (self.energy)(&alone) <= self.usable_j {
                    format!(
                        "the battery left ({:.0} kJ above the reserve) does not fly the next line and back home: change the battery and resume from home",
                        allowed_j.max(0.0) / 1000.0
                    )
                } else if self.landing_sites.is_empty() {
                    format!(
                        "sweep line {line} alone, flown from home and back, needs more than one battery's {:.0} kJ above its reserve: use a vehicle with a larger battery or a smaller field",
                        self.usable_j / 1000.0
                    )
                } else {
                    format!(
                        "sweep line {line} alone, flown from where its sortie takes off to the landing site nearest its end, needs more than one battery's {:.0} kJ above its reserve: add landing sites nearer to it, or use a vehicle with a larger battery",
                        self.usable_j / 1000.0
                    )
                }));
            };
            if sorties.len() == self.max_sorties {
                return Err(PlanError::Infeasible(format!(
                    "the plan needs more than max_sorties = {} sorties ({:.0} kJ in all, {:.0} kJ per battery)",
                    self.max_sorties,
                    needed_j / 1000.0,
                    self.usable_j / 1000.0
                )));
            }
            let (sortie, landed_at, _) = landed(good)?;
            sorties.push(sortie);
            base = landed_at;
            i = good;
        }
        Ok(base)
    }

    /// Where a sortie whose last line ends at `end` may land, best first: home alone without
    /// landing sites; else the few places nearest the way from `end` to the next sortie's
    /// first line `next` (the last sortie: nearest `end`).
    fn landing_places(&self, home: Coord, end: Coord, next: Option<Coord>) -> Vec<Coord> {
        if self.landing_sites.is_empty() {
            return vec![home];
        }
        let detour = |p: Coord| distance(end, p) + next.map_or(0.0, |n| distance(p, n));
        let mut places: Vec<Coord> = std::iter::once(home).chain(self.landing_sites.iter().copied()).collect();
        places.sort_by(|a, b| detour(*a).total_cmp(&detour(*b)));
        places.truncate(LANDING_PLACES_TRIED);
        places
    }

    /// Without a home: each battery flies on from where the last one ran out, as far as it can;
    /// the result is the piece after which each battery but the last is changed.
    fn swaps(&self, route: &FlightPath, sweeps: &[usize]) -> Result<Vec<usize>, PlanError> {
        let mut swaps: Vec<usize> = Vec::new();
        let (mut start, mut i) = (0, 0);
        let stretch = |from: usize, to: usize| FlightPath { pieces: route.pieces[from..=to].to_vec() };
        let allowed_j = |swaps: &[usize]| if swaps.is_empty() { self.first_usable_j } else { self.usable_j };
        while (self.energy)(&stretch(start, route.pieces.len() - 1)) > allowed_j(&swaps) {
            let fits = |j: usize| -> Result<bool, PlanError> { Ok((self.energy)(&stretch(start, sweeps[j - 1])) <= allowed_j(&swaps)) };
            if i == sweeps.len() || !fits(i + 1)? {
                return Err(PlanError::Infeasible(format!(
                    "the flight to sweep line {} and along it needs more than one battery's {:.0} kJ above its reserve: use a vehicle with a larger battery or a smaller field",
                    i + 1,
                    self.usable_j / 1000.0
                )));
            }
            let good = last_fitting(i, sweeps.len(), fits)?;
            swaps.push(sweeps[good - 1]);
            (start, i) = (sweeps[good - 1] + 1, good);
            if start == route.pieces.len() {
                break;
            }
        }
        Ok(swaps)
    }

    /// `from` (home) → the route's pieces `first..=last` → home.
    fn sortie(&self, route: &FlightPath, from: Coord, home: Coord, first: usize, last: usize) -> Result<FlightPath, PlanError> {
        let mut path = self.outbound(route, from, first, last)?;
        let b = &route.pieces[last];
        let exit_dir = heading(b.points[b.points.len() - 2], b.end());
        let back = (self.connect)(Pose::at(b.end(), exit_dir), Pose::at(home, heading(b.end(), home))).ok_or_else(|| unreachable(&route.pieces[first]))?;
        path.push(PieceKind::Transit, back, 0.0);
        Ok(path)
    }

    /// `from` (home) → the route's pieces `first..=last`, without the way back. Where no
    /// connection of its own reaches the first line (a fixed wing beside a zone), a route that
    /// starts at `from` lends its own way to its first line (a resumed plan's: its original's).
    fn outbound(&self, route: &FlightPath, from: Coord, first: usize, last: usize) -> Result<FlightPath, PlanError> {
        let a = &route.pieces[first];
        let entry = Pose::at(a.start(), heading(a.points[0], a.points[1]));
        let mut path = FlightPath::default();
        match (self.connect)(Pose::at(from, heading(from, entry.coord())), entry) {
            Some(out) => path.push(PieceKind::Transit, out, 0.0),
            None if leads_from(route, from, first) => path.pieces.extend_from_slice(&route.pieces[..first]),
            None => return Err(unreachable(a)),
        }
        path.pieces.extend_from_slice(&route.pieces[first..=last]);
        Ok(path)
    }
}

/// Whether the route starts at `from` and reaches piece `first` without a sweep before it.
fn leads_from(route: &FlightPath, from: Coord, first: usize) -> bool {
    let start = route.pieces.first().map(Piece::start);
    first > 0 && start.is_some_and(|s| (s.x - from.x).hypot(s.y - from.y) < 1e-6) && route.pieces[..first].iter().all(|p| p.kind != PieceKind::Sweep)
}

fn unreachable(line: &Piece) -> PlanError {
    PlanError::Infeasible(format!("no clear path joins home to sweep line at ({:.1}, {:.1}) in the local frame", line.start().x, line.start().y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 30 kJ a battery, at most 20 sorties, returning to `home`.
    fn budget<'a>(home: Option<Coord>, connect: &'a dyn Fn(Pose, Pose) -> Option<Vec<Coord>>, energy: &'a dyn Fn(&FlightPath) -> f64) -> Budget<'a> {
        Budget { home, landing_sites: &[], first_from: None, usable_j: 30_000.0, first_usable_j: 30_000.0, max_sorties: 20, connect, energy }
    }

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
    fn a_first_line_no_connection_reaches_is_flown_to_the_routes_own_way() {
        let home = Coord { x: -50.0, y: 0.0 };
        let mut route = FlightPath::default();
        // the route's own way from home to its first line, round something
        route.push(PieceKind::Transit, vec![home, Coord { x: -50.0, y: -40.0 }, Coord { x: 0.0, y: 0.0 }], 0.0);
        route.pieces.extend(lines(40, 300.0).pieces);
        let first_line = Coord { x: 0.0, y: 0.0 };
        // no connection of the vehicle's own reaches the first line's start
        let connect = |a: Pose, b: Pose| (b.coord() != first_line).then(|| vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let budget = budget(Some(home), &connect, &energy);
        let sorties = budget.split(&route).expect("split").sorties;
        assert!(sorties.len() > 1);
        assert_eq!(sorties[0].pieces[0], route.pieces[0], "the first sortie flies the route's own way there");
        // a later sortie from home has lines before it: no way of the route's to lend
        let later = lines(40, 300.0);
        assert!(budget.outbound(&later, home, 0, 0).is_err());
    }

    #[test]
    fn sorties_stay_within_the_battery_and_fly_every_line_once_in_order() {
        let route = lines(40, 300.0);
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0; // 10 J/m
        let budget = budget(Some(Coord { x: -50.0, y: 0.0 }), &connect, &energy);
        let sorties = budget.split(&route).unwrap().sorties;
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
            let home = Coord { x: -50.0, y: 0.0 };
            let longer = budget.sortie(&route, home, home, sweeps[first], sweeps[first + n]).unwrap();
            assert!(energy(&longer) > 30_000.0);
            first += n;
        }
        let tiny = Budget { usable_j: 1_000.0, first_usable_j: 1_000.0, home: None, ..budget };
        assert_eq!(tiny.split(&lines(1, 10.0)).unwrap().battery_swaps, vec![], "a plan that fits needs no home");
    }

    /// A block whose last line has no way home does not fit, and a longer one may: each sortie
    /// still takes the most lines that fit.
    #[test]
    fn a_line_with_no_way_home_does_not_end_the_sortie_early() {
        let route = lines(40, 300.0);
        let home = Coord { x: -50.0, y: 0.0 };
        // no way home from the lines' far ends (x = 300: every other line)
        let connect = |a: Pose, b: Pose| (b.coord() != home || a.x < 1.0).then(|| vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let budget = budget(Some(home), &connect, &energy);
        let sorties = budget.split(&route).unwrap().sorties;
        let sweeps: Vec<usize> = route.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep).map(|(i, _)| i).collect();
        let mut first = 0;
        for s in &sorties {
            assert!(energy(s) <= 30_000.0 && s.end() == Some(home));
            let n = s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count();
            for more in first + n..sweeps.len() {
                let longer = budget.sortie(&route, home, home, sweeps[first], sweeps[more]);
                assert!(longer.is_err() || energy(&longer.unwrap()) > 30_000.0, "a sortie of lines {first}..{} could have flown to line {more}", first + n - 1);
            }
            first += n;
        }
        assert_eq!(first, 40);
    }

    /// A long corridor's lines end to end: from home alone the far lines are out of reach;
    /// with landing sites along it each sortie lands at one and the next leaves from there.
    #[test]
    fn sorties_hop_between_landing_sites_along_a_corridor() {
        let c = |x, y| Coord { x, y };
        let mut route = FlightPath::default();
        for k in 0..60 {
            let (a, b) = (c(300.0 * k as f64, 0.0), c(300.0 * k as f64 + 290.0, 0.0));
            if k > 0 {
                route.push(PieceKind::Transit, vec![route.end().unwrap(), a], 0.0);
            }
            route.push(PieceKind::Sweep, vec![a, b], 5.0);
        }
        let home = c(-50.0, 0.0);
        let sites: Vec<Coord> = (1..=9).map(|k| c(2000.0 * k as f64, -30.0)).collect();
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let budget = Budget { max_sorties: 50, ..budget(Some(home), &connect, &energy) };
        assert!(budget.split(&route).is_err(), "from home alone the far lines are beyond one battery");
        let hopping = Budget { landing_sites: &sites, ..budget };
        let sorties = hopping.split(&route).expect("split").sorties;
        let places: Vec<Coord> = std::iter::once(home).chain(sites.iter().copied()).collect();
        let mut base = home;
        for s in &sorties {
            assert!(energy(s) <= 30_000.0);
            assert_eq!(s.pieces[0].start(), base, "each sortie leaves from where the last one landed");
            base = s.end().unwrap();
            assert!(places.contains(&base), "a sortie lands at home or a landing site, not at {base:?}");
        }
        let flown: Vec<Coord> = sorties.iter().flat_map(|s| s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).map(|p| p.start())).collect();
        let planned: Vec<Coord> = route.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).map(|p| p.start()).collect();
        assert_eq!(flown, planned);
        // each site is 30 m off the line: a sortie's ways out and back cost at most a site
        // spacing and a few metres more than its lines
        let overhead: f64 = sorties.iter().map(FlightPath::length).sum::<f64>() - route.length();
        assert!(overhead < sorties.len() as f64 * 2100.0, "{overhead:.0} m besides the route over {} sorties", sorties.len());
    }

    /// Sorties end before every break (a resumed plan's original sortie ends), and split the
    /// stretches between them as a route is split.
    #[test]
    fn no_sortie_flies_over_a_break() {
        let route = lines(40, 300.0);
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let budget = budget(Some(Coord { x: -50.0, y: 0.0 }), &connect, &energy);
        // pieces 2k are the lines, 2k + 1 the turns: breaks before lines 5 and 21
        let breaks = [9, 41];
        let sorties = budget.split_between(&route, &breaks).unwrap().sorties;
        let starts: Vec<Coord> = route.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).map(|p| p.start()).collect();
        let mut line = 0;
        for s in &sorties {
            let n = s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count();
            assert!(energy(s) <= 30_000.0);
            let crosses = |b: usize| line < b && line + n > b;
            assert!(!crosses(5) && !crosses(21), "a sortie flies lines {line} to {} over a break", line + n - 1);
            assert_eq!(s.pieces.iter().find(|p| p.kind == PieceKind::Sweep).unwrap().start(), starts[line]);
            line += n;
        }
        assert_eq!(line, 40);
        assert!(sorties.len() > budget.split(&route).unwrap().sorties.len(), "the breaks cost sorties here");
    }

    /// A resumed plan's first sortie starts where the aircraft is, on the battery it has left;
    /// the next ones leave home on fresh ones.
    #[test]
    fn a_first_sortie_in_the_air_flies_on_the_battery_left() {
        let route = lines(40, 300.0);
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let (home, aircraft) = (Coord { x: -50.0, y: 0.0 }, Coord { x: 150.0, y: -40.0 });
        let budget = Budget { first_from: Some(aircraft), first_usable_j: 10_000.0, ..budget(Some(home), &connect, &energy) };
        let sorties = budget.split(&route).unwrap().sorties;
        assert_eq!(sorties[0].pieces[0].start(), aircraft);
        assert!(energy(&sorties[0]) <= 10_000.0 && sorties[0].pieces.iter().any(|p| p.kind == PieceKind::Sweep));
        for s in &sorties[1..] {
            assert!(s.pieces[0].start() == home && energy(s) <= 30_000.0);
        }
        let flown = sorties.iter().flat_map(|s| &s.pieces).filter(|p| p.kind == PieceKind::Sweep).count();
        assert_eq!(flown, 40);
        let empty = Budget { first_usable_j: 500.0, ..budget };
        assert!(matches!(empty.split(&route), Err(PlanError::Infeasible(why)) if why.contains("battery left")));
    }

    #[test]
    fn without_home_batteries_run_out_at_line_ends_and_each_stretch_fits() {
        let route = lines(40, 300.0);
        let connect = |a: Pose, b: Pose| Some(vec![a.coord(), b.coord()]);
        let energy = |p: &FlightPath| p.length() * 10.0;
        let budget = budget(None, &connect, &energy);
        let split = budget.split(&route).unwrap();
        assert_eq!(split.sorties, vec![route.clone()], "flown as planned");
        let sweeps: Vec<usize> = route.pieces.iter().enumerate().filter(|(_, p)| p.kind == PieceKind::Sweep).map(|(i, _)| i).collect();
        let swaps = &budget.swaps(&route, &sweeps).unwrap();
        assert_eq!(split.battery_swaps, swaps.iter().map(|&k| route.pieces[k].end()).collect::<Vec<_>>());
        assert!(!swaps.is_empty());
        let mut start = 0;
        for &k in swaps.iter().chain([&(route.pieces.len() - 1)]) {
            let stretch = FlightPath { pieces: route.pieces[start..=k].to_vec() };
            assert!(energy(&stretch) <= 30_000.0, "stretch from piece {start} to {k}");
            start = k + 1;
        }
        for (n, &k) in swaps.iter().enumerate() {
            assert_eq!(route.pieces[k].kind, PieceKind::Sweep, "battery {} runs out at a line's end", n + 1);
            // greedy: the next line would not have fitted
            let from = if n == 0 { 0 } else { swaps[n - 1] + 1 };
            let longer = FlightPath { pieces: route.pieces[from..=k + 2].to_vec() };
            assert!(energy(&longer) > 30_000.0);
        }
        // fewest batteries: the total energy over one battery, rounded up, at least
        assert!(swaps.len() + 1 >= (energy(&route) / 30_000.0).ceil() as usize);
        let hopeless = Budget { usable_j: 1_000.0, first_usable_j: 1_000.0, ..budget };
        assert!(matches!(hopeless.split(&route), Err(PlanError::Infeasible(_))));
    }
}
