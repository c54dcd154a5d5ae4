//! Inspection of structures (seed 001, spec `inspection.md`): a multirotor flies to
//! viewpoints around extruded footprints and photographs as much of the chosen faces as a
//! budget allows.
//!
//! - [`scene`]: prisms, their triangles (a BVH for lines of sight) and keep-out volumes;
//! - [`poi`]: points of interest on the target faces;
//! - [`visibility`]: what a camera pose sees (frustum, range, incidence, occlusion);
//! - [`viewpoints`]: sampling camera poses, at the start and near the best path;
//! - [`legs`]: collision-free legs in 2.5D and their length, time and energy;
//! - [`orienteering`]: the union-reward orienteering search.

pub mod legs;
pub mod orienteering;
pub mod poi;
pub mod scene;
pub mod viewpoints;
pub mod visibility;

#[cfg(test)]
mod tests;

use std::sync::RwLock;
use std::time::Instant;

use geo::{BoundingRect, Coord, Intersects, MultiPolygon, Polygon, Rect};

use crate::error::{InputError, PlanError};
use crate::field::Structure;
use crate::metrics::{InspectionStats, Stats, TargetCoverage};
use crate::params::inspection::{BudgetLimit, Extension, Face, InspectionSpec, PLANNER_ID, Target};
use crate::planners::Progress;
use crate::stop::Stop;
use crate::vehicle::Vehicle;
use legs::{Leg, LegPlanner, Stationary};
use orienteering::{END, Instance, Pricer, START, Search};
use poi::{Poi, TargetGroup};
use scene::{Point3, Prism, Scene};
use viewpoints::{Sampler, Viewpoint, halton};
use visibility::Optics;

/// Most points of interest one plan samples.
pub const MAX_POIS: usize = 200_000;

/// Most viewpoints the search holds, sampled and added (the cost table grows with their
/// square: 2 000 take 32 MB).
pub const MAX_VIEWPOINTS: usize = 2_000;

/// Iterations of the search, and iterations without a better path, after which it stops.
const MAX_ITERATIONS: usize = 1_000;
const PATIENCE: usize = 80;

/// Default farthest range without a required ground sample distance, metres.
const DEFAULT_RANGE_M: [f64; 2] = [1.0, 12.0];

/// Everything the inspection needs, in the mission's local frame.
pub struct InspectionInput<'a> {
    pub structures: &'a [Structure],
    /// Obstacles (footprint, height): they hide and block, and are not inspected.
    pub obstacles: &'a [(Polygon, f64)],
    pub no_fly_zones: &'a MultiPolygon,
    /// Where the drone may fly.
    pub geofence: &'a MultiPolygon,
    pub vehicle: &'a Vehicle,
    pub spec: &'a InspectionSpec,
    /// The camera's fields of view, degrees.
    pub fov_deg: [f64; 2],
    /// Farthest range a required ground sample distance allows, metres.
    pub gsd_range_m: Option<f64>,
    pub start: Coord,
    pub end: Coord,
}

/// A viewpoint of the flown path, with what it adds.
#[derive(Debug, Clone, PartialEq)]
pub struct FlownViewpoint {
    pub pose: visibility::Pose,
    pub at: Point3,
    /// Compass bearing of the camera, degrees.
    pub yaw_deg: f64,
    pub gimbal_pitch_deg: f64,
    /// Points it sees that no viewpoint before it saw, and their weight.
    pub new_pois: usize,
    pub weighted_gain: f64,
    /// Since take-off, on arrival.
    pub eta_s: f64,
    pub energy_j: f64,
}

/// A target group's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupCoverage {
    pub name: String,
    pub face: Face,
    pub seen: usize,
    pub total: usize,
    pub weighted_seen: f64,
    pub weighted_total: f64,
}

/// Why the search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchEnd {
    Iterations,
    NoImprovement,
    TimeLimit,
}

