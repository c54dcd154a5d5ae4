//! One vehicle's flight composed from the stages (plan its area, raise it over obstacles, cut
//! it into sorties, estimate it), and a fleet's: the area shared out by `fleet`, each part
//! flown by its drone, and what the fleet adds to the statistics.

use std::sync::Arc;

use geo::{Area, Coord, MultiPolygon};

use super::energy::{EnergyModel, PathEstimate};
use super::error::PlanError;
use super::field::Field;
use super::frame::LocalFrame;
use super::geom::{distance, grow, polyline_length};
use super::metrics::{self, Stats};
use super::params::{Landing, Objective, Pattern};
use super::path::{FlightPath, Piece, PieceKind};
use super::planners::{self, Problem, Progress};
use super::route::connect::{Connector, FlightEnds};
use super::route::visibility::TransitPlanner;
use super::stop::Stop;
use super::terrain::profile::{self, Ground};
use super::turn::climb::Obstacles;
use super::turn::trochoid::Drift;
use super::turn::{self, TurnModel};
use super::vehicle::VehicleKind;
use super::wind::{Tariff, Wind};
use super::{fleet, params, pattern, sortie, sweep, vehicle};

/// Everything a planner needs, validated and in the local frame.
pub(crate) struct Prepared {
    pub resolved: params::Resolved,
    pub planner: &'static dyn planners::Planner,
    pub field: Field,
    pub region: MultiPolygon,
    pub keep_out: MultiPolygon,
    pub walls: MultiPolygon,
    pub start: Option<Coord>,
    pub end: Option<Coord>,
    /// Each fleet drone's home (its own, or the mission's).
    pub fleet_homes: Vec<Option<Coord>>,
    /// More places than home where a sortie may land and the next take off.
    pub landing_sites: Vec<Coord>,
    /// A ground vehicle's headland.
    pub ground: Option<planners::headland::GroundSetup>,
}

/// Where a vehicle's flight starts and ends, and the home it returns to between sorties.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Ends {
    pub start: Option<Coord>,
    pub end: Option<Coord>,
    pub home: Option<Coord>,
    /// The flight starts in the air at `start` (a resumed plan's): no take-off.
    pub airborne: bool,
    /// Share of its capacity the first battery has (1: a fresh one).
    pub first_battery: f64,
}

impl Ends {
    /// A flight from `start` to `end` with fresh batteries, returning to `home` between sorties.
    pub fn new(start: Option<Coord>, end: Option<Coord>, home: Option<Coord>) -> Self {
        Ends { start, end, home, airborne: false, first_battery: 1.0 }
    }
}

/// What a fleet fixes for each drone's part: every part is swept along the bands it was cut
/// into, so that neighbouring drones' lines lie side by side; transits fly in the drone's layer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FleetPart {
    sweep_angle: f64,
    transit_altitude_m: Option<f64>,
}

impl FleetPart {
    /// Drone `k`'s part resumed: its lines are the original's (the direction matters not), its
    /// transits in its layer.
    pub fn in_layer(resolved: &params::Resolved, k: usize) -> Self {
        FleetPart { sweep_angle: resolved.sweep_angle.unwrap_or(0.0), transit_altitude_m: transit_layer(resolved, k) }
    }
}

/// The altitude drone `k` of a fleet flies its transits at, with `altitude_separation_m`.
fn transit_layer(resolved: &params::Resolved, k: usize) -> Option<f64> {
    resolved.altitude_separation_m.map(|sep| resolved.altitude_m.unwrap_or(0.0) + (k + 1) as f64 * sep)
}

/// One vehicle's flight: what its planner made of its area, cut into sorties (raised over
/// obstacles) and estimated by its energy model.
pub(crate) struct Flight {
    pub vehicle: vehicle::Vehicle,
    pub planned: planners::PlannedPath,
    pub sorties: Vec<FlightPath>,
    pub estimates: Vec<PathEstimate>,
    /// Without a home: where its batteries run out.
    pub battery_swaps: Vec<Coord>,
    /// Energy of the whole route in one flight.
    pub needed_j: f64,
    pub lost_coverage_m: f64,
    /// Over terrain: how each sortie lies over the ground (empty: flown above home).
    pub laid: Vec<profile::Laid>,
    /// In wind: the duration and energy of the plan made as in still air, flown in the wind.
    pub still_air_in_wind: Option<(f64, f64)>,
}

impl Flight {
    fn duration_s(&self) -> f64 {
        self.estimates.iter().map(PathEstimate::duration_s).sum()
    }

    pub fn energy_j(&self) -> f64 {
        self.estimates.iter().map(PathEstimate::energy_j).sum()
    }

    pub fn batteries_needed(&self) -> usize {
        if self.battery_swaps.is_empty() { (self.energy_j() / self.vehicle.battery.usable_j()).ceil().max(1.0) as usize } else { self.battery_swaps.len() + 1 }
    }

