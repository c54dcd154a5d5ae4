//! Flight files as an autopilot flies them: the kinematic follower (`export::follower`) flown
//! over the waypoint files of the random fields, for a fixed wing and a multirotor, both
//! firmwares: lines entered settled, turns where the plan turns, no turn back after take-off,
//! the landing sequence, photos and durations as the plan says.

use coverplan_planner::archive;
use coverplan_planner::export::follower::{self, Flown, FollowerSpec};
use coverplan_planner::export::{self, AltitudeFrame, ExportOptions, ExportRequest, Firmware};
use coverplan_planner::frame::LocalFrame;
use coverplan_planner::path::PieceKind;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop, plan};
use geo::Coord;
use serde_json::{Value, json};

fn fixture(path: &str) -> Value {
    serde_json::from_slice(&std::fs::read(format!("{}/../tests/fixtures/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()).unwrap()
}

/// A rectangle `width × height` metres with its south-west corner at the frame's origin, and
/// a home `home_back` metres south-west of that corner.
fn rectangle(frame: &LocalFrame, width: f64, height: f64, home_back: f64) -> (Value, [f64; 2]) {
    let corners = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height), (0.0, 0.0)];
    let ring: Vec<[f64; 2]> = corners.iter().map(|&(x, y)| frame.to_wgs84(Coord { x, y })).collect();
    (json!({"type": "Polygon", "coordinates": [ring]}), frame.to_wgs84(Coord { x: -home_back, y: -home_back }))
}

/// One sortie: the plan's pieces `(kind, points in the follower's frame)` and what the follower
/// flew from its file.
struct Sortie {
    pieces: Vec<(PieceKind, Vec<Coord>)>,
    flown: Flown,
}

struct Case {
    output: PlanOutput,
    /// The plan's photos, `[lon, lat]`.
    photos: Vec<[f64; 2]>,
    sorties: Vec<Sortie>,
    /// The vehicle's lead-in, metres.
    lead_in_m: f64,
    /// The no-fly zones in WGS84.
    zones: Option<geo::MultiPolygon>,
}

fn fly_case(area: &Value, home: [f64; 2], params: Value, firmware: Firmware) -> Case {
    fly_case_with_zones(area, None, home, params, firmware)
}

fn fly_case_with_zones(area: &Value, zones: Option<&Value>, home: [f64; 2], params: Value, firmware: Firmware) -> Case {
    let params: PlanParams = serde_json::from_value(params).unwrap();
    let profiles = builtin_profiles();
    let mission = MissionGeometry { home: Some(home), no_fly_zones: zones, ..MissionGeometry::area(area) };
    let output =
        plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).unwrap_or_else(|e| panic!("{e} ({:?} at {home:?})", params.vehicle.profile));
    let request = ExportRequest {
        name: "flown",
        mission: mission.clone(),
        params: &params,
        profiles: &profiles,
        trajectory: &output.trajectory,
        options: ExportOptions { firmware, altitude_frame: AltitudeFrame::Amsl, altitude_m: None, max_waypoints: None },
    };
    let file = export::export("waypoints", &request).unwrap();
    let files = if archive::is_zip(&file.bytes) { archive::unzip(&file.bytes).unwrap().into_iter().map(|f| f.1).collect() } else { vec![file.bytes] };
    let vehicle = params.resolve(&profiles).unwrap().vehicle;
    let (climb_mps, descent_mps) = vehicle.vertical_rates_mps();
    let spec = FollowerSpec {
        kind: vehicle.kind,
        firmware,
        cruise_speed_mps: vehicle.cruise_speed_mps,
        turn_radius_m: vehicle.turn_radius_m,
        acceleration_mps2: vehicle.acceleration_mps2,
        climb_mps,
        descent_mps,
    };
    let zones = zones.map(|z| serde_json::from_value::<geojson::Geometry>(z.clone()).unwrap());
    let zones: Option<geo::MultiPolygon> = zones.map(|g| geo::MultiPolygon::try_from(g).unwrap());
    // the plan as the exporters read it: its sorties' pieces and its photos
    let planned = export::Flight::from_trajectory(&output.trajectory, 0.0).unwrap();
    let sorties = files
        .iter()
        .zip(&planned.sorties)
        .map(|(bytes, pieces)| {
            let items = export::wpl::read(std::str::from_utf8(bytes).unwrap()).unwrap();
            let flown = follower::fly(&items, &spec);
            let pieces = pieces.iter().map(|p| (p.kind, p.points.iter().map(|q| flown.frame.to_local(q[0], q[1])).collect())).collect();
            Sortie { pieces, flown }
        })
        .collect();
    let lead_in_m = vehicle.lead_in_m(params.lead_in_m);
    Case { photos: planned.photos.iter().map(|p| p.at).collect(), output, sorties, lead_in_m, zones }
}

