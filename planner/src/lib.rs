//! The planner: geometry in, plan out. Pure: no I/O, no async runtime, no database.
//!
//! The stages, one module each, in the order a plan flows through them (a module uses only
//! modules above it in this list, which `tests/it/architecture.rs` checks; this root composes
//! them all):
//!
//! - [`error`], `archive` (zips and XML from outside, read with limits), [`geom`], [`frame`]
//!   (WGS84 ⇄ local metres), [`path`] (the flight path), [`wind`] (the wind triangle),
//!   [`stop`] (cancellation and time limits, asked by every long loop): the vocabulary every
//!   stage shares;
//! - [`mesh`]: Wavefront OBJ models of structures, read with limits;
//! - [`terrain`]: the user's elevation model (GeoTIFF, SRTM), and the altitude profile that
//!   keeps a path at its height above that ground;
//! - `field`: parse, validate and normalise the mission;
//! - `sweep`: parallel sweep lines over an area, and the width of a shape across a direction;
//! - `decompose`: cells, each swept by `sweep`'s lines in its own direction;
//! - `turn`: how the vehicle joins one line to the next (straight, Dubins, trochoidal in wind),
//!   and climbs over obstacles;
//! - `route`: the order of cells and lines (GTSP) and transits around no-fly zones;
//! - [`energy`]: time and energy of a path, one model per file;
//! - [`vehicle`], [`camera`], [`params`]: the request's vehicle, camera and parameters;
//! - `sortie`: splitting a plan that needs several batteries;
//! - [`metrics`]: one measure of every plan, and the rule that chooses among plans;
//! - [`planners`]: each composes the stages into a method; its registry lists every planner;
//! - `pattern`: the area flown again in further passes (a double grid, obliques);
//! - `fleet`: one area flown by several drones at once (bands per drone sized so that they land
//!   together, and the check that no two come too close at the same time);
//! - [`farm`]: a whole farm's fields shared among machines over working days, each field
//!   planned on its own first, with transits in a straight line or along roads;
//! - [`patrol`]: several UAVs revisiting the cells of a grid over the area (NC-Drone and the
//!   methods it was compared with), simulated, with the metrics of seed 002;
//! - [`inspection`]: a multirotor's flight to viewpoints around structures that sees as much
//!   of their faces as a budget allows (seed 001);
//! - [`export`]: the trajectory as GeoJSON, and the files of flight planners, Google Earth and
//!   farm terminals written from it; [`import`]: missions read from such files;
//!   [`estimate`]: a given route's time and energy;
//! - `routing_study` (feature `routing-study`): routing kept for comparison in the benchmark,
//!   not used by planners;
//! - `compose`: one vehicle's flight from the stages (plan, obstacles, sorties, estimate), and a
//!   fleet's; `report`: the finished plan's statistics and trajectory;
//! - `resume`: what a plan has left once its flight stopped, flown like a plan ([`resume`]);
//!   this root validates the request and composes the stages.
//!
//! The crate exports what the service and the CLI use; the stages in plain text are private.

pub mod archive;
pub mod camera;
mod compose;
mod decompose;
pub mod energy;
pub mod error;
pub mod estimate;
pub mod export;
pub mod farm;
mod field;
mod fleet;
pub mod frame;
pub mod geom;
pub mod import;
pub mod inspection;
pub mod mesh;
pub mod metrics;
pub mod params;
pub mod path;
pub mod patrol;
mod pattern;
pub mod planners;
mod report;
mod resume;
mod route;
#[cfg(any(test, feature = "routing-study"))]
pub mod routing_study;
mod sortie;
pub mod stop;
mod sweep;
pub mod terrain;
mod turn;
pub mod vehicle;
pub mod wind;

use std::time::Instant;

use geo::{Area, BooleanOps, Contains, Coord};
use rayon::prelude::*;

pub use error::{InputError, PlanError};
pub use field::{FieldLimits, MissionGeometry};
/// The geometry types of the planner's interface.
pub use geo;
/// The trajectory's type.
pub use geojson;
pub use metrics::Stats;
pub use params::PlanParams;
pub use planners::Progress;
pub use stop::Stop;

use compose::{Ends, Prepared, Stages};
use field::Field;
use geom::grow;
use route::visibility::TransitPlanner;
use turn::TurnModel;
use turn::climb::Obstacles;

/// A finished plan.
#[derive(Debug, Clone)]
pub struct PlanOutput {
    pub stats: Stats,
    pub trajectory: geojson::FeatureCollection,
}

/// Longest sweep the service plans in one job (area / spacing), in km.
pub const MAX_SWEEP_KM: f64 = 2_000.0;