    /// Time of the pieces that do not grow with the area flown: the legs between home and the
    /// area, take-off and landing.
    fn fixed_s(&self) -> f64 {
        let legs = |s: &FlightPath, e: &PathEstimate| {
            let first = s.pieces.first().filter(|p| p.kind == PieceKind::Transit).map_or(0.0, |_| e.pieces[0].duration_s);
            let last = s.pieces.last().filter(|p| p.kind == PieceKind::Transit && s.pieces.len() > 1).map_or(0.0, |_| e.pieces[e.pieces.len() - 1].duration_s);
            first + last + e.takeoff_landing_s()
        };
        self.sorties.iter().zip(&self.estimates).map(|(s, e)| legs(s, e)).sum()
    }
}

/// The ground a plan over terrain follows, and how.
pub(crate) struct Terrain<'a> {
    pub ground: Ground<'a>,
    pub settings: profile::Settings,
}

/// What every vehicle's flight shares.
pub(crate) struct Stages<'a> {
    pub prepared: &'a Prepared,
    pub transit: &'a TransitPlanner,
    pub obstacles: Option<&'a Obstacles>,
    pub terrain: Option<&'a Terrain<'a>>,
    pub stop: &'a Stop,
}

impl Stages<'_> {
    /// Plans `region` for `vehicle` and cuts the path into sorties from `ends.home`; a fleet's
    /// `part` fixes the sweep direction and the altitude of transits.
    pub fn fly(&self, vehicle: &vehicle::Vehicle, ends: Ends, region: &MultiPolygon, part: Option<FleetPart>, progress: &dyn Progress) -> Result<Flight, PlanError> {
        let planner = self.prepared.planner;
        let resolved = &self.prepared.resolved;
        let by_length = |p: &planners::PlannedPath| p.path.length();
        let one_set =
            |problem: &Problem<'_>| if resolved.optimal_direction { plan_every_direction(planner, problem, progress, &by_length) } else { planner.plan(problem, progress) };
        let plan = |problem: &Problem<'_>| match resolved.pattern {
            Pattern::Grid => one_set(problem),
            Pattern::DoubleGrid => pattern::double_grid(planner, problem, &one_set, progress),
            Pattern::Oblique => pattern::oblique(planner, problem, &one_set, resolved.oblique.as_ref().expect("an oblique plan's view"), progress),
        };
        let still_air = self.fly_route(vehicle, ends, region, part, &plan);
        let wind = resolved.wind.filter(|w| w.speed_mps > 0.0 && resolved.objective != Objective::Length);
        match (wind, resolved.sweep_angle, part) {
            // (a pattern's directions are all fixed by its first set)
            (Some(wind), None, None) if resolved.pattern == Pattern::Grid => self.fly_in_wind(vehicle, ends, region, still_air, wind),
            _ => still_air,
        }
    }

    /// In wind: the still-air plan against plans swept along and across the wind, or, with
    /// `sweep_direction` `optimal`, the direction the model in wind ranks first (docs/methods.md,
    /// wind §3). In a strong wind a fixed wing may find no way to turn where it did in still
    /// air: then another direction may.
    fn fly_in_wind(&self, vehicle: &vehicle::Vehicle, ends: Ends, region: &MultiPolygon, still_air: Result<Flight, PlanError>, wind: Wind) -> Result<Flight, PlanError> {
        let (planner, resolved) = (self.prepared.planner, &self.prepared.resolved);
        let (mut flights, mut failed) = (Vec::new(), None);
        let still_air_flown = still_air.is_ok();
        keep(&mut flights, &mut failed, still_air)?;
        if resolved.optimal_direction {
            let model = |p: &planners::PlannedPath| vehicle.energy_model_in(Some(&wind)).estimate(&p.path, resolved.altitude_m);
            let score = |p: &planners::PlannedPath| objective_figure(resolved.objective, &p.path, &model(p));
            let plan = |problem: &Problem<'_>| plan_every_direction(planner, problem, &|_| true, &score);
            keep(&mut flights, &mut failed, self.fly_route(vehicle, ends, region, None, &plan))?;
        } else {
            let v = wind.velocity();
            let downwind = v.y.atan2(v.x).rem_euclid(std::f64::consts::PI);
            for angle in [downwind, (downwind + std::f64::consts::FRAC_PI_2) % std::f64::consts::PI] {
                if self.stop.requested() {
                    return Err(PlanError::Cancelled);
                }
                let plan = |problem: &Problem<'_>| planner.plan(&Problem { sweep_angle: Some(angle), ..*problem }, &|_| true);
                keep(&mut flights, &mut failed, self.fly_route(vehicle, ends, region, None, &plan))?;
            }
        }
        match failed {
            Some(e) if flights.is_empty() => Err(e),
            _ => Ok(least_in_wind(flights, region, resolved, still_air_flown)),
        }
    }

    /// Flies the route `route` makes from the problem (its connector joins what it needs), cut
    /// into sorties from `ends.home` like a planned one.
    pub fn fly_route(
        &self,
        vehicle: &vehicle::Vehicle,
        ends: Ends,
        region: &MultiPolygon,
        part: Option<FleetPart>,
        route: &dyn Fn(&Problem<'_>) -> Result<planners::PlannedPath, PlanError>,
    ) -> Result<Flight, PlanError> {
        let Prepared { resolved, field, keep_out, walls, .. } = self.prepared;
        let turn = vehicle.turn_model();
        // a fixed wing flies its turns in the wind
        let drift = match (turn, resolved.wind) {
            (TurnModel::Dubins(_), Some(w)) if w.speed_mps > 0.0 => Some(Drift { wind: w.velocity(), airspeed: vehicle.cruise_speed_mps }),
            _ => None,
        };
        // fixed wing: corners far enough from the zones to turn around them (in wind too: the
        // hops between them are trochoids, each checked against the zones)
        let detour = match turn {
            TurnModel::Dubins(r) => Some(TransitPlanner::new(&grow(&field.no_fly_zones, resolved.nfz_margin_m + r), walls)),
            TurnModel::Straight => None,
        };
        // a multirotor's routes weigh each direction by what it costs in the wind
        let tariff = match (turn, resolved.wind) {
            (TurnModel::Straight, Some(w)) if w.speed_mps > 0.0 && resolved.objective != Objective::Length => Some(Arc::new(wind_tariff(vehicle, &w, resolved.objective))),
            _ => None,
        };
        let connector = Connector::new(turn, self.transit, detour.as_ref()).with_ends(self.flight_ends(vehicle, &ends)).in_wind(drift).priced_by(tariff).stopping_on(self.stop);
        let problem = Problem {
            region,
            keep_out,
            transit: self.transit,
            connector: &connector,
            layout: resolved.layout,
            sweep_angle: part.map_or(resolved.sweep_angle, |p| Some(p.sweep_angle)),
            start: ends.start,
            end: ends.end,
            start_heading: resolved.start_heading,
            end_heading: resolved.end_heading,
            allow_reentry: resolved.allow_reentry,
            obstacles: self.obstacles,
            coverage_penalty: resolved.coverage_penalty,
            vehicle,
            objective: resolved.objective,
            wind: resolved.wind,
            ground: self.prepared.ground.as_ref(),
            corridors: &field.corridors,
        };
        let planned = route(&problem)?;
        // climbs over obstacles are flown by every sortie, so they are priced when splitting
        let flown = |p: &FlightPath| {
            let (mut path, lost) = self.obstacles.map_or((p.clone(), 0.0), |obs| obs.raise(p));
            if let Some(layer) = part.and_then(|p| p.transit_altitude_m) {
                let survey = resolved.altitude_m.unwrap_or(0.0);
                for piece in path.pieces.iter_mut().filter(|piece| piece.kind == PieceKind::Transit) {
                    lift(piece, survey, layer, resolved.max_climb_deg);
                }
            }
            (path, lost)
        };
        // over terrain every sortie flies its climbs and descents: priced when splitting too
        let laid = |p: &FlightPath| self.terrain.map(|t| profile::lay(p, &t.ground, &t.settings)).transpose();
        if self.terrain.is_some() {
            laid(&flown(&planned.path).0)?;
        }
        let model = vehicle.energy_model_in(resolved.wind.as_ref());
        let energy_of = |p: &FlightPath| {
            let path = flown(p).0;
            let path = laid(&path).ok().flatten().map_or(path, |l| l.0);
            model.estimate(&path, resolved.altitude_m).energy_j()
        };
        let connect = |a: turn::dubins::Pose, b: turn::dubins::Pose| connector.path(a, b);
        let battery = &vehicle.battery;
        let budget = sortie::Budget {
            home: ends.home,
            landing_sites: self.landing_sites(&ends),
            first_from: ends.start.filter(|_| ends.airborne),
            usable_j: battery.usable_j(),
            first_usable_j: battery.energy_wh * 3600.0 * (ends.first_battery - battery.reserve),
            max_sorties: resolved.max_sorties,
            connect: &connect,
            energy: &energy_of,
        };
        let split = if planned.sortie_breaks.is_empty() {
            budget.split(&planned.path)?
        } else {
            // a resumed plan: split anew, or at the original's sortie ends, whichever is shorter
            let length = |s: &sortie::Split| s.sorties.iter().map(FlightPath::length).sum::<f64>();
            match (budget.split(&planned.path), budget.split_between(&planned.path, &planned.sortie_breaks)) {
                (Ok(anew), Ok(kept)) => {
                    if length(&kept) < length(&anew) {
                        kept
                    } else {
                        anew
                    }
                }
                (Ok(split), Err(_)) | (Err(_), Ok(split)) => split,
                (Err(e), Err(_)) => return Err(e),
            }
        };
        let mut lost_coverage_m = 0.0;
        let mut laid_sorties = Vec::new();
        let mut sorties: Vec<FlightPath> = Vec::with_capacity(split.sorties.len());
        for s in &split.sorties {
            let (path, lost) = flown(s);
            lost_coverage_m += lost;
            match laid(&path)? {
                Some((path, report)) => {
                    laid_sorties.push(report);
                    sorties.push(path);
                }
                None => sorties.push(path),
            }
        }
        let mut estimates: Vec<PathEstimate> = sorties.iter().map(|s| model.estimate(s, resolved.altitude_m)).collect();
        if let Some(first) = estimates.first_mut().filter(|_| ends.airborne) {
            first.takeoff = Default::default();
        }
        Ok(Flight {
            vehicle: vehicle.clone(),
            planned,
            sorties,
            estimates,
            battery_swaps: split.battery_swaps,
            needed_j: split.needed_j,
            lost_coverage_m,
            laid: laid_sorties,
            still_air_in_wind: None,
        })
    }

    /// Where a flight's sorties may land besides home: the landing sites, for a flight that
    /// has a home to come back to (the first sortie leaves from it).
    fn landing_sites(&self, ends: &Ends) -> &[Coord] {
        if ends.home.is_some() { &self.prepared.landing_sites } else { &[] }
    }

    /// A fixed wing's straights: a lead-in before every line, a climb-out from the launch point
    /// and, landing `auto`, the approach into the flight's end; none for other vehicles.
    fn flight_ends(&self, vehicle: &vehicle::Vehicle, ends: &Ends) -> FlightEnds {
        let resolved = &self.prepared.resolved;
        if vehicle.kind != VehicleKind::FixedWing {
            return FlightEnds::default();
        }
        let altitude = resolved.altitude_m.unwrap_or(0.0);
        // sorties may land at the landing sites and take off from them again
        let and_sites = |point: Coord| -> Vec<Coord> { std::iter::once(point).chain(self.landing_sites(ends).iter().copied()).collect() };
        let landing = match (resolved.landing, ends.end.or(ends.home)) {
            (Landing::Auto, Some(point)) => Some((and_sites(point), vehicle.landing_approach_m(altitude), resolved.landing_heading)),
            _ => None,
        };
        let climb_out = ends.home.or(ends.start).map(|launch| (and_sites(launch), vehicle::climb_out_m(altitude)));
        FlightEnds { lead_in_m: vehicle.lead_in_m(resolved.lead_in_m), climb_out, landing }
    }

    /// Plans the fleet: the area split among the drones (docs/methods.md, fleets), each part
    /// flown by its drone from its home. A drone not needed has no flight.
    pub fn fly_fleet(&self, progress: &dyn Progress) -> Result<(Vec<Option<Flight>>, FleetPlan), PlanError> {
        let Prepared { resolved, region, fleet_homes: homes, .. } = self.prepared;
        // a drone sharing a home waits until the one before has climbed and flown out of the way
        let clear_s: Vec<f64> = resolved
            .fleet
            .iter()
            .map(|d| {
                let climb = d.vehicle.energy_model().estimate(&FlightPath::default(), resolved.altitude_m).takeoff.duration_s;
                climb + 2.0 * fleet::timeline::CONFLICT_DISTANCE_M / d.vehicle.cruise_speed_mps
            })
            .collect();
        let departures = fleet::timeline::departures(homes, &clear_s);
        let layers: Vec<Option<f64>> = (0..homes.len()).map(|k| transit_layer(resolved, k)).collect();
        let drones: Vec<fleet::Drone> = resolved
            .fleet
            .iter()
            .zip(homes)
            .zip(&departures)
            .map(|((d, &home), &departure_s)| fleet::Drone { cruise_speed_mps: d.vehicle.cruise_speed_mps, home, departure_s })
            .collect();
        let angle = resolved.sweep_angle.unwrap_or_else(|| sweep::fewest_lines_direction(region, resolved.layout));
        let plan_part = |k: usize, part: &MultiPolygon| -> Result<(Flight, fleet::PartTimes), PlanError> {
            let ends = Ends::new(homes[k], homes[k], homes[k]);
            let flight = self.fly(&resolved.fleet[k].vehicle, ends, part, Some(FleetPart { sweep_angle: angle, transit_altitude_m: layers[k] }), &|_| true)?;
            let times = fleet::PartTimes { duration_s: flight.duration_s(), fixed_s: flight.fixed_s() };
            Ok((flight, times))
        };
        let rounds = |round: usize| !self.stop.requested() && progress.report(0.1 + 0.8 * (round + 1) as f64 / fleet::ROUNDS as f64);
        let assignment = fleet::assign(region, angle, resolved.line_spacing_m, &drones, &plan_part, &rounds)?;
        let mut areas = Vec::with_capacity(drones.len());
        let flights = assignment
            .parts
            .into_iter()
            .map(|p| {
                areas.push(p.as_ref().map_or(0.0, |(part, _)| part.unsigned_area()));
                p.map(|(_, flight)| flight)
            })
            .collect();
        Ok((flights, FleetPlan { departures, layers, areas, altitude_m: resolved.altitude_m, conflict_m: fleet::timeline::CONFLICT_DISTANCE_M }))
    }

    /// Plans several ground machines in one field (docs/methods.md, ground vehicles §6): the
    /// swaths laid once and shared out in bands ([`headland::share_out`]), each band (and the
    /// first machine's headland passes) routed for the machine's own turns; each machine sets
    /// off once it meets no other closer than the working width at the same time. Where the
    /// fastest machine alone is done no later, it works the field alone.
    pub fn fly_ground_fleet(&self, progress: &dyn Progress) -> Result<(Vec<Option<Flight>>, FleetPlan), PlanError> {
        let Prepared { resolved, region, ground, .. } = self.prepared;
        let machines = &resolved.fleet;
        let width = ground.as_ref().expect("a ground plan has its headland").spec.working_width_m;
        let fastest = (0..machines.len()).max_by(|&a, &b| machines[a].vehicle.cruise_speed_mps.total_cmp(&machines[b].vehicle.cruise_speed_mps).then(b.cmp(&a))).expect("a fleet");
        let (shared, alone) = rayon::join(|| self.share_field(), || self.fly(&machines[fastest].vehicle, self.ground_ends(fastest), region, None, &|_| true));
        let (mut flights, mut departures) = shared?;
        if !progress.report(0.9) {
            return Err(PlanError::Cancelled);
        }
        let done = |flights: &[Option<Flight>], departures: &[f64]| flights.iter().zip(departures).filter_map(|(f, d)| f.as_ref().map(|f| d + f.duration_s())).fold(0.0, f64::max);
        match alone {
            Ok(alone) if alone.duration_s() <= done(&flights, &departures) => {
                flights = (0..machines.len()).map(|_| None).collect();
                flights[fastest] = Some(alone);
                departures = vec![0.0; machines.len()];
            }
            Err(PlanError::Cancelled) => return Err(PlanError::Cancelled),
            _ => {}
        }
        let areas =
            flights.iter().map(|f| f.as_ref().map_or(0.0, |f| f.planned.path.pieces.iter().filter(|p| p.kind.works()).map(|p| p.length() * 2.0 * p.half_swath_m).sum())).collect();
        Ok((flights, FleetPlan { departures, layers: vec![None; machines.len()], areas, altitude_m: None, conflict_m: width }))
    }

    /// Where ground machine `k` of a fleet starts and ends: its home, else the plan's start and end.
    fn ground_ends(&self, k: usize) -> Ends {
        let Prepared { fleet_homes: homes, start, end, .. } = self.prepared;
        Ends::new(homes[k].or(*start), homes[k].or(*end), homes[k])
    }

    /// [`Self::fly_ground_fleet`]'s shared plan: each machine's flight (none for a machine not
    /// needed) and when it sets off.
    fn share_field(&self) -> Result<(Vec<Option<Flight>>, Vec<f64>), PlanError> {
        use planners::headland::{self, Swaths};
        use rayon::prelude::*;
        let Prepared { resolved, region, ground, .. } = self.prepared;
        let setup = ground.as_ref().expect("a ground plan has its headland");
        let machines = &resolved.fleet;
        let speeds: Vec<f64> = machines.iter().map(|m| m.vehicle.cruise_speed_mps).collect();
        // the first machine lays the swaths and shares them out; the others lay their bands
        // again at the same direction and phase for their own turns
        let shared: std::sync::OnceLock<(Swaths, Vec<headland::Share>)> = std::sync::OnceLock::new();
        let first = self.fly_route(&machines[0].vehicle, self.ground_ends(0), region, None, &|problem| {
            let laid = Swaths::lay(problem, setup);
            let passes_m: f64 = setup.rings().iter().map(|r| crate::geom::polyline_length(r)).sum();
            let r = problem.vehicle.planning_radius_m();
            let shares = headland::share_out(&laid, passes_m, std::f64::consts::PI * r + 2.0 * r, &speeds);
            let flown = headland::work(problem, setup, &laid, &shares[0], &|_| true);
            let _ = shared.set((laid, shares));
            flown
        })?;
        if self.stop.requested() {
            return Err(PlanError::Cancelled);
        }
        let (laid, shares) = shared.get().expect("set by the first machine's plan");
        let others: Vec<Option<Flight>> = (1..machines.len())
            .into_par_iter()
            .map(|k| {
                if shares[k].from == f64::INFINITY {
                    return Ok(None);
                }
                let route = |problem: &Problem<'_>| headland::work(problem, setup, laid, &shares[k], &|_| true);
                self.fly_route(&machines[k].vehicle, self.ground_ends(k), region, None, &route).map(Some)
            })
            .collect::<Result<_, PlanError>>()?;
        let flights: Vec<Option<Flight>> = std::iter::once(Some(first)).chain(others).collect();
        let departures = ground_departures(&flights, setup.spec.working_width_m);
        Ok((flights, departures))
    }
}