impl SearchEnd {
    pub fn as_str(self) -> &'static str {
        match self {
            SearchEnd::Iterations => "iterations",
            SearchEnd::NoImprovement => "no_improvement",
            SearchEnd::TimeLimit => "time_limit",
        }
    }
}

#[derive(Debug, Clone)]
pub struct InspectionPlan {
    /// From the start to the first viewpoint, between viewpoints, to the end.
    pub legs: Vec<Leg>,
    pub viewpoints: Vec<FlownViewpoint>,
    pub pois: Vec<Poi>,
    pub seen: Vec<bool>,
    pub groups: Vec<GroupCoverage>,
    /// Yaw and capture time and energy at the viewpoints (the legs hold the rest).
    pub stationary_s: f64,
    pub stationary_j: f64,
    pub budget: BudgetLimit,
    /// The path's cost under the budget's measure.
    pub budget_used: f64,
    pub viewpoints_sampled: usize,
    pub sampling_tries: usize,
    pub iterations: usize,
    pub search_end: SearchEnd,
    pub warnings: Vec<String>,
    pub optics: Optics,
}

impl InspectionPlan {
    pub fn length_m(&self) -> f64 {
        self.legs.iter().map(|l| l.length_m).sum()
    }

    pub fn duration_s(&self) -> f64 {
        self.legs.iter().map(|l| l.time_s).sum::<f64>() + self.stationary_s
    }

    pub fn energy_j(&self) -> f64 {
        self.legs.iter().map(|l| l.energy_j).sum::<f64>() + self.stationary_j
    }

    /// Weighted share of the points of interest seen.
    pub fn coverage(&self) -> f64 {
        let total: f64 = self.pois.iter().map(|p| p.weight).sum();
        let seen: f64 = self.pois.iter().zip(&self.seen).filter(|(_, s)| **s).map(|(p, _)| p.weight).sum();
        if total > 0.0 { seen / total } else { 0.0 }
    }
}

impl InspectionPlan {
    /// The plan's figures as every plan reports them, with the inspection's own.
    pub fn stats(&self) -> Stats {
        let length_m = self.length_m();
        let energy_j = self.energy_j();
        let seen: f64 = self.pois.iter().zip(&self.seen).filter(|(_, s)| **s).map(|(p, _)| p.weight).sum();
        let (measure, limit) = (self.budget.measure_name().0, self.budget.value());
        Stats {
            length_m,
            transit_length_m: length_m,
            duration_s: self.duration_s(),
            energy_j,
            energy_wh: energy_j / 3600.0,
            sorties: 1,
            batteries_needed: 1,
            warnings: self.warnings.clone(),
            planner: PLANNER_ID.into(),
            photos: self.viewpoints.len(),
            inspection_coverage: Some(self.coverage()),
            inspection: Some(InspectionStats {
                pois: self.pois.len(),
                pois_seen: self.seen.iter().filter(|s| **s).count(),
                weighted_total: self.pois.iter().map(|p| p.weight).sum(),
                weighted_seen: seen,
                targets: self
                    .groups
                    .iter()
                    .map(|g| TargetCoverage {
                        name: g.name.clone(),
                        face: match g.face {
                            Face::Walls => "walls".into(),
                            Face::Roof => "roof".into(),
                        },
                        seen: g.seen,
                        total: g.total,
                        weighted_seen: g.weighted_seen,
                        weighted_total: g.weighted_total,
                        coverage: if g.weighted_total > 0.0 { g.weighted_seen / g.weighted_total } else { 0.0 },
                    })
                    .collect(),
                viewpoints: self.viewpoints.len(),
                viewpoints_sampled: self.viewpoints_sampled,
                budget_measure: measure.into(),
                budget_limit: limit,
                budget_used: self.budget_used,
                iterations: self.iterations,
                search_end: self.search_end.as_str().into(),
                fov_deg: [self.optics.hfov_deg, self.optics.vfov_deg],
                range_m: [self.optics.min_range_m, self.optics.max_range_m],
            }),
            ..Stats::default()
        }
    }
}

