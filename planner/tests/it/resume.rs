//! Resuming a plan whose flight stopped: over the random fields (holes as no-fly zones), for a
//! multirotor and a fixed wing, at random cuts (in sweeps, turns, transits, at sortie ends),
//! the part flown and the resumed plan cover what the original covers, the resumed plan is no
//! longer than what the original had left but for the way to its first line and the stretch
//! flown again, and it never enters a no-fly zone.

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::geojson::{FeatureCollection, GeometryValue};
use coverplan_planner::params::resume::ResumeParams;
use coverplan_planner::path::{FlightPath, Piece, PieceKind};
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop, metrics, plan, resume};
use geo::{BooleanOps, Coord, Intersects, LineString, MultiPolygon};
use proptest::prelude::*;
use serde::Deserialize;
use serde_json::{Value, json};

fn fixture(path: &str) -> Value {
    serde_json::from_slice(&std::fs::read(format!("{}/../tests/fixtures/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()).unwrap()
}

/// The flown pieces of a trajectory in the local frame: kind, points and seq.
fn pieces(trajectory: &FeatureCollection, frame: &LocalFrame) -> Vec<(PieceKind, Vec<Coord>, usize)> {
    trajectory
        .features
        .iter()
        .filter_map(|f| {
            let props = f.properties.as_ref()?;
            let kind = PieceKind::deserialize(props.get("kind")?).ok()?;
            let GeometryValue::LineString { coordinates } = &f.geometry.as_ref()?.value else { return None };
            Some((kind, coordinates.iter().map(|p| frame.to_local(p[0], p[1])).collect(), props["seq"].as_u64()? as usize))
        })
        .collect()
}

/// A path of the sweeps among `pieces`, each covering `half` either side.
fn sweeps(pieces: impl IntoIterator<Item = (PieceKind, Vec<Coord>)>, half: f64) -> FlightPath {
    let pieces = pieces.into_iter().filter(|(k, p)| *k == PieceKind::Sweep && p.len() >= 2).map(|(kind, points)| Piece::new(kind, points, half));
    FlightPath { pieces: pieces.collect() }
}

/// `points` up to `along` metres.
fn up_to(points: &[Coord], along: f64) -> Vec<Coord> {
    let mut out = vec![points[0]];
    let mut walked = 0.0;
    for w in points.windows(2) {
        let step = (w[1] - w[0]).x.hypot((w[1] - w[0]).y);
        if walked + step >= along {
            out.push(w[0] + (w[1] - w[0]) * ((along - walked) / step).clamp(0.0, 1.0));
            return out;
        }
        walked += step;
        out.push(w[1]);
    }
    out
}

/// A GeoJSON Polygon or MultiPolygon.
fn multipolygon(v: &Value) -> MultiPolygon {
    match geo::Geometry::try_from(serde_json::from_value::<geojson::Geometry>(v.clone()).unwrap()).unwrap() {
        geo::Geometry::Polygon(p) => MultiPolygon(vec![p]),
        geo::Geometry::MultiPolygon(m) => m,
        other => panic!("not polygons: {other:?}"),
    }
}

struct Case {
    mission_area: Value,
    zones: Value,
    home: [f64; 2],
    params: PlanParams,
}

/// The random field `k` with a home 40 m beyond its first corner, and a battery for a part of
/// the plan; `None` where no plan flies from that home (it is cut off by a zone).
fn case(k: usize, fixed_wing: bool) -> Option<Case> {
    let index = fixture("random-fields/index.json");
    let names: Vec<String> =
        index.as_array().unwrap().iter().map(|e| e["file"].as_str().unwrap().to_owned()).filter(|f| f.ends_with("_00.json") || f.ends_with("_01.json")).collect();
    let field = fixture(&format!("random-fields/{}", names[k % names.len()]));
    let ring = field["area"]["coordinates"][0].as_array().unwrap();
    let corner = [ring[0][0].as_f64().unwrap(), ring[0][1].as_f64().unwrap()];
    let frame = LocalFrame::new(corner[0], corner[1]);
    let home = frame.to_wgs84(Coord { x: -40.0, y: -40.0 });
    let vehicle = if fixed_wing { "generic_fixed_wing" } else { "iris" };
    let params = |battery_wh: Option<f64>| -> PlanParams {
        serde_json::from_value(json!({"vehicle": {"profile": vehicle, "battery_wh": battery_wh}, "line_spacing_m": 30, "altitude_m": 60})).unwrap()
    };
    // a battery for a third of the plan or a half, so that it flies in sorties (one line and
    // the legs to it and back may need more on a small field)
    let mission = MissionGeometry { home: Some(home), no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
    let try_plan = |p: &PlanParams| plan(&mission, p, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never());
    let whole = try_plan(&params(None)).ok()?;
    let params = [2.6, 1.6].into_iter().map(|share| params(Some(whole.stats.energy_wh / 0.75 / share))).find(|p| try_plan(p).is_ok()).unwrap_or_else(|| params(None));
    Some(Case { mission_area: field["area"].clone(), zones: field["no_fly_zones"].clone(), home, params })
}

/// The sortie of the piece numbered `seq`.
fn sortie_of(trajectory: &FeatureCollection, seq: usize) -> usize {
    let props = trajectory.features.iter().filter_map(|f| f.properties.as_ref());
    props.filter(|p| p.get("seq").and_then(|s| s.as_u64()) == Some(seq as u64)).find_map(|p| p.get("sortie").and_then(|s| s.as_u64())).unwrap_or(1) as usize
}

/// The longest way out and home of any one sortie: its first and last pieces where they are
/// transits.
fn sortie_ends_m(trajectory: &FeatureCollection) -> f64 {
    let mut pieces: std::collections::BTreeMap<u64, Vec<Option<f64>>> = Default::default();
    for p in trajectory.features.iter().filter_map(|f| f.properties.as_ref()) {
        let flown = p.get("kind").and_then(|k| k.as_str()).filter(|k| ["transit", "sweep", "turn"].contains(k));
        if let (Some(sortie), Some(length), Some(kind)) = (p.get("sortie").and_then(|s| s.as_u64()), p.get("length_m").and_then(|l| l.as_f64()), flown) {
            pieces.entry(sortie).or_default().push((kind == "transit").then_some(length));
        }
    }
    let end = |piece: Option<&Option<f64>>| piece.copied().flatten().unwrap_or(0.0);
    pieces.values().map(|lengths| end(lengths.first()) + end(lengths.last())).fold(0.0, f64::max)
}

fn check_resume(k: usize, fixed_wing: bool, cut_at: f64, fraction: f64, photos_back: u32) -> Result<(), TestCaseError> {
    let Some(c) = case(k, fixed_wing) else { return Err(TestCaseError::reject("no plan flies from this home")) };
    let mission = MissionGeometry { home: Some(c.home), no_fly_zones: Some(&c.zones), ..MissionGeometry::area(&c.mission_area) };
    let profiles = builtin_profiles();
    let original: PlanOutput = plan(&mission, &c.params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let frame = LocalFrame::new(c.home[0], c.home[1]);
    let flown = pieces(&original.trajectory, &frame);
    let cut = ((cut_at * flown.len() as f64) as usize).min(flown.len() - 1);
    let request: ResumeParams = serde_json::from_value(json!({"at": {"seq": flown[cut].2, "fraction": fraction}, "photos_back": photos_back})).unwrap();
    let request = request.check().unwrap();
    let what = format!("case {k}, fixed wing {fixed_wing}, cut at piece {cut} of {} ({:?}) × {fraction:.2}", flown.len(), flown[cut].0);

    let resumed = match resume(&mission, &c.params, &profiles, &FieldLimits::default(), &original.trajectory, &request, &|_| true, &Stop::never()) {
        Ok(r) => r,
        // a cut after the last line leaves nothing, and says so
        Err(e) if e.to_string().contains("nothing is left") => {
            prop_assert!(flown[cut..].iter().skip(1).all(|p| p.0 != PieceKind::Sweep), "{what}: {e}");
            return Ok(());
        }
        // the small battery cannot fly the first line left from home and back: said so
        Err(e) if e.to_string().contains("alone, flown from home and back") => return Ok(()),
        Err(e) => return Err(TestCaseError::fail(format!("{what}: {e}"))),
    };
    let stats = resumed.stats.resume.clone().expect("a resumed plan says where it resumed");
    let left = pieces(&resumed.trajectory, &frame);
    // coverage: the part flown and the resumed plan together cover what the original covers
    let zones = multipolygon(&c.zones);
    let local = |mp: &MultiPolygon| geo::MapCoords::map_coords(mp, |p| frame.to_local(p.x, p.y));
    let area = multipolygon(&c.mission_area);
    let region = local(&area).difference(&local(&zones));
    let half = 15.0;
    let along = fraction * flown[cut].1.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum::<f64>();
    let done = flown[..cut].iter().map(|p| (p.0, p.1.clone())).chain([(flown[cut].0, up_to(&flown[cut].1, along))]);
    let original_cover = metrics::covered_area(&sweeps(flown.iter().map(|p| (p.0, p.1.clone())), half), &region, None);
    let both = metrics::covered_area(&sweeps(done.chain(left.iter().map(|p| (p.0, p.1.clone()))), half), &region, None);
    prop_assert!(both >= original_cover - 0.001 * geo::Area::unsigned_area(&region), "{what}: {both:.0} m² against the original's {original_cover:.0} m²");
    // length: what the original had left, the way to the first line and the stretch again,
    // and a way home and out for each sortie more than the original had left (the way to the
    // first line can leave the first sortie too little for the rest of the cut one)
    let to_first_line: f64 = left.iter().take_while(|p| p.0 != PieceKind::Sweep).map(|p| p.1.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum::<f64>()).sum();
    let cut_sortie = sortie_of(&original.trajectory, flown[cut].2);
    let sorties_left = original.stats.sorties.saturating_sub(cut_sortie) + 1;
    let more_sorties = resumed.stats.sorties.saturating_sub(sorties_left) as f64;
    let costliest_break = sortie_ends_m(&resumed.trajectory);
    prop_assert!(
        resumed.stats.length_m <= stats.original_left_m + to_first_line + stats.overlap_m + more_sorties * costliest_break + 1.0,
        "{what}: {:.0} m in {} sorties against {:.0} m left (of {} sorties), {to_first_line:.0} m to the first line and {:.0} m again",
        resumed.stats.length_m,
        resumed.stats.sorties,
        stats.original_left_m,
        original.stats.sorties,
        stats.overlap_m
    );
    prop_assert!(stats.overlap_m <= photos_back as f64 * 15.0 + 1e-6, "{what}: {stats:?}");
    // never into a zone
    let zones = local(&zones);
    for (kind, points, seq) in &left {
        prop_assert!(!zones.intersects(&LineString::from(points.clone())), "{what}: piece {seq} ({kind:?}) enters a no-fly zone");
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]
    #[test]
    fn a_resumed_plan_covers_what_was_left_and_no_more(k in 0usize..64, fixed_wing in any::<bool>(), cut_at in 0.0f64..1.0, fraction in 0.0f64..=1.0, photos_back in 0u32..4) {
        check_resume(k, fixed_wing, cut_at, fraction, photos_back)?;
    }
}

/// A flight's log made from the plan: the path flown up to `along` metres of the sweep `cut`,
/// a position every 2 m with up to half a metre of noise. (It ends there: a log without the
/// autopilot's mode and without photos cannot tell a way home flown along a line not yet
/// flown from that line's work; docs/methods.md, resume §4.)
fn flown_track(flown: &[(PieceKind, Vec<Coord>, usize)], cut: usize, along: f64, seed: u64) -> Vec<Coord> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut noise = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 1.0
    };
    let mut points: Vec<Coord> = Vec::new();
    for (i, (_, p, _)) in flown.iter().enumerate().take(cut + 1) {
        let p = if i == cut { up_to(p, along) } else { p.clone() };
        points.extend(p);
    }
    let mut track = Vec::new();
    for w in points.windows(2) {
        let n = ((w[1] - w[0]).x.hypot((w[1] - w[0]).y) / 2.0).ceil().max(1.0) as usize;
        for i in 0..n {
            let t = i as f64 / n as f64;
            track.push(w[0] + (w[1] - w[0]) * t + Coord { x: noise(), y: noise() });
        }
    }
    track
}

fn check_log_resume(k: usize, fixed_wing: bool, cut_at: f64, fraction: f64, seed: u64) -> Result<(), TestCaseError> {
    let Some(c) = case(k, fixed_wing) else { return Err(TestCaseError::reject("no plan flies from this home")) };
    let mission = MissionGeometry { home: Some(c.home), no_fly_zones: Some(&c.zones), ..MissionGeometry::area(&c.mission_area) };
    let profiles = builtin_profiles();
    let original: PlanOutput = plan(&mission, &c.params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let frame = LocalFrame::new(c.home[0], c.home[1]);
    let flown = pieces(&original.trajectory, &frame);
    let sweeps: Vec<usize> = flown.iter().enumerate().filter(|(_, p)| p.0 == PieceKind::Sweep).map(|(i, _)| i).collect();
    let cut = sweeps[((cut_at * sweeps.len() as f64) as usize).min(sweeps.len() - 1)];
    let len: f64 = flown[cut].1.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum();
    let track = flown_track(&flown, cut, fraction * len, seed);
    let request: ResumeParams = serde_json::from_value(json!({"flown": {"track": track.iter().map(|p| frame.to_wgs84(*p)).collect::<Vec<_>>()}})).unwrap();
    let request = request.check().map_err(|e| TestCaseError::fail(e.to_string()))?;
    // a flight stopped on the way to a sortie's first line, or just into it, whose way out from
    // home ran along a later line in that line's direction, is not told from that line's work
    // (docs/methods.md, resume §4)
    let after_way_out = cut == sweeps[0] || flown[..cut].iter().rev().take_while(|p| p.0 != PieceKind::Sweep).any(|p| p.0 == PieceKind::Transit);
    prop_assume!(!after_way_out || fraction * len >= 15.0 + 8.0, "stopped on the way out to a sortie's first line");
    let what = format!("case {k}, fixed wing {fixed_wing}, cut on piece {cut} (seq {}) at {:.0} of {len:.0} m", flown[cut].2, fraction * len);
    let resumed = match resume(&mission, &c.params, &profiles, &FieldLimits::default(), &original.trajectory, &request, &|_| true, &Stop::never()) {
        Ok(r) => r,
        Err(e) if e.to_string().contains("nothing is left") => {
            prop_assert!(cut == *sweeps.last().unwrap(), "{what}: {e}");
            return Ok(());
        }
        Err(e) if e.to_string().contains("alone, flown from home and back") => return Ok(()),
        Err(e) => return Err(TestCaseError::fail(format!("{what}: {e}"))),
    };
    let found = resumed.stats.resume.clone().expect("a resumed plan says where it resumed");
    // the last sample done is within a sample spacing (half the line spacing) and the
    // tolerance of where the flight stopped; before the first sample, the line before
    let trigger = 15.0;
    let next_sweep = sweeps.iter().find(|&&i| i > cut).map(|&i| flown[i].2);
    if fraction * len >= trigger + 8.0 && len - fraction * len <= trigger + 8.0 && Some(found.seq) == next_sweep {
        // stopped within a trigger distance and the tolerance of the line's end: its last sample
        // is done, so the line is finished and the cut is the next line's start
        prop_assert!(found.fraction == 0.0, "{what}: {found:?}");
    } else if fraction * len >= trigger + 8.0 {
        prop_assert_eq!(found.seq, flown[cut].2, "{}: {:?}", what, found);
        let at = found.fraction * len;
        prop_assert!(at <= fraction * len + 8.0 && at >= fraction * len - trigger - 8.0, "{what}: found at {at:.0} m: {found:?}");
    } else {
        prop_assert!(found.seq <= flown[cut].2, "{what}: {found:?}");
    }
    // a flight that flew every line before the cut as planned has nothing to fly again
    prop_assert!(found.redone_m.is_none(), "{what}: {found:?}");
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]
    #[test]
    fn a_log_of_the_plan_flown_and_stopped_gives_back_its_stop(k in 0usize..64, cut_at in 0.0f64..1.0, fraction in 0.0f64..=1.0, seed in any::<u64>()) {
        // a multirotor: a fixed wing's connections run along other lines, and a track alone
        // (no photos, no mode) cannot tell them from those lines' work (docs/methods.md, resume §4)
        check_log_resume(k, false, cut_at, fraction, seed)?;
    }
}

/// A ground vehicle's plan stopped in a swath: what is left is the rest of that swath and every
/// swath and headland pass after it, their tramlines still marked, driven to along the headland
/// from home; nothing before the cut is worked again, and the crop is crossed no more often
/// than the original crossed it.
#[test]
fn a_ground_plan_resumed_works_the_swaths_left_and_keeps_to_the_headland() {
    let profiles = builtin_profiles();
    for name in ["nl-parcel-b", "ee-field-3-holes"] {
        let m = fixture(&format!("real-fields/{name}.json"));
        let corner = &m["area"]["coordinates"][0][0];
        let home = [corner[0].as_f64().unwrap(), corner[1].as_f64().unwrap()];
        let mission = MissionGeometry { home: Some(home), ..MissionGeometry::area(&m["area"]) };
        let params: PlanParams = serde_json::from_value(json!({"vehicle": {"profile": "tractor_sprayer"}, "headland_passes": 2, "tramline_every": 3})).unwrap();
        let original = plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let frame = LocalFrame::new(home[0], home[1]);
        let flown = pieces(&original.trajectory, &frame);
        let tramlines: std::collections::HashSet<u64> = original
            .trajectory
            .features
            .iter()
            .filter_map(|f| f.properties.as_ref())
            .filter(|p| p.get("tramline") == Some(&json!(true)))
            .filter_map(|p| p.get("seq").and_then(Value::as_u64))
            .collect();
        let worked = |p: &(PieceKind, Vec<Coord>, usize)| matches!(p.0, PieceKind::Sweep | PieceKind::Headland);
        let mut checked = 0;
        for share in [0.3, 0.6, 0.9] {
            let Some(cut) = (((share * flown.len() as f64) as usize)..flown.len()).find(|&k| flown[k].0 == PieceKind::Sweep) else { continue };
            checked += 1;
            let request: ResumeParams = serde_json::from_value(json!({"at": {"seq": flown[cut].2, "fraction": 0.5}, "photos_back": 0})).unwrap();
            let resumed = resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &request.check().unwrap(), &|_| true, &Stop::never())
                .unwrap_or_else(|e| panic!("{name}, cut at piece {cut}: {e}"));
            let left = pieces(&resumed.trajectory, &frame);
            let what = format!("{name}, cut at piece {cut} of {}", flown.len());
            let same = |a: Coord, b: Coord| (a - b).x.hypot((a - b).y) < 0.05;
            // the cut swath from its middle, then every piece worked after it, in order
            let left_worked: Vec<&(PieceKind, Vec<Coord>, usize)> = left.iter().filter(|p| worked(p)).collect();
            let after: Vec<&(PieceKind, Vec<Coord>, usize)> = flown[cut + 1..].iter().filter(|p| worked(p)).collect();
            assert_eq!(left_worked.len(), after.len() + 1, "{what}");
            let (cut_points, first) = (&flown[cut].1, &left_worked[0].1);
            assert!(same(*first.last().unwrap(), *cut_points.last().unwrap()), "{what}: the cut swath's end");
            let middle = up_to(cut_points, 0.5 * cut_points.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum::<f64>());
            assert!(same(first[0], *middle.last().unwrap()), "{what}: the cut swath from where it stopped");
            for (a, b) in after.iter().zip(&left_worked[1..]) {
                assert!(a.0 == b.0 && same(a.1[0], b.1[0]) && same(*a.1.last().unwrap(), *b.1.last().unwrap()), "{what}: piece {} of the original", a.2);
            }
            // tramlines still marked
            let tramlines_after = flown[cut..].iter().filter(|p| p.0 == PieceKind::Sweep && tramlines.contains(&(p.2 as u64))).count();
            let g = resumed.stats.ground.as_ref().expect("a ground plan's figures");
            assert_eq!(g.tramlines, tramlines_after, "{what}");
            // driven along the headland: no more crossings of the crop than the original's
            let crossed = original.stats.ground.as_ref().unwrap().mainland_crossings;
            assert!(g.mainland_crossings <= crossed, "{what}: {} crossings of the crop, the original {crossed}", g.mainland_crossings);
            eprintln!("{what}: {} pieces worked left, {} tramlines, {} crossings (the original {crossed})", left_worked.len(), g.tramlines, g.mainland_crossings);
        }
        assert!(checked >= 2, "{name}: {} pieces, {checked} cuts in swaths", flown.len());
    }
}

/// A fleet's drone that stopped resumes its own part from its home, and no other drone's: named
/// by the trajectory's `vehicle` with `at`, or found by its position.
#[test]
fn a_fleets_drone_resumes_its_own_part_and_no_other() {
    let profiles = builtin_profiles();
    let field = fixture("random-fields/h03_00.json");
    let corner = &field["area"]["coordinates"][0][0];
    let frame = LocalFrame::new(corner[0].as_f64().unwrap(), corner[1].as_f64().unwrap());
    let home = frame.to_wgs84(Coord { x: -40.0, y: -40.0 });
    let mission = MissionGeometry { home: Some(home), no_fly_zones: Some(&field["no_fly_zones"]), ..MissionGeometry::area(&field["area"]) };
    let params: PlanParams = serde_json::from_value(json!({"vehicle": {"profile": "iris"}, "vehicles": 2, "line_spacing_m": 30, "altitude_m": 60})).unwrap();
    let original = plan(&mission, &params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).unwrap();
    // (drone, seq, first point, last point) of each sweep
    let sweeps_of = |fc: &FeatureCollection| -> Vec<(Option<u64>, u64, Coord, Coord)> {
        fc.features
            .iter()
            .filter_map(|f| {
                let p = f.properties.as_ref()?;
                (p.get("kind")? == "sweep").then_some(())?;
                let GeometryValue::LineString { coordinates } = &f.geometry.as_ref()?.value else { return None };
                let at = |c: &coverplan_planner::geojson::Position| frame.to_local(c[0], c[1]);
                Some((p.get("vehicle").and_then(Value::as_u64), p["seq"].as_u64()?, at(&coordinates[0]), at(coordinates.last()?)))
            })
            .collect()
    };
    let all = sweeps_of(&original.trajectory);
    let same = |a: Coord, b: Coord| (a - b).x.hypot((a - b).y) < 0.05;
    for drone in [0u64, 1] {
        let own: Vec<_> = all.iter().filter(|s| s.0 == Some(drone)).collect();
        assert!(own.len() >= 4, "drone {drone}: {} sweeps", own.len());
        let (_, seq, a, b) = *own[own.len() / 2];
        let middle = frame.to_wgs84((a + b) * 0.5);
        let heading = coverplan_planner::params::math_to_bearing((b - a).y.atan2((b - a).x));
        for request in [json!({"at": {"seq": seq, "fraction": 0.5, "vehicle": drone}}), json!({"position": middle, "heading_deg": heading})] {
            let request: ResumeParams = serde_json::from_value(request).unwrap();
            let resumed = resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &request.check().unwrap(), &|_| true, &Stop::never())
                .unwrap_or_else(|e| panic!("drone {drone}: {e}"));
            let left = sweeps_of(&resumed.trajectory);
            // the cut line from its middle, then the drone's own lines after it, and only those
            assert_eq!(left.len(), own.len() - own.len() / 2, "drone {drone}");
            assert!(same(left[0].3, b), "drone {drone}: the cut line to its end");
            for (o, l) in own[own.len() / 2 + 1..].iter().zip(&left[1..]) {
                assert!(same(o.2, l.2) && same(o.3, l.3), "drone {drone}: its line {} again", o.1);
            }
            let starts = resumed.trajectory.features.iter().find_map(|f| match &f.geometry.as_ref()?.value {
                GeometryValue::LineString { coordinates } => Some(frame.to_local(coordinates[0][0], coordinates[0][1])),
                _ => None,
            });
            assert!(starts.is_some_and(|s| same(s, Coord { x: -40.0, y: -40.0 })), "drone {drone}: from home, {starts:?}");
        }
    }
    // a log is its drone's: the track of drone 1 flown to the middle of a line resumes drone 1
    let own: Vec<_> = all.iter().filter(|s| s.0 == Some(1)).collect();
    let (_, seq, _, b) = *own[own.len() / 2];
    let mut track: Vec<[f64; 2]> = Vec::new();
    for f in &original.trajectory.features {
        let Some(p) = f.properties.as_ref().filter(|p| p.get("vehicle") == Some(&json!(1)) && p.contains_key("kind")) else { continue };
        let Some(GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
        let local: Vec<Coord> = coordinates.iter().map(|c| frame.to_local(c[0], c[1])).collect();
        let length: f64 = local.windows(2).map(|w| (w[1] - w[0]).x.hypot((w[1] - w[0]).y)).sum();
        let stop_here = p["seq"].as_u64() == Some(seq);
        let flown = up_to(&local, if stop_here { length / 2.0 } else { length });
        // a position every 2 m
        for w in flown.windows(2) {
            let n = ((w[1] - w[0]).x.hypot((w[1] - w[0]).y) / 2.0).ceil().max(1.0) as usize;
            track.extend((0..n).map(|i| frame.to_wgs84(w[0] + (w[1] - w[0]) * (i as f64 / n as f64))));
        }
        if stop_here {
            break;
        }
    }
    let logged: ResumeParams = serde_json::from_value(json!({"flown": {"track": track}})).unwrap();
    let resumed = resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &logged.check().unwrap(), &|_| true, &Stop::never()).unwrap();
    let left = sweeps_of(&resumed.trajectory);
    assert!(same(left[0].3, b), "the log's drone's cut line, to its end");
    assert!(left.iter().all(|l| own.iter().any(|o| same(o.3, l.3))), "only drone 1's lines");
    // `at` must name the drone: each drone's pieces are numbered on their own
    let unnamed: ResumeParams = serde_json::from_value(json!({"at": {"seq": all[0].1, "fraction": 0.5}})).unwrap();
    let refused = resume(&mission, &params, &profiles, &FieldLimits::default(), &original.trajectory, &unnamed.check().unwrap(), &|_| true, &Stop::never());
    assert!(refused.as_ref().is_err_and(|e| e.to_string().contains("which drone")), "{:?}", refused.map(|_| ()));
}
