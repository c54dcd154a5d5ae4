//! Export stage: the plan in the files other tools load, one format per file.
//!
//! Every format is written from the trajectory as stored (WGS84 GeoJSON, [`geojson`]) and the
//! mission, so a finished plan can be written in any format without planning it again. Adding a
//! format means adding a file with an [`Exporter`] and a line in [`EXPORTERS`].
//! Conventions (coordinate order, winding, altitude reference) follow docs/methods.md, interop.

mod farm_day;
pub use farm_day::{DayStretch, export_day};
mod flight;
pub mod follower;
pub mod geojson;
mod isoxml;
pub use isoxml::{FarmTask, FarmTaskData};
mod kml;
mod mission_items;
pub use mission_items::{MissionItem, autopilot_distance_m};
mod qgc_plan;
pub mod wpl;
mod wpml;
mod xml;

use geo::{MapCoords, MultiPolygon};
use serde::{Deserialize, Serialize};

use super::archive;
use super::error::{InputError, check_range};
use super::field::{Field, FieldLimits, MissionGeometry};
use super::params::guidance::Guidance;
use super::params::{FleetVehicle, Landing, PlanParams, inspection};
use super::planners::MethodKind;
use super::vehicle::{Vehicle, VehicleKind};
pub use flight::{Flight, FlownPiece, PlanPhoto};

/// The autopilot a flight file is written for: it decides the vehicle's home item and how
/// "keep the heading" is said.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Firmware {
    #[default]
    Ardupilot,
    Px4,
}

/// How a flight file over terrain says its altitudes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum AltitudeFrame {
    /// Above mean sea level as planned (`MAV_FRAME_GLOBAL`; DJI: relative to the take-off
    /// point, from the same heights).
    #[default]
    Amsl,
    /// Above the ground under each waypoint (`MAV_FRAME_GLOBAL_TERRAIN_ALT`), for vehicles with
    /// a rangefinder or terrain data: the autopilot holds the height itself.
    Terrain,
}

/// Choices of the caller that are not part of the plan.
#[derive(Debug, Clone, Copy, Default)]
pub struct ExportOptions {
    pub firmware: Firmware,
    /// Plans over terrain: the frame of the flight files' altitudes.
    pub altitude_frame: AltitudeFrame,
    /// Flight altitude above home for formats that need one, when the plan has none.
    pub altitude_m: Option<f64>,
    /// Most waypoints the controller loads (formats with a `waypoint_limit`; default the
    /// format's `default_max_waypoints`).
    pub max_waypoints: Option<usize>,
}

/// The range of `max_waypoints`: a part must hold its take-off, its way back onto the route and
/// a line; DJI's waypoint routes hold at most 65 535.
pub const MAX_WAYPOINTS_RANGE: (usize, usize) = (10, 65_535);

/// Altitude above home written in flight files of plans made without an altitude or a camera.
pub const DEFAULT_ALTITUDE_M: f64 = 50.0;

/// What a plan is exported from: the mission as stored, the parameters and vehicles it was
/// planned with, and its trajectory.
pub struct ExportRequest<'a> {
    pub name: &'a str,
    pub mission: MissionGeometry<'a>,
    pub params: &'a PlanParams,
    pub profiles: &'a [Vehicle],
    pub trajectory: &'a ::geojson::FeatureCollection,
    pub options: ExportOptions,
}

/// A written file.
#[derive(Debug, Clone)]
pub struct ExportFile {
    pub file_name: String,
    pub media_type: &'static str,
    pub bytes: Vec<u8>,
}

/// The mission's outlines in WGS84 (x = longitude, y = latitude): exteriors counter-clockwise,
/// holes clockwise.
#[derive(Clone)]
pub struct Outlines {
    pub fields: MultiPolygon,
    pub no_fly_zones: MultiPolygon,
    pub home: Option<[f64; 2]>,
    /// The plan's landing sites, `[lon, lat]`: sorties may land at them and take off again.
    pub landing_sites: Vec<[f64; 2]>,
}

/// Where one sortie takes off and lands.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Bases {
    /// Where it takes off, and where an autopilot's return flies back to (`None`: the mission
    /// has no home, and each flight lands where it ends).
    pub home: Option<[f64; 2]>,
    /// The landing site it lands at when that is not `home` (a plan with landing sites): the
    /// file lands it there, since a return would fly back to where it took off.
    pub lands_at: Option<[f64; 2]>,
}