/// The target groups the request names, with their priorities.
fn target_groups(structures: &[Structure], targets: &[Target]) -> Result<Vec<TargetGroup>, InputError> {
    let both = [Face::Walls, Face::Roof];
    let mut groups: Vec<TargetGroup> = Vec::new();
    let mut add = |prism: usize, face: Face, priority: f64| match groups.iter_mut().find(|g| g.prism == prism && g.face == face) {
        Some(g) => g.priority = g.priority.max(priority),
        None => groups.push(TargetGroup { prism, face, priority }),
    };
    if targets.is_empty() {
        for (i, _) in structures.iter().enumerate() {
            both.iter().for_each(|&f| add(i, f, 1.0));
        }
    }
    let find = |name: &str, at: String| {
        structures.iter().position(|s| s.name == name).ok_or_else(|| {
            let known: Vec<&str> = structures.iter().map(|s| s.name.as_str()).collect();
            InputError::new("unknown_target", at, format!("no structure is named `{name}`; targets are walls, roof or one of: {}", known.join(", ")))
        })
    };
    for (t, target) in targets.iter().enumerate() {
        match target {
            Target::Named(n) if n == "walls" || n == "roof" => {
                let face = if n == "walls" { Face::Walls } else { Face::Roof };
                (0..structures.len()).for_each(|i| add(i, face, 1.0));
            }
            Target::Named(n) => {
                let i = find(n, format!("/targets/{t}"))?;
                both.iter().for_each(|&f| add(i, f, 1.0));
            }
            Target::Detailed(d) => {
                let i = find(&d.name, format!("/targets/{t}/name"))?;
                let faces = d.faces.as_deref().unwrap_or(&both);
                faces.iter().for_each(|&f| add(i, f, d.priority.unwrap_or(1.0)));
            }
        }
    }
    Ok(groups)
}

/// The request members (of `PlanParams`) an inspection reads, for `GET /api/v1/planners`.
pub const PARAMETERS: &[&str] = &["planner", "budget", "targets", "camera", "gsd_cm", "vehicle", "start", "end", "seed", "time_limit_s", "inspection"];

/// What the search starts from: the targets' points, the scene, the camera's reach, the ends.
struct Setup {
    groups: Vec<TargetGroup>,
    scene: Scene,
    pois: Vec<Poi>,
    optics: Optics,
    /// Lowest and highest viewpoint altitude, and the highest a leg may climb to.
    altitudes: [f64; 2],
    ceiling: f64,
    ends: [Point3; 2],
}

/// Checks an inspection without planning it: what [`plan`] refuses as input before its
/// search, this refuses.
pub fn check(input: &InspectionInput<'_>) -> Result<(), InputError> {
    setup(input).map(|_| ())
}