/// When each ground machine sets off: in turn, each as soon as it meets none of those before it
/// closer than `width_m` at the same time.
fn ground_departures(flights: &[Option<Flight>], width_m: f64) -> Vec<f64> {
    use fleet::timeline::{Track, encounters};
    let mut departures = vec![0.0; flights.len()];
    let mut tracks: Vec<Track> = Vec::new();
    for (k, f) in flights.iter().enumerate() {
        let Some(f) = f else { continue };
        // no encounter is left once the others are done
        let others_end = tracks.iter().map(Track::end_s).fold(0.0, f64::max);
        tracks.push(Track::new(&f.sorties, &f.estimates, 0.0, 0.0));
        let me = tracks.len() - 1;
        while let Some(e) = encounters(&tracks, width_m).into_iter().find(|e| e.vehicles.contains(&me)) {
            if tracks[me].departure_s > others_end {
                break;
            }
            tracks[me].departure_s += (e.to_s - e.from_s).max(GROUND_STAGGER_S);
        }
        departures[k] = tracks[me].departure_s;
    }
    departures
}

/// The least a ground machine's departure is put back by at a time, seconds.
const GROUND_STAGGER_S: f64 = 10.0;

/// Keeps a candidate flight; one that cannot be flown is no candidate (its error is kept in
/// `failed` if it is the first), but a cancellation ends the search.
fn keep(flights: &mut Vec<Flight>, failed: &mut Option<PlanError>, flight: Result<Flight, PlanError>) -> Result<(), PlanError> {
    match flight {
        Ok(f) => flights.push(f),
        Err(PlanError::Cancelled) => return Err(PlanError::Cancelled),
        Err(e) => {
            failed.get_or_insert(e);
        }
    }
    Ok(())
}