/// Most sweep lines ordered one by one (`line_gtsp`, `auto`, and every fixed-wing plan): the
/// route tables grow with their square (about 700 lines took 6 s and 600 MB with `line_gtsp`).
pub const MAX_ROUTED_LINES: usize = 800;

/// Most corners transits are routed around (the visibility graph checks every pair of them
/// against every zone: 1.4 s for 1 921 corners on two cores).
pub const MAX_TRANSIT_CORNERS: usize = 2000;

/// Checks a mission without planning it: the same validation as [`plan`] applies first.
pub fn validate_mission(mission: &MissionGeometry<'_>, limits: &FieldLimits) -> Result<(), InputError> {
    Field::parse(mission, limits).map(|_| ())
}

fn prepare(mission: &MissionGeometry<'_>, params: &PlanParams, profiles: &[vehicle::Vehicle], limits: &FieldLimits) -> Result<Prepared, InputError> {
    let resolved = params.resolve(profiles)?;
    let planner = chosen_planner(params, resolved.vehicle.kind)?;
    if resolved.headland.is_some() != planner.for_ground_vehicles() {
        let why = if resolved.headland.is_some() { "a ground vehicle is planned with planner headland" } else { "this planner plans ground vehicles: give vehicle kind ground" };
        return Err(InputError::new("planner_vehicle_mismatch", "/planner", why));
    }
    if !resolved.fleet.is_empty() && resolved.headland.is_none() && !planner.plans_fleet_parts() {
        let fleet_planners: Vec<&str> = planners::registry().iter().filter(|p| p.plans_fleet_parts()).map(|p| p.id()).collect();
        return Err(InputError::new(
            "planner_not_for_fleets",
            "/planner",
            format!("a fleet's parts are planned with {}: their lines follow the bands the field is cut into", fleet_planners.join(", ")),
        ));
    }
    if resolved.pattern != params::Pattern::Grid {
        if !planner.lays_parallel_lines() {
            return Err(InputError::new("not_for_planner", "/pattern", format!("planner {} flies no parallel lines, which the pattern repeats", planner.id())));
        }
        if resolved.headland.is_some() {
            return Err(InputError::new("not_for_ground_vehicles", "/pattern", "a ground vehicle works its field once: leave out pattern"));
        }
        if !resolved.fleet.is_empty() {
            return Err(InputError::new(
                "pattern_not_for_fleets",
                "/pattern",
                "a fleet's drones fly bands side by side: the pattern's other passes would cross the other drones' bands",
            ));
        }
    }
    if params.swath_ends.is_some() && !planner.lays_parallel_lines() {
        return Err(InputError::new("not_for_planner", "/swath_ends", format!("planner {} flies no parallel lines, so has no line ends to place", planner.id())));
    }
    let field = Field::parse(mission, limits)?;
    let sweep_km = field.area.unsigned_area() / resolved.line_spacing_m / 1000.0;
    if sweep_km > MAX_SWEEP_KM {
        return Err(InputError::new("plan_too_long", "/line_spacing_m", format!("this spacing needs about {sweep_km:.0} km of sweep lines; the limit is {MAX_SWEEP_KM} km")));
    }
    let keep_out = grow(&field.no_fly_zones, resolved.nfz_margin_m);
    let corners = TransitPlanner::node_count(&keep_out);
    if corners > MAX_TRANSIT_CORNERS {
        return Err(InputError::new(
            "too_many_zone_corners",
            "/no_fly_zones",
            format!(
                "routing around the no-fly zones (grown by the margin) takes {corners} corners; the limit is {MAX_TRANSIT_CORNERS}: simplify their outlines or merge small zones"
            ),
        ));
    }
    let walls = grow(&field.no_fly_zones, resolved.nfz_margin_m / 2.0);
    let region = if keep_out.0.is_empty() { field.area.clone() } else { field.area.difference(&keep_out) };
    if region.unsigned_area() < 1.0 {
        return Err(InputError::new("nothing_to_cover", "/no_fly_zones", "the no-fly zones and their margin cover the whole field"));
    }
    if planner.follows_corridors() && field.corridors.is_empty() {
        return Err(InputError::new("no_corridor", "/planner", format!("planner {} flies corridors: give the area a LineString feature with its width as width_m", planner.id())));
    }
    if planner.follows_corridors() && field.polygon_fields > 0 {
        return Err(InputError::new(
            "not_for_planner",
            "/area",
            format!("planner {} flies corridors only: plan the area's polygon fields in a mission of their own", planner.id()),
        ));
    }
    // a corridor's lines follow its centre line: none is ordered one by one
    let routes_lines = !planner.follows_corridors() && (planner.orders_lines_one_by_one() || matches!(resolved.vehicle.turn_model(), TurnModel::Dubins(_)));
    // the line count and a ground vehicle's headland (most of the set-up) side by side
    let too_many_lines = || -> Result<(), InputError> {
        if !routes_lines {
            return Ok(());
        }
        // the fewest of four headings: the planners search headings with near the fewest lines
        let lines = [0.0, 45.0, 90.0, 135.0].into_par_iter().map(|deg: f64| sweep::sweep(&region, &keep_out, deg.to_radians(), resolved.layout).segment_count()).min().unwrap_or(0);
        if lines > MAX_ROUTED_LINES {
            return Err(InputError::new(
                "too_many_lines",
                "/line_spacing_m",
                format!("this plan orders about {lines} sweep lines one by one; the limit is {MAX_ROUTED_LINES}: widen the spacing, or use boustrophedon with a multirotor"),
            ));
        }
        Ok(())
    };
    let headland = || resolved.headland.clone().map(|spec| ground_setup(spec, &resolved.vehicle, &field, &region)).transpose();
    let (lines_checked, ground) = rayon::join(too_many_lines, headland);
    lines_checked?;
    let local = |p: [f64; 2], pointer: &str| -> Result<Coord, InputError> {
        let c = field.frame.to_local(p[0], p[1]);
        if walls.contains(&c) {
            return Err(InputError::new("point_in_no_fly_zone", pointer, "this point lies inside a no-fly zone or its margin"));
        }
        Ok(c)
    };
    if !field.obstacles.is_empty() && resolved.altitude_m.is_none() {
        return Err(InputError::new(
            "altitude_missing",
            "/altitude_m",
            "the mission has obstacles: give the flight altitude (altitude_m, or a camera with gsd_cm) so that the plan can climb over them",
        ));
    }
    let ground = ground?;
    check_terrain(mission, &resolved, &field)?;
    let start = resolved.start.map(|p| local(p, "/start/position")).transpose()?.or(field.home);
    let end = resolved.end.map(|p| local(p, "/end/position")).transpose()?.or(field.home);
    let fleet_homes =
        resolved.fleet.iter().enumerate().map(|(k, d)| d.home.map(|p| local(p, &format!("/fleet/{k}/home"))).transpose().map(|h| h.or(field.home))).collect::<Result<_, _>>()?;
    if !resolved.landing_sites.is_empty() && field.home.is_none() {
        return Err(InputError::new(
            "home_missing",
            "/landing_sites",
            "landing sites are where sorties land besides home: give the mission a home, where the first one leaves from",
        ));
    }
    let landing_sites = resolved.landing_sites.iter().enumerate().map(|(k, &p)| local(p, &format!("/landing_sites/{k}"))).collect::<Result<_, _>>()?;
    Ok(Prepared { resolved, planner, field, region, keep_out, walls, start, end, fleet_homes, landing_sites, ground })
}