impl Bases {
    /// A sortie from `home` and back.
    pub fn home(home: Option<[f64; 2]>) -> Self {
        Bases { home, lands_at: None }
    }
}

/// How the vehicle flies the exported path.
#[derive(Debug, Clone, Copy)]
pub struct FlightSettings {
    pub kind: VehicleKind,
    pub firmware: Firmware,
    /// Above home, metres.
    pub altitude_m: f64,
    pub cruise_speed_mps: f64,
    pub turn_radius_m: f64,
    pub line_spacing_m: f64,
    /// Distance between photos on sweeps, when a camera was given (the flight files trigger at
    /// the plan's own photos where they can, at this step where they cannot).
    pub trigger_distance_m: Option<f64>,
    /// Seconds held at an inspection's viewpoint for its picture.
    pub hold_s: f64,
    /// Plans over terrain: how altitudes are said.
    pub altitude_frame: AltitudeFrame,
    /// How each flight ends: the autopilot's return, or a landing written in the file.
    pub landing: Landing,
    /// Lines written as their two ends, the camera triggered from the first to the last
    /// (no waypoints where its photos start and stop): for controllers with few waypoints.
    pub compact_lines: bool,
    /// The farm's guidance line a ground plan followed.
    pub guidance: Option<Guidance>,
}

/// Everything an exporter writes from.
pub struct ExportJob<'a> {
    pub name: &'a str,
    pub outlines: Outlines,
    pub flight: Flight,
    pub settings: FlightSettings,
    pub trajectory: &'a ::geojson::FeatureCollection,
    /// Most waypoints a file may hold (formats with a `waypoint_limit`).
    pub max_waypoints: Option<usize>,
}

/// A sortie's take-off or landing within this of a place is there (plans write places
/// exactly; this allows for rounding through the trajectory's degrees).
const AT_PLACE_M: f64 = 1.0;

impl ExportJob<'_> {
    /// Where sortie `k` takes off and lands: the mission's home, or with landing sites the
    /// site it leaves from and the one it lands at.
    pub fn bases(&self, sortie: usize) -> Bases {
        let home = self.outlines.home;
        let pieces = &self.flight.sorties[sortie];
        let (Some(first), Some(last)) = (pieces.first().and_then(|p| p.points.first()), pieces.last().and_then(|p| p.points.last())) else { return Bases::home(home) };
        if self.outlines.landing_sites.is_empty() {
            return Bases::home(home);
        }
        let place_at = |p: &[f64; 3]| {
            let frame = crate::frame::LocalFrame::new(p[0], p[1]);
            let near = |q: &&[f64; 2]| {
                let c = frame.to_local(q[0], q[1]);
                c.x.hypot(c.y) < AT_PLACE_M
            };
            home.iter().chain(&self.outlines.landing_sites).find(near).copied()
        };
        let takes_off = place_at(first).or(home);
        Bases { home: takes_off, lands_at: place_at(last).filter(|&q| Some(q) != takes_off) }
    }
}

/// What names a file format and its files, and which plans it can say.
#[derive(Debug, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Format {
    /// The `format` query value.
    pub id: &'static str,
    /// What a user picks it by: the tool that loads it, and its file type.
    pub label: &'static str,
    pub media_type: &'static str,
    /// File name ending.
    pub extension: &'static str,
    /// A format that describes one flight: a plan of several sorties becomes a zip of one file
    /// per sortie.
    pub one_flight_per_file: bool,
    /// Autopilot commands, written for the `firmware` asked (`ardupilot` or `px4`).
    pub firmware_commands: bool,
    /// The kinds of plan it can say.
    #[cfg_attr(feature = "schema", schema(value_type = Vec<MethodKind>))]
    pub plans: &'static [MethodKind],
    /// The trajectory as the planner stored it: served without reading it.
    pub verbatim: bool,
    /// Honours `max_waypoints`: past it, lines become their two ends, then the flight is
    /// split into missions (a zip), each starting where the last ended.
    pub waypoint_limit: bool,
    /// The limit when none is asked for (the controller this format is mostly flown from).
    pub default_max_waypoints: Option<usize>,
}

