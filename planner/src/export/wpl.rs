//! The MAVLink `QGC WPL 110` text file that Mission Planner and ArduPilot load (docs/methods.md,
//! interop §4): tab-separated items, item 0 the home position, latitude in column 9 and longitude
//! in column 10. Written by hand: a dozen lines, and no crate writes it.

use std::fmt::Write;

use super::mission_items::{self, MissionItem, launch};
use super::{ALL_METHODS, ExportJob, Exporter, Format, number};
use crate::error::InputError;

pub struct WaypointList;

impl Exporter for WaypointList {
    fn format(&self) -> &'static Format {
        &Format {
            id: "waypoints",
            label: "Mission Planner / ArduPilot (.waypoints)",
            media_type: "text/plain; charset=utf-8",
            extension: ".waypoints",
            one_flight_per_file: true,
            firmware_commands: true,
            plans: ALL_METHODS,
            verbatim: false,
            waypoint_limit: true,
            default_max_waypoints: None,
        }
    }

    fn write(&self, job: &ExportJob<'_>, sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(mission_items::limited_items(job, sortie)?.iter().map(|items| file(job, sortie, items)).collect())
    }
}

/// The `QGC WPL 110` text of `items`, flown in `sortie`.
fn file(job: &ExportJob<'_>, sortie: usize, items: &[MissionItem]) -> Vec<u8> {
    let [lon, lat] = launch(&job.flight.sorties[sortie], job.bases(sortie).home);
    let mut text = String::from("QGC WPL 110\n");
    // item 0: home, absolute frame (over terrain at the ground's height), current
    let home_altitude = job.flight.launch_ground_m(sortie).unwrap_or(0.0);
    writeln!(text, "0\t1\t0\t16\t0\t0\t0\t0\t{}\t{}\t{}\t1", number(lat, 8), number(lon, 8), number(home_altitude, 2)).expect("write to String");
    for (k, item) in items.iter().enumerate() {
        let [lat, lon, alt] = item.position.unwrap_or([0.0; 3]);
        let params: Vec<String> = item.params.iter().map(|p| p.map_or("nan".to_owned(), |v| number(v, 6))).collect();
        writeln!(text, "{}\t0\t{}\t{}\t{}\t{}\t{}\t{}\t1", k + 1, item.frame, item.command, params.join("\t"), number(lat, 8), number(lon, 8), number(alt, 2))
            .expect("write to String");
    }
    text.into_bytes()
}

/// The mission items of a `QGC WPL 110` file, its home (item 0) left out: what an autopilot
/// loads from it, for the follower (`export::follower`) and for checks of written files.
pub fn read(text: &str) -> Result<Vec<MissionItem>, InputError> {
    let mut lines = text.lines();
    if lines.next().map(str::trim) != Some("QGC WPL 110") {
        return Err(InputError::new("invalid_waypoints", "/", "a waypoint file starts with `QGC WPL 110`"));
    }
    lines
        .enumerate()
        .filter(|(_, line)| !line.trim().is_empty())
        .skip(1)
        .map(|(k, line)| {
            let at = format!("/lines/{}", k + 1);
            let columns: Vec<&str> = line.split('\t').collect();
            if columns.len() != 12 {
                return Err(InputError::new("invalid_waypoints", at, format!("{} columns where an item has 12", columns.len())));
            }
            let integer =
                |c: usize| columns[c].trim().parse::<u16>().map_err(|_| InputError::new("invalid_waypoints", at.clone(), format!("column {} is not a whole number", c + 1)));
            let number = |c: usize| columns[c].trim().parse::<f64>().ok().filter(|v| v.is_finite());
            let frame = integer(2)? as u8;
            let position = (frame != mission_items::FRAME_MISSION).then(|| [number(8).unwrap_or(0.0), number(9).unwrap_or(0.0), number(10).unwrap_or(0.0)]);
            Ok(MissionItem { command: integer(3)?, frame, params: [number(4), number(5), number(6), number(7)], position })
        })
        .collect()
}