/// Over terrain: the mission has an elevation model, and it covers the fields, home, start and
/// end (and the drones' homes) with a margin.
fn check_terrain(mission: &MissionGeometry<'_>, resolved: &params::Resolved, field: &Field) -> Result<(), InputError> {
    if resolved.terrain.is_none() {
        return Ok(());
    }
    let model = mission.terrain.ok_or_else(|| {
        InputError::new(
            "terrain_missing",
            "/altitude_reference",
            "the mission has no elevation model to follow: upload one (PUT /api/v1/missions/{id}/terrain, or coverplan plan --terrain FILE.tif), or plan with altitude_reference \"home\"",
        )
    })?;
    let mut places = terrain_places(field, mission.home);
    places.extend(resolved.start.map(|p| ("the start".to_string(), "/start/position".to_string(), p)));
    places.extend(resolved.end.map(|p| ("the end".to_string(), "/end/position".to_string(), p)));
    for (k, d) in resolved.fleet.iter().enumerate() {
        places.extend(d.home.map(|h| (format!("drone {k}'s home"), format!("/fleet/{k}/home"), h)));
    }
    for (k, &site) in resolved.landing_sites.iter().enumerate() {
        places.push((format!("landing site {k}"), format!("/landing_sites/{k}"), site));
    }
    model.check_covers(&places)
}