/// The plans every format can say.
const ALL_METHODS: &[MethodKind] = &[MethodKind::Coverage, MethodKind::Inspection];
/// Coverage plans only (an inspection's viewpoints have no swaths, and its gimbal and yaw
/// cannot be said).
const COVERAGE_ONLY: &[MethodKind] = &[MethodKind::Coverage];

/// One file format.
pub trait Exporter: Sync {
    fn format(&self) -> &'static Format;
    /// Writes the files: one, or (a format with a `waypoint_limit`) as many missions as keep
    /// each within `job.max_waypoints`; `sortie` (0-based) limits a one-flight format to that
    /// sortie.
    fn write(&self, job: &ExportJob<'_>, sortie: usize) -> Result<Vec<Vec<u8>>, InputError>;
}

/// Every export format, in the order menus list them; the first is the default.
pub static EXPORTERS: &[&dyn Exporter] = &[&geojson::GeoJsonFile, &qgc_plan::QgcPlan, &wpl::WaypointList, &wpml::Wpml, &kml::Kml, &kml::Kmz, &isoxml::TaskData];

/// The format a trajectory is given in when none is asked for.
pub fn default_format() -> &'static Format {
    EXPORTERS[0].format()
}

/// Every format, for `GET /api/v1/formats`.
pub fn formats() -> Vec<&'static Format> {
    EXPORTERS.iter().map(|e| e.format()).collect()
}

pub fn find(id: &str) -> Option<&'static dyn Exporter> {
    EXPORTERS.iter().copied().find(|e| e.format().id == id)
}

/// The `format` values, for messages and documents.
pub fn format_ids() -> Vec<&'static str> {
    EXPORTERS.iter().map(|e| e.format().id).collect()
}

/// A file name made of the mission's name: letters, digits, `-` and `_` only.
pub fn file_stem(name: &str) -> String {
    let stem: String = name.trim().chars().take(80).map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
    let stem = stem.trim_matches('_');
    if stem.is_empty() { "mission".to_owned() } else { stem.to_owned() }
}

/// Writes a plan in `format`. A fleet's plan is a zip of one file per drone (and per sortie for
/// one-flight formats), each written for that drone's vehicle and home; its GeoJSON stays the
/// one trajectory, each feature with its `vehicle`.
pub fn export(format: &str, request: &ExportRequest<'_>) -> Result<ExportFile, InputError> {
    let Written { mut files, media_type, bundle } = written(format, request, &file_stem(request.name))?;
    if files.len() == 1 && bundle.is_none() {
        let (file_name, bytes) = files.pop().expect("one file");
        return Ok(ExportFile { file_name, media_type, bytes });
    }
    let file_name = bundle.unwrap_or_else(|| format!("{}-{format}-parts.zip", file_stem(request.name)));
    Ok(ExportFile { file_name, media_type: "application/zip", bytes: archive::zip(&files) })
}

/// The files of one export, named from a stem: one, or several to be zipped (sorties, parts,
/// a fleet's drones) under `bundle` when it says so.
struct Written {
    files: Vec<(String, Vec<u8>)>,
    media_type: &'static str,
    /// The zip's name where the files are always zipped (a fleet's).
    bundle: Option<String>,
}

