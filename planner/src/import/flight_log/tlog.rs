//! MAVLink telemetry logs (`.tlog`), as ground stations write them: each message as it came
//! over the link, after the time it came (8 bytes, big-endian microseconds). The records are
//! cut here (that container is not MAVLink's); each message is checked and decoded by the
//! `mavlink` crate (ArduPilot's dialect, a superset of the common one).

use mavlink::MavlinkReader;
use mavlink::dialects::ardupilotmega::{MavAutopilot, MavMessage, MavType};

use super::{FlightLog, Gathered, LogFormat, unreadable};
use crate::error::InputError;
use crate::vehicle::VehicleKind;

const V1: u8 = 0xFE;
const V2: u8 = 0xFD;
const TIME_BYTES: usize = 8;

/// A tlog starts with a time and a MAVLink frame.
pub(super) fn is_tlog(bytes: &[u8]) -> bool {
    matches!(bytes.get(TIME_BYTES), Some(&V1 | &V2))
}

/// The length of the frame at the start of `frame`, header and checksum (and signature)
/// included; `None` where it is not a frame's start.
fn frame_len(frame: &[u8]) -> Option<usize> {
    match (frame.first()?, frame.get(1)) {
        (&V1, Some(&len)) => Some(8 + len as usize),
        (&V2, Some(&len)) => {
            let signed = frame.get(2)? & 0x01 != 0;
            Some(12 + len as usize + if signed { 13 } else { 0 })
        }
        _ => None,
    }
}

fn kind(mavtype: MavType) -> Option<VehicleKind> {
    use MavType::*;
    match mavtype {
        MAV_TYPE_FIXED_WING => Some(VehicleKind::FixedWing),
        MAV_TYPE_QUADROTOR | MAV_TYPE_HEXAROTOR | MAV_TYPE_OCTOROTOR | MAV_TYPE_TRICOPTER | MAV_TYPE_COAXIAL | MAV_TYPE_HELICOPTER | MAV_TYPE_DODECAROTOR | MAV_TYPE_DECAROTOR => {
            Some(VehicleKind::Multirotor)
        }
        MAV_TYPE_GROUND_ROVER => Some(VehicleKind::Ground),
        _ => None,
    }
}

/// Whether the autopilot's mode is its mission (ArduPilot's AUTO, PX4's AUTO MISSION); `None`
/// for an autopilot whose modes are not read here.
fn flies_mission(autopilot: MavAutopilot, mavtype: MavType, custom_mode: u32) -> Option<bool> {
    match autopilot {
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA => Some(custom_mode == if kind(mavtype) == Some(VehicleKind::Multirotor) { 3 } else { 10 }),
        // main mode AUTO (4), sub mode MISSION (4)
        MavAutopilot::MAV_AUTOPILOT_PX4 => Some((custom_mode >> 16) & 0xff == 4 && custom_mode >> 24 == 4),
        _ => None,
    }
}

pub(super) fn read(bytes: &[u8]) -> Result<FlightLog, InputError> {
    let mut gathered = Gathered::default();
    // the first autopilot heard is the vehicle; other systems on the link are left out
    let mut vehicle_system = None;
    let (mut at, mut decoded) = (0, 0usize);
    while at < bytes.len() {
        let frame = &bytes[(at + TIME_BYTES).min(bytes.len())..];
        let Some(len) = frame_len(frame) else {
            if frame.is_empty() || frame.len() < 3 {
                return Err(unreadable(format!("the log ends inside a record at byte {at} of {}: it was cut short", bytes.len())));
            }
            return Err(unreadable(format!("no MAVLink message starts at byte {} (a damaged log, or not a telemetry log)", at + TIME_BYTES)));
        };
        if frame.len() < len {
            return Err(unreadable(format!("the log ends inside a message at byte {at} of {}: it was cut short", bytes.len())));
        }
        at += TIME_BYTES + len;
        // a message the dialect does not know, or one damaged on the link, is skipped
        let Ok((header, message)) = MavlinkReader::new(&frame[..len]).read_any_message::<MavMessage>() else { continue };
        decoded += 1;
        match message {
            MavMessage::HEARTBEAT(h) if h.autopilot != MavAutopilot::MAV_AUTOPILOT_INVALID => {
                if vehicle_system.is_none() {
                    vehicle_system = Some(header.system_id);
                }
                if vehicle_system == Some(header.system_id) {
                    gathered.vehicle = gathered.vehicle.or(kind(h.mavtype));
                    if let Some(flying) = flies_mission(h.autopilot, h.mavtype, h.custom_mode) {
                        gathered.mission(flying);
                    }
                }
            }
            _ if vehicle_system.is_some_and(|s| s != header.system_id) => {}
            MavMessage::GLOBAL_POSITION_INT(p) => gathered.position(p.lon as f64 / 1e7, p.lat as f64 / 1e7),
            MavMessage::CAMERA_FEEDBACK(c) => gathered.photo(Some((c.lng as f64 / 1e7, c.lat as f64 / 1e7))),
            MavMessage::CAMERA_TRIGGER(_) => gathered.photo(None),
            MavMessage::SYS_STATUS(s) => gathered.battery(s.battery_remaining as f64 / 100.0),
            _ => {}
        }
    }
    if decoded == 0 {
        return Err(unreadable("the log holds no MAVLink message this server reads"));
    }
    gathered.finish(LogFormat::Tlog)
}