/// The figure `objective` ranks a path and its estimate by.
fn objective_figure(objective: Objective, path: &FlightPath, e: &PathEstimate) -> f64 {
    match objective {
        Objective::Energy => e.energy_j(),
        Objective::Time => e.duration_s(),
        Objective::Length => path.length(),
    }
}

/// What a metre over the ground costs `vehicle` in `wind` by its direction, relative to still
/// air: a long straight leg's time or energy (by `objective`) in the wind over the same leg's
/// in still air (docs/methods.md, wind §3).
fn wind_tariff(vehicle: &vehicle::Vehicle, wind: &Wind, objective: Objective) -> Tariff {
    // long enough that starting and stopping weigh little against the cruise
    const LEG_M: f64 = 5000.0;
    let figure = |model: &dyn EnergyModel, u: Coord| {
        let mut leg = FlightPath::default();
        leg.push(PieceKind::Sweep, vec![Coord { x: 0.0, y: 0.0 }, u * LEG_M], 0.0);
        let e = &model.pieces(&leg)[0];
        if objective == Objective::Time { e.duration_s } else { e.energy_j }
    };
    let still_air = figure(vehicle.energy_model().as_ref(), Coord { x: 1.0, y: 0.0 });
    let in_wind = vehicle.energy_model_in(Some(wind));
    Tariff::sampled(|u| figure(in_wind.as_ref(), u) / still_air)
}