/// Writes a plan in `format` as files named from `stem`.
fn written(format: &str, request: &ExportRequest<'_>, stem: &str) -> Result<Written, InputError> {
    let exporter = find(format).ok_or_else(|| InputError::new("unknown_format", "/format", format!("no export format `{format}`; known: {}", format_ids().join(", "))))?;
    let planned = FileParams::of(request.params, request.profiles)?;
    let Format { id, media_type, extension, one_flight_per_file, verbatim, .. } = *exporter.format();
    if !exporter.format().plans.contains(&planned.method) {
        let able: Vec<&str> = EXPORTERS.iter().map(|e| e.format()).filter(|f| f.plans.contains(&planned.method)).map(|f| f.id).collect();
        return Err(InputError::new("format_not_applicable", "/format", format!("this {:?} plan is exported as {}", planned.method, able.join(", ")).to_lowercase()));
    }
    if request.options.max_waypoints.is_some() && !exporter.format().waypoint_limit {
        let limited: Vec<&str> = EXPORTERS.iter().map(|e| e.format()).filter(|f| f.waypoint_limit).map(|f| f.id).collect();
        return Err(InputError::new("format_not_applicable", "/max_waypoints", format!("max_waypoints limits the flight files a controller loads: {}", limited.join(", "))));
    }
    if let Some(max) = request.options.max_waypoints {
        check_range(max as f64, MAX_WAYPOINTS_RANGE.0 as f64, MAX_WAYPOINTS_RANGE.1 as f64, "/max_waypoints", "waypoints per mission")?;
    }
    let write_all = |job: &ExportJob<'_>, stem: &str| -> Result<Vec<(String, Vec<u8>)>, InputError> {
        let sorties = if one_flight_per_file { job.flight.sorties.len() } else { 1 };
        let mut files = Vec::new();
        for k in 0..sorties {
            let parts = exporter.write(job, k)?;
            let count = parts.len();
            for (j, bytes) in parts.into_iter().enumerate() {
                let sortie = if sorties > 1 { format!("-sortie-{}", k + 1) } else { String::new() };
                let part = if count > 1 { format!("-part-{}", j + 1) } else { String::new() };
                files.push((format!("{stem}{sortie}{part}{extension}"), bytes));
            }
        }
        Ok(files)
    };
    let (outlines, altitude_m) = outlines_and_altitude(request, &planned)?;
    if planned.fleet.is_empty() || verbatim {
        let job = prepare(request, exporter.format(), &planned, &planned.vehicle, outlines, altitude_m, request.trajectory)?;
        let files = write_all(&job, stem)?;
        let bundle = (job.flight.sorties.len() > 1 && one_flight_per_file && files.len() > 1).then(|| format!("{stem}-{id}-sorties.zip"));
        return Ok(Written { files, media_type, bundle });
    }
    let mut files = Vec::new();
    for (k, drone) in planned.fleet.iter().enumerate() {
        let own = |f: &&::geojson::Feature| f.property("vehicle").and_then(|v| v.as_u64()) == Some(k as u64);
        let features: Vec<::geojson::Feature> = request.trajectory.features.iter().filter(own).cloned().collect();
        if features.is_empty() {
            continue;
        }
        let trajectory = ::geojson::FeatureCollection { bbox: None, features, foreign_members: request.trajectory.foreign_members.clone() };
        let own_home = Outlines { home: drone.home.or(request.mission.home), ..outlines.clone() };
        let job = prepare(request, exporter.format(), &planned, &drone.vehicle, own_home, altitude_m, &trajectory)?;
        files.extend(write_all(&job, &format!("{stem}-drone-{}", k + 1))?);
    }
    Ok(Written { files, media_type, bundle: Some(format!("{stem}-{id}-fleet.zip")) })
}

/// Runs `write` on the one vehicle's job of `request` as `format` would write it (not for a
/// fleet's plan, whose files are each drone's).
fn with_job<T>(request: &ExportRequest<'_>, format: &Format, write: impl FnOnce(&ExportJob<'_>) -> T) -> Result<T, InputError> {
    let planned = FileParams::of(request.params, request.profiles)?;
    if !format.plans.contains(&planned.method) || !planned.fleet.is_empty() {
        return Err(InputError::new("format_not_applicable", "/format", format!("this plan is not written as {}", format.id)));
    }
    let (outlines, altitude_m) = outlines_and_altitude(request, &planned)?;
    let job = prepare(request, format, &planned, &planned.vehicle, outlines, altitude_m, request.trajectory)?;
    Ok(write(&job))
}

/// What the parameters say about the files: the vehicles, the altitude, the spacing, the
/// camera's trigger and, for an inspection, the hold at each viewpoint.
struct FileParams {
    method: MethodKind,
    vehicle: Vehicle,
    fleet: Vec<FleetVehicle>,
    altitude_m: Option<f64>,
    line_spacing_m: f64,
    trigger_distance_m: Option<f64>,
    hold_s: Option<f64>,
    landing: Landing,
    guidance: Option<Guidance>,
    landing_sites: Vec<[f64; 2]>,
}

