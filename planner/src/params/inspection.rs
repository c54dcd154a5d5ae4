//! Parameters of planner `inspection`: what to look at, the budget, the camera's reach and
//! the search's effort (docs/methods.md, Inspection).

use serde::{Deserialize, Serialize};

use crate::error::{InputError, check_range};

/// The planner id of the inspection of structures.
pub const PLANNER_ID: &str = "inspection";

/// A structure's faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Face {
    Walls,
    Roof,
}

/// What to inspect: `"walls"` or `"roof"` of every structure, a structure's name (its walls
/// and roof), or `{name, faces, priority}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(untagged)]
pub enum Target {
    Named(String),
    Detailed(DetailedTarget),
}

#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct DetailedTarget {
    /// A structure's `name`.
    pub name: String,
    /// Default: walls and roof.
    pub faces: Option<Vec<Face>>,
    /// Weight of each of its points, 0.01 to 100 (default 1).
    #[cfg_attr(feature = "schema", schema(minimum = 0.01, maximum = 100.0))]
    pub priority: Option<f64>,
}

/// The flight's limit: exactly one of the three.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Path length in metres (climbs included), 10 to 100 000.
    #[cfg_attr(feature = "schema", schema(minimum = 10.0, maximum = 100000.0))]
    pub max_length_m: Option<f64>,
    /// Flight time in seconds (legs, yaw and captures), 10 to 86 400.
    #[cfg_attr(feature = "schema", schema(minimum = 10.0, maximum = 86400.0))]
    pub max_time_s: Option<f64>,
    /// Energy in joules from the vehicle's model, 1 000 to 10⁹.
    #[cfg_attr(feature = "schema", schema(minimum = 1000.0, maximum = 1e9))]
    pub max_energy_j: Option<f64>,
}

/// How the search adds viewpoints near its best path between iterations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Extension {
    /// Only the initial viewpoints.
    None,
    /// Inside a ball around a viewpoint of the path.
    #[default]
    Sphere,
    /// On a spheroid whose foci are two consecutive viewpoints of the path.
    Ellipse,
}

/// The inspection's geometry and effort; every member is optional.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct InspectionOptions {
    /// Spacing of the points of interest on the faces, 0.1 to 10 m (default 0.5).
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 10.0))]
    pub poi_spacing_m: Option<f64>,
    /// Nearest and farthest a point may be from the camera to count as seen, metres (default
    /// [1, 12], or the farthest from `gsd_cm`).
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub range_m: Option<[f64; 2]>,
    /// Steepest angle between a face's normal and the line of sight, 10 to 89° (default 75).
    #[cfg_attr(feature = "schema", schema(minimum = 10.0, maximum = 89.0))]
    pub max_incidence_deg: Option<f64>,
    /// Lowest and highest gimbal pitch, degrees (negative: down; default [-90, 30]).
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub gimbal_pitch_deg: Option<[f64; 2]>,
    /// The drone's radius, 0.05 to 10 m (default 0.5).
    #[cfg_attr(feature = "schema", schema(minimum = 0.05, maximum = 10.0))]
    pub body_radius_m: Option<f64>,
    /// Clearance kept beyond the body from every structure and obstacle, 0 to 50 m (default 2).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 50.0))]
    pub safety_margin_m: Option<f64>,
    /// Lowest and highest altitude of a viewpoint above ground, metres (default: 2 to the
    /// tallest target's top plus the farthest range).
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub altitude_range_m: Option<[f64; 2]>,
    /// Viewpoints sampled before the search, 10 to 3 000 (default 300).
    #[cfg_attr(feature = "schema", schema(minimum = 10, maximum = 3000))]
    pub viewpoints: Option<u32>,
    /// Default `sphere`.
    pub extension: Option<Extension>,
    /// Viewpoints added per iteration with an extension, 1 to 50 (default 5).
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 50))]
    pub extension_per_iteration: Option<u32>,
    /// Hover at each viewpoint to take the picture, 0 to 60 s (default 1).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 60.0))]
    pub capture_s: Option<f64>,
    /// Add the points of interest to the trajectory, seen and unseen (default false).
    pub show_unseen: Option<bool>,
}

