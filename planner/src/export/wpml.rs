//! DJI WPML: a KMZ holding `wpmz/template.kml` and `wpmz/waylines.wpml`, the waypoint route
//! that DJI Pilot 2 opens: heights relative to the take-off point, a speed per waypoint, and on
//! each sweep the plan's photos (an action group taking one every step of the line, from a
//! waypoint at its first photo to one half a step past its last).
//! Written with quick-xml: no crate writes WPML.

use super::flight::{CameraPose, Waypoint, photos_by_pass, waypoints};
use super::mission_items::{Triggers, line_triggers};
use super::xml::Xml;
use super::{Bases, COVERAGE_ONLY, ExportJob, Exporter, Format, number};
use crate::archive;
use crate::error::InputError;
use crate::path::PieceKind;
use crate::vehicle::VehicleKind;

pub struct Wpml;

const NAMESPACE: &str = "http://www.dji.com/wpmz/1.0.6";
/// Mavic 3 Enterprise and its wide camera (DJI's `droneEnumValue` 77, `payloadEnumValue` 66).
const DRONE: (&str, &str) = ("77", "0");
const PAYLOAD: &str = "66";
/// Waypoints DJI's RC 2 controller loads: DJI Fly crashes on a route of more than 99
/// (YLabs-FPV/YMapper issue 8); the RC 2 shows "a hundred-and-some-odd" before it freezes
/// (hotosm/drone-flightplan pull request 19). DJI Pilot 2 on an enterprise controller takes up
/// to 65 535: give `max_waypoints` for it.
pub const DJI_RC2_WAYPOINTS: usize = 99;
/// DJI's speed range for waypoint routes, m/s.
const SPEED_RANGE: (f64, f64) = (1.0, 15.0);

impl Exporter for Wpml {
    fn format(&self) -> &'static Format {
        &Format {
            id: "wpml",
            label: "DJI Pilot 2 (WPML .kmz)",
            media_type: "application/vnd.google-earth.kmz",
            extension: ".kmz",
            one_flight_per_file: true,
            firmware_commands: false,
            plans: COVERAGE_ONLY,
            verbatim: false,
            waypoint_limit: true,
            default_max_waypoints: Some(DJI_RC2_WAYPOINTS),
        }
    }

    fn write(&self, job: &ExportJob<'_>, sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        multirotor_only(job)?;
        let planned = route(job, sortie, false);
        let Some(max) = job.max_waypoints.filter(|&max| planned.points.len() > max) else { return Ok(vec![kmz(job, sortie, &planned, 0..planned.points.len(), true)]) };
        // lines as their two ends; then missions, each beginning where the last ended
        let route = route(job, sortie, true);
        let parts = missions(&route, max)?;
        let count = parts.len();
        Ok(parts.into_iter().enumerate().map(|(j, range)| kmz(job, sortie, &route, range, j + 1 == count)).collect())
    }
}

fn multirotor_only(job: &ExportJob<'_>) -> Result<(), InputError> {
    if job.settings.kind != VehicleKind::Multirotor {
        return Err(InputError::new("format_not_applicable", "format", "DJI WPML routes are flown by DJI multirotors; export a fixed-wing plan as `plan` or `waypoints`"));
    }
    Ok(())
}

/// The waypoints DJI flies, and the photo groups along them: first and last waypoint, step.
struct Route {
    points: Vec<Waypoint>,
    triggers: Vec<(usize, usize, f64)>,
}

/// On a straight sweep the camera runs from the plan's first photo to half a step past its
/// last (waypoints added there), at the line's own step; `compact`: from the line's start to
/// its end, no waypoint added.
fn route(job: &ExportJob<'_>, sortie: usize, compact: bool) -> Route {
    let pieces = &job.flight.sorties[sortie];
    let photos = photos_by_pass(&job.flight.photos);
    let mut points = Vec::new();
    let mut triggers: Vec<(usize, usize, f64)> = Vec::new();
    for w in waypoints(pieces, None) {
        let piece = &pieces[w.piece];
        if let (Some(distance), true) = (job.settings.trigger_distance_m, piece.kind == PieceKind::Sweep && w.index == 1) {
            let from = points.len().saturating_sub(1);
            match line_triggers(piece, w.piece, photos.get(&piece.camera.map(|c| c.pass)), None) {
                Triggers::Line(line) if compact => triggers.push((from, points.len(), line.step_m)),
                Triggers::Line(line) => {
                    let start = line.start.map_or(from, |p| {
                        points.push(p);
                        points.len() - 1
                    });
                    let stop = line.stop.map_or(points.len(), |p| {
                        points.push(p);
                        points.len() - 1
                    });
                    triggers.push((start, stop, line.step_m));
                }
                Triggers::None => {}
                Triggers::Bent => triggers.push((from, points.len(), distance)),
            }
        }
        points.push(w);
    }
    Route { points, triggers }
}