/// The places an elevation model must cover: every field's outline and home.
fn terrain_places(field: &Field, home: Option<[f64; 2]>) -> Vec<(String, String, [f64; 2])> {
    let mut places: Vec<(String, String, [f64; 2])> = Vec::new();
    for (k, polygon) in field.area.0.iter().enumerate() {
        places.extend(polygon.exterior().coords().map(|&c| (format!("field {}", k + 1), "/area".to_string(), field.frame.to_wgs84(c))));
    }
    places.extend(home.map(|h| ("home".to_string(), "/home".to_string(), h)));
    places
}

/// Checks that `model` covers the mission's fields and home with a margin (an elevation model
/// uploaded for it); a plan's start and end are checked when it is planned.
pub fn check_terrain_covers(mission: &MissionGeometry<'_>, model: &terrain::ElevationModel, limits: &FieldLimits) -> Result<(), InputError> {
    let field = Field::parse(mission, limits)?;
    model.check_covers(&terrain_places(&field, mission.home))
}

/// The ground a plan over terrain follows: the lookup spans the fields, home, start and end
/// and a kilometre around them (a path beyond is sampled exactly).
fn terrain_stage<'a>(mission: &MissionGeometry<'a>, prepared: &Prepared) -> Option<compose::Terrain<'a>> {
    let (model, spec, height_m) = (mission.terrain?, prepared.resolved.terrain?, prepared.resolved.altitude_m?);
    let rect = geo::BoundingRect::bounding_rect(&prepared.field.area)?;
    let (mut lo, mut hi) = (rect.min(), rect.max());
    let homes = prepared.fleet_homes.iter().flatten().chain(&prepared.landing_sites).copied();
    for c in [prepared.start, prepared.end, prepared.field.home].into_iter().flatten().chain(homes) {
        lo = Coord { x: lo.x.min(c.x), y: lo.y.min(c.y) };
        hi = Coord { x: hi.x.max(c.x), y: hi.y.max(c.y) };
    }
    let margin = Coord { x: 1000.0, y: 1000.0 };
    let ground = terrain::profile::Ground::new(model, prepared.field.frame, [lo - margin, hi + margin]);
    let settings = terrain::profile::Settings { height_m, tolerance_m: spec.tolerance_m, climb: spec.climb, descent: spec.descent };
    Some(compose::Terrain { ground, settings })
}

/// A ground vehicle's headland, refused where it leaves no room: no mainland, or a headland
/// narrower than the turning radius (no turn at a swath's end would stay in the field).
fn ground_setup(spec: params::HeadlandSpec, vehicle: &vehicle::Vehicle, field: &Field, region: &geo::MultiPolygon) -> Result<planners::headland::GroundSetup, InputError> {
    if !field.obstacles.is_empty() {
        return Err(InputError::new("obstacles", "/obstacles", "a ground vehicle cannot climb over obstacles: give them as holes of the field or as no-fly zones"));
    }
    let radius = vehicle.planning_radius_m();
    let reach = vehicle.steering().reach_ahead();
    if reach > spec.width_m {
        return Err(InputError::new(
            "headland_too_narrow",
            "/headland_passes",
            format!("turning at a swath's end takes {reach:.1} m beyond it; the headland is {:.1} m wide: add passes or give headland_width_m", spec.width_m),
        ));
    }
    let headland = decompose::headland::headland(region, spec.width_m, spec.passes, radius);
    if headland.mainland.0.is_empty() {
        // the widest place: the last point left as the field is shrunk
        let (mut lo, mut hi) = (0.0, spec.width_m);
        for _ in 0..12 {
            let mid = (lo + hi) / 2.0;
            if geo::Buffer::buffer(region, -mid).0.is_empty() { hi = mid } else { lo = mid }
        }
        let centre = geo::Centroid::centroid(&geo::Buffer::buffer(region, -lo)).map_or(Coord { x: 0.0, y: 0.0 }, |p| p.0);
        let [lon, lat] = field.frame.to_wgs84(centre);
        return Err(InputError::new(
            "field_too_narrow",
            "/headland_passes",
            format!(
                "the field is at most {:.1} m wide (at [{lon:.6}, {lat:.6}]): two headlands of {:.1} m leave no room for swaths; use fewer passes or a narrower headland_width_m",
                2.0 * lo,
                spec.width_m
            ),
        ));
    }
    if let Some(payload) = &spec.payload {
        use geo::{Distance, Euclidean};
        let reach = params::payload::REFILL_POINT_REACH_M;
        for (k, p) in payload.refill_points.iter().enumerate() {
            let off = Euclidean.distance(&geo::Point(field.frame.to_local(p[0], p[1])), region);
            if off > reach {
                return Err(InputError::new(
                    "refill_point_far",
                    format!("/payload/refill_points/{k}"),
                    format!("refill point {k} lies {off:.0} m from the field: give points on its boundary or at its entrances, at most {reach:.0} m from it"),
                ));
            }
        }
    }
    Ok(planners::headland::GroundSetup { spec, headland, frame: field.frame })
}

