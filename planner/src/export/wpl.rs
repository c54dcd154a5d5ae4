//! The MAVLink `QGC WPL 110` text file that Mission Planner and ArduPilot load (docs/methods.md,
//! interop §4): tab-separated items, item 0 the home position, latitude in column 9 and longitude
//! in column 10. Written by hand: a dozen lines, and no crate writes it.

use std::fmt::Write;

use super::mission_items::{self, launch};
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
        }
    }

    fn write(&self, job: &ExportJob<'_>, sortie: usize) -> Result<Vec<u8>, InputError> {
        let pieces = &job.flight.sorties[sortie];
        let items = mission_items::mission_items(pieces, &job.flight.views, &job.flight.photos, &job.settings, job.outlines.home);
        let [lon, lat] = launch(pieces, job.outlines.home);
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
        Ok(text.into_bytes())
    }
}