fn setup(input: &InspectionInput<'_>) -> Result<Setup, InputError> {
    let spec = input.spec;
    if input.structures.is_empty() {
        return Err(InputError::new("no_structures", "/structures", "an inspection needs the mission's structures: polygons with height_m"));
    }
    let groups = target_groups(input.structures, &spec.targets)?;
    let mut prisms: Vec<Prism> = input
        .structures
        .iter()
        .map(|s| Prism { name: s.name.clone(), footprint: s.footprint.clone(), base_m: s.base_m, top_m: s.base_m + s.height_m, is_structure: true, mesh: s.mesh.clone() })
        .collect();
    prisms.extend(input.obstacles.iter().enumerate().map(|(i, (p, h))| Prism {
        name: format!("obstacle-{}", i + 1),
        footprint: p.clone(),
        base_m: 0.0,
        top_m: *h,
        is_structure: false,
        mesh: None,
    }));
    let scene = Scene::new(prisms, input.no_fly_zones, input.geofence.clone(), spec.body_radius_m, spec.safety_margin_m);
    let pois = poi::sample(&scene.prisms, &groups, spec.poi_spacing_m);
    if pois.len() > MAX_POIS {
        return Err(InputError::new(
            "too_many_points",
            "/inspection/poi_spacing_m",
            format!("the targets give {} points of interest at this spacing; the limit is {MAX_POIS}: widen poi_spacing_m", pois.len()),
        ));
    }
    if pois.is_empty() {
        return Err(InputError::new("nothing_to_inspect", "/targets", "the targets have no face to see (every one lies inside another structure)"));
    }
    let range = spec.range_m.unwrap_or(DEFAULT_RANGE_M);
    let optics = Optics {
        hfov_deg: input.fov_deg[0],
        vfov_deg: input.fov_deg[1],
        min_range_m: range[0],
        max_range_m: input.gsd_range_m.map_or(range[1], |r| r.min(range[1])),
        max_incidence_deg: spec.max_incidence_deg,
    };
    if optics.max_range_m <= optics.min_range_m {
        return Err(InputError::new(
            "range_too_short",
            "/gsd_cm",
            format!("this ground sample distance needs the camera within {:.2} m, nearer than the least range", optics.max_range_m),
        ));
    }
    let tallest = scene.prisms.iter().map(|p| p.top_m).fold(0.0, f64::max);
    let altitudes = spec.altitude_range_m.unwrap_or([2.0, tallest + spec.safety_margin_m + optics.max_range_m]);
    let ceiling = altitudes[1].max(tallest + spec.safety_margin_m + spec.body_radius_m + 1.0);
    let ends = [([input.start.x, input.start.y, spec.start_altitude_m], "/start"), ([input.end.x, input.end.y, spec.end_altitude_m], "/end")];
    for (p, at) in ends {
        if !scene.is_free(p, false) {
            return Err(InputError::new("position_not_free", at, "this position lies in a no-fly zone or within the clearance of a structure or obstacle"));
        }
    }
    Ok(Setup { groups, scene, pois, optics, altitudes, ceiling, ends: [ends[0].0, ends[1].0] })
}

/// The share of the progress the search spans: sampling comes before it, measuring after.
const SEARCH_PROGRESS: (f64, f64) = (0.15, 0.95);