/// Checks a plan request without planning: what [`plan`] would refuse as input, this refuses.
pub fn check_plan(mission: &MissionGeometry<'_>, params: &PlanParams, profiles: &[vehicle::Vehicle], limits: &FieldLimits) -> Result<(), InputError> {
    if params.planner.as_deref() == Some(INSPECTION) {
        return inspection::check(&prepare_inspection(mission, params, profiles, limits)?.input());
    }
    prepare(mission, params, profiles, limits).map(|_| ())
}

/// The planner id of the inspection of structures.
pub const INSPECTION: &str = params::inspection::PLANNER_ID;

/// What planner `inspection` says of itself in the planners' list.
pub const INSPECTION_DESCRIPTION: &str = "Inspection of structures (seed 001): viewpoints around the mission's structures, chosen and ordered within a budget \
     (length, time or energy) to see the largest weighted share of their walls and roofs; a multirotor, collision-free legs in 2.5D";

struct InspectionSetup {
    field: Field,
    vehicle: vehicle::Vehicle,
    spec: params::inspection::InspectionSpec,
    fov_deg: [f64; 2],
    gsd_range_m: Option<f64>,
    start: Coord,
    end: Coord,
}

impl InspectionSetup {
    fn input(&self) -> inspection::InspectionInput<'_> {
        inspection::InspectionInput {
            structures: &self.field.structures,
            obstacles: &self.field.obstacles,
            no_fly_zones: &self.field.no_fly_zones,
            geofence: &self.field.area,
            vehicle: &self.vehicle,
            spec: &self.spec,
            fov_deg: self.fov_deg,
            gsd_range_m: self.gsd_range_m,
            start: self.start,
            end: self.end,
        }
    }
}

/// Every method a plan request may name, as `GET /api/v1/planners` lists them: the coverage
/// planners of [`planners::registry`], then the inspection of structures, then patrols.
pub fn catalogue() -> Vec<planners::PlannerInfo> {
    let inspection = planners::PlannerInfo {
        id: INSPECTION,
        name: "Inspection of structures",
        method: planners::MethodKind::Inspection,
        description: INSPECTION_DESCRIPTION,
        direction_rule: "none: viewpoints, not sweep lines",
        vehicle_kinds: vec![vehicle::VehicleKind::Multirotor],
        default_for: Vec::new(),
        fleets: false,
        parameters: inspection::PARAMETERS.to_vec(),
    };
    let patrol = planners::PlannerInfo {
        id: patrol::PLANNER_ID,
        name: "Patrol with several UAVs",
        method: planners::MethodKind::Patrol,
        description: patrol::DESCRIPTION,
        direction_rule: "none: a grid's cells, revisited",
        vehicle_kinds: vec![vehicle::VehicleKind::Multirotor],
        default_for: Vec::new(),
        fleets: false,
        parameters: patrol::PARAMETERS.to_vec(),
    };
    planners::registry().iter().map(|p| planners::PlannerInfo::of(*p)).chain([inspection, patrol]).collect()
}

/// The preset an inspection's camera defaults to.
const INSPECTION_CAMERA: &str = "dji_mavic3_enterprise";

fn prepare_inspection(mission: &MissionGeometry<'_>, params: &PlanParams, profiles: &[vehicle::Vehicle], limits: &FieldLimits) -> Result<InspectionSetup, InputError> {
    let (vehicle, spec) = params.resolve_inspection(profiles)?;
    let field = Field::parse(mission, limits)?;
    let camera = params.camera.clone().unwrap_or_else(|| camera::Camera { preset: Some(INSPECTION_CAMERA.into()), ..camera::Camera::default() });
    let (fov_deg, gsd_per_m) = camera.field_of_view()?;
    let gsd_range_m = match params.gsd_cm {
        Some(g) => {
            error::check_range(g, 0.01, 1_000.0, "/gsd_cm", "cm/px")?;
            Some(g / 100.0 / gsd_per_m)
        }
        None => None,
    };
    let local = |p: Option<[f64; 2]>| p.map(|[lon, lat]| field.frame.to_local(lon, lat));
    let start = local(params::checked_position(&params.start, "start")?)
        .or(field.home)
        .ok_or_else(|| InputError::new("start_missing", "/start", "an inspection starts somewhere: give start, or the mission's home"))?;
    let end = local(params::checked_position(&params.end, "end")?).unwrap_or(start);
    Ok(InspectionSetup { field, vehicle, spec, fov_deg, gsd_range_m, start, end })
}

