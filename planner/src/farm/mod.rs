//! Whole farms: which machine works which field on which day, and in which order
//! (docs/methods.md, farms).
//!
//! Each field is planned on its own first (a plan says how long its work takes and where it
//! begins and ends); [`schedule`] then shares the fields among the machines over working
//! days, each day leaving from and returning to the machine's depot, so that the last machine
//! is home as early as it can be. Transits between places are priced by a [`Transit`]: in a
//! straight line ([`StraightLine`]) or along a road network ([`RoadNetwork`]).

mod days;
mod road_network;
mod rounds;
mod schedule;
mod schedule_csv;
mod straight_line;

pub use road_network::{MAX_ROAD_POINTS, RoadNetwork};
pub use schedule::{Day, Leg, LegKind, MAX_FIELDS, MAX_MACHINES, MIN_PIECE_S, MachineSchedule, Schedule, Stretch, Unscheduled, check_setup, schedule};
pub use schedule_csv::schedule_csv;
pub use straight_line::StraightLine;

use serde::{Deserialize, Serialize};

/// `[longitude, latitude]`, degrees (WGS84).
pub type LonLat = [f64; 2];

/// A field as the schedule sees it: its plan's working time and where that work begins and ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldWork {
    pub entry: LonLat,
    pub exit: LonLat,
    pub work_s: f64,
}

/// A machine of the farm: where it sleeps, how long it works a day, how fast it drives between
/// fields, and how often it must refill.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// A name for the schedule (default: `machine 1`, `machine 2`, …).
    #[serde(default)]
    pub name: Option<String>,
    /// `[lon, lat]`: where the machine starts and ends each day.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub depot: [f64; 2],
    /// Its working hours a day, transits included (default: the window's).
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 24))]
    #[serde(default)]
    pub hours_per_day: Option<f64>,
    /// Its speed between fields, m/s (default 8.3 m/s, 30 km/h).
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 60))]
    #[serde(default)]
    pub road_speed_mps: Option<f64>,
    /// Working time one tank or battery lasts, s; past it the machine stops for `refill_s`
    /// (default: it never needs to).
    #[cfg_attr(feature = "schema", schema(minimum = 60, maximum = 10_000_000))]
    #[serde(default)]
    pub endurance_s: Option<f64>,
    /// How long a refill takes, s (default 900).
    #[cfg_attr(feature = "schema", schema(minimum = 0, maximum = 86400))]
    #[serde(default)]
    pub refill_s: Option<f64>,
}

/// The working days: from a date, so many days, so many hours a day from a time of day.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Window {
    /// The first working day, `YYYY-MM-DD`.
    #[cfg_attr(feature = "schema", schema(pattern = r"^\d{4}-\d{2}-\d{2}$", example = "2027-04-12"))]
    pub start_date: String,
    /// Working days (1 to 366); work that takes longer is scheduled past them and said so.
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 366))]
    pub days: u32,
    /// Working hours a day (default 10).
    #[cfg_attr(feature = "schema", schema(minimum = 0.5, maximum = 24))]
    #[serde(default)]
    pub hours_per_day: Option<f64>,
    /// When the working day begins, `HH:MM` (default `07:00`).
    #[cfg_attr(feature = "schema", schema(pattern = r"^\d{2}:\d{2}$"))]
    #[serde(default)]
    pub day_start: Option<String>,
}

pub const DEFAULT_HOURS_PER_DAY: f64 = 10.0;
pub const DEFAULT_ROAD_SPEED_MPS: f64 = 8.3;
pub const DEFAULT_REFILL_S: f64 = 900.0;

/// Prices the way between two places, in metres. Computed once for all the schedule's places.
pub trait Transit: Sync {
    /// `distances[i * n + j]`: metres from `places[i]` to `places[j]` (n = `places.len()`).
    fn distances(&self, places: &[LonLat]) -> Vec<f64>;
}
