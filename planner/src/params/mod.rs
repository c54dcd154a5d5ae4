//! Plan parameters as clients send them, and their validated form.

pub mod guidance;
pub mod inspection;
pub mod payload;
pub mod resume;

use serde::{Deserialize, Serialize};

use super::camera::{Camera, CameraPlan, OBLIQUE_HORIZON_MARGIN_DEG, ObliqueView};
use super::error::{InputError, check_range};
use super::sweep::LineLayout;
pub use super::sweep::ends::SwathEnds;
use super::vehicle::{Vehicle, VehicleKind, VehicleParams};
use super::wind::Wind;
use inspection::{Budget, InspectionOptions, InspectionRequest, InspectionSpec, Target};

/// Pattern `oblique`'s gimbal pitch unless asked otherwise: halfway between level and straight
/// down, the usual choice for oblique photogrammetry.
pub const DEFAULT_OBLIQUE_PITCH_DEG: f64 = -45.0;

/// A position with a heading, as a compass bearing (degrees clockwise from north).
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct PoseParam {
    /// [longitude, latitude]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub position: [f64; 2],
    #[cfg_attr(feature = "schema", schema(minimum = -360.0, maximum = 360.0))]
    pub heading_deg: Option<f64>,
    /// Inspection: height above ground, 0 to 1 000 m (default 0: on the ground).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1000.0))]
    pub altitude_m: Option<f64>,
}

/// Most landing sites a plan may name.
pub const MAX_LANDING_SITES: usize = 50;

/// The members only planner `inspection` reads (and the start's and end's `altitude_m`).
pub const INSPECTION_ONLY_MEMBERS: [&str; 4] = ["targets", "budget", "inspection", "seed"];

/// The members planner `inspection` refuses: they shape coverage plans.
pub const COVERAGE_ONLY_MEMBERS: [&str; 17] = [
    "line_spacing_m",
    "altitude_m",
    "heading_deg",
    "sweep_direction",
    "side_overlap",
    "front_overlap",
    "fleet",
    "vehicles",
    "headland_passes",
    "objective",
    "lead_in_m",
    "landing",
    "landing_heading_deg",
    "wind",
    "pattern",
    "oblique_pitch_deg",
    "landing_sites",
];

/// Members only a ground vehicle's plan reads.
pub const GROUND_ONLY_MEMBERS: [&str; 7] = ["headland_passes", "headland_width_m", "headland_order", "overlap", "guidance", "tramline_every", "payload"];

/// Members of plans over terrain (`altitude_reference` `terrain`).
pub const TERRAIN_MEMBERS: [&str; 3] = ["terrain_tolerance_m", "max_climb_mps", "max_descent_mps"];

/// The pointer of the first of `members` that `given` says the request holds.
fn first_given(members: &[&str], given: &[bool]) -> Option<String> {
    members.iter().zip(given).find(|(_, given)| **given).map(|(member, _)| format!("/{member}"))
}