/// Of flights planned in the same wind, the first (the still-air plan, when `first_is_still_air`)
/// unless another covers as much and costs less by the objective.
fn least_in_wind(flights: Vec<Flight>, region: &MultiPolygon, resolved: &params::Resolved, first_is_still_air: bool) -> Flight {
    let area = region.unsigned_area().max(1e-9);
    let figure = |f: &Flight| -> (f64, f64) {
        let cost = f.sorties.iter().zip(&f.estimates).map(|(s, e)| objective_figure(resolved.objective, s, e)).sum();
        (cost, metrics::covered_area(&f.planned.path, region, resolved.layout.photographed()) / area)
    };
    let figures: Vec<(f64, f64)> = flights.iter().map(figure).collect();
    let (cost0, coverage0) = figures[0];
    let best = (1..flights.len()).filter(|&k| figures[k].1 >= coverage0 - 1e-6 && figures[k].0 < cost0).min_by(|&a, &b| figures[a].0.total_cmp(&figures[b].0)).unwrap_or(0);
    let still_air_in_wind = first_is_still_air.then(|| (flights[0].duration_s(), flights[0].energy_j()));
    let mut chosen = flights.into_iter().nth(best).expect("an index of the flights");
    chosen.still_air_in_wind = still_air_in_wind;
    chosen
}