/// The route cut into missions of at most `max` waypoints, each beginning at the waypoint the
/// last ended at, never within a photo group.
fn missions(route: &Route, max: usize) -> Result<Vec<std::ops::Range<usize>>, InputError> {
    let n = route.points.len();
    let inside_group = |k: usize| route.triggers.iter().any(|&(start, stop, _)| start < k && k < stop);
    let mut parts = Vec::new();
    let mut from = 0;
    while n - from > max {
        let Some(last) = (from + 1..from + max).rev().find(|&k| !inside_group(k)) else {
            return Err(InputError::new("max_waypoints_too_few", "/max_waypoints", format!("a line's photos take more than {max} waypoints: give a larger max_waypoints")));
        };
        parts.push(from..last + 1);
        from = last;
    }
    parts.push(from..n);
    Ok(parts)
}

/// The KMZ of the waypoints `range` of `route`; `last`: the sortie's last mission, which goes
/// home (the others hold where they end, for the next).
fn kmz(job: &ExportJob<'_>, sortie: usize, route: &Route, range: std::ops::Range<usize>, last: bool) -> Vec<u8> {
    let template = document(job, sortie, route, range.clone(), last, false);
    let waylines = document(job, sortie, route, range, last, true);
    archive::zip(&[("wpmz/template.kml".to_owned(), template), ("wpmz/waylines.wpml".to_owned(), waylines)])
}