fn plan_inspection(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    progress: &dyn Progress,
    stop: &Stop,
) -> Result<PlanOutput, PlanError> {
    let started = Instant::now();
    let s = prepare_inspection(mission, params, profiles, limits)?;
    if !progress.report(0.1) {
        return Err(PlanError::Cancelled);
    }
    let planned = inspection::plan(&s.input(), progress, stop)?;
    let trajectory = export::geojson::inspection_collection(&s.field.frame, &planned, s.spec.show_unseen);
    let mut stats = planned.stats();
    if planned.energy_j() > s.vehicle.battery.usable_j() {
        stats.batteries_needed = (planned.energy_j() / s.vehicle.battery.usable_j()).ceil() as usize;
        stats.warnings.push(format!(
            "this flight needs {:.0} kJ; one battery gives {:.0} kJ above its reserve: give a budget in max_energy_j to keep it to one battery",
            planned.energy_j() / 1000.0,
            s.vehicle.battery.usable_j() / 1000.0
        ));
    }
    stats.planning_time_ms = started.elapsed().as_secs_f64() * 1000.0;
    progress.report(1.0);
    Ok(PlanOutput { stats, trajectory })
}

/// Plans `mission` with `params`; `vehicle.profile` names one of `profiles`. `progress` is
/// called between stages and may cancel; `stop` is asked inside every long loop and ends the
/// plan with [`PlanError::Cancelled`] soon after it is raised or its deadline passes.
pub fn plan(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    progress: &dyn Progress,
    stop: &Stop,
) -> Result<PlanOutput, PlanError> {
    let stopping = |fraction: f64| !stop.requested() && progress.report(fraction);
    let planned = if params.planner.as_deref() == Some(INSPECTION) {
        plan_inspection(mission, params, profiles, limits, &stopping, stop)
    } else {
        plan_until(mission, params, profiles, limits, &stopping, stop)
    };
    match planned {
        // stages cut short after a stop may fail or return anything: neither is the answer
        _ if stop.requested() => Err(PlanError::Cancelled),
        planned => planned,
    }
}

fn plan_until(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    progress: &dyn Progress,
    stop: &Stop,
) -> Result<PlanOutput, PlanError> {
    let started = Instant::now();
    let prepared = prepare(mission, params, profiles, limits)?;
    if !progress.report(0.1) {
        return Err(PlanError::Cancelled);
    }
    let Prepared { resolved, field, region, .. } = &prepared;
    let (mut stats, trajectory) = with_stages(mission, &prepared, stop, |stages| {
        let (flights, fleet) = if resolved.fleet.is_empty() {
            let flight = stages.fly(&resolved.vehicle, Ends::new(prepared.start, prepared.end, field.home), region, None, progress)?;
            (vec![Some(flight)], None)
        } else {
            let (flights, fleet) = if prepared.ground.is_some() { stages.fly_ground_fleet(progress)? } else { stages.fly_fleet(progress)? };
            (flights, Some(fleet))
        };
        report::finish(&prepared, &flights, fleet, stages.terrain.is_some())
    })?;
    stats.planning_time_ms = started.elapsed().as_secs_f64() * 1000.0;
    progress.report(1.0);
    Ok(PlanOutput { stats, trajectory })
}

/// Hands `fly` the stages every flight of `prepared` shares: transits round the zones, climbs
/// over obstacles, the ground under a plan over terrain.
fn with_stages<T>(mission: &MissionGeometry<'_>, prepared: &Prepared, stop: &Stop, fly: impl FnOnce(&Stages<'_>) -> T) -> T {
    let Prepared { resolved, field, keep_out, walls, .. } = prepared;
    let transit = TransitPlanner::new(keep_out, walls);
    let obstacles = resolved
        .altitude_m
        .filter(|_| !field.obstacles.is_empty())
        .map(|altitude| Obstacles::new(&field.obstacles, altitude, resolved.obstacle_clearance_m, resolved.max_climb_deg, resolved.coverage_penalty));
    let terrain = terrain_stage(mission, prepared);
    fly(&Stages { prepared, transit: &transit, obstacles: obstacles.as_ref(), terrain: terrain.as_ref(), stop })
}