/// Flies a transit in its drone's layer: it climbs from the survey altitude to `layer` over its
/// first metres at `max_climb_deg`, and descends over its last (a transit too short to reach the
/// layer peaks halfway), with a vertex where each ramp ends, so that the energy model prices the
/// climb; altitudes already higher (over obstacles) are kept.
fn lift(piece: &mut Piece, survey: f64, layer: f64, max_climb_deg: f64) {
    let slope = max_climb_deg.to_radians().tan();
    let ramp = (layer - survey) / slope;
    let mut points: Vec<(Coord, f64)> = piece.points.iter().enumerate().map(|(i, &c)| (c, piece.z.get(i).copied().unwrap_or(survey))).collect();
    let length = polyline_length(&piece.points);
    for at in [ramp.min(length / 2.0), (length - ramp).max(length / 2.0)] {
        points = with_vertex_at(&points, at);
    }
    let mut along = 0.0;
    let mut previous = points[0].0;
    for (c, z) in &mut points {
        along += distance(previous, *c);
        previous = *c;
        let climbed = along.min(length - along).max(0.0) * slope;
        *z = z.max(survey + climbed.min(layer - survey));
    }
    piece.points = points.iter().map(|p| p.0).collect();
    piece.z = points.iter().map(|p| p.1).collect();
}

