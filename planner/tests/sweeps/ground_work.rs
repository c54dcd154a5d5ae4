//! Ground work over generated fields with ponds: refill trips (`payload`: the tank never runs
//! dry, every trip reaches a refill point, the breaks cost no more than the operator's rule)
//! and machines sharing a field (`vehicles`, `fleet`), each still worked inside its edges and
//! round its ponds.

use geo::{Coord, MultiPolygon};
use proptest::prelude::*;
use serde_json::{Value, json};

use crate::ground_plans::{PondField, check, frame_of, ground, pond_field, run};
use crate::planner_properties::to_local_mp;
use coverplan_planner::PlanOutput;
use coverplan_planner::frame::LocalFrame;

/// Each piece of the trajectory: its vehicle (of machines sharing the field), kind, whether the
/// tank is refilled where it ends, its points in `frame`.
fn trajectory(out: &PlanOutput, frame: &LocalFrame) -> Vec<(u64, String, bool, Vec<Coord>)> {
    let lines = out.trajectory.features.iter().filter_map(|f| {
        let p = f.properties.as_ref()?;
        let geojson::GeometryValue::LineString { coordinates } = &f.geometry.as_ref()?.value else { return None };
        let refill = p.get("refill").and_then(Value::as_bool).unwrap_or(false);
        let vehicle = p.get("vehicle").and_then(Value::as_u64).unwrap_or(0);
        Some((vehicle, p.get("kind")?.as_str()?.to_owned(), refill, coordinates.iter().map(|c| frame.to_local(c[0], c[1])).collect()))
    });
    lines.collect()
}

/// Each machine's tank, measured from the trajectory alone (`capacity`, `per_m2` taken by each
/// square metre of a `width` wide implement): it never runs dry, and every trip ends at one of
/// `stations`. What is worked and the trips, all machines together.
fn tanks(out: &PlanOutput, frame: &LocalFrame, stations: &[Coord], (capacity, per_m2, width): (f64, f64, f64), name: &str) -> Result<(f64, usize), TestCaseError> {
    let mut left: std::collections::HashMap<u64, f64> = std::collections::HashMap::new();
    let (mut worked, mut trips) = (0.0, 0);
    // positions are written to 1e-7° (about a centimetre): each piece's length within 2 cm
    let mut slack: std::collections::HashMap<u64, f64> = std::collections::HashMap::new();
    let rounding = 0.02 * width * per_m2;
    for (vehicle, kind, refill, points) in trajectory(out, frame) {
        let (left, slack) = (left.entry(vehicle).or_insert(capacity), slack.entry(vehicle).or_insert(0.0));
        if kind == "sweep" || kind == "headland" {
            let used = length(&points) * width * per_m2;
            *left -= used;
            worked += used;
            *slack += rounding;
            prop_assert!(*left >= -*slack, "{}: machine {}'s tank runs dry ({} left)", name, vehicle, left);
        }
        if refill {
            let end = *points.last().unwrap();
            let near = stations.iter().map(|s| (end - *s).x.hypot((end - *s).y)).fold(f64::INFINITY, f64::min);
            prop_assert!(near < 0.05, "{}: a trip ends {} m from the nearest refill point", name, near);
            (*left, *slack) = (capacity, 0.0);
            trips += 1;
        }
    }
    Ok((worked, trips))
}