/// What `original` (a plan of `mission` with `params`, as its trajectory) has left once its
/// flight stopped where `request` says, planned as a plan: the lines not flown (the cut one
/// from `photos_back` trigger distances before the cut), from home or from the aircraft in the
/// air, split into sorties again (docs/methods.md, resume).
#[allow(clippy::too_many_arguments)]
pub fn resume(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    original: &geojson::FeatureCollection,
    request: &params::resume::Resume,
    progress: &dyn Progress,
    stop: &Stop,
) -> Result<PlanOutput, PlanError> {
    let started = Instant::now();
    let (prepared, remainder) = prepare_resume(mission, params, profiles, limits, original, request)?;
    if !progress.report(0.1) {
        return Err(PlanError::Cancelled);
    }
    let Prepared { resolved, field, region, .. } = &prepared;
    let airborne = request.airborne_at.map(|[lon, lat]| field.frame.to_local(lon, lat));
    // of a fleet, the drone that stopped flies the rest of its part from its home, in its layer
    let (vehicle, (start, end, home), part) = match remainder.vehicle() {
        Some(k) => {
            let drone = resolved.fleet.get(k).ok_or_else(|| PlanError::Infeasible(format!("the plan's trajectory names drone {k}, which its fleet does not have")))?;
            let home = prepared.fleet_homes[k];
            (&drone.vehicle, (home, home, home), Some(compose::FleetPart::in_layer(resolved, k)))
        }
        None => (&resolved.vehicle, (prepared.start, prepared.end, field.home), None),
    };
    let ends = Ends { airborne: airborne.is_some(), first_battery: request.battery_remaining, ..Ends::new(airborne.or(start), end, home) };
    let (mut stats, mut trajectory) = with_stages(mission, &prepared, stop, |stages| {
        let flight = stages.fly_route(vehicle, ends, region, part, &|problem| remainder.route(problem))?;
        report::finish(&prepared, &[Some(flight)], None, stages.terrain.is_some())
    })?;
    if let params::resume::Cut::Flown(flown) = &request.cut {
        trajectory.features.push(resume::track_feature(flown));
    }
    stats.resume = Some(remainder.stats(&field.frame));
    stats.planning_time_ms = started.elapsed().as_secs_f64() * 1000.0;
    progress.report(1.0);
    Ok(PlanOutput { stats, trajectory })
}

/// Checks a resume request without planning: what [`resume`] would refuse as input (the kind
/// of plan, the cut), this refuses.
pub fn check_resume(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    original: &geojson::FeatureCollection,
    request: &params::resume::Resume,
) -> Result<(), InputError> {
    prepare_resume(mission, params, profiles, limits, original, request).map(|_| ())
}

fn prepare_resume(
    mission: &MissionGeometry<'_>,
    params: &PlanParams,
    profiles: &[vehicle::Vehicle],
    limits: &FieldLimits,
    original: &geojson::FeatureCollection,
    request: &params::resume::Resume,
) -> Result<(Prepared, resume::Remainder), InputError> {
    if params.planner.as_deref() == Some(INSPECTION) {
        return Err(InputError::new("not_resumable", "/at", "an inspection is not resumed: plan it again with the viewpoints left as its targets"));
    }
    if params.payload.is_some() {
        return Err(InputError::new(
            "not_resumable",
            "/at",
            "a plan with a payload is not resumed yet: the tank's level where it stopped is not carried; plan the field again with the worked part as a hole",
        ));
    }
    let prepared = prepare(mission, params, profiles, limits)?;
    let resolved = &prepared.resolved;
    if let Some([lon, lat]) = request.airborne_at
        && prepared.walls.contains(&prepared.field.frame.to_local(lon, lat))
    {
        return Err(InputError::new("point_in_no_fly_zone", "/position", "the aircraft is inside a no-fly zone or its margin: fly it out, then resume"));
    }
    // without a camera, half a line's width stands for the trigger distance
    let footprint = resolved.camera.map(|c| c.footprint());
    let sampling = resume::Sampling {
        trigger_m: footprint.map_or(resolved.line_spacing_m / 2.0, |f| f.photo_spacing_m),
        footprint_along_m: footprint.map(|f| f.along_m),
        tolerance_m: (resolved.line_spacing_m / 4.0).max(1.0),
    };
    let remainder = resume::Remainder::new(original, &prepared.field.frame, request, &sampling)?;
    Ok((prepared, remainder))
}

/// The planner a request names, or the registry's default for its vehicle's kind.
fn chosen_planner(params: &PlanParams, kind: vehicle::VehicleKind) -> Result<&'static dyn planners::Planner, InputError> {
    match params.planner.as_deref() {
        Some(id) => planners::find(id).ok_or_else(|| unknown_planner(id)),
        None => planners::default_for(kind).ok_or_else(|| InputError::new("unknown_planner", "/planner", format!("no planner is the default for a {kind:?} vehicle: name one"))),
    }
}

