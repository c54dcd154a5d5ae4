//! PX4 logs (`.ulg`), read with the `yule_log` crate: the log describes its own topics.
//! Positions come from `vehicle_global_position`, photos from `camera_capture` (with their
//! place) or `camera_trigger` (at the last position), the battery from `battery_status`, the
//! vehicle and whether it flies its mission from `vehicle_status`.

use std::io::Cursor;

use yule_log::builder::ULogParserBuilder;
use yule_log::model::inst::{FieldValue, Format};
use yule_log::model::msg::UlogMessage;

use super::{FlightLog, Gathered, LogFormat, unreadable};
use crate::error::InputError;
use crate::vehicle::VehicleKind;

const MAGIC: [u8; 7] = [0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35];
/// `vehicle_status.nav_state` while the mission is flown.
const AUTO_MISSION: f64 = 3.0;
const TOPICS: [&str; 5] = ["vehicle_global_position", "camera_capture", "camera_trigger", "battery_status", "vehicle_status"];

pub(super) fn is_ulog(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

/// A scalar field of a logged message, as f64.
fn number(data: &Format, name: &str) -> Option<f64> {
    let field = data.fields.iter().find(|f| &*f.name == name)?;
    Some(match field.value {
        FieldValue::ScalarU8(v) => v as f64,
        FieldValue::ScalarU16(v) => v as f64,
        FieldValue::ScalarU32(v) => v as f64,
        FieldValue::ScalarU64(v) => v as f64,
        FieldValue::ScalarI8(v) => v as f64,
        FieldValue::ScalarI16(v) => v as f64,
        FieldValue::ScalarI32(v) => v as f64,
        FieldValue::ScalarI64(v) => v as f64,
        FieldValue::ScalarF32(v) => v as f64,
        FieldValue::ScalarF64(v) => v,
        FieldValue::ScalarBool(v) => v as u8 as f64,
        _ => return None,
    })
}

/// PX4's `vehicle_status.vehicle_type`.
fn kind(vehicle_type: f64, is_vtol: bool) -> Option<VehicleKind> {
    match vehicle_type as u8 {
        _ if is_vtol => None,
        1 => Some(VehicleKind::Multirotor),
        2 => Some(VehicleKind::FixedWing),
        3 => Some(VehicleKind::Ground),
        _ => None,
    }
}

pub(super) fn read(bytes: &[u8]) -> Result<FlightLog, InputError> {
    let parser =
        ULogParserBuilder::new(Cursor::new(bytes)).set_subscription_allow_list(TOPICS).build().map_err(|e| unreadable(format!("the PX4 log's header is not readable: {e}")))?;
    let mut gathered = Gathered::default();
    for (read, message) in parser.enumerate() {
        let message = message.map_err(|e| unreadable(format!("the PX4 log is damaged or cut short after {read} messages: {e}")))?;
        let UlogMessage::LoggedData(logged) = message else { continue };
        let data = &logged.data;
        match &*data.name {
            "vehicle_global_position" => {
                if let (Some(lon), Some(lat)) = (number(data, "lon"), number(data, "lat")) {
                    gathered.position(lon, lat);
                }
            }
            "camera_capture" => gathered.photo(number(data, "lon").zip(number(data, "lat"))),
            "camera_trigger" => gathered.photo(None),
            "battery_status" => {
                if let Some(r) = number(data, "remaining") {
                    gathered.battery(r);
                }
            }
            "vehicle_status" => {
                if gathered.vehicle.is_none() {
                    gathered.vehicle = number(data, "vehicle_type").and_then(|t| kind(t, number(data, "is_vtol").is_some_and(|v| v != 0.0)));
                }
                if let Some(state) = number(data, "nav_state") {
                    gathered.mission(state == AUTO_MISSION);
                }
            }
            _ => {}
        }
    }
    gathered.finish(LogFormat::Ulog)
}