/// The budget, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BudgetLimit {
    LengthM(f64),
    TimeS(f64),
    EnergyJ(f64),
}

impl BudgetLimit {
    pub fn value(self) -> f64 {
        match self {
            BudgetLimit::LengthM(v) | BudgetLimit::TimeS(v) | BudgetLimit::EnergyJ(v) => v,
        }
    }

    /// Of something's length, time and energy, the one this budget counts.
    pub fn measure(self, length_m: f64, time_s: f64, energy_j: f64) -> f64 {
        match self {
            BudgetLimit::LengthM(_) => length_m,
            BudgetLimit::TimeS(_) => time_s,
            BudgetLimit::EnergyJ(_) => energy_j,
        }
    }

    pub fn unit(self) -> &'static str {
        self.measure_name().1
    }

    /// The measure's name in `stats.inspection.budget_measure`, and its unit.
    pub fn measure_name(self) -> (&'static str, &'static str) {
        match self {
            BudgetLimit::LengthM(_) => ("length_m", "m"),
            BudgetLimit::TimeS(_) => ("time_s", "s"),
            BudgetLimit::EnergyJ(_) => ("energy_j", "J"),
        }
    }
}

/// The inspection's parameters, validated; geometry in metres and degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct InspectionSpec {
    pub targets: Vec<Target>,
    pub budget: BudgetLimit,
    pub poi_spacing_m: f64,
    /// Range given, or `None` for the default (which a `gsd_cm` may narrow).
    pub range_m: Option<[f64; 2]>,
    pub max_incidence_deg: f64,
    pub gimbal_pitch_deg: [f64; 2],
    pub body_radius_m: f64,
    pub safety_margin_m: f64,
    pub altitude_range_m: Option<[f64; 2]>,
    pub viewpoints: usize,
    pub extension: Extension,
    pub extension_per_iteration: usize,
    pub capture_s: f64,
    pub show_unseen: bool,
    pub seed: u64,
    /// How long the search may run before it returns its best path.
    pub search_time: std::time::Duration,
    /// Start and end altitudes above ground (default 0: take-off and landing).
    pub start_altitude_m: f64,
    pub end_altitude_m: f64,
}

fn pair(v: Option<[f64; 2]>, lo: f64, hi: f64, pointer: &str, unit: &str) -> Result<Option<[f64; 2]>, InputError> {
    let Some([a, b]) = v else { return Ok(None) };
    check_range(a, lo, hi, &format!("{pointer}/0"), unit)?;
    check_range(b, lo, hi, &format!("{pointer}/1"), unit)?;
    if a >= b {
        return Err(InputError::new("range_reversed", pointer, format!("the first value ({a}) must be below the second ({b})")));
    }
    Ok(Some([a, b]))
}

/// An inspection's time limit when the request gives none, seconds.
pub const DEFAULT_TIME_LIMIT_S: f64 = 20.0;
/// The share of the time limit the search may use.
const SEARCH_SHARE: f64 = 0.9;

/// The request's inspection members, checked one by one with their places.
pub struct InspectionRequest<'a> {
    pub targets: Option<&'a [Target]>,
    pub budget: Option<&'a Budget>,
    pub options: Option<&'a InspectionOptions>,
    pub seed: Option<u64>,
    pub time_limit_s: Option<f64>,
    pub start_altitude_m: Option<f64>,
    pub end_altitude_m: Option<f64>,
}

