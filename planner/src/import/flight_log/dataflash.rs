//! ArduPilot DataFlash logs (`.bin`), as the autopilot writes them on its SD card, read with the
//! `ardupilot-binlog` crate (the log describes its own messages in `FMT` records). Positions
//! come from `POS` (the estimate), or `GPS` where a log has no `POS`; photos from `CAM`
//! (`TRIG` where the camera's feedback pin is not wired); the battery from `BAT`; the vehicle
//! from the firmware's name in the first `MSG`s; the mission flown from `MODE` (AUTO).

use std::io::Cursor;

use ardupilot_binlog::{Entry, Reader};

use super::{FlightLog, Gathered, LogFormat, unreadable};
use crate::error::InputError;
use crate::vehicle::VehicleKind;

const MAGIC: [u8; 2] = [0xA3, 0x95];
/// The type of the `FMT` record that opens every log.
const FMT: u8 = 0x80;

pub(super) fn is_dataflash(bytes: &[u8]) -> bool {
    bytes.len() >= 3 && bytes[..2] == MAGIC && bytes[2] == FMT
}

fn degrees(entry: &Entry, field: &str) -> Option<f64> {
    entry.get_f64(field).map(|v| v / 1e7)
}

fn firmware_kind(text: &str) -> Option<VehicleKind> {
    if text.starts_with("ArduPlane") {
        Some(VehicleKind::FixedWing)
    } else if text.starts_with("ArduCopter") || text.starts_with("Heli") {
        Some(VehicleKind::Multirotor)
    } else if text.starts_with("ArduRover") {
        Some(VehicleKind::Ground)
    } else {
        None
    }
}

pub(super) fn read(bytes: &[u8]) -> Result<FlightLog, InputError> {
    let mut reader = Reader::new(Cursor::new(bytes));
    let (mut estimated, mut fixes) = (Gathered::default(), Gathered::default());
    let mut consumed = 0usize;
    let mut triggers = Gathered::default();
    let mut vehicle = None;
    while let Some(entry) = reader.next() {
        let Ok(entry) = entry else { continue };
        consumed += reader.formats().get(&entry.msg_type).map_or(0, |f| f.msg_len as usize);
        let at = |e: &Entry| degrees(e, "Lng").zip(degrees(e, "Lat"));
        match entry.name.as_str() {
            "POS" => {
                if let Some((lon, lat)) = at(&entry) {
                    estimated.position(lon, lat);
                }
            }
            "GPS" if entry.get_f64("Status").is_none_or(|s| s >= 3.0) => {
                if let Some((lon, lat)) = at(&entry) {
                    fixes.position(lon, lat);
                }
            }
            "CAM" => estimated.photo(at(&entry)),
            "TRIG" => triggers.photo(at(&entry)),
            "BAT" => {
                if let Some(pct) = entry.get_f64("RemPct").filter(|p| *p > 0.0) {
                    estimated.battery(pct / 100.0);
                }
            }
            "MSG" => vehicle = vehicle.or_else(|| entry.get_str("Message").and_then(firmware_kind)),
            "MODE" => {
                // AUTO: 3 on a copter, 10 on a plane or rover
                let auto = if vehicle == Some(VehicleKind::Multirotor) { 3.0 } else { 10.0 };
                if let Some(mode) = entry.get_f64("ModeNum").or_else(|| entry.get_f64("Mode")) {
                    estimated.mission(mode == auto);
                    fixes.mission(mode == auto);
                    triggers.mission(mode == auto);
                }
            }
            _ => {}
        }
    }
    // a log cut short inside its last record: what is left is less than a record, and starts one
    let tail = &bytes[consumed.min(bytes.len())..];
    let longest = reader.formats().values().map(|f| f.msg_len as usize).max().unwrap_or(0);
    if !tail.is_empty() && tail.len() < longest && tail.starts_with(&MAGIC[..tail.len().min(2)]) {
        return Err(unreadable(format!("the log ends inside a record at byte {consumed} of {}: it was cut short", bytes.len())));
    }
    if consumed == 0 {
        return Err(unreadable("the log holds no record this server reads"));
    }
    let mut gathered = if estimated.track.len() >= 2 { estimated } else { Gathered { photos: estimated.photos, battery_remaining: estimated.battery_remaining, ..fixes } };
    if gathered.photos.is_empty() {
        gathered.photos = triggers.photos;
    }
    gathered.vehicle = vehicle;
    gathered.finish(LogFormat::Dataflash)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `FMT` record describing message `kind` named `name` with fields `format`, `labels`.
    fn fmt(kind: u8, len: u8, name: &str, format: &str, labels: &str) -> Vec<u8> {
        let field = |s: &str, n: usize| {
            let mut b = s.as_bytes().to_vec();
            b.resize(n, 0);
            b
        };
        [vec![0xA3, 0x95, FMT, kind, len], field(name, 4), field(format, 16), field(labels, 64)].concat()
    }

    fn record(kind: u8, fields: &[i32]) -> Vec<u8> {
        [vec![0xA3, 0x95, kind], fields.iter().flat_map(|v| v.to_le_bytes()).collect()].concat()
    }

    fn log(points: usize) -> Vec<u8> {
        let mut bytes = [fmt(10, 11, "POS", "LL", "Lat,Lng"), fmt(11, 11, "CAM", "LL", "Lat,Lng"), fmt(12, 67, "MSG", "Z", "Message")].concat();
        bytes.extend([vec![0xA3, 0x95, 12], b"ArduPlane V4.6.0".to_vec(), vec![0; 48]].concat());
        for k in 0..points {
            let (lat, lng) = (473_000_000 + k as i32 * 100, 85_000_000);
            bytes.extend(record(10, &[lat, lng]));
            if k % 5 == 0 {
                bytes.extend(record(11, &[lat, lng]));
            }
        }
        bytes
    }

    #[test]
    fn positions_photos_and_the_firmware_are_read_and_a_cut_log_is_refused() {
        let bytes = log(20);
        let read = super::super::read(&bytes).unwrap();
        assert_eq!(read.format, LogFormat::Dataflash);
        assert_eq!(read.vehicle, Some(VehicleKind::FixedWing));
        // 1.1 m apart: every position is kept
        assert_eq!(read.flown.track.len(), 20);
        assert_eq!(read.flown.photos.len(), 4);
        assert!((read.flown.track[3][1] - 47.30003).abs() < 1e-9 && (read.flown.track[3][0] - 8.5).abs() < 1e-9);
        let cut = super::super::read(&bytes[..bytes.len() - 4]).unwrap_err();
        assert_eq!(cut.code, "log_unreadable", "{cut}");
        assert!(cut.to_string().contains("cut short"), "{cut}");
        let none = super::super::read(&log(0)).unwrap_err();
        assert_eq!(none.code, "log_without_position");
    }
}