/// Plans the inspection; refusals that need the scene (no structures, too many points, a start
/// or end within the clearance, a budget that does not reach from the start to the end) are
/// input errors.
pub fn plan(input: &InspectionInput<'_>, progress: &dyn Progress, stop: &Stop) -> Result<InspectionPlan, PlanError> {
    let spec = input.spec;
    let Setup { groups, scene, pois, optics, altitudes, ceiling, ends: ends3 } = setup(input)?;
    let index = poi::index(&pois);
    let pitch_range = spec.gimbal_pitch_deg.map(f64::to_radians);
    let mut sampler = Sampler::new(&scene, &pois, &index, optics, pitch_range, spec.seed);
    // the sampling volume: the targets' box grown by the range
    let bb = geo::MultiPoint::from(pois.iter().map(|p| Coord { x: p.at[0], y: p.at[1] }).collect::<Vec<_>>()).bounding_rect().expect("points");
    let (lo, size) = (
        [bb.min().x - optics.max_range_m, bb.min().y - optics.max_range_m, altitudes[0]],
        [bb.width() + 2.0 * optics.max_range_m, bb.height() + 2.0 * optics.max_range_m, altitudes[1] - altitudes[0]],
    );
    // viewpoints lie inside the fields (the geofence): targets beyond the camera's reach of
    // every field cannot be seen, whatever the range or the margin
    let reach = Rect::new(Coord { x: lo[0], y: lo[1] }, Coord { x: lo[0] + size[0], y: lo[1] + size[1] });
    if !scene.geofence.intersects(&reach.to_polygon()) {
        return Err(InputError::new(
            "targets_outside_area",
            "/targets",
            format!(
                "the structures to inspect lie more than {:.0} m (the camera's range) from every field: viewpoints must be inside a field, \
                 which is the inspection's geofence; draw the field round the structures",
                optics.max_range_m
            ),
        )
        .into());
    }
    let mut next = 1 + spec.seed.wrapping_mul(7_919) % 1_000_003;
    let (mut views, tries) = sampler.collect(spec.viewpoints, 200 * spec.viewpoints, |_| {
        let h = halton(next);
        next += 1;
        Some([lo[0] + size[0] * h[0], lo[1] + size[1] * h[1], lo[2] + size[2] * h[2]])
    });
    let mut warnings = Vec::new();
    if views.len() < spec.viewpoints {
        warnings.push(format!("{} of {} viewpoints were found in {tries} tries: few places see enough of the targets from outside the clearance", views.len(), spec.viewpoints));
    }
    if views.is_empty() {
        return Err(PlanError::Infeasible(
            "no viewpoint inside the fields and outside the structures' clearance sees the targets: widen the camera's range (inspection.range_m), \
             lower inspection.safety_margin_m, or draw the field further round the structures"
                .into(),
        ));
    }
    if stop.requested() {
        return Err(PlanError::Cancelled);
    }
    let legs = LegPlanner::new(&scene, input.vehicle, ceiling);
    let still = Stationary::of(input.vehicle);
    let (capture_s, capture_j) = still.hover(spec.capture_s);
    let capture = spec.budget.measure(0.0, capture_s, capture_j);
    let weights: Vec<f64> = pois.iter().map(|p| p.weight).collect();
    let pricer = LegPricer { legs: &legs, nodes: RwLock::new(vec![(ends3[START], None), (ends3[END], None)]), budget: spec.budget, still };
    let room = if spec.extension == Extension::None { views.len() } else { MAX_VIEWPOINTS };
    let mut inst = Instance::new(&pricer, weights, spec.budget.value(), room);
    if !inst.edge(START, END).is_finite() {
        return Err(PlanError::Infeasible("no free way leads from the start to the end".into()));
    }
    if inst.edge(START, END) > inst.budget {
        return Err(InputError::new(
            "budget_too_small",
            "/budget",
            format!("the way from the start to the end alone costs {:.1} {}; the budget is {}", inst.edge(START, END), spec.budget.unit(), spec.budget.value()),
        )
        .into());
    }
    let add_views = |inst: &mut Instance, added: &[Viewpoint]| {
        for view in added {
            if inst.add_viewpoint(view.sees.clone(), capture) {
                pricer.nodes.write().expect("nodes").push((view.pose.at, Some(view.pose.yaw)));
            }
        }
    };
    add_views(&mut inst, &views);
    let started = Instant::now();
    let mut search = Search::new(&inst, spec.seed);
    let search_end = loop {
        if stop.requested() {
            return Err(PlanError::Cancelled);
        }
        if search.iterations >= MAX_ITERATIONS {
            break SearchEnd::Iterations;
        }
        if search.since_improvement >= PATIENCE {
            break SearchEnd::NoImprovement;
        }
        if started.elapsed() >= spec.search_time {
            break SearchEnd::TimeLimit;
        }
        // the search ends at whichever of its three limits comes first
        let done = (search.iterations as f64 / MAX_ITERATIONS as f64)
            .max(search.since_improvement as f64 / PATIENCE as f64)
            .max(started.elapsed().as_secs_f64() / spec.search_time.as_secs_f64());
        if !progress.report(SEARCH_PROGRESS.0 + (SEARCH_PROGRESS.1 - SEARCH_PROGRESS.0) * done.min(1.0)) {
            return Err(PlanError::Cancelled);
        }
        search.iterate(&inst);
        if spec.extension != Extension::None && views.len() < MAX_VIEWPOINTS && !search.best.tour.is_empty() {
            let path: Vec<Point3> = std::iter::once(ends3[START]).chain(search.best.tour.iter().map(|&k| views[k].pose.at)).chain([ends3[END]]).collect();
            let mean_leg = legs::length_3d(&path) / (path.len() - 1) as f64;
            let want = spec.extension_per_iteration.min(MAX_VIEWPOINTS - views.len());
            let (added, _) = sampler.collect(want, 50 * want, |s| {
                let pick = 1 + (s.uniform_index(path.len() - 2));
                Some(match spec.extension {
                    Extension::Ellipse => s.on_spheroid(path[pick], path[pick + 1]),
                    _ => s.in_ball(path[pick], mean_leg / 8.0),
                })
            });
            add_views(&mut inst, &added);
            views.extend(added);
        }
    };
    let tour = search.best.tour.clone();
    if tour.is_empty() {
        let nearest = (0..inst.viewpoints()).map(|k| inst.edge(START, k + 2) + inst.node_cost[k] + inst.edge(k + 2, END)).fold(f64::INFINITY, f64::min);
        warnings.push(format!(
            "no viewpoint fits in the budget: the cheapest one costs {nearest:.1} {} from the start to the end; the budget is {}",
            spec.budget.unit(),
            spec.budget.value()
        ));
    }
    finish(FinishInput { inst: &inst, tour, views: &views, legs: &legs, ends: ends3, pois, groups, scene: &scene, still, spec, optics }, search, search_end, tries, warnings)
}