/// `points` (with altitudes) with a vertex at `at` metres along, unless one is within a centimetre.
fn with_vertex_at(points: &[(Coord, f64)], at: f64) -> Vec<(Coord, f64)> {
    let mut out = Vec::with_capacity(points.len() + 1);
    let mut along = 0.0;
    let mut placed = false;
    for (i, &(c, z)) in points.iter().enumerate() {
        if i > 0 && !placed {
            let (a, za) = points[i - 1];
            let step = distance(a, c);
            if along + step > at + 0.01 && at > along + 0.01 {
                let f = (at - along) / step;
                out.push((a + (c - a) * f, za + (z - za) * f));
                placed = true;
            }
            along += step;
        }
        out.push((c, z));
    }
    out
}

/// What a plan over terrain adds to the statistics: heights above ground, climbs, waypoints.
pub(crate) fn report_terrain(flights: &[&Flight], stats: &mut Stats) {
    let mut t = crate::terrain::TerrainStats {
        altitude_reference: "terrain".into(),
        height_above_ground_m: [f64::INFINITY, f64::NEG_INFINITY],
        sweep_height_above_ground_m: [f64::INFINITY, f64::NEG_INFINITY],
        ..Default::default()
    };
    let (mut points, mut sweep_m, mut off_band_m) = (0usize, 0.0, 0.0);
    for f in flights {
        for (sortie, laid) in f.sorties.iter().zip(&f.laid) {
            off_band_m += laid.sweep_off_band_m;
            points += 1;
            for (piece, &[lo, hi]) in sortie.pieces.iter().zip(&laid.piece_heights) {
                let widen = |r: &mut [f64; 2]| *r = [r[0].min(lo), r[1].max(hi)];
                widen(&mut t.height_above_ground_m);
                if piece.kind == PieceKind::Sweep {
                    widen(&mut t.sweep_height_above_ground_m);
                    sweep_m += polyline_length(&piece.points);
                }
                points += piece.points.len() - 1;
                for z in piece.z.windows(2) {
                    t.climb_m += (z[1] - z[0]).max(0.0);
                    t.descent_m += (z[0] - z[1]).max(0.0);
                }
            }
        }
    }
    let round = |v: f64| (v * 100.0).round() / 100.0;
    t.height_above_ground_m = t.height_above_ground_m.map(round);
    t.sweep_height_above_ground_m = t.sweep_height_above_ground_m.map(|v| if v.is_finite() { round(v) } else { 0.0 });
    t.sweep_outside_tolerance_m = round(off_band_m);
    (t.climb_m, t.descent_m) = (round(t.climb_m), round(t.descent_m));
    t.waypoints_per_sweep_km = if sweep_m > 0.0 { round(points as f64 / (sweep_m / 1000.0)) } else { 0.0 };
    if off_band_m > 0.0 {
        stats.warnings.push(format!(
            "over {off_band_m:.0} m of sweep the ground rises or falls faster than the vehicle may climb or descend (max_climb_mps, max_descent_mps; a fixed wing's max_climb_deg): \
             there the height above ground leaves the tolerance (it never drops below its floor); the images there are at another scale"
        ));
    }
    stats.terrain = Some(t);
}

/// What a fleet plan adds to the statistics.
pub(crate) struct FleetPlan {
    departures: Vec<f64>,
    layers: Vec<Option<f64>>,
    areas: Vec<f64>,
    altitude_m: Option<f64>,
    /// Two vehicles closer than this at the same time (and at the same altitude) conflict.
    conflict_m: f64,
}