/// The id of the method a request is planned with (the one it names, or the default for its
/// vehicle), for labels; `None` when the request would be refused.
pub fn method_id(params: &PlanParams, profiles: &[vehicle::Vehicle]) -> Option<&'static str> {
    if params.planner.as_deref() == Some(INSPECTION) {
        return Some(INSPECTION);
    }
    let resolved = params.resolve(profiles).ok()?;
    chosen_planner(params, resolved.vehicle.kind).ok().map(|p| p.id())
}

/// The vehicles a request flies (its fleet's, first to last, or its one vehicle), resolved
/// from `profiles`: the profiles a queued job keeps.
pub fn vehicles_flown(params: &PlanParams, profiles: &[vehicle::Vehicle]) -> Result<Vec<vehicle::Vehicle>, InputError> {
    if params.planner.as_deref() == Some(INSPECTION) {
        return Ok(vec![params.resolve_inspection(profiles)?.0]);
    }
    let resolved = params.resolve(profiles)?;
    if resolved.fleet.is_empty() {
        return Ok(vec![resolved.vehicle]);
    }
    // with the vehicle a fleet's request leaves out (the default profile), which resolving
    // the request again looks up
    let left_out = params.vehicle.resolve(profiles, "/vehicle")?;
    Ok(resolved.fleet.into_iter().map(|d| d.vehicle).chain([left_out]).collect())
}

fn unknown_planner(id: &str) -> InputError {
    let known: Vec<&str> = planners::registry().iter().map(|p| p.id()).chain([INSPECTION]).collect();
    InputError::new("unknown_planner", "/planner", format!("no planner named `{id}`; known: {}", known.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// The ground a ground plan covers, measured by the planner beside its search, is the
    /// ground its path covers: whatever the order of the swaths, the pass each ring is entered
    /// at and the way round it is driven (a field with two ponds, headland passes first and
    /// last, starting from each corner).
    #[test]
    fn a_ground_plans_swept_ground_measured_beside_the_search_is_its_paths() {
        // 300 m × 200 m at 45° N, ponds given in metres from the south-west corner
        let (lon0, lat0) = (10.0, 45.0);
        let at = |x: f64, y: f64| [lon0 + x / (111_320.0 * 45f64.to_radians().cos()), lat0 + y / 110_574.0];
        let ring = |pts: &[(f64, f64)]| pts.iter().chain(&pts[..1]).map(|&(x, y)| at(x, y)).collect::<Vec<_>>();
        let outer = ring(&[(0.0, 0.0), (300.0, 0.0), (280.0, 200.0), (0.0, 170.0)]);
        let ponds = [ring(&[(60.0, 60.0), (100.0, 55.0), (95.0, 100.0)]), ring(&[(180.0, 90.0), (220.0, 90.0), (220.0, 130.0), (180.0, 130.0)])];
        let area = json!({"type": "Polygon", "coordinates": [outer, ponds[0], ponds[1]]});
        let profiles = vehicle::builtin_profiles();
        let mut checked = 0;
        for order in ["first", "last"] {
            for corner in [(1.0, 1.0), (299.0, 1.0), (279.0, 199.0), (1.0, 169.0)] {
                let params: PlanParams = serde_json::from_value(json!({
                    "vehicle": {"kind": "ground", "working_width_m": 6, "turn_radius_m": 7},
                    "headland_order": order,
                    "start": {"position": at(corner.0, corner.1)},
                }))
                .unwrap();
                let mission = MissionGeometry::area(&area);
                let prepared = prepare(&mission, &params, &profiles, &FieldLimits::default()).unwrap();
                let transit = TransitPlanner::new(&prepared.keep_out, &prepared.walls);
                let stop = Stop::never();
                let stages = Stages { prepared: &prepared, transit: &transit, obstacles: None, terrain: None, stop: &stop };
                let ends = Ends::new(prepared.start, prepared.end, None);
                let flight = stages.fly(&prepared.resolved.vehicle, ends, &prepared.region, None, &|_| true).unwrap();
                let planned = &flight.planned;
                let measured = planned.swept.as_ref().expect("the headland planner measures its swept ground");
                let (swept, strip_area) = metrics::swept_and_strip_area(&planned.path);
                assert!(measured.0 == swept && measured.1 == strip_area, "order {order}, start {corner:?}: {} m² against {} m²", measured.0.unsigned_area(), swept.unsigned_area());
                assert!(planned.path.pieces.iter().filter(|p| p.kind == path::PieceKind::Headland).count() >= 6, "two passes round the edge and each pond");
                checked += 1;
            }
        }
        assert_eq!(checked, 8);
    }
}