/// Parameters of a plan.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct PlanParams {
    /// Planner id, as listed by `GET /api/v1/planners`; default `boustrophedon`, or `headland`
    /// for a ground vehicle.
    pub planner: Option<String>,
    /// Distance between sweep lines; required unless a camera is given.
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 2000.0))]
    pub line_spacing_m: Option<f64>,
    /// The camera, by `preset` (`GET /api/v1/cameras`) or by its figures: sets the line spacing
    /// from the side overlap and the photo positions from the front overlap (an inspection's
    /// default: the `dji_mavic3_enterprise` preset).
    pub camera: Option<Camera>,
    /// Flight altitude above ground; with a camera, or instead `gsd_cm`.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 5000.0))]
    pub altitude_m: Option<f64>,
    /// Wanted ground sample distance, in cm per pixel (camera only).
    #[cfg_attr(feature = "schema", schema(minimum = 0.01, maximum = 1000.0))]
    pub gsd_cm: Option<f64>,
    /// Overlap of neighbouring lines' images, 0 to 0.95 (default 0.7).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.95))]
    pub side_overlap: Option<f64>,
    /// Overlap of consecutive images along a line, 0 to 0.95 (default 0.8).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.95))]
    pub front_overlap: Option<f64>,
    /// Compass bearing of the sweep lines; absent: the planner chooses.
    #[cfg_attr(feature = "schema", schema(minimum = -360.0, maximum = 360.0))]
    pub heading_deg: Option<f64>,
    /// Without `heading_deg`: `planner` (default) lets the planner apply its own rule;
    /// `optimal` plans every direction (2° apart, refined to 0.5°) and keeps the shortest per
    /// covered area among those that cover 99 % (or, when none does, within 1 % of the best).
    pub sweep_direction: Option<SweepDirection>,
    /// The vehicle: a `profile` (`GET /api/v1/vehicles`), a `kind` (multirotor, fixed_wing or
    /// ground), or both, with overrides of its figures.
    #[serde(default)]
    pub vehicle: VehicleParams,
    /// Where the flight starts, `{position: [lon, lat], heading_deg}` (default: the mission's
    /// home, heading free).
    pub start: Option<PoseParam>,
    /// Where the flight ends, `{position: [lon, lat], heading_deg}` (default: the mission's home).
    pub end: Option<PoseParam>,
    /// Line-level routing may leave a field and come back to it (default true); false flies
    /// each field in one block.
    pub allow_reentry: Option<bool>,
    /// With obstacles: clearance kept above and around them, 0 to 200 m (default 10).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 200.0))]
    pub obstacle_clearance_m: Option<f64>,
    /// With obstacles: steepest climb and descent, 1 to 60° (default 30).
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 60.0))]
    pub max_climb_deg: Option<f64>,
    /// What `altitude_m` is measured from: `home` (default: one altitude above the take-off
    /// point) or `terrain` (the height above the ground of the mission's elevation model,
    /// `PUT /api/v1/missions/{id}/terrain`; the trajectory's heights are then above mean sea
    /// level).
    pub altitude_reference: Option<AltitudeReference>,
    /// With `altitude_reference` `terrain`: how far the height above ground may stray on
    /// sweeps, and below it anywhere, 0.5 to 100 m (default 5).
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 100.0))]
    pub terrain_tolerance_m: Option<f64>,
    /// With `altitude_reference` `terrain`, a multirotor: fastest climb, 0.1 to 20 m/s
    /// (default: its energy model's climb rate, or 3). A fixed wing climbs at `max_climb_deg`.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 20.0))]
    pub max_climb_mps: Option<f64>,
    /// With `altitude_reference` `terrain`, a multirotor: fastest descent, 0.1 to 20 m/s
    /// (default: its energy model's descent rate, or 2). A fixed wing descends at `max_climb_deg`.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 20.0))]
    pub max_descent_mps: Option<f64>,
    /// Metres of path that one metre of sweep lost costs when choosing the order and the
    /// direction, 0 to 1000 (default 10): sweep flown too high to image over an obstacle, or
    /// (`line_gtsp`, fixed wing) cut short to leave room to turn before a no-fly zone.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1000.0))]
    pub coverage_penalty: Option<f64>,
    /// Clearance kept from no-fly zones by sweeps, 1 to 500 m; connections keep half of it
    /// (default 10, and for a fixed wing twice a quarter of its L1 distance more: 40 m at
    /// 15 m/s, the room an autopilot following waypoints strays from a turn;
    /// docs/flight-files.md).
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 500.0))]
    pub nfz_margin_m: Option<f64>,
    /// Fixed wing: metres flown straight on each line's extension before the line, for an
    /// autopilot to settle on it before the camera starts, 0 to 1000 m (default: eight seconds
    /// at cruise speed, twice the distance ArduPlane's default L1 guidance looks ahead);
    /// shortened where it would enter a no-fly zone.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1000.0))]
    pub lead_in_m: Option<f64>,
    /// How each flight ends: `return` (default) sends the vehicle home (a multirotor lands
    /// there; a fixed wing circles home for the pilot to land it); `auto` writes a landing at
    /// home (a fixed wing: `DO_LAND_START`, an approach along `landing_heading_deg` and
    /// `NAV_LAND`). Without a home every flight lands where it ends.
    pub landing: Option<Landing>,
    /// With `landing` `auto`, a fixed wing: the compass bearing it lands on (default: the
    /// heading it arrives home on).
    #[cfg_attr(feature = "schema", schema(minimum = -360.0, maximum = 360.0))]
    pub landing_heading_deg: Option<f64>,
    /// What planner `auto` minimises (default `energy`).
    pub objective: Option<Objective>,
    /// A steady wind: headings, turns, times, energies and sorties account for it
    /// (docs/methods.md, wind).
    pub wind: Option<Wind>,
    /// Most sorties a plan may be split into when one battery is not enough, 1 to 100
    /// (default 20); splitting needs the mission's home.
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 100))]
    pub max_sorties: Option<u32>,
    /// More places than the mission's home to land, change the battery and take off again,
    /// `[[lon, lat], …]`, at most 50: each sortie lands at the one that best serves it and the
    /// next (the nearest to where it stops and to where the next begins), and the next takes
    /// off there, so that a long corridor is flown in hops. Needs the mission's home (where
    /// the first sortie leaves from); a fixed wing lands at them by itself (`landing` `auto`).
    #[cfg_attr(feature = "schema", schema(max_items = 50))]
    pub landing_sites: Option<Vec<[f64; 2]>>,
    /// Seconds the plan may take, 0.1 to 86 400; past them it fails with `time_limit`. The
    /// service caps it at its own limit (`COVERPLAN_JOB_TIMEOUT_S`, also the default). An
    /// inspection's search instead returns its best path once nine tenths of it have passed
    /// (default 20 s), leaving the rest to measure the plan.
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 86400.0))]
    pub time_limit_s: Option<f64>,
    /// Several drones fly the field together, 2 to 16 of them: each entry is a vehicle (as
    /// `vehicle`) with an optional `home` of its own. The field is split so that the last drone
    /// lands as early as possible. Instead of `vehicle` and `vehicles`.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 16))]
    pub fleet: Option<Vec<FleetMember>>,
    /// A fleet of this many copies of `vehicle`, 2 to 16, all taking off from the mission's home.
    #[cfg_attr(feature = "schema", schema(minimum = 2, maximum = 16))]
    pub vehicles: Option<u32>,
    /// Fleet: each drone's transits fly in a layer of its own, this many metres above the
    /// previous drone's (the first one this far above the survey altitude), 1 to 200 m.
    /// Without it every drone flies at the survey altitude and the plan reports where two
    /// drones come close at the same time (`stats.conflicts`).
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 200.0))]
    pub altitude_separation_m: Option<f64>,
    /// Ground vehicle: working passes round the field's edge and every hole, 1 to 20 (default
    /// 2, or as many as cover `headland_width_m`).
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 20))]
    pub headland_passes: Option<u32>,
    /// Ground vehicle: width of the headland, 1 to 500 m (default: the passes times the
    /// working width).
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 500.0))]
    pub headland_width_m: Option<f64>,
    /// Ground vehicle: work the headland passes after the swaths (`last`, default) or before.
    pub headland_order: Option<HeadlandOrder>,
    /// Where swaths (or sweep lines) end at a slanted edge of the area they work: `balanced`
    /// runs each on while a quarter of its width still has area to work; `full_width` until its
    /// whole width has worked the area; `centre_line` stops it where its centre line meets the
    /// edge, shortest but leaving a triangle beside each end (the rule of Fields2Cover's swath
    /// generator). At a straight slanted edge `balanced` leaves a quarter of the triangle
    /// `centre_line` leaves, for half the length `full_width` adds; it runs further where that
    /// would leave more than 0.5 % of the area. Default: `balanced` for a ground vehicle (at its
    /// headland), `full_width` for an aircraft (at the field's edge and its holes; not for
    /// `e_spiral` and `eg_cpp`, which fly no parallel lines).
    pub swath_ends: Option<SwathEnds>,
    /// What the lines make: `grid` (default), one set of parallel lines; `double_grid`, a
    /// second set across the first (at 90°), flown after it, for 3D models; `oblique`, the
    /// grid flown with the camera straight down, then four times with it pitched to
    /// `oblique_pitch_deg`, looking along the lines, left of them, back and right (a multirotor
    /// with a camera). Aircraft, with a planner that lays parallel lines; not for a fleet.
    pub pattern: Option<Pattern>,
    /// Pattern `oblique`: the gimbal's pitch on the oblique passes, as gimbals say it (−90
    /// straight down, 0 level), −80 to −20 (default −45). Each oblique pass flies the area moved
    /// h / tan(pitch) back from where it looks, so that its images centre on the area.
    #[cfg_attr(feature = "schema", schema(minimum = -80.0, maximum = -20.0))]
    pub oblique_pitch_deg: Option<f64>,
    /// Ground vehicle: share of the working width neighbouring swaths overlap, 0 to 0.5
    /// (default 0).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 0.5))]
    pub overlap: Option<f64>,
    /// Ground vehicle: the farm's guidance line (an AB or A+ line) the swaths follow: parallel
    /// to it and whole swath widths (the working width less the overlap) from it. Instead of
    /// `heading_deg`.
    pub guidance: Option<guidance::Guidance>,
    /// Ground vehicle: every this many swaths one is left as a tramline (controlled traffic: a
    /// sprayer this many times the working width follows them), 2 to 100. With `guidance` the
    /// guidance line's own swath is one; without, the middle swath of the first n from the
    /// field's edge (where a sprayer flush with the edge drives): the edge on the right of the
    /// swaths driven at their bearing below 180° (`stats.sweep_heading_deg`).
    #[cfg_attr(feature = "schema", schema(minimum = 2, maximum = 100))]
    pub tramline_every: Option<u32>,
    /// Ground vehicle: a tank that runs empty (a sprayer, a spreader) or full (a harvester),
    /// and where it is refilled or unloaded: the route breaks off where the trips there and
    /// back cost the least non-working distance, and drives them along the headland.
    pub payload: Option<payload::Payload>,
    /// Inspection: what to look at (default: the walls and roof of every structure).
    pub targets: Option<Vec<Target>>,
    /// Inspection: the flight's limit, in metres, seconds or joules.
    pub budget: Option<Budget>,
    /// Inspection: the camera's reach, the gimbal, clearances and the search's effort.
    pub inspection: Option<InspectionOptions>,
    /// Inspection: the random seed; the same seed gives the same plan (default 0).
    pub seed: Option<u64>,
}