impl InspectionRequest<'_> {
    pub fn resolve(&self) -> Result<InspectionSpec, InputError> {
        let budget = self.budget.ok_or_else(|| InputError::new("budget_missing", "/budget", "an inspection needs a budget: max_length_m, max_time_s or max_energy_j"))?;
        let given: Vec<BudgetLimit> = [budget.max_length_m.map(BudgetLimit::LengthM), budget.max_time_s.map(BudgetLimit::TimeS), budget.max_energy_j.map(BudgetLimit::EnergyJ)]
            .into_iter()
            .flatten()
            .collect();
        let budget = match given.as_slice() {
            [one] => *one,
            [] => return Err(InputError::new("budget_missing", "/budget", "give one of max_length_m, max_time_s, max_energy_j")),
            _ => return Err(InputError::new("budget_twice", "/budget", "give only one of max_length_m, max_time_s, max_energy_j")),
        };
        match budget {
            BudgetLimit::LengthM(v) => check_range(v, 10.0, 100_000.0, "/budget/max_length_m", "m")?,
            BudgetLimit::TimeS(v) => check_range(v, 10.0, 86_400.0, "/budget/max_time_s", "s")?,
            BudgetLimit::EnergyJ(v) => check_range(v, 1_000.0, 1e9, "/budget/max_energy_j", "J")?,
        }
        let targets = self.targets.map(<[Target]>::to_vec).unwrap_or_default();
        for (i, t) in targets.iter().enumerate() {
            if let Target::Detailed(d) = t
                && let Some(p) = d.priority
            {
                check_range(p, 0.01, 100.0, &format!("/targets/{i}/priority"), "")?;
            }
        }
        let o = self.options.cloned().unwrap_or_default();
        let within = |v: Option<f64>, default: f64, lo: f64, hi: f64, name: &str, unit: &str| -> Result<f64, InputError> {
            let v = v.unwrap_or(default);
            check_range(v, lo, hi, &format!("/inspection/{name}"), unit)?;
            Ok(v)
        };
        let count = |v: Option<u32>, default: u32, lo: u32, hi: u32, name: &str| -> Result<usize, InputError> {
            let v = v.unwrap_or(default);
            if !(lo..=hi).contains(&v) {
                return Err(InputError::new("parameter_out_of_range", format!("/inspection/{name}"), format!("{v} is outside the accepted range [{lo}, {hi}]")));
            }
            Ok(v as usize)
        };
        // the plan's own limit ends the job: the search stops short of it to measure its path
        let search_time = std::time::Duration::from_secs_f64(SEARCH_SHARE * self.time_limit_s.unwrap_or(DEFAULT_TIME_LIMIT_S));
        let altitude = |v: Option<f64>, pointer: &str| -> Result<f64, InputError> {
            let v = v.unwrap_or(0.0);
            check_range(v, 0.0, 1_000.0, pointer, "m")?;
            Ok(v)
        };
        Ok(InspectionSpec {
            targets,
            budget,
            poi_spacing_m: within(o.poi_spacing_m, 0.5, 0.1, 10.0, "poi_spacing_m", "m")?,
            range_m: pair(o.range_m, 0.1, 500.0, "/inspection/range_m", "m")?,
            max_incidence_deg: within(o.max_incidence_deg, 75.0, 10.0, 89.0, "max_incidence_deg", "°")?,
            gimbal_pitch_deg: pair(o.gimbal_pitch_deg, -90.0, 90.0, "/inspection/gimbal_pitch_deg", "°")?.unwrap_or([-90.0, 30.0]),
            body_radius_m: within(o.body_radius_m, 0.5, 0.05, 10.0, "body_radius_m", "m")?,
            safety_margin_m: within(o.safety_margin_m, 2.0, 0.0, 50.0, "safety_margin_m", "m")?,
            altitude_range_m: pair(o.altitude_range_m, 0.5, 1_000.0, "/inspection/altitude_range_m", "m")?,
            viewpoints: count(o.viewpoints, 300, 10, 3_000, "viewpoints")?,
            extension: o.extension.unwrap_or_default(),
            extension_per_iteration: count(o.extension_per_iteration, 5, 1, 50, "extension_per_iteration")?,
            capture_s: within(o.capture_s, 1.0, 0.0, 60.0, "capture_s", "s")?,
            show_unseen: o.show_unseen.unwrap_or(false),
            seed: self.seed.unwrap_or(0),
            search_time,
            start_altitude_m: altitude(self.start_altitude_m, "/start/altitude_m")?,
            end_altitude_m: altitude(self.end_altitude_m, "/end/altitude_m")?,
        })
    }
}
