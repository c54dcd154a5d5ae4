//! Planner `corridor` over generated corridors: winding, with bends sharper than a fixed
//! wing's turning radius, some crossed by a no-fly zone. The plan covers the corridor, never
//! enters a zone, and stays within the corridor plus the room its turns need.

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, plan};
use geo::{Coord, Distance, Euclidean, Intersects, LineString, Point, Polygon};
use proptest::prelude::*;
use serde_json::{Value, json};

/// A winding centre line from the origin: legs of `legs` (length, turn in degrees).
pub(crate) fn centre_line(legs: &[(f64, f64)]) -> Vec<Coord> {
    let (mut at, mut heading) = (Coord { x: 0.0, y: 0.0 }, 0.0f64);
    let mut points = vec![at];
    for &(length, turn) in legs {
        heading += turn.to_radians();
        at = at + Coord { x: heading.cos(), y: heading.sin() } * length;
        points.push(at);
    }
    points
}

/// A square no-fly zone of side `side` centred half way along the line.
fn zone_halfway(line: &[Coord], side: f64) -> Polygon {
    let total: f64 = line.windows(2).map(|w| Euclidean.distance(w[0], w[1])).sum();
    let mut left = total / 2.0;
    let mut mid = line[0];
    for w in line.windows(2) {
        let len = Euclidean.distance(w[0], w[1]);
        if left <= len {
            mid = w[0] + (w[1] - w[0]) * (left / len);
            break;
        }
        left -= len;
    }
    let h = side / 2.0;
    Polygon::new(LineString::from(vec![(mid.x - h, mid.y - h), (mid.x + h, mid.y - h), (mid.x + h, mid.y + h), (mid.x - h, mid.y + h), (mid.x - h, mid.y - h)]), vec![])
}

struct Planned {
    /// Each trajectory line in the local frame, with its kind.
    lines: Vec<(String, Vec<Coord>)>,
    coverage: f64,
}

fn plan_corridor(frame: &LocalFrame, line: &[Coord], width: f64, zone: Option<&Polygon>, params: Value) -> Planned {
    let wgs = |c: &Coord| json!(frame.to_wgs84(*c));
    let area = json!({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"width_m": width},
        "geometry": {"type": "LineString", "coordinates": line.iter().map(wgs).collect::<Vec<_>>()}}]});
    let zones = zone.map(|z| json!({"type": "Polygon", "coordinates": [z.exterior().0.iter().map(wgs).collect::<Vec<_>>()]}));
    let mission = MissionGeometry { no_fly_zones: zones.as_ref(), ..MissionGeometry::area(&area) };
    let params: PlanParams = serde_json::from_value(params).expect("params");
    let out = plan(&mission, &params, &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned");
    let lines = out
        .trajectory
        .features
        .iter()
        .filter_map(|f| {
            let kind = f.properties.as_ref()?.get("kind")?.as_str()?.to_owned();
            let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { return None };
            Some((kind, coordinates.iter().map(|p| frame.to_local(p[0], p[1])).collect()))
        })
        .collect();
    Planned { lines, coverage: out.stats.coverage_ratio }
}