/// How a flight ends.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Landing {
    /// Return to launch: the autopilot's own return.
    #[default]
    Return,
    /// A landing sequence at home, written in the flight file and timed in the plan.
    Auto,
}

/// What a plan's altitude is measured from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum AltitudeReference {
    /// One altitude above the take-off point.
    #[default]
    Home,
    /// A height above the ground of the mission's elevation model.
    Terrain,
}

/// Terrain following, validated: slopes in metres of height per metre flown.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainSpec {
    pub tolerance_m: f64,
    pub climb: f64,
    pub descent: f64,
}

/// What a plan's lines make.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Pattern {
    /// One set of parallel lines.
    #[default]
    Grid,
    /// A second set across the first, at 90°.
    DoubleGrid,
    /// The grid with the camera straight down, then four oblique passes.
    Oblique,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum HeadlandOrder {
    First,
    #[default]
    Last,
}

/// A ground vehicle's headland, validated.
#[derive(Debug, Clone, PartialEq)]
pub struct HeadlandSpec {
    pub width_m: f64,
    pub passes: usize,
    pub order: HeadlandOrder,
    pub swath_ends: SwathEnds,
    /// The implement's width: what each swath and pass works.
    pub working_width_m: f64,
    /// The guidance line the swaths follow.
    pub guidance: Option<guidance::GuidanceLine>,
    /// Every this many swaths one is a tramline.
    pub tramline_every: Option<usize>,
    /// The tank and its refill points.
    pub payload: Option<payload::Payload>,
}

/// One drone of a fleet: the fields of `vehicle`, and `home`.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
// read through a map: serde's `flatten` would let unknown fields pass unnoticed
#[serde(try_from = "serde_json::Map<String, serde_json::Value>")]
pub struct FleetMember {
    #[serde(flatten)]
    pub vehicle: VehicleParams,
    /// [longitude, latitude] this drone takes off from and lands at; default: the mission's home.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub home: Option<[f64; 2]>,
}

impl TryFrom<serde_json::Map<String, serde_json::Value>> for FleetMember {
    type Error = serde_json::Error;

    fn try_from(mut fields: serde_json::Map<String, serde_json::Value>) -> Result<Self, Self::Error> {
        let home = fields.remove("home").map(serde_json::from_value).transpose()?.flatten();
        Ok(FleetMember { vehicle: serde_json::from_value(serde_json::Value::Object(fields))?, home })
    }
}

/// Most drones in one fleet.
pub const MAX_FLEET: usize = 16;

