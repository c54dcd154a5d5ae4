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

/// What a reader gathers, in log order: each position and photo with whether the autopilot
/// flew its mission then.
#[derive(Default)]
struct Gathered {
    track: Vec<([f64; 2], bool)>,
    photos: Vec<([f64; 2], bool)>,
    battery_remaining: Option<f64>,
    vehicle: Option<VehicleKind>,
    /// Whether the autopilot flies its mission now, where the log says.
    in_mission: bool,
    /// Whether the log ever shows the mission flown: then the track and photos outside it (a
    /// return home with the camera still triggering) are not the plan's work.
    mission_seen: bool,
}

impl Gathered {
    /// The autopilot's mode changed: flying its mission or not.
    fn mission(&mut self, flying: bool) {
        self.in_mission = flying;
        self.mission_seen |= flying;
    }

    /// A position of the vehicle, degrees; none (0, 0) or out of range (no GPS fix) is skipped.
    fn position(&mut self, lon: f64, lat: f64) {
        if valid(lon, lat) {
            self.track.push(([lon, lat], self.in_mission));
        }
    }

    /// A photo taken at `lon`, `lat`, or at the last position when the log gives none.
    fn photo(&mut self, at: Option<(f64, f64)>) {
        match at.filter(|&(lon, lat)| valid(lon, lat)) {
            Some((lon, lat)) => self.photos.push(([lon, lat], self.in_mission)),
            None => self.photos.extend(self.track.last().map(|&(p, _)| (p, self.in_mission))),
        }
    }

    /// The battery left, 0 to 1; a value out of range (unknown) is skipped.
    fn battery(&mut self, remaining: f64) {
        if (0.0..=1.0).contains(&remaining) {
            self.battery_remaining = Some(remaining);
        }
    }

    fn finish(self, format: LogFormat) -> Result<FlightLog, InputError> {
        let counted = |(p, in_mission): &([f64; 2], bool)| (*in_mission || !self.mission_seen).then_some(*p);
        // a vehicle standing still logs the same place many times: one is kept
        let mut track: Vec<[f64; 2]> = Vec::new();
        let mut last: Option<LocalFrame> = None;
        for p in self.track.iter().filter_map(counted) {
            if last.as_ref().map(|f| f.to_local(p[0], p[1])).is_some_and(|d| d.x.hypot(d.y) < TRACK_STEP_M) {
                continue;
            }
            last = Some(LocalFrame::new(p[0], p[1]));
            track.push(p);
        }
        let photos: Vec<[f64; 2]> = self.photos.iter().filter_map(counted).collect();
        if track.len() < 2 {
            return Err(InputError::new("log_without_position", "/flown/track", "the log holds no positions of the aircraft moving (or none at all): was its GPS on, did it fly?"));
        }
        if track.len() > MAX_TRACK_POINTS || photos.len() > MAX_FLOWN_PHOTOS {
            return Err(InputError::new(
                "too_many_points",
                "/flown/track",
                format!("the log holds {} positions and {} photos; at most {MAX_TRACK_POINTS} and {MAX_FLOWN_PHOTOS} are read", track.len(), photos.len()),
            ));
        }
        let flown = Flown { track, photos, battery_remaining: self.battery_remaining, tolerance_m: None };
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

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> Vec<u8> {
        std::fs::read(format!("{}/../tests/fixtures/flight-logs/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    }

    /// Logs written by autopilots (tests/fixtures/flight-logs/README.md).
    #[test]
    fn real_logs_are_read() {
        let vtol = read(&fixture("ardupilot-vtol.tlog")).unwrap();
        assert_eq!((vtol.format, vtol.vehicle), (LogFormat::Tlog, Some(VehicleKind::FixedWing)));
        assert!(vtol.flown.track.len() > 100, "{} positions", vtol.flown.track.len());
        assert!(vtol.flown.track.iter().all(|p| (p[0] - 149.165).abs() < 0.05 && (p[1] + 35.362).abs() < 0.05), "near Canberra");
        assert!(vtol.flown.battery_remaining.is_none_or(|b| (0.0..=1.0).contains(&b)));
        // a simulated PX4 vehicle that never left home: read through, and said so
        let standing = read(&fixture("px4-sitl-events.ulg")).unwrap_err();
        assert_eq!(standing.code, "log_without_position", "{standing}");
    }

    #[test]
    fn what_is_not_a_log_or_is_cut_short_is_refused_in_words() {
        for bytes in [&b""[..], b"hello, this is not a log", &[0u8; 64]] {
            let e = read(bytes).unwrap_err();
            assert_eq!(e.code, "log_unreadable", "{e}");
        }
        let tlog = fixture("ardupilot-vtol.tlog");
        let cut = read(&tlog[..tlog.len() - 5]).unwrap_err();
        assert!(cut.code == "log_unreadable" && cut.to_string().contains("cut short"), "{cut}");
        let ulog = fixture("px4-sitl-events.ulg");
        let cut = read(&ulog[..ulog.len() / 2 + 3]).unwrap_err();
        assert!(["log_unreadable", "log_without_position"].contains(&cut.code), "{cut}");
    }
}