fn distance_to_polyline(p: Coord, line: &[Coord]) -> f64 {
    line.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let len2 = d.x * d.x + d.y * d.y;
            let t = if len2 > 0.0 { (((p - w[0]).x * d.x + (p - w[0]).y * d.y) / len2).clamp(0.0, 1.0) } else { 0.0 };
            let q = w[0] + d * t;
            (p - q).x.hypot((p - q).y)
        })
        .fold(f64::INFINITY, f64::min)
}

fn percentile(mut v: Vec<f64>, q: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// What the follower's flight shows against the plan.
#[derive(Debug, Default)]
struct Figures {
    /// Per line entered over its whole lead-in: how near its start the follower passes.
    line_start_off_m: Vec<f64>,
    /// Lines entered with a shorter lead-in (blocked by a no-fly zone).
    lines_without_lead_in: usize,
    /// Off the lines while flying them: 95th percentile.
    sweep_off_p95_m: f64,
    /// Off the planned path after the take-off climb: 95th percentile and worst.
    path_off_p95_m: f64,
    path_off_max_m: f64,
    /// Per sortie: the follower's duration over the plan's; and over all sorties.
    duration_ratio: Vec<f64>,
    total_duration_ratio: f64,
    /// Photos taken and planned, and the most they differ by on one line.
    photos: (usize, usize),
    photos_off_per_line: usize,
    landed: usize,
    /// Sorties whose first waypoint lay behind the aircraft once it had climbed.
    turned_back: usize,
    /// Track samples inside a no-fly zone.
    zone_intrusions: usize,
}

/// On the straight `line`: the sample's distance from it and how far along it, when the
/// sample (the step `from → to`) lies beside it and flies its way.
fn beside(line: &[Coord], from: Coord, to: Coord) -> Option<(f64, f64)> {
    let (a, b) = (line[0], line[line.len() - 1]);
    let len = (b - a).x.hypot((b - a).y);
    let unit = (b - a) / len;
    let along = (to - a).x * unit.x + (to - a).y * unit.y;
    let across = ((to - a).x * unit.y - (to - a).y * unit.x).abs();
    let step = to - from;
    let aligned = step.x * unit.x + step.y * unit.y > 0.94 * step.x.hypot(step.y);
    ((0.0..=len).contains(&along) && aligned).then_some((across, along))
}

fn figures(case: &Case) -> Figures {
    let mut f = Figures::default();
    let (mut sweep_off, mut path_off) = (Vec::new(), Vec::new());
    let mut totals = (0.0, 0.0);
    for (k, Sortie { pieces, flown }) in case.sorties.iter().enumerate() {
        let path: Vec<Coord> = pieces.iter().flat_map(|p| p.1.iter().copied()).collect();
        let sweeps: Vec<&Vec<Coord>> = pieces.iter().filter(|p| p.0 == PieceKind::Sweep).map(|p| &p.1).collect();
        let airborne = flown.track.iter().position(|s| s.item > 0).unwrap_or(0);
        for s in flown.track[airborne..].iter().step_by(5) {
            path_off.push(distance_to_polyline(s.at, &path));
        }
        // how near the line's first metre the aircraft passes, flying the line's way
        let starts: Vec<f64> = sweeps
            .iter()
            .map(|line| {
                let (a, b) = (line[0], line[line.len() - 1]);
                let unit = (b - a) / (b - a).x.hypot((b - a).y);
                flown
                    .track
                    .windows(2)
                    .filter(|w| {
                        let step = w[1].at - w[0].at;
                        step.x * unit.x + step.y * unit.y > 0.94 * step.x.hypot(step.y)
                    })
                    .map(|w| (w[1].at - a).x.hypot((w[1].at - a).y))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        // the lines the plan enters straight over the whole lead-in
        let led_in: Vec<bool> = pieces
            .windows(2)
            .filter(|w| w[1].0 == PieceKind::Sweep)
            .map(|w| {
                let before = &w[0].1;
                let (a, b) = (before[before.len().saturating_sub(2)], before[before.len() - 1]);
                let line = &w[1].1;
                let along = (line[1] - line[0]) / (line[1] - line[0]).x.hypot((line[1] - line[0]).y);
                let straight = (b - a).x * along.y - (b - a).y * along.x;
                straight.abs() < 0.01 && (b - a).x.hypot((b - a).y) >= 0.99 * case.lead_in_m
            })
            .collect();
        for w in flown.track.windows(2).step_by(2) {
            // the line this sample flies: the nearest it lies beside, flown its way, nearer than
            // half the spacing
            let nearest = sweeps.iter().filter_map(|line| beside(line, w[0].at, w[1].at)).map(|b| b.0).fold(f64::INFINITY, f64::min);
            if nearest < 0.45 * case.output.stats.line_spacing_m {
                sweep_off.push(nearest);
            }
        }
        let first_is_led = led_in.len() < sweeps.len();
        for (i, off) in starts.into_iter().enumerate() {
            // a sortie's first line follows its transit from home
            let led = if first_is_led { i > 0 && led_in[i - 1] } else { led_in[i] };
            if led || case.lead_in_m == 0.0 {
                f.line_start_off_m.push(off);
            } else {
                f.lines_without_lead_in += 1;
            }
        }
        // photos line by line, each counted to its nearest line
        let planned: Vec<Coord> = case.photos.iter().map(|p| flown.frame.to_local(p[0], p[1])).collect();
        let taken: Vec<Coord> = flown.photos.iter().map(|p| flown.frame.to_local(p[0], p[1])).collect();
        let per_line = |photos: &[Coord]| {
            let mut counts = vec![0usize; sweeps.len()];
            for p in photos {
                let nearest = sweeps.iter().enumerate().map(|(i, line)| (i, distance_to_polyline(*p, line))).min_by(|a, b| a.1.total_cmp(&b.1));
                if let Some((i, _)) = nearest.filter(|n| n.1 < 0.5 * case.output.stats.line_spacing_m) {
                    counts[i] += 1;
                }
            }
            counts
        };
        let (planned, flown_counts) = (per_line(&planned), per_line(&taken));
        f.photos_off_per_line = f.photos_off_per_line.max(planned.iter().zip(&flown_counts).map(|(a, b)| a.abs_diff(*b)).max().unwrap_or(0));
        f.photos.0 += taken.len();
        let planned_s = case.output.stats.sortie_totals.get(k).map_or(case.output.stats.duration_s, |t| t.duration_s);
        f.duration_ratio.push(flown.duration_s / planned_s);
        totals = (totals.0 + flown.duration_s, totals.1 + planned_s);
        f.landed += usize::from(flown.landed);
        f.turned_back += usize::from(flown.turned_back_after_take_off);
        if let Some(zones) = &case.zones {
            use geo::Contains;
            f.zone_intrusions += flown.track.iter().filter(|s| zones.contains(&geo::Point::from(flown.frame.to_wgs84(s.at)))).count();
        }
    }
    f.photos.1 = case.output.stats.photos;
    f.total_duration_ratio = totals.0 / totals.1;
    f.sweep_off_p95_m = percentile(sweep_off, 0.95);
    f.path_off_p95_m = percentile(path_off.clone(), 0.95);
    f.path_off_max_m = path_off.iter().copied().fold(0.0, f64::max);
    f
}

/// The two missions flown in software-in-the-loop (issue 57), as the follower flies them: a
/// fixed wing over a 1.5 × 1 km field (60 m spacing, 80 m) and a multirotor over a 27 ha
/// rectangle (40 m, `dji_mavic3_enterprise`). `cargo test -p coverplan-planner --test it
/// simulated -- --nocapture` prints the figures docs/flight-files.md quotes.
#[test]
fn the_two_simulated_missions_fly_as_planned() {
    let frame = LocalFrame::new(8.55, 47.37);
    let (area, home) = rectangle(&frame, 1500.0, 1000.0, 100.0);
    for landing in ["return", "auto"] {
        let params = json!({"vehicle": {"profile": "generic_fixed_wing"}, "line_spacing_m": 60, "altitude_m": 80, "landing": landing});
        let plane = figures(&fly_case(&area, home, params, Firmware::Ardupilot));
        eprintln!("fixed wing, landing {landing}: {plane:#?}");
        assert!(plane.line_start_off_m.iter().copied().fold(0.0, f64::max) < 1.0, "{plane:?}");
        assert!(plane.sweep_off_p95_m < 1.0, "{plane:?}");
        assert!(plane.path_off_p95_m < 12.0 && plane.path_off_max_m < 20.0, "{plane:?}");
        assert!(plane.duration_ratio.iter().all(|r| (r - 1.0).abs() < 0.05), "{plane:?}");
        assert_eq!(plane.landed, if landing == "auto" { plane.duration_ratio.len() } else { 0 });
        assert_eq!(plane.turned_back, 0, "{plane:?}");
    }
    let (area, home) = rectangle(&frame, 600.0, 450.0, 20.0);
    let params = json!({"vehicle": {"profile": "iris"}, "camera": {"preset": "dji_mavic3_enterprise"}, "altitude_m": 40});
    let copter = figures(&fly_case(&area, home, params, Firmware::Ardupilot));
    eprintln!("multirotor: {copter:#?}");
    assert!(copter.photos_off_per_line <= 1, "{copter:?}");
    assert!(copter.duration_ratio.iter().all(|r| (r - 1.0).abs() < 0.05), "{copter:?}");
    assert_eq!(copter.landed, copter.duration_ratio.len());
}

/// A spiral keeps its camera triggering through its rings' corners (a photo at each corner):
/// over seed 002's polygon near Pisa with the camera its authors flew (IRIS, 10 m, 100°,
/// 2386 × 2386 px, side overlap 0.1), each firmware's file takes the plan's photos within one a
/// leg, flies in the plan's time within 5 % and lands.
#[test]
fn a_spiral_takes_its_photos_through_its_corners() {
    let fixture = fixture("seed002/pisa-polygon.json");
    let home: [f64; 2] = serde_json::from_value(fixture["home"].clone()).unwrap();
    for firmware in [Firmware::Ardupilot, Firmware::Px4] {
        let mut params = crate::energy_planners::flights_camera("e_spiral");
        params["landing"] = json!("auto");
        let f = figures(&fly_case(&fixture["area"], home, params, firmware));
        eprintln!("spiral, {firmware:?}: photos {} of {}, time {:.3} of the plan's", f.photos.0, f.photos.1, f.total_duration_ratio);
        // counted in all (a corner's photo lies on two legs, which the count by leg cannot share)
        assert!(f.photos.0.abs_diff(f.photos.1) <= f.line_start_off_m.len(), "{firmware:?}: {f:?}");
        assert!((f.total_duration_ratio - 1.0).abs() < 0.05, "{firmware:?}: {f:?}");
        assert_eq!(f.landed, f.duration_ratio.len(), "{firmware:?}: {f:?}");
    }
}

/// Over the random fields (holes as no-fly zones), a fixed wing and a multirotor with a camera,
/// each firmware, landing `auto` and not: the follower flies every line from its start, stays
/// near the plan and out of every zone, takes the plan's photos within one a line, lands when
/// asked, and takes the plan's time within 5 %.
#[test]
fn the_random_fields_fly_as_planned() {
    let index = fixture("random-fields/index.json");
    let names: Vec<String> = index.as_array().unwrap().iter().map(|e| e["file"].as_str().unwrap().to_owned()).filter(|f| f.ends_with("_00.json")).collect();
    assert!(names.len() >= 16, "{names:?}");
    let mut flights = 0;
    for (k, name) in names.iter().enumerate() {
        let field = fixture(&format!("random-fields/{name}"));
        let zones = &field["no_fly_zones"];
        // home: 50 m outside the field's first corner, away from its centre
        let ring = field["area"]["coordinates"][0].as_array().unwrap();
        let corner = [ring[0][0].as_f64().unwrap(), ring[0][1].as_f64().unwrap()];
        let frame = LocalFrame::new(corner[0], corner[1]);
        let centre = ring.iter().map(|p| frame.to_local(p[0].as_f64().unwrap(), p[1].as_f64().unwrap())).fold(Coord { x: 0.0, y: 0.0 }, |a, c| a + c / ring.len() as f64);
        let away = -centre / centre.x.hypot(centre.y).max(1e-9) * 50.0;
        let home = frame.to_wgs84(away);
        let firmware = if k % 2 == 0 { Firmware::Ardupilot } else { Firmware::Px4 };
        let landing = if k % 3 == 0 { "return" } else { "auto" };
        for vehicle in ["generic_fixed_wing", "iris"] {
            let params = json!({"vehicle": {"profile": vehicle}, "camera": {"preset": "dji_phantom4_pro"}, "altitude_m": 60, "landing": landing});
            let case = fly_case_with_zones(&field["area"], Some(zones), home, params, firmware);
            let f = figures(&case);
            let what = format!("{name}, {vehicle}, {firmware:?}, landing {landing}: {f:?}");
            let starts = &f.line_start_off_m;
            eprintln!(
                "{name} {vehicle}: lines entered within {:.2} m ({} without their whole lead-in), off the plan p95 {:.1} m, max {:.1} m, time {:.3} of the plan's, photos {} of {}, {} s in zones",
                starts.iter().copied().fold(0.0, f64::max),
                f.lines_without_lead_in,
                f.path_off_p95_m,
                f.path_off_max_m,
                f.total_duration_ratio,
                f.photos.0,
                f.photos.1,
                f.zone_intrusions as f64 * 0.05
            );
            assert!(starts.iter().all(|&off| off < 2.0), "{what}: a line entered off");
            assert_eq!(f.landed, if landing == "auto" || vehicle == "iris" { f.duration_ratio.len() } else { 0 }, "{what}");
            assert_eq!(f.turned_back, 0, "{what}: a waypoint behind the aircraft after take-off");
            if vehicle == "iris" {
                // as many photos as the plan's, within one a line (counting them line by line,
                // lines split by a hole trade photos at their ends)
                assert!(f.path_off_max_m < 0.1 && f.photos.0.abs_diff(f.photos.1) <= f.line_start_off_m.len() && f.zone_intrusions == 0, "{what}");
                // the measured model times short legs and their corners its own way: within 8 %
                // over the plan on fields with holes (1.3 % a sortie on the open rectangle)
                assert!((f.total_duration_ratio - 1.0).abs() < 0.08, "{what}");
            } else {
                // what a fixed wing that follows waypoints does on fields with holes: lines cut
                // short by the zones lose their lead-ins and are flown unsettled, turns are flown
                // wider than their arcs (the plan's time allows for it; docs/flight-files.md)
                assert!(f.path_off_p95_m < 15.0, "{what}");
                // taken where it flies: a line flown off may lend photos to its neighbour
                assert!(f.photos.0.abs_diff(f.photos.1) <= f.line_start_off_m.len() + f.lines_without_lead_in, "{what}");
                assert!((f.total_duration_ratio - 1.0).abs() < 0.05, "{what}");
                assert_eq!(f.zone_intrusions, 0, "{what}: the follower flew into a no-fly zone");
            }
            flights += f.duration_ratio.len();
        }
    }
    assert!(flights >= 32, "{flights}");
}