/// A drone of a fleet, validated.
#[derive(Debug, Clone)]
pub struct FleetVehicle {
    pub vehicle: Vehicle,
    /// [longitude, latitude]; `None`: the mission's home.
    pub home: Option<[f64; 2]>,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    #[default]
    Energy,
    Time,
    Length,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum SweepDirection {
    #[default]
    Planner,
    Optimal,
}

impl Default for PlanParams {
    fn default() -> Self {
        serde_json::from_str("{}").expect("defaults")
    }
}

/// Validated parameters, in planner units.
#[derive(Debug, Clone)]
pub struct Resolved {
    pub line_spacing_m: f64,
    pub camera: Option<CameraPlan>,
    /// How lines are laid across each cell: re-fitted to the camera's footprint when there is
    /// a camera, centred otherwise.
    pub layout: LineLayout,
    pub optimal_direction: bool,
    pub altitude_m: Option<f64>,
    /// Sweep direction as a math angle (radians counter-clockwise from east, mod π).
    pub sweep_angle: Option<f64>,
    pub pattern: Pattern,
    /// Pattern `oblique`: what the camera sees on the oblique passes.
    pub oblique: Option<ObliqueView>,
    pub vehicle: Vehicle,
    pub start: Option<[f64; 2]>,
    pub end: Option<[f64; 2]>,
    /// Headings at the start and the end, math radians.
    pub start_heading: Option<f64>,
    pub end_heading: Option<f64>,
    pub allow_reentry: bool,
    pub nfz_margin_m: f64,
    pub obstacle_clearance_m: f64,
    pub max_climb_deg: f64,
    pub coverage_penalty: f64,
    pub objective: Objective,
    /// The wind at the flight altitude.
    pub wind: Option<Wind>,
    pub max_sorties: usize,
    /// `landing_sites`, `[lon, lat]`, checked.
    pub landing_sites: Vec<[f64; 2]>,
    /// The drones of a fleet, in the request's order; empty for one vehicle (`vehicle`).
    pub fleet: Vec<FleetVehicle>,
    pub altitude_separation_m: Option<f64>,
    /// A ground vehicle's headland; `None` for an aircraft.
    pub headland: Option<HeadlandSpec>,
    /// `altitude_reference` `terrain`.
    pub terrain: Option<TerrainSpec>,
    /// Fixed wing: the lead-in asked, metres (`None`: the vehicle's default).
    pub lead_in_m: Option<f64>,
    pub landing: Landing,
    /// Fixed wing landing `auto`: the landing direction, math radians.
    pub landing_heading: Option<f64>,
}

/// A start or end's position, checked; `name` is its member.
pub fn checked_position(p: &Option<PoseParam>, name: &str) -> Result<Option<[f64; 2]>, InputError> {
    let Some(p) = p else { return Ok(None) };
    check_lon_lat(p.position, &format!("/{name}/position"))?;
    if let Some(h) = p.heading_deg {
        check_range(h, -360.0, 360.0, &format!("/{name}/heading_deg"), "°")?;
    }
    Ok(Some(p.position))
}

/// A `[lon, lat]` member at `pointer` within the globe's ranges.
pub(crate) fn check_lon_lat([lon, lat]: [f64; 2], pointer: &str) -> Result<(), InputError> {
    check_range(lon, -180.0, 180.0, &format!("{pointer}/0"), "°")?;
    check_range(lat, -90.0, 90.0, &format!("{pointer}/1"), "°")
}

/// Compass bearing (clockwise from north, degrees) to a math angle (counter-clockwise from
/// east, radians).
pub fn bearing_to_math(bearing_deg: f64) -> f64 {
    (90.0 - bearing_deg).to_radians()
}

/// Math angle to compass bearing in [0, 360).
pub fn math_to_bearing(angle: f64) -> f64 {
    (90.0 - angle.to_degrees()).rem_euclid(360.0)
}

impl PlanParams {
    /// Validates the parameters; `vehicle.profile` is looked up in `profiles`.
    pub fn resolve(&self, profiles: &[Vehicle]) -> Result<Resolved, InputError> {
        let given = [self.targets.is_some(), self.budget.is_some(), self.inspection.is_some(), self.seed.is_some()];
        let pose_altitude = |p: &Option<PoseParam>| p.as_ref().is_some_and(|p| p.altitude_m.is_some());
        let pointer =
            first_given(&INSPECTION_ONLY_MEMBERS, &given).or_else(|| first_given(&["start/altitude_m", "end/altitude_m"], &[pose_altitude(&self.start), pose_altitude(&self.end)]));
        if let Some(pointer) = pointer {
            return Err(InputError::new("not_an_inspection", pointer, "this member is for planner inspection"));
        }
        let vehicle = self.vehicle.resolve(profiles, "/vehicle")?;
        let fleet = self.resolve_fleet(&vehicle, profiles)?;
        // a fleet of ground machines works one field with one implement width: the first
        // machine stands for them where the plan needs one vehicle (the headland, the swaths)
        let vehicle = match fleet.first() {
            Some(first) if fleet.iter().any(|m| m.vehicle.kind == VehicleKind::Ground) => {
                let width = |m: &FleetVehicle| m.vehicle.ground.map(|g| g.working_width_m);
                if let Some(k) = fleet.iter().position(|m| m.vehicle.kind != VehicleKind::Ground || width(m) != width(first)) {
                    return Err(InputError::new(
                        "fleet_mixed",
                        format!("/fleet/{k}"),
                        "the machines sharing a field are ground vehicles with the same working width (the swaths are laid once for all of them)",
                    ));
                }
                first.vehicle.clone()
            }
            _ => vehicle,
        };
        let altitude_separation_m = match self.altitude_separation_m {
            Some(_) if fleet.is_empty() => {
                return Err(InputError::new("not_a_fleet", "/altitude_separation_m", "altitude layers separate the drones of a fleet: give fleet or vehicles"));
            }
            Some(sep) => Some(check_range(sep, 1.0, 200.0, "/altitude_separation_m", "m").map(|_| sep)?),
            None => None,
        };
        let overlap = |v: Option<f64>, default: f64, pointer: &str| -> Result<f64, InputError> {
            let v = v.unwrap_or(default);
            check_range(v, 0.0, 0.95, pointer, "")?;
            Ok(v)
        };
        let side = overlap(self.side_overlap, 0.7, "/side_overlap")?;
        let front = overlap(self.front_overlap, 0.8, "/front_overlap")?;
        let camera = match &self.camera {
            Some(c) => Some(c.plan(self.altitude_m, self.gsd_cm, side, front)?),
            None => None,
        };
        let headland = self.headland(&vehicle)?;
        if vehicle.kind == VehicleKind::Ground {
            let refuse = |pointer: &str, why: &str| Err(InputError::new("not_for_ground_vehicles", pointer, why));
            if self.line_spacing_m.is_some() || camera.is_some() {
                return refuse(if camera.is_some() { "/camera" } else { "/line_spacing_m" }, "a ground vehicle's swaths are its working width apart (less the overlap)");
            }
        }
        // a ground vehicle's swaths are ended by its headland spec; an aircraft's lines run
        // full width unless asked
        let aircraft_ends = if headland.is_some() { SwathEnds::FullWidth } else { self.swath_ends.unwrap_or(SwathEnds::FullWidth) };
        let line_spacing_m = match (&headland, self.line_spacing_m, &camera) {
            (Some(h), _, _) => h.working_width_m * (1.0 - self.overlap.unwrap_or(0.0)),
            (None, Some(s), _) => s,
            (None, None, Some(c)) => c.line_spacing_m,
            (None, None, None) => {
                return Err(InputError::new("spacing_missing", "/line_spacing_m", "give line_spacing_m, or a camera to derive it from"));
            }
        };
        if self.line_spacing_m.is_none() && !(0.5..=2_000.0).contains(&line_spacing_m) {
            // from the camera's footprint, or the implement's width less the overlap
            let at = if camera.is_some() { "/camera" } else { "/overlap" };
            return Err(InputError::new("spacing_out_of_range", at, format!("these figures space the lines {line_spacing_m:.2} m apart; the spacing is 0.5 to 2 000 m")));
        }
        check_range(line_spacing_m, 0.5, 2_000.0, "/line_spacing_m", "m")?;
        let altitude_m = camera.map(|c| c.altitude_m).or(self.altitude_m);
        if let Some(a) = altitude_m {
            check_range(a, 1.0, 5_000.0, "/altitude_m", "m")?;
        }
        if let Some(h) = self.heading_deg {
            check_range(h, -360.0, 360.0, "/heading_deg", "°")?;
        }
        let optimal_direction = self.sweep_direction == Some(SweepDirection::Optimal);
        if optimal_direction && !fleet.is_empty() {
            return Err(InputError::new(
                "direction_for_fleet",
                "/sweep_direction",
                "a fleet sweeps every part along the bands the field is cut into: give heading_deg, or leave sweep_direction out",
            ));
        }
        if optimal_direction && self.heading_deg.is_some() {
            return Err(InputError::new("direction_twice", "/sweep_direction", "heading_deg fixes the direction: leave out sweep_direction \"optimal\""));
        }
        let within = |v: Option<f64>, default: f64, lo: f64, hi: f64, pointer: &str, unit: &str| -> Result<f64, InputError> {
            let v = v.unwrap_or(default);
            check_range(v, lo, hi, pointer, unit)?;
            Ok(v)
        };
        let obstacle_clearance_m = within(self.obstacle_clearance_m, 10.0, 0.0, 200.0, "/obstacle_clearance_m", "m")?;
        let max_climb_deg = within(self.max_climb_deg, 30.0, 1.0, 60.0, "/max_climb_deg", "°")?;
        let coverage_penalty = within(self.coverage_penalty, 10.0, 0.0, 1000.0, "/coverage_penalty", "")?;
        // a tractor drives up to a fence; an aircraft keeps its distance, a fixed wing room
        // besides to stray from its turns on either side
        let tracking = fleet.iter().map(|m| &m.vehicle).chain([&vehicle]).map(Vehicle::turn_tracking_m).fold(0.0, f64::max);
        let nfz_margin_m = self.nfz_margin_m.unwrap_or(if headland.is_some() { 1.0 } else { 10.0 + 2.0 * tracking });
        check_range(nfz_margin_m, 1.0, 500.0, "/nfz_margin_m", "m")?;
        if let Some(limit) = self.time_limit_s {
            check_range(limit, 0.1, 86_400.0, "/time_limit_s", "s")?;
        }
        let max_sorties = self.max_sorties.unwrap_or(20);
        if !(1..=100).contains(&max_sorties) {
            return Err(InputError::new("parameter_out_of_range", "/max_sorties", format!("{max_sorties} is outside the accepted range [1, 100]")));
        }
        let terrain = self.terrain(&vehicle, altitude_m, max_climb_deg)?;
        let (lead_in_m, landing, landing_heading) = self.flight_ends(&vehicle, &fleet)?;
        let wind = self.wind(&vehicle, &fleet, altitude_m)?;
        let landing_sites = self.landing_sites(&vehicle, &fleet, landing)?;
        Ok(Resolved {
            line_spacing_m,
            camera,
            layout: LineLayout { spacing: line_spacing_m, footprint: camera.map(|c| c.footprint()), ends: aircraft_ends, phase: None },
            optimal_direction,
            altitude_m,
            sweep_angle: self.heading_deg.map(bearing_to_math),
            pattern: self.pattern.unwrap_or_default(),
            oblique: self.oblique(camera.as_ref(), &vehicle)?,
            vehicle,
            start: checked_position(&self.start, "start")?,
            end: checked_position(&self.end, "end")?,
            start_heading: self.start.as_ref().and_then(|p| p.heading_deg).map(bearing_to_math),
            end_heading: self.end.as_ref().and_then(|p| p.heading_deg).map(bearing_to_math),
            allow_reentry: self.allow_reentry.unwrap_or(true),
            nfz_margin_m,
            obstacle_clearance_m,
            max_climb_deg,
            coverage_penalty,
            objective: self.objective.unwrap_or_default(),
            wind,
            max_sorties: max_sorties as usize,
            landing_sites,
            fleet,
            altitude_separation_m,
            headland,
            terrain,
            lead_in_m,
            landing,
            landing_heading,
        })
    }