/// Legs between the nodes (the start, the end, then the viewpoints) under the budget's
/// measure; the camera's turn between two viewpoints is part of their leg.
struct LegPricer<'a> {
    legs: &'a LegPlanner<'a>,
    /// Each node's position, and its camera's yaw (none at the start and the end: the
    /// take-off and landing headings are free).
    nodes: RwLock<Vec<(Point3, Option<f64>)>>,
    budget: BudgetLimit,
    still: Stationary,
}

impl Pricer for LegPricer<'_> {
    fn pair(&self, u: usize, v: usize) -> (f64, f64) {
        let ((a, yaw_a), (b, yaw_b)) = {
            let nodes = self.nodes.read().expect("nodes");
            (nodes[u], nodes[v])
        };
        let Some(there) = self.legs.way(a, b, self.budget, fenced(u, v)) else { return (f64::INFINITY, f64::INFINITY) };
        let turn = match (yaw_a, yaw_b) {
            (Some(x), Some(y)) => {
                let (t, e) = self.still.yaw(turn_deg(x, y));
                self.budget.measure(0.0, t, e)
            }
            _ => 0.0,
        };
        let back = match self.budget {
            // the same way backwards is as long
            BudgetLimit::LengthM(_) => there.length_m,
            _ => legs::reversed(&there, self.legs.vehicle()).cost(self.budget),
        };
        (there.cost(self.budget) + turn, back + turn)
    }
}

struct FinishInput<'a> {
    inst: &'a Instance<'a>,
    tour: Vec<usize>,
    views: &'a [Viewpoint],
    legs: &'a LegPlanner<'a>,
    ends: [Point3; 2],
    pois: Vec<Poi>,
    groups: Vec<TargetGroup>,
    scene: &'a Scene,
    still: Stationary,
    spec: &'a InspectionSpec,
    optics: Optics,
}