fn legs() -> impl Strategy<Value = Vec<(f64, f64)>> {
    // bends up to 150°: sharper than any turning radius flies
    prop::collection::vec((120.0..600.0f64, -150.0..150.0f64), 3..8)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]
    #[test]
    fn a_corridor_plan_covers_the_corridor_and_keeps_to_it(legs in legs(), width in 15.0..160.0f64, spacing in 20.0..60.0f64, fixed_wing in any::<bool>(), zoned in any::<bool>()) {
        let frame = LocalFrame::new(5.0, 52.0);
        let line = centre_line(&legs);
        let zone = zoned.then(|| zone_halfway(&line, 40.0));
        let profile = if fixed_wing { "generic_fixed_wing" } else { "iris" };
        let planned = plan_corridor(&frame, &line, width, zone.as_ref(), json!({"planner": "corridor", "line_spacing_m": spacing, "vehicle": {"profile": profile}}));
        // beside a zone the lines stop at its margin, a fixed wing's where it can still turn
        // (a half circle clear of the zone): the stretch before that is lost (down to 0.93 of
        // the corridor outside the zones in 418 cases, issue 55's closing note)
        // Legs shorter than twice the width bend again before a fixed wing's lines beside them
        // settle (it leaves a line at a bend sharper than it follows): there its coverage is
        // measured lower (down to 0.973 in 56 cases, issue 55's closing note)
        let tight = legs.iter().any(|&(length, _)| length < 2.0 * width);
        // a fixed wing's lines stop where a half turn (50 m) still clears the zone and its
        // margin: on each side of the zone at most that turn's reach and a line spacing of the
        // centre line is lost, a share that grows as the corridor shortens (0.865 measured on a
        // 414 m corridor 15 m wide, where this bound is 0.66)
        let length: f64 = legs.iter().map(|l| l.0).sum();
        let goal = match (zoned, fixed_wing) {
            (false, true) if tight => 0.95,
            (false, _) => 0.995,
            (true, false) => 0.95,
            (true, true) => (1.0 - 2.0 * (50.0 + spacing) / length).min(0.9),
        };
        prop_assert!(planned.coverage >= goal, "coverage {:.4}", planned.coverage);
        let centre = LineString::new(line.clone());
        // sweeps within the corridor (past its ends by half a swath), a fixed wing's out to
        // the mitred corners of its sharp bends (at most 4 offsets out, the mitre limit); turns
        // within the room a turning circle (50 m) needs beyond those
        let (reach, half) = (if fixed_wing { 2.0 * width } else { width / 2.0 }, spacing / 2.0);
        let room = if fixed_wing { 4.0 * 50.0 + spacing } else { spacing };
        for (kind, points) in &planned.lines {
            if let Some(z) = &zone {
                prop_assert!(!z.intersects(&LineString::new(points.clone())), "a {kind} enters the no-fly zone");
            }
            if kind == "transit" {
                continue;
            }
            for &p in points {
                let off = Euclidean.distance(&Point(p), &centre);
                let limit = if kind == "sweep" { reach + half + 1e-6 } else { reach + room };
                prop_assert!(off <= limit, "a {kind} point {off:.1} m from the centre line (width {width:.1})");
            }
        }
    }
}

#[test]
fn a_corridor_mission_refuses_what_it_cannot_plan() {
    let frame = LocalFrame::new(5.0, 52.0);
    let line: Vec<Value> = [(0.0, 0.0), (1000.0, 0.0)].iter().map(|&(x, y)| json!(frame.to_wgs84(Coord { x, y }))).collect();
    let plan_of = |area: Value, planner: &str| {
        let params: PlanParams = serde_json::from_value(json!({"planner": planner, "line_spacing_m": 20, "vehicle": {"profile": "iris"}})).unwrap();
        plan(&MissionGeometry::area(&area), &params, &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never())
    };
    let no_width = json!({"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": line}});
    let err = plan_of(no_width, "corridor").expect_err("refused");
    assert!(format!("{err:?}").contains("corridor_width_missing"), "{err:?}");
    let bare = json!({"type": "LineString", "coordinates": line});
    assert!(format!("{:?}", plan_of(bare, "corridor").err()).contains("corridor_width_missing"));
    let square: Vec<Value> = [(0.0, 100.0), (100.0, 100.0), (100.0, 200.0), (0.0, 200.0), (0.0, 100.0)].iter().map(|&(x, y)| json!(frame.to_wgs84(Coord { x, y }))).collect();
    let polygon = json!({"type": "Polygon", "coordinates": [square]});
    assert!(format!("{:?}", plan_of(polygon.clone(), "corridor").err()).contains("no_corridor"));
    let both = json!({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"width_m": 30}, "geometry": {"type": "LineString", "coordinates": line}},
        {"type": "Feature", "properties": {}, "geometry": polygon}]});
    assert!(format!("{:?}", plan_of(both.clone(), "corridor").err()).contains("not_for_planner"));
    // any other planner covers a corridor as the area it is
    let out = plan_of(both, "boustrophedon").expect("planned");
    assert!(out.stats.coverage_ratio >= 0.99, "coverage {}", out.stats.coverage_ratio);
}