    /// Pattern `oblique`: the view of the camera at the pitch asked for.
    fn oblique(&self, camera: Option<&CameraPlan>, vehicle: &Vehicle) -> Result<Option<ObliqueView>, InputError> {
        if self.pattern != Some(Pattern::Oblique) {
            return match self.oblique_pitch_deg {
                Some(_) => {
                    Err(InputError::new("pitch_without_oblique", "/oblique_pitch_deg", "oblique_pitch_deg pitches the camera of pattern oblique's passes: give pattern oblique"))
                }
                None => Ok(None),
            };
        }
        if vehicle.kind != VehicleKind::Multirotor {
            return Err(InputError::new("not_a_multirotor", "/pattern", "an oblique pass holds the camera's heading while it flies its lines both ways: give a multirotor"));
        }
        let Some(camera) = camera else {
            return Err(InputError::new("camera_missing", "/pattern", "the oblique passes are laid from what the camera sees: give camera"));
        };
        let pitch = self.oblique_pitch_deg.unwrap_or(DEFAULT_OBLIQUE_PITCH_DEG);
        check_range(pitch, -80.0, -20.0, "/oblique_pitch_deg", "°")?;
        camera.oblique(pitch).map(Some).map_err(|steepest| {
            InputError::new(
                "oblique_view_reaches_horizon",
                "/oblique_pitch_deg",
                format!("at {pitch}° this camera's image reaches within {OBLIQUE_HORIZON_MARGIN_DEG}° of the horizon: pitch it to {steepest:.1}° or further down"),
            )
        })
    }

