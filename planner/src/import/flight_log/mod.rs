//! Flight logs read for what a flight did: its track, where its camera took photos, the battery
//! left and the kind of vehicle that flew. Three formats, each read with the maintained crate
//! made for it: MAVLink telemetry (`.tlog`, `mavlink`), PX4 ULog (`.ulg`, `yule_log`) and
//! ArduPilot DataFlash (`.bin`, `ardupilot-binlog`). The format is told by the file's first
//! bytes, not its name.

mod dataflash;
mod tlog;
mod ulog;

use serde::Serialize;

use crate::error::InputError;
use crate::frame::LocalFrame;
use crate::params::resume::{Flown, MAX_FLOWN_PHOTOS, MAX_TRACK_POINTS};
use crate::vehicle::VehicleKind;

/// The formats read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LogFormat {
    Tlog,
    Ulog,
    Dataflash,
}

/// What a log says of its flight.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightLog {
    pub format: LogFormat,
    pub flown: Flown,
    /// The kind of vehicle the autopilot flew, where the log says.
    pub vehicle: Option<VehicleKind>,
}

/// Track points closer than this to the last one kept are left out (a vehicle standing still
/// logs the same place many times).
const TRACK_STEP_M: f64 = 0.5;

/// What a reader gathers, in log order.
#[derive(Default)]
struct Gathered {
    track: Vec<[f64; 2]>,
    photos: Vec<[f64; 2]>,
    battery_remaining: Option<f64>,
    vehicle: Option<VehicleKind>,
    last: Option<(LocalFrame, [f64; 2])>,
    /// Whether the autopilot flies its mission, where the log says: the track and photos
    /// outside it (a return home with the camera still triggering) are not the plan's work.
    in_mission: Option<bool>,
}

impl Gathered {
    /// A position of the vehicle, degrees; none (0, 0) or out of range (no GPS fix) is skipped.
    fn position(&mut self, lon: f64, lat: f64) {
        if !valid(lon, lat) || self.in_mission == Some(false) {
            return;
        }
        if let Some((frame, _)) = &self.last {
            let p = frame.to_local(lon, lat);
            if p.x.hypot(p.y) < TRACK_STEP_M {
                return;
            }
        }
        self.last = Some((LocalFrame::new(lon, lat), [lon, lat]));
        self.track.push([lon, lat]);
    }

    /// A photo taken at `lon`, `lat`, or at the last position when the log gives none.
    fn photo(&mut self, at: Option<(f64, f64)>) {
        if self.in_mission == Some(false) {
            return;
        }
        match at.filter(|&(lon, lat)| valid(lon, lat)) {
            Some((lon, lat)) => self.photos.push([lon, lat]),
            None => self.photos.extend(self.last.as_ref().map(|(_, p)| *p)),
        }
    }

    /// The battery left, 0 to 1; a value out of range (unknown) is skipped.
    fn battery(&mut self, remaining: f64) {
        if (0.0..=1.0).contains(&remaining) {
            self.battery_remaining = Some(remaining);
        }
    }

    fn finish(self, format: LogFormat) -> Result<FlightLog, InputError> {
        if self.track.len() < 2 {
            return Err(InputError::new("log_without_position", "/flown/track", "the log holds no positions of the aircraft (or one): was its GPS on?"));
        }
        if self.track.len() > MAX_TRACK_POINTS || self.photos.len() > MAX_FLOWN_PHOTOS {
            return Err(InputError::new(
                "too_many_points",
                "/flown/track",
                format!("the log holds {} positions and {} photos; at most {MAX_TRACK_POINTS} and {MAX_FLOWN_PHOTOS} are read", self.track.len(), self.photos.len()),
            ));
        }
        let flown = Flown { track: self.track, photos: self.photos, battery_remaining: self.battery_remaining, tolerance_m: None };
        Ok(FlightLog { format, flown, vehicle: self.vehicle })
    }
}

fn valid(lon: f64, lat: f64) -> bool {
    lon.is_finite() && lat.is_finite() && lon.abs() <= 180.0 && lat.abs() <= 90.0 && (lon != 0.0 || lat != 0.0)
}

/// An unreadable log: what is wrong, in words.
fn unreadable(what: impl Into<String>) -> InputError {
    InputError::new("log_unreadable", "/flown", what)
}

/// Reads a flight log of any of the formats.
pub fn read(bytes: &[u8]) -> Result<FlightLog, InputError> {
    if bytes.is_empty() {
        return Err(unreadable("the log is empty"));
    }
    if ulog::is_ulog(bytes) {
        ulog::read(bytes)
    } else if dataflash::is_dataflash(bytes) {
        dataflash::read(bytes)
    } else if tlog::is_tlog(bytes) {
        tlog::read(bytes)
    } else {
        Err(unreadable("this is not a flight log read here: send a MAVLink telemetry log (.tlog), a PX4 log (.ulg) or an ArduPilot DataFlash log (.bin)"))
    }
}