/// The flown path: its legs recomputed (the same ones the search priced), what each viewpoint
/// adds, and the figures per target.
fn finish(f: FinishInput<'_>, search: Search, search_end: SearchEnd, tries: usize, warnings: Vec<String>) -> Result<InspectionPlan, PlanError> {
    let nodes: Vec<usize> = std::iter::once(START).chain(f.tour.iter().map(|&k| k + 2)).chain([END]).collect();
    let position = |n: usize| if n < 2 { f.ends[n] } else { f.views[n - 2].pose.at };
    let mut legs_flown = Vec::new();
    for w in nodes.windows(2) {
        let (u, v) = (w[0], w[1]);
        let (a, b) = (position(u), position(v));
        // the table priced each pair from the lower node to the higher, and the other way as
        // that leg reversed
        let leg = if u < v { f.legs.leg(a, b, f.spec.budget, fenced(u, v)) } else { f.legs.leg(b, a, f.spec.budget, fenced(u, v)).map(|l| legs::reversed(&l, f.legs.vehicle())) };
        legs_flown.push(leg.ok_or_else(|| PlanError::Infeasible("a leg the search used has no free way".into()))?);
    }
    let mut seen = vec![false; f.pois.len()];
    let (mut eta, mut energy) = (0.0, 0.0);
    let (mut stationary_s, mut stationary_j) = (0.0, 0.0);
    let mut flown = Vec::new();
    let mut prev_yaw: Option<f64> = None;
    for (j, &k) in f.tour.iter().enumerate() {
        let v = &f.views[k];
        eta += legs_flown[j].time_s;
        energy += legs_flown[j].energy_j;
        if let Some(y) = prev_yaw {
            let (t, e) = f.still.yaw(turn_deg(y, v.pose.yaw));
            stationary_s += t;
            stationary_j += e;
            eta += t;
            energy += e;
        }
        prev_yaw = Some(v.pose.yaw);
        let new: Vec<u32> = v.sees.iter().copied().filter(|&p| !seen[p as usize]).collect();
        new.iter().for_each(|&p| seen[p as usize] = true);
        flown.push(FlownViewpoint {
            pose: v.pose,
            at: v.pose.at,
            yaw_deg: crate::params::math_to_bearing(v.pose.yaw),
            gimbal_pitch_deg: v.pose.pitch.to_degrees(),
            new_pois: new.len(),
            weighted_gain: new.iter().map(|&p| f.pois[p as usize].weight).sum(),
            eta_s: eta,
            energy_j: energy,
        });
        let (t, e) = f.still.hover(f.spec.capture_s);
        stationary_s += t;
        stationary_j += e;
        eta += t;
        energy += e;
    }
    let groups = f
        .groups
        .iter()
        .enumerate()
        .map(|(g, group)| {
            let members = f.pois.iter().zip(&seen).filter(|(p, _)| p.group == g);
            let mut c = GroupCoverage { name: f.scene.prisms[group.prism].name.clone(), face: group.face, seen: 0, total: 0, weighted_seen: 0.0, weighted_total: 0.0 };
            for (p, s) in members {
                c.total += 1;
                c.weighted_total += p.weight;
                if *s {
                    c.seen += 1;
                    c.weighted_seen += p.weight;
                }
            }
            c
        })
        .collect();
    let budget_used = legs_flown.iter().map(|l| l.cost(f.spec.budget)).sum::<f64>() + f.spec.budget.measure(0.0, stationary_s, stationary_j);
    debug_assert!((budget_used - f.inst.tour_cost(&f.tour)).abs() <= 1e-6 * budget_used.max(1.0), "{budget_used} vs {}", f.inst.tour_cost(&f.tour));
    Ok(InspectionPlan {
        legs: legs_flown,
        viewpoints: flown,
        pois: f.pois,
        seen,
        groups,
        stationary_s,
        stationary_j,
        budget: f.spec.budget,
        budget_used,
        viewpoints_sampled: f.views.len(),
        sampling_tries: tries,
        iterations: search.iterations,
        search_end,
        warnings,
        optics: f.optics,
    })
}

/// The smaller turn from one yaw to another, degrees.
fn turn_deg(a: f64, b: f64) -> f64 {
    let d = (b - a).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d).to_degrees()
}

/// Whether the leg between nodes `u` and `v` must stay in the geofence: the start and the end
/// may lie outside the area; viewpoints never do.
fn fenced(u: usize, v: usize) -> bool {
    u >= 2 && v >= 2
}