    /// The wind carried to the flight altitude, checked against every vehicle flying in it.
    fn wind(&self, vehicle: &Vehicle, fleet: &[FleetVehicle], altitude_m: Option<f64>) -> Result<Option<Wind>, InputError> {
        let Some(given) = &self.wind else { return Ok(None) };
        given.check("/wind")?;
        let wind = given.at_altitude(altitude_m);
        if fleet.is_empty() {
            vehicle.check_wind(&wind, "/wind", "/vehicle")?;
        }
        for (k, member) in fleet.iter().enumerate() {
            member.vehicle.check_wind(&wind, "/wind", &format!("/fleet/{k}/vehicle"))?;
        }
        Ok(Some(wind))
    }

    /// The lead-in, the landing and its heading, checked against the vehicles they are for.
    fn flight_ends(&self, vehicle: &Vehicle, fleet: &[FleetVehicle]) -> Result<(Option<f64>, Landing, Option<f64>), InputError> {
        let fixed_wing = vehicle.kind == VehicleKind::FixedWing || fleet.iter().any(|m| m.vehicle.kind == VehicleKind::FixedWing);
        let not_fixed_wing = |pointer: &str| InputError::new("not_a_fixed_wing", pointer, "this member is for a fixed-wing aircraft");
        if let Some(m) = self.lead_in_m {
            if !fixed_wing {
                return Err(not_fixed_wing("/lead_in_m"));
            }
            check_range(m, 0.0, 1000.0, "/lead_in_m", "m")?;
        }
        let landing = self.landing.unwrap_or_default();
        if landing == Landing::Auto && vehicle.kind == VehicleKind::Ground {
            return Err(InputError::new("not_for_ground_vehicles", "/landing", "a ground vehicle does not land: leave out landing"));
        }
        let heading = match self.landing_heading_deg {
            Some(_) if !fixed_wing => return Err(not_fixed_wing("/landing_heading_deg")),
            Some(_) if landing != Landing::Auto => {
                return Err(InputError::new("not_landing", "/landing_heading_deg", "a landing heading is for landing \"auto\""));
            }
            Some(h) => Some(check_range(h, -360.0, 360.0, "/landing_heading_deg", "°").map(|_| bearing_to_math(h))?),
            None => None,
        };
        Ok((self.lead_in_m, landing, heading))
    }

    /// The landing sites, checked against the vehicle and how it lands.
    fn landing_sites(&self, vehicle: &Vehicle, fleet: &[FleetVehicle], landing: Landing) -> Result<Vec<[f64; 2]>, InputError> {
        let Some(sites) = &self.landing_sites else { return Ok(Vec::new()) };
        if sites.len() > MAX_LANDING_SITES {
            return Err(InputError::new("parameter_out_of_range", "/landing_sites", format!("{} landing sites; at most {MAX_LANDING_SITES}", sites.len())));
        }
        if vehicle.kind == VehicleKind::Ground {
            return Err(InputError::new("not_for_ground_vehicles", "/landing_sites", "a ground vehicle does not land: leave out landing_sites"));
        }
        if !fleet.is_empty() {
            return Err(InputError::new("landing_sites_for_fleet", "/landing_sites", "each drone of a fleet flies from its own home: leave out landing_sites"));
        }
        if vehicle.kind == VehicleKind::FixedWing && landing != Landing::Auto {
            return Err(InputError::new(
                "not_landing",
                "/landing_sites",
                "a fixed wing's return flies back to where it took off: to land at another site it lands by itself, give landing \"auto\"",
            ));
        }
        for (k, &site) in sites.iter().enumerate() {
            check_lon_lat(site, &format!("/landing_sites/{k}"))?;
        }
        Ok(sites.clone())
    }