fn length(points: &[Coord]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

    /// Star-shaped fields of 2 to 30 ha with up to three ponds, a sprayer of 3 to 12 m with
    /// one or two passes, a tank holding a sixth to two thirds of what the field takes, and one
    /// or two refill points at corners of the field's edge.
    #[test]
    fn the_tank_never_runs_dry_and_every_trip_reaches_a_refill_point(
        field in pond_field(80.0),
        width in 3.0..12.0f64,
        turn_radius in 2.0..8.0f64,
        passes in 1u32..3,
        reverse in any::<bool>(),
        share in 0.15..0.7f64,
        corners in prop::collection::vec(0usize..10, 1..3),
        harvest in any::<bool>(),
        refill_s in prop_oneof![Just(0.0), 60.0..3600.0f64],
    ) {
        let PondField { area, ponds: nfz, name } = field;
        let ring = area["coordinates"][0].as_array().expect("a ring").clone();
        let points: Vec<Value> = corners.iter().map(|&c| ring[c % (ring.len() - 1)].clone()).collect();
        let headland = (passes as f64 * width).max(turn_radius + 1.0);
        let rate = 200.0;
        // the field's area, roughly: what the tank's share is of
        let frame = frame_of(&area);
        let field = to_local_mp(&frame, &area);
        let amount = geo::Area::unsigned_area(&field) / 10_000.0 * rate;
        let capacity = (share * amount).max(1.0);
        let mut params = ground(width, turn_radius, json!({
            "headland_width_m": headland,
            "payload": {"capacity": capacity, "rate_per_ha": rate, "harvest": harvest, "refill_points": points, "refill_s": refill_s},
        }));
        params.vehicle.reverse_allowed = Some(reverse);
        params.vehicle.headland_speed_mps = Some(1.5);
        let name = format!("{name}, {width:.1} m, radius {turn_radius:.1}, reverse {reverse}, tank {capacity:.0} of {amount:.0}, stands {refill_s:.0} s");
        let out = match run(&area, None, &params) {
            Ok(out) => out,
            Err(coverplan_planner::PlanError::Input(e)) if e.code == "field_too_narrow" => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(format!("{name}: {e}"))),
        };
        let holes = to_local_mp(&frame, &nfz);
        check(&area, &if holes.0.is_empty() { MultiPolygon(vec![]) } else { holes }, &out, turn_radius, 0.99, &name)?;
        let stations: Vec<Coord> = points.iter().map(|p| frame.to_local(p[0].as_f64().unwrap(), p[1].as_f64().unwrap())).collect();
        let per_m2 = rate / 10_000.0;
        let (worked, trips) = tanks(&out, &frame, &stations, (capacity, per_m2, width), &name)?;
        let figures = out.stats.ground.as_ref().and_then(|g| g.payload.as_ref()).expect("payload figures");
        prop_assert_eq!(figures.trips, trips, "{}", name);
        // each trip stands its refill time, counted in the plan's duration
        prop_assert!((figures.refill_stops_s - trips as f64 * refill_s).abs() < 1e-6, "{}: {} s standing for {} trips", name, figures.refill_stops_s, trips);
        let pieces: Vec<&serde_json::Map<String, Value>> = out.trajectory.features.iter().filter_map(|f| f.properties.as_ref()).filter(|p| p.contains_key("duration_s")).collect();
        let seconds = |p: &serde_json::Map<String, Value>| p["duration_s"].as_f64().unwrap_or(0.0);
        for p in pieces.iter().filter(|p| p.get("refill") == Some(&json!(true))) {
            prop_assert!(seconds(p) >= refill_s - 0.01, "{}: a trip to a refill point of {} s", name, seconds(p));
        }
        let total: f64 = pieces.iter().map(|p| seconds(p)).sum();
        prop_assert!((out.stats.duration_s - total).abs() <= 0.01 * pieces.len() as f64, "{}: the plan's {} s, its pieces' {} s", name, out.stats.duration_s, total);
        prop_assert!((figures.amount - worked).abs() <= 1e-3 * worked, "{}: {} reported, {} worked", name, figures.amount, worked);
        prop_assert!(trips as f64 >= (worked / capacity).ceil() - 1.0, "{}: {} trips for {} worked from a tank of {}", name, trips, worked, capacity);
        // fewer crossings of the crop first, then shorter, each stand counted as the metres
        // driven on the headland in its time
        let stand_m = refill_s * 1.5;
        let ours = (figures.trip_crossings, figures.trip_distance_m + figures.trips as f64 * stand_m);
        let rule = (figures.rule_trip_crossings, figures.rule_trip_distance_m.unwrap_or(f64::INFINITY) + figures.rule_trips as f64 * stand_m);
        prop_assert!(ours.0 < rule.0 || (ours.0 == rule.0 && ours.1 <= rule.1 + 1e-6), "{}: {:?} against the rule's {:?}", name, ours, rule);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Two or three machines share a generated field with ponds, with or without tanks: the
    /// field is still worked inside its edges and round its ponds, no tank runs dry, no two
    /// machines come within the working width at the same time, and the last one is done no
    /// later than one machine alone.
    #[test]
    fn machines_sharing_a_field_are_done_no_later_and_never_meet(
        field in pond_field(120.0),
        width in 3.0..12.0f64,
        turn_radius in 2.0..8.0f64,
        machines in 2u32..4,
        reverse in any::<bool>(),
        tank in any::<bool>(),
    ) {
        let PondField { area, ponds: nfz, name } = field;
        let frame = frame_of(&area);
        let headland = (2.0 * width).max(turn_radius + 1.0);
        let mut alone = ground(width, turn_radius, json!({"headland_width_m": headland}));
        alone.vehicle.reverse_allowed = Some(reverse);
        // with a tank holding a quarter of what the field takes, refilled at its first corner
        let corner = area["coordinates"][0][0].clone();
        let capacity = geo::Area::unsigned_area(&to_local_mp(&frame, &area)) / 10_000.0 * 200.0 / 4.0;
        if tank {
            alone.payload = Some(serde_json::from_value(json!({"capacity": capacity.max(1.0), "rate_per_ha": 200, "refill_points": [corner]})).unwrap());
        }
        let mut fleet = alone.clone();
        fleet.vehicles = Some(machines);
        let name = format!("{name}, {width:.1} m, radius {turn_radius:.1}, reverse {reverse}, {machines} machines");
        let (one, shared) = match (run(&area, None, &alone), run(&area, None, &fleet)) {
            (Ok(one), Ok(shared)) => (one, shared),
            (Err(coverplan_planner::PlanError::Input(e)), _) if e.code == "field_too_narrow" => return Ok(()),
            (a, b) => return Err(TestCaseError::fail(format!("{name}: {:?} {:?}", a.err(), b.err()))),
        };
        let holes = to_local_mp(&frame, &nfz);
        let holes = if holes.0.is_empty() { MultiPolygon(vec![]) } else { holes };
        check(&area, &holes, &one, turn_radius, 0.99, &format!("{name}, one alone"))?;
        check(&area, &holes, &shared, turn_radius, 0.99, &name)?;
        let s = &shared.stats;
        prop_assert_eq!(s.conflicts.as_ref().map(Vec::len), Some(0), "{}", name);
        if tank {
            let at = frame.to_local(corner[0].as_f64().unwrap(), corner[1].as_f64().unwrap());
            let (_, trips) = tanks(&shared, &frame, &[at], (capacity.max(1.0), 0.02, width), &name)?;
            prop_assert_eq!(s.ground.as_ref().and_then(|g| g.payload.as_ref()).map(|p| p.trips), Some(trips), "{}", name);
        }
        let makespan = s.makespan_s.expect("a fleet's makespan");
        // (the fastest machine alone where sharing is no sooner)
        prop_assert!(makespan <= one.stats.duration_s + 1e-6, "{}: the last machine finishes at {} s, one alone at {} s", name, makespan, one.stats.duration_s);
    }
}