/// `template.kml` (`executable` false) or `waylines.wpml` (true): the same route, in the two
/// vocabularies DJI uses for them.
fn document(job: &ExportJob<'_>, sortie: usize, route: &Route, range: std::ops::Range<usize>, last: bool, executable: bool) -> Vec<u8> {
    let s = &job.settings;
    let pieces = &job.flight.sorties[sortie];
    let points = &route.points;
    // over terrain the heights are above mean sea level: DJI's are relative to the take-off
    // point (its WGS84 mode is ellipsoidal, not sea level), so the launch ground comes off
    let launch_ground = job.flight.launch_ground_m(sortie).unwrap_or(0.0);
    let speed = |k: usize| pieces[points[k].piece].speed_mps.clamp(SPEED_RANGE.0, SPEED_RANGE.1);
    let cruise = number(s.cruise_speed_mps.clamp(SPEED_RANGE.0, SPEED_RANGE.1), 2);
    let mut x = Xml::new();
    x.open("kml", &[("xmlns", "http://www.opengis.net/kml/2.2"), ("xmlns:wpml", NAMESPACE)]).open("Document", &[]);
    if !executable {
        x.leaf("wpml:author", "coverplan");
    }
    x.open("wpml:missionConfig", &[])
        .leaf("wpml:flyToWaylineMode", "safely")
        .leaf(
            "wpml:finishAction",
            match job.bases(sortie) {
                _ if !last => "noAction",
                // DJI's return flies back to where it took off: at another site it lands itself
                Bases { home: Some(_), lands_at: None } => "goHome",
                _ => "autoLand",
            },
        )
        .leaf("wpml:exitOnRCLost", "executeLostAction")
        .leaf("wpml:executeRCLostAction", "goBack")
        .leaf("wpml:takeOffSecurityHeight", &number(s.altitude_m.clamp(1.2, 1500.0), 2))
        .leaf("wpml:globalTransitionalSpeed", &cruise);
    x.open("wpml:droneInfo", &[]).leaf("wpml:droneEnumValue", DRONE.0).leaf("wpml:droneSubEnumValue", DRONE.1).close("wpml:droneInfo");
    x.open("wpml:payloadInfo", &[]).leaf("wpml:payloadEnumValue", PAYLOAD).leaf("wpml:payloadPositionIndex", "0").close("wpml:payloadInfo");
    x.close("wpml:missionConfig");
    x.open("Folder", &[]);
    if executable {
        x.leaf("wpml:templateId", "0").leaf("wpml:executeHeightMode", "relativeToStartPoint").leaf("wpml:waylineId", "0").leaf("wpml:autoFlightSpeed", &cruise);
    } else {
        x.leaf("wpml:templateType", "waypoint").leaf("wpml:templateId", "0");
        x.open("wpml:waylineCoordinateSysParam", &[]).leaf("wpml:coordinateMode", "WGS84").leaf("wpml:heightMode", "relativeToStartPoint").close("wpml:waylineCoordinateSysParam");
        x.leaf("wpml:autoFlightSpeed", &cruise).leaf("wpml:globalHeight", &number(s.altitude_m, 2)).leaf("wpml:caliFlightEnable", "0").leaf("wpml:gimbalPitchMode", "manual");
        x.open("wpml:globalWaypointHeadingParam", &[]).leaf("wpml:waypointHeadingMode", "followWayline").close("wpml:globalWaypointHeadingParam");
        x.leaf("wpml:globalWaypointTurnMode", "toPointAndStopWithDiscontinuityCurvature").leaf("wpml:globalUseStraightLine", "1");
    }
    // an oblique plan's passes: the camera of the leg leaving each waypoint (or of the one
    // reaching it, at the last)
    let camera = |k: usize| pieces[points[k.min(points.len() - 1)].piece].camera;
    let leaving = |k: usize| if k + 1 < points.len() { camera(k + 1) } else { camera(k) };
    let mut group = 0;
    let first = range.start;
    for (k, w) in points.iter().enumerate().take(range.end).skip(first) {
        let [lon, lat, altitude] = w.position;
        let altitude = altitude - launch_ground;
        x.open("Placemark", &[]).open("Point", &[]).leaf("coordinates", &format!("{},{}", number(lon, 8), number(lat, 8))).close("Point");
        x.leaf("wpml:index", &(k - first).to_string());
        let facing = leaving(k).and_then(|c| c.heading_deg);
        if executable {
            x.leaf("wpml:executeHeight", &number(altitude, 2)).leaf("wpml:waypointSpeed", &number(speed(k), 2));
            heading_param(&mut x, facing);
            x.open("wpml:waypointTurnParam", &[])
                .leaf("wpml:waypointTurnMode", "toPointAndStopWithDiscontinuityCurvature")
                .leaf("wpml:waypointTurnDampingDist", "0")
                .close("wpml:waypointTurnParam");
        } else {
            x.leaf("wpml:height", &number(altitude, 2)).leaf("wpml:useGlobalHeight", "0").leaf("wpml:waypointSpeed", &number(speed(k), 2)).leaf("wpml:useGlobalSpeed", "0");
            match facing {
                None => x.leaf("wpml:useGlobalHeadingParam", "1"),
                Some(_) => heading_param(x.leaf("wpml:useGlobalHeadingParam", "0"), facing),
            };
            x.leaf("wpml:useGlobalTurnParam", "1");
        }
        x.leaf("wpml:useStraightLine", "1");
        // a pass begins on the leg leaving this waypoint: turn the vehicle and pitch the gimbal
        // (and where a mission begins within a pass)
        if let Some(pose) = leaving(k).filter(|c| k == first || camera(k).map(|c| c.pass) != Some(c.pass)) {
            // the vehicle faces the pass before's heading, or the way it came
            let facing_before = camera(k).and_then(|c| c.heading_deg).or_else(|| (k > 0).then(|| bearing(points[k - 1].position, w.position)));
            pose_group(&mut x, group, k - first, pose, facing_before);
            group += 1;
        }
        // a group beginning at a mission's last waypoint is the next mission's
        for &(start, stop, step) in route.triggers.iter().filter(|t| t.0 == k && t.1 < range.end) {
            photo_group(&mut x, group, start - first, stop - first, step);
            group += 1;
        }
        x.close("Placemark");
    }
    x.close("Folder").close("Document").close("kml");
    x.finish()
}

/// How the vehicle's heading is flown to this waypoint: along the route, or held at
/// `facing_deg` (a compass bearing).
fn heading_param(x: &mut Xml, facing_deg: Option<f64>) -> &mut Xml {
    x.open("wpml:waypointHeadingParam", &[]);
    match facing_deg {
        None => x.leaf("wpml:waypointHeadingMode", "followWayline"),
        Some(bearing) => x
            .leaf("wpml:waypointHeadingMode", "smoothTransition")
            .leaf("wpml:waypointHeadingAngle", &number(signed_degrees(bearing), 2))
            .leaf("wpml:waypointHeadingAngleEnable", "1")
            .leaf("wpml:waypointHeadingPathMode", "followBadArc"),
    };
    x.close("wpml:waypointHeadingParam")
}