    fn terrain(&self, vehicle: &Vehicle, altitude_m: Option<f64>, max_climb_deg: f64) -> Result<Option<TerrainSpec>, InputError> {
        let given = [self.terrain_tolerance_m.is_some(), self.max_climb_mps.is_some(), self.max_descent_mps.is_some()];
        if self.altitude_reference != Some(AltitudeReference::Terrain) {
            return match first_given(&TERRAIN_MEMBERS, &given) {
                Some(pointer) => Err(InputError::new("not_over_terrain", pointer, "this member is for plans over terrain: give altitude_reference \"terrain\"")),
                None => Ok(None),
            };
        }
        if vehicle.kind == VehicleKind::Ground {
            return Err(InputError::new("not_for_ground_vehicles", "/altitude_reference", "a ground vehicle drives on the ground: leave out altitude_reference"));
        }
        if altitude_m.is_none() {
            return Err(InputError::new("altitude_missing", "/altitude_m", "over terrain, give the height above ground to fly at (altitude_m, or a camera with gsd_cm)"));
        }
        let tolerance_m = self.terrain_tolerance_m.unwrap_or(5.0);
        check_range(tolerance_m, 0.5, 100.0, "/terrain_tolerance_m", "m")?;
        let (climb, descent) = if vehicle.kind == VehicleKind::FixedWing {
            // the climb and descent rates: a fixed wing's are its climb angle
            if let Some(pointer) = first_given(&TERRAIN_MEMBERS[1..], &given[1..]) {
                return Err(InputError::new("not_for_fixed_wing", pointer, "a fixed wing climbs and descends at max_climb_deg"));
            }
            let slope = max_climb_deg.to_radians().tan();
            (slope, slope)
        } else {
            let (climb_default, descent_default) = vehicle.vertical_rates_mps();
            let climb = self.max_climb_mps.unwrap_or(climb_default);
            let descent = self.max_descent_mps.unwrap_or(descent_default);
            check_range(climb, 0.1, 20.0, "/max_climb_mps", "m/s")?;
            check_range(descent, 0.1, 20.0, "/max_descent_mps", "m/s")?;
            // at cruise speed: slower legs climb more steeply at the same rate, so this is the
            // shallowest slope the vehicle flies
            (climb / vehicle.cruise_speed_mps, descent / vehicle.cruise_speed_mps)
        };
        Ok(Some(TerrainSpec { tolerance_m, climb, descent }))
    }

    /// The inspection's vehicle and parameters (planner `inspection`): a multirotor, which
    /// stops and turns on the spot at each viewpoint.
    pub fn resolve_inspection(&self, profiles: &[Vehicle]) -> Result<(Vehicle, InspectionSpec), InputError> {
        let given = [
            self.line_spacing_m.is_some(),
            self.altitude_m.is_some(),
            self.heading_deg.is_some(),
            self.sweep_direction.is_some(),
            self.side_overlap.is_some(),
            self.front_overlap.is_some(),
            self.fleet.is_some(),
            self.vehicles.is_some(),
            self.headland_passes.is_some(),
            self.objective.is_some(),
            self.lead_in_m.is_some(),
            self.landing.is_some(),
            self.landing_heading_deg.is_some(),
            self.wind.is_some(),
            self.pattern.is_some(),
            self.oblique_pitch_deg.is_some(),
            self.landing_sites.is_some(),
        ];
        if let Some(pointer) = first_given(&COVERAGE_ONLY_MEMBERS, &given) {
            return Err(InputError::new("not_for_inspection", pointer, "an inspection flies to viewpoints around structures: this member is for coverage plans"));
        }
        let vehicle = self.vehicle.resolve(profiles, "/vehicle")?;
        if vehicle.kind != VehicleKind::Multirotor {
            return Err(InputError::new("not_a_multirotor", "/vehicle", "an inspection stops and turns at each viewpoint: give a multirotor"));
        }
        if let Some(limit) = self.time_limit_s {
            check_range(limit, 0.1, 86_400.0, "/time_limit_s", "s")?;
        }
        let spec = InspectionRequest {
            targets: self.targets.as_deref(),
            budget: self.budget.as_ref(),
            options: self.inspection.as_ref(),
            seed: self.seed,
            time_limit_s: self.time_limit_s,
            start_altitude_m: self.start.as_ref().and_then(|p| p.altitude_m),
            end_altitude_m: self.end.as_ref().and_then(|p| p.altitude_m),
        }
        .resolve()?;
        Ok((vehicle, spec))
    }

    /// A ground vehicle's headland; the headland parameters are refused for an aircraft.
    fn headland(&self, vehicle: &Vehicle) -> Result<Option<HeadlandSpec>, InputError> {
        let Some(ground) = vehicle.ground.filter(|_| vehicle.kind == VehicleKind::Ground) else {
            let given = [
                self.headland_passes.is_some(),
                self.headland_width_m.is_some(),
                self.headland_order.is_some(),
                self.overlap.is_some(),
                self.guidance.is_some(),
                self.tramline_every.is_some(),
                self.payload.is_some(),
            ];
            return match first_given(&GROUND_ONLY_MEMBERS, &given) {
                Some(pointer) => Err(InputError::new(
                    "not_a_ground_vehicle",
                    pointer,
                    "headlands, swath overlap, guidance lines, tramlines and payloads are for ground vehicles (vehicle kind ground)",
                )),
                None => Ok(None),
            };
        };
        let overlap = self.overlap.unwrap_or(0.0);
        check_range(overlap, 0.0, 0.5, "/overlap", "")?;
        if self.guidance.is_some() && self.heading_deg.is_some() {
            return Err(InputError::new("guidance_and_heading", "/heading_deg", "the swaths follow the guidance line: give guidance or heading_deg, not both"));
        }
        let guidance = self.guidance.map(|g| g.validate()).transpose()?;
        if let Some(n) = self.tramline_every {
            check_range(n as f64, 2.0, 100.0, "/tramline_every", "swaths")?;
        }
        if let Some(p) = &self.payload {
            p.validate()?;
        }
        let step = ground.working_width_m * (1.0 - overlap);
        if let Some(p) = self.headland_passes
            && !(1..=20).contains(&p)
        {
            return Err(InputError::new("parameter_out_of_range", "/headland_passes", format!("{p} is outside the accepted range [1, 20]")));
        }
        if let Some(w) = self.headland_width_m {
            check_range(w, 1.0, 500.0, "/headland_width_m", "m")?;
        }
        let (width_m, passes) = match (self.headland_width_m, self.headland_passes) {
            (Some(w), Some(p)) if p as f64 * ground.working_width_m < w - 1e-9 => {
                return Err(InputError::new("headland_not_covered", "/headland_passes", format!("{p} passes of {} m cannot work a headland {w} m wide", ground.working_width_m)));
            }
            (Some(w), Some(p)) => (w, p as usize),
            (Some(w), None) => (w, ((w / step) - 1e-9).ceil().max(1.0) as usize),
            (None, p) => {
                let p = p.unwrap_or(2) as usize;
                (p as f64 * step, p)
            }
        };
        Ok(Some(HeadlandSpec {
            width_m,
            passes,
            order: self.headland_order.unwrap_or_default(),
            swath_ends: self.swath_ends.unwrap_or_default(),
            working_width_m: ground.working_width_m,
            guidance,
            tramline_every: self.tramline_every.map(|n| n as usize),
            payload: self.payload.clone(),
        }))
    }