impl FleetPlan {
    /// Per-drone totals, the makespan, and the conflicts between drones.
    pub fn report(&self, flights: &[Option<Flight>], frame: &LocalFrame, stats: &mut Stats) {
        let mut tracks = Vec::new();
        let mut flying = Vec::new();
        let mut sortie = 0;
        for (k, f) in flights.iter().enumerate() {
            let profile = f.as_ref().map_or_else(String::new, |f| f.vehicle.profile.clone());
            let mut totals = metrics::VehicleTotals {
                vehicle: k,
                profile,
                area_m2: self.areas[k],
                sweep_lines: 0,
                sorties: 0,
                length_m: 0.0,
                duration_s: 0.0,
                energy_j: 0.0,
                departure_s: self.departures[k],
                landing_s: self.departures[k],
                transit_altitude_m: self.layers[k],
            };
            if let Some(f) = f {
                totals.sweep_lines = f.sorties.iter().flat_map(|s| &s.pieces).filter(|p| p.kind == PieceKind::Sweep).count();
                totals.sorties = f.sorties.len();
                totals.length_m = f.sorties.iter().map(FlightPath::length).sum();
                totals.duration_s = f.duration_s();
                totals.energy_j = f.energy_j();
                totals.landing_s = self.departures[k] + totals.duration_s;
                for _ in &f.sorties {
                    stats.sortie_totals[sortie].vehicle = Some(k);
                    sortie += 1;
                }
                tracks.push(fleet::timeline::Track::new(&f.sorties, &f.estimates, self.departures[k], self.altitude_m.unwrap_or(0.0)));
                flying.push(k);
            }
            stats.vehicles.push(totals);
        }
        let conflicts: Vec<metrics::Conflict> = fleet::timeline::encounters(&tracks, self.conflict_m)
            .into_iter()
            .map(|e| metrics::Conflict { vehicles: e.vehicles.map(|i| flying[i]), from_s: e.from_s, to_s: e.to_s, closest_m: e.closest_m, position: frame.to_wgs84(e.at) })
            .collect();
        if !conflicts.is_empty() {
            stats.warnings.push(format!(
                "{} times two drones come within {} m of each other at the same altitude (stats.conflicts): give altitude_separation_m, separate homes, or fewer drones",
                conflicts.len(),
                self.conflict_m
            ));
        }
        stats.conflicts = Some(conflicts);
        stats.makespan_s = Some(stats.vehicles.iter().map(|v| v.landing_s).fold(0.0, f64::max));
    }
}

/// Sweep directions tried by `sweep_direction: optimal`: every 2°, then 0.5° around the best.
const DIRECTION_STEP_DEG: f64 = 2.0;

/// A direction tried by `sweep_direction: optimal`: its angle, the share of the field its plan
/// covers, and the plan.
type Tried = (f64, f64, planners::PlannedPath);

/// Plans with every sweep direction and keeps the least costly plan by `cost` (its length in
/// still air) by [`metrics::best_covering`], the rule `auto` chooses planners by (a fixed wing's
/// shortest plan is often the one whose lines stop short of a no-fly zone); ties: the smaller
/// angle.
fn plan_every_direction(
    planner: &dyn planners::Planner,
    problem: &Problem<'_>,
    progress: &dyn Progress,
    cost: &(dyn Fn(&planners::PlannedPath) -> f64 + Sync),
) -> Result<planners::PlannedPath, PlanError> {
    use rayon::prelude::*;
    let area = problem.region.unsigned_area();
    let run = |angle: f64| {
        planner
            .plan(&Problem { sweep_angle: Some(angle), ..*problem }, &|_| true)
            .map(|p| (angle, metrics::covered_area(&p.path, problem.region, problem.layout.photographed()) / area, p))
    };
    let best = |tried: &[Tried]| metrics::best_covering(tried, |t| t.1, |t| cost(&t.2)).expect("at least one direction was tried");
    let grid: Vec<f64> = (0..(180.0 / DIRECTION_STEP_DEG) as usize).map(|k| (k as f64 * DIRECTION_STEP_DEG).to_radians()).collect();
    let mut tried: Vec<Tried> = Vec::with_capacity(grid.len() + 6);
    // a chunk per progress report, so that a cancelled job stops soon
    for (k, chunk) in grid.chunks(8).enumerate() {
        let results: Vec<Result<Tried, PlanError>> = chunk.par_iter().map(|&a| run(a)).collect();
        tried.extend(results.into_iter().collect::<Result<Vec<_>, _>>()?);
        if !progress.report(0.1 + 0.8 * (k + 1) as f64 * 8.0 / grid.len() as f64) {
            return Err(PlanError::Cancelled);
        }
    }
    let around = tried[best(&tried)].0;
    let fine: Vec<f64> = [-1.5f64, -1.0, -0.5, 0.5, 1.0, 1.5].iter().map(|d| (around + d.to_radians()).rem_euclid(std::f64::consts::PI)).collect();
    let refined: Vec<Result<Tried, PlanError>> = fine.par_iter().map(|&a| run(a)).collect();
    tried.extend(refined.into_iter().collect::<Result<Vec<_>, _>>()?);
    // ties go to the smaller angle
    tried.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (sweep_angle, _, planned) = tried.swap_remove(best(&tried));
    Ok(planners::PlannedPath { sweep_angle, ..planned })
}