/// A bearing as DJI says headings: −180 to 180, 0 north.
fn signed_degrees(bearing: f64) -> f64 {
    (bearing + 180.0).rem_euclid(360.0) - 180.0
}

/// Compass bearing from `a` to `b` (`[lon, lat, …]`).
fn bearing(a: [f64; 3], b: [f64; 3]) -> f64 {
    let east = (b[0] - a[0]) * a[1].to_radians().cos();
    east.atan2(b[1] - a[1]).to_degrees().rem_euclid(360.0)
}

/// At waypoint `at`, where a pass of an oblique plan begins: the vehicle turned to the pass's
/// heading (the shorter way from `facing_before`) and the gimbal pitched.
fn pose_group(x: &mut Xml, id: usize, at: usize, pose: CameraPose, facing_before: Option<f64>) {
    x.open("wpml:actionGroup", &[])
        .leaf("wpml:actionGroupId", &id.to_string())
        .leaf("wpml:actionGroupStartIndex", &at.to_string())
        .leaf("wpml:actionGroupEndIndex", &at.to_string())
        .leaf("wpml:actionGroupMode", "sequence");
    x.open("wpml:actionTrigger", &[]).leaf("wpml:actionTriggerType", "reachPoint").close("wpml:actionTrigger");
    let mut action = 0;
    if let Some(bearing) = pose.heading_deg {
        x.open("wpml:action", &[]).leaf("wpml:actionId", &action.to_string()).leaf("wpml:actionActuatorFunc", "rotateYaw");
        let clockwise = facing_before.is_none_or(|from| signed_degrees(bearing - from) >= 0.0);
        x.open("wpml:actionActuatorFuncParam", &[])
            .leaf("wpml:aircraftHeading", &number(signed_degrees(bearing), 2))
            .leaf("wpml:aircraftPathMode", if clockwise { "clockwise" } else { "counterClockwise" });
        x.close("wpml:actionActuatorFuncParam").close("wpml:action");
        action += 1;
    }
    x.open("wpml:action", &[]).leaf("wpml:actionId", &action.to_string()).leaf("wpml:actionActuatorFunc", "gimbalRotate");
    x.open("wpml:actionActuatorFuncParam", &[])
        .leaf("wpml:gimbalHeadingYawBase", "aircraft")
        .leaf("wpml:gimbalRotateMode", "absoluteAngle")
        .leaf("wpml:gimbalPitchRotateEnable", "1")
        .leaf("wpml:gimbalPitchRotateAngle", &number(pose.gimbal_pitch_deg, 2))
        .leaf("wpml:gimbalRollRotateEnable", "0")
        .leaf("wpml:gimbalRollRotateAngle", "0")
        .leaf("wpml:gimbalYawRotateEnable", "0")
        .leaf("wpml:gimbalYawRotateAngle", "0")
        .leaf("wpml:gimbalRotateTimeEnable", "0")
        .leaf("wpml:gimbalRotateTime", "0")
        .leaf("wpml:payloadPositionIndex", "0");
    x.close("wpml:actionActuatorFuncParam").close("wpml:action").close("wpml:actionGroup");
}

/// Photos every `distance` metres from waypoint `start` to waypoint `stop`.
fn photo_group(x: &mut Xml, id: usize, start: usize, stop: usize, distance: f64) {
    x.open("wpml:actionGroup", &[])
        .leaf("wpml:actionGroupId", &id.to_string())
        .leaf("wpml:actionGroupStartIndex", &start.to_string())
        .leaf("wpml:actionGroupEndIndex", &stop.to_string())
        .leaf("wpml:actionGroupMode", "sequence");
    x.open("wpml:actionTrigger", &[]).leaf("wpml:actionTriggerType", "multipleDistance").leaf("wpml:actionTriggerParam", &number(distance, 2)).close("wpml:actionTrigger");
    x.open("wpml:action", &[]).leaf("wpml:actionId", "0").leaf("wpml:actionActuatorFunc", "takePhoto");
    x.open("wpml:actionActuatorFuncParam", &[]).leaf("wpml:payloadPositionIndex", "0").close("wpml:actionActuatorFuncParam");
    x.close("wpml:action").close("wpml:actionGroup");
}