    /// The fleet asked for by `fleet` or `vehicles`; empty for one vehicle.
    fn resolve_fleet(&self, vehicle: &Vehicle, profiles: &[Vehicle]) -> Result<Vec<FleetVehicle>, InputError> {
        let size = |n: usize, pointer: &str| {
            if (2..=MAX_FLEET).contains(&n) { Ok(()) } else { Err(InputError::new("fleet_size", pointer, format!("a fleet has 2 to {MAX_FLEET} drones, not {n}"))) }
        };
        match (&self.fleet, self.vehicles) {
            (None, None) => Ok(Vec::new()),
            (Some(_), Some(_)) => Err(InputError::new("fleet_twice", "/vehicles", "give either fleet (each drone) or vehicles (copies of vehicle), not both")),
            (None, Some(n)) => {
                size(n as usize, "/vehicles")?;
                Ok(vec![FleetVehicle { vehicle: vehicle.clone(), home: None }; n as usize])
            }
            (Some(members), None) => {
                size(members.len(), "/fleet")?;
                if self.vehicle != VehicleParams::default() {
                    return Err(InputError::new("fleet_twice", "/vehicle", "with fleet, give each drone's vehicle in its entry and leave out vehicle"));
                }
                members
                    .iter()
                    .enumerate()
                    .map(|(k, m)| {
                        if let Some([lon, lat]) = m.home {
                            check_range(lon, -180.0, 180.0, &format!("/fleet/{k}/home/0"), "°")?;
                            check_range(lat, -90.0, 90.0, &format!("/fleet/{k}/home/1"), "°")?;
                        }
                        Ok(FleetVehicle { vehicle: m.vehicle.resolve(profiles, &format!("/fleet/{k}"))?, home: m.home })
                    })
                    .collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bearings_and_math_angles() {
        assert!((bearing_to_math(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((bearing_to_math(90.0)).abs() < 1e-12);
        assert!((math_to_bearing(std::f64::consts::PI) - 270.0).abs() < 1e-9);
    }

    #[test]
    fn fleets_are_checked_drone_by_drone() {
        let profiles = crate::vehicle::builtin_profiles();
        let resolve = |v: serde_json::Value| {
            serde_json::from_value::<PlanParams>(v).map_err(|e| e.to_string()).and_then(|p| p.resolve(&profiles).map_err(|e| format!("{} {}", e.code, e.pointer)))
        };
        let fleet =
            resolve(serde_json::json!({"line_spacing_m": 20, "fleet": [{"profile": "iris", "home": [7.0, 45.0]}, {"profile": "generic_multirotor", "cruise_speed_mps": 5}]}))
                .unwrap();
        assert_eq!(fleet.fleet.len(), 2);
        assert_eq!((fleet.fleet[0].vehicle.profile.as_str(), fleet.fleet[0].home), ("iris", Some([7.0, 45.0])));
        assert_eq!(fleet.fleet[1].vehicle.cruise_speed_mps, 5.0);
        let copies = resolve(serde_json::json!({"line_spacing_m": 20, "vehicles": 3, "vehicle": {"profile": "iris"}})).unwrap();
        assert!(copies.fleet.iter().all(|d| d.vehicle.profile == "iris" && d.home.is_none()) && copies.fleet.len() == 3);
        let refused = |v: serde_json::Value| resolve(v).unwrap_err();
        assert!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{"profil": "iris"}, {}]})).contains("profil"));
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}, {"profile": "zeppelin"}]})), "unknown_vehicle_profile /fleet/1/profile");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}, {"cruise_speed_mps": 1e9}]})), "parameter_out_of_range /fleet/1/cruise_speed_mps");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}, {"home": [7.0, 95.0]}]})), "parameter_out_of_range /fleet/1/home/1");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "vehicles": 1})), "fleet_size /vehicles");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "vehicles": 17})), "fleet_size /vehicles");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}]})), "fleet_size /fleet");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}, {}], "vehicles": 2})), "fleet_twice /vehicles");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "fleet": [{}, {}], "vehicle": {"profile": "iris"}})), "fleet_twice /vehicle");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "altitude_separation_m": 10})), "not_a_fleet /altitude_separation_m");
        assert_eq!(refused(serde_json::json!({"line_spacing_m": 20, "vehicles": 2, "altitude_separation_m": 0.5})), "parameter_out_of_range /altitude_separation_m");
    }

    #[test]
    fn refuses_absurd_values_with_their_place() {
        let p: PlanParams = serde_json::from_str(r#"{"line_spacing_m": -3}"#).unwrap();
        let profiles = crate::vehicle::builtin_profiles();
        assert_eq!(p.resolve(&profiles).unwrap_err().pointer, "/line_spacing_m");
        let p: PlanParams = serde_json::from_str(r#"{"line_spacing_m": 20, "vehicle": {"cruise_speed_mps": 1e9}}"#).unwrap();
        assert_eq!(p.resolve(&profiles).unwrap_err().pointer, "/vehicle/cruise_speed_mps");
        let p: PlanParams = serde_json::from_str(r#"{}"#).unwrap();
        assert_eq!(p.resolve(&profiles).unwrap_err().code, "spacing_missing");
        assert!(serde_json::from_str::<PlanParams>(r#"{"vehicle": {"kind": "boat"}}"#).is_err());
    }
}