impl FileParams {
    fn of(params: &PlanParams, profiles: &[Vehicle]) -> Result<FileParams, InputError> {
        if params.planner.as_deref() == Some(inspection::PLANNER_ID) {
            let (vehicle, spec) = params.resolve_inspection(profiles)?;
            return Ok(FileParams {
                method: MethodKind::Inspection,
                vehicle,
                fleet: Vec::new(),
                altitude_m: None,
                line_spacing_m: 0.0,
                trigger_distance_m: None,
                hold_s: Some(spec.capture_s),
                landing: Landing::Return,
                guidance: None,
                landing_sites: Vec::new(),
            });
        }
        let r = params.resolve(profiles)?;
        let trigger_distance_m = r.camera.map(|c| c.photo_spacing_m);
        Ok(FileParams {
            method: MethodKind::Coverage,
            vehicle: r.vehicle,
            fleet: r.fleet,
            altitude_m: r.altitude_m,
            line_spacing_m: r.line_spacing_m,
            trigger_distance_m,
            hold_s: None,
            landing: r.landing,
            guidance: params.guidance,
            landing_sites: r.landing_sites,
        })
    }
}

/// The mission's outlines in WGS84 (with its home) and the altitude flight files are written at:
/// read once for every vehicle's files. An inspection takes off to its first point above the
/// ground.
fn outlines_and_altitude(request: &ExportRequest<'_>, planned: &FileParams) -> Result<(Outlines, f64), InputError> {
    // the mission was validated when stored: its own limits, not the service's current ones
    let unlimited = FieldLimits { max_area_ha: f64::INFINITY, max_vertices: usize::MAX, max_radius_km: f64::INFINITY, min_area_m2: 0.0 };
    let field = Field::parse(&request.mission, &unlimited)?;
    let to_wgs84 = |p: &MultiPolygon| p.map_coords(|c| field.frame.to_wgs84(c).into());
    let outlines =
        Outlines { fields: to_wgs84(&field.area), no_fly_zones: to_wgs84(&field.no_fly_zones), home: request.mission.home, landing_sites: planned.landing_sites.clone() };
    if let Some(a) = request.options.altitude_m {
        check_range(a, 1.0, 10_000.0, "/altitude_m", "m above home")?;
    }
    let first_airborne = || {
        request.trajectory.features.iter().filter_map(|f| f.geometry.as_ref()).find_map(|g| match &g.value {
            ::geojson::GeometryValue::LineString { coordinates } => coordinates.iter().filter_map(|p| p.as_slice().get(2).copied()).find(|&z| z >= 0.5),
            _ => None,
        })
    };
    let planned_altitude = planned.altitude_m.or_else(|| planned.hold_s.and_then(|_| first_airborne()));
    Ok((outlines, request.options.altitude_m.or(planned_altitude).unwrap_or(DEFAULT_ALTITUDE_M)))
}

/// What one vehicle's files are written from: `trajectory` holds its pieces only, `outlines` its home.
fn prepare<'a>(
    request: &ExportRequest<'a>,
    format: &Format,
    planned: &FileParams,
    vehicle: &Vehicle,
    outlines: Outlines,
    altitude_m: f64,
    trajectory: &'a ::geojson::FeatureCollection,
) -> Result<ExportJob<'a>, InputError> {
    let settings = FlightSettings {
        kind: vehicle.kind,
        firmware: request.options.firmware,
        altitude_m,
        cruise_speed_mps: vehicle.cruise_speed_mps,
        turn_radius_m: vehicle.turn_radius_m,
        line_spacing_m: planned.line_spacing_m,
        trigger_distance_m: planned.trigger_distance_m,
        hold_s: planned.hold_s.unwrap_or(0.0),
        altitude_frame: request.options.altitude_frame,
        landing: planned.landing,
        compact_lines: false,
        guidance: planned.guidance,
    };
    let flight = Flight::from_trajectory(trajectory, altitude_m)?;
    let max_waypoints = request.options.max_waypoints.or(format.default_max_waypoints).filter(|_| format.waypoint_limit);
    Ok(ExportJob { name: request.name, outlines, flight, settings, trajectory, max_waypoints })
}

/// `v` rounded to `decimals` places, as text without trailing zeros.
pub(crate) fn number(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
    if s == "-0" { "0".to_owned() } else { s.to_owned() }
}
