//! `landing_sites` over generated corridors longer than a battery flies there and back: each
//! sortie lands at home or a landing site, the next takes off where it landed, every sortie
//! fits its battery, and the flight files take off and land where the plan does.

use coverplan_planner::export::{self, AltitudeFrame, ExportOptions, ExportRequest, Firmware};
use coverplan_planner::frame::LocalFrame;
use coverplan_planner::vehicle::builtin_profiles;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanParams, Stop, archive, plan};
use geo::Coord;
use proptest::prelude::*;
use serde_json::{Value, json};

use super::corridors::centre_line;

/// Points every `every` metres along `line`, `side` metres to its left and right in turn.
fn beside(line: &[Coord], every: f64, side: f64) -> Vec<Coord> {
    let mut places = Vec::new();
    let mut next = every;
    let mut walked = 0.0;
    for w in line.windows(2) {
        let d = w[1] - w[0];
        let length = d.x.hypot(d.y);
        let (along, normal) = (d / length, Coord { x: -d.y / length, y: d.x / length });
        while next <= walked + length {
            let sign = if places.len() % 2 == 0 { 1.0 } else { -1.0 };
            places.push(w[0] + along * (next - walked) + normal * (side * sign));
            next += every;
        }
        walked += length;
    }
    places
}

/// Each sortie's points in order (`[lon, lat]`), from the trajectory's `sortie` property.
fn sorties(trajectory: &geojson::FeatureCollection) -> Vec<Vec<[f64; 2]>> {
    let mut out: Vec<Vec<[f64; 2]>> = Vec::new();
    for f in &trajectory.features {
        let Some(geojson::GeometryValue::LineString { coordinates }) = f.geometry.as_ref().map(|g| &g.value) else { continue };
        let Some(k) = f.property("sortie").and_then(Value::as_u64) else { continue };
        let k = k as usize - 1;
        if out.len() <= k {
            out.resize(k + 1, Vec::new());
        }
        out[k].extend(coordinates.iter().map(|p| [p[0], p[1]]));
    }
    out
}

fn legs() -> impl Strategy<Value = Vec<(f64, f64)>> {
    // gentle bends on long legs: coverage is another test's; this one is about where sorties land
    prop::collection::vec((1500.0..3000.0f64, -60.0..60.0f64), 3..5)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]
    #[test]
    fn sorties_hop_along_a_corridor_between_landing_sites(legs in legs(), every in 0.5..1.0f64, side in 40.0..120.0f64, fixed_wing in any::<bool>()) {
        let frame = LocalFrame::new(5.0, 52.0);
        let line = centre_line(&legs);
        let wgs = |c: Coord| frame.to_wgs84(c);
        let area = json!({"type": "Feature", "properties": {"width_m": 60}, "geometry": {"type": "LineString", "coordinates": line.iter().map(|&c| wgs(c)).collect::<Vec<_>>()}});
        let home = wgs(Coord { x: -80.0, y: -60.0 });
        // sites a fraction of a battery's range apart (about 4 km for either)
        let (profile, battery_wh, landing, range) = if fixed_wing { ("generic_fixed_wing", 12.0, "auto", 4000.0) } else { ("iris", 40.0, "return", 4000.0) };
        let sites: Vec<[f64; 2]> = beside(&line, every * range / 4.0, side).into_iter().map(wgs).collect();
        let mission = MissionGeometry { home: Some(home), ..MissionGeometry::area(&area) };
        let params = |sites: &[[f64; 2]]| -> PlanParams {
            serde_json::from_value(json!({"planner": "corridor", "altitude_m": 40, "vehicle": {"profile": profile, "battery_wh": battery_wh},
                "landing": landing, "landing_sites": sites, "max_sorties": 100, "camera": {"preset": "dji_mavic3_enterprise"}, "side_overlap": 0.3})).unwrap()
        };
        let with_sites = params(&sites);
        let profiles = builtin_profiles();
        let out = plan(&mission, &with_sites, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned with landing sites");
        let hops = sorties(&out.trajectory);
        prop_assert!(hops.len() >= 2, "{} sortie", hops.len());
        prop_assert!(out.stats.coverage_ratio >= 0.99, "coverage {:.4}", out.stats.coverage_ratio);
        let places: Vec<[f64; 2]> = std::iter::once(home).chain(sites.iter().copied()).collect();
        let metres = |a: [f64; 2], b: [f64; 2]| { let (p, q) = (frame.to_local(a[0], a[1]), frame.to_local(b[0], b[1])); (p.x - q.x).hypot(p.y - q.y) };
        let place_at = |p: [f64; 2]| places.iter().copied().find(|&q| metres(p, q) < 0.5);
        for (k, points) in hops.iter().enumerate() {
            let (first, last) = (points[0], *points.last().unwrap());
            prop_assert!(place_at(first).is_some(), "sortie {} takes off away from home and every landing site", k + 1);
            prop_assert!(place_at(last).is_some(), "sortie {} lands away from home and every landing site", k + 1);
            if k > 0 {
                prop_assert!(metres(first, *hops[k - 1].last().unwrap()) < 0.5, "sortie {} does not take off where sortie {} landed", k + 1, k);
            }
        }
        for s in &out.stats.sortie_totals {
            prop_assert!(s.battery_used <= 1.0 + 1e-9, "sortie {} uses {:.3} of its battery", s.sortie, s.battery_used);
        }
        // from home alone the far end costs more flying, when it can be reached at all
        if let Ok(alone) = plan(&mission, &params(&[]), &profiles, &FieldLimits::default(), &|_| true, &Stop::never()) {
            prop_assert!(alone.stats.length_m > out.stats.length_m, "from home alone {:.0} m, hopping {:.0} m", alone.stats.length_m, out.stats.length_m);
        }

        // the flight files: each sortie's home where it takes off; one landing elsewhere lands
        // there itself (a return would fly back to where it took off)
        let options = ExportOptions { firmware: Firmware::Ardupilot, altitude_frame: AltitudeFrame::Amsl, altitude_m: None, max_waypoints: None };
        let request = ExportRequest { name: "hops", mission: mission.clone(), params: &with_sites, profiles: &profiles, trajectory: &out.trajectory, options };
        let zip = export::export("waypoints", &request).unwrap().bytes;
        let files = archive::unzip(&zip).unwrap();
        prop_assert_eq!(files.len(), hops.len());
        for (k, (name, bytes)) in files.iter().enumerate() {
            let text = std::str::from_utf8(bytes).unwrap();
            let home_item: Vec<f64> = text.lines().nth(1).unwrap().split('\t').map(|v| v.parse().unwrap()).collect();
            prop_assert!(metres([home_item[9], home_item[8]], hops[k][0]) < 0.5, "{name}: home item away from where the sortie takes off");
            let items = export::wpl::read(text).unwrap();
            let last = items.last().unwrap();
            let (from, to) = (hops[k][0], *hops[k].last().unwrap());
            if metres(from, to) < 0.5 && landing == "return" {
                prop_assert_eq!(last.command, 20, "{}: a sortie back where it took off returns to launch", name);
            } else {
                let at = last.position.unwrap();
                prop_assert_eq!(last.command, 21, "{}: a sortie landing at another site lands itself", name);
                prop_assert!(metres([at[1], at[0]], to) < 0.5, "{name}: lands away from where the plan lands");
            }
        }
        if !fixed_wing {
            let request = ExportRequest { options: ExportOptions { max_waypoints: Some(65_535), ..options }, ..request };
            let kmzs = archive::unzip(&export::export("wpml", &request).unwrap().bytes).unwrap();
            for (k, (name, kmz)) in kmzs.iter().enumerate() {
                let parts = archive::unzip(kmz).unwrap();
                let waylines = String::from_utf8(parts.into_iter().find(|p| p.0 == "wpmz/waylines.wpml").unwrap().1).unwrap();
                let elsewhere = metres(hops[k][0], *hops[k].last().unwrap()) >= 0.5;
                let finish = if elsewhere { "autoLand" } else { "goHome" };
                prop_assert!(waylines.contains(&format!("<wpml:finishAction>{finish}</wpml:finishAction>")), "{name}: no finishAction {finish}");
            }
        }
    }
}

#[test]
fn landing_sites_are_refused_where_they_mean_nothing() {
    let frame = LocalFrame::new(5.0, 52.0);
    let line: Vec<[f64; 2]> = [(0.0, 0.0), (3000.0, 0.0)].iter().map(|&(x, y)| frame.to_wgs84(Coord { x, y })).collect();
    let area = json!({"type": "Feature", "properties": {"width_m": 60}, "geometry": {"type": "LineString", "coordinates": line}});
    let site = frame.to_wgs84(Coord { x: 1500.0, y: 80.0 });
    let refused = |home: Option<[f64; 2]>, extra: Value| {
        let mut body = json!({"planner": "corridor", "line_spacing_m": 30, "vehicle": {"profile": "iris"}, "landing_sites": [site]});
        body.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        let params: PlanParams = serde_json::from_value(body).unwrap();
        let mission = MissionGeometry { home, ..MissionGeometry::area(&area) };
        let err = plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect_err("refused");
        format!("{err:?}")
    };
    let home = Some(frame.to_wgs84(Coord { x: -50.0, y: 0.0 }));
    assert!(refused(None, json!({})).contains("home_missing"));
    assert!(refused(home, json!({"vehicle": {"profile": "generic_fixed_wing"}})).contains("not_landing"));
    assert!(refused(home, json!({"vehicle": {"profile": "tractor_sprayer"}, "planner": "headland", "line_spacing_m": null})).contains("not_for_ground_vehicles"));
    let fleet = refused(home, json!({"vehicle": {}, "fleet": [{"profile": "iris"}, {"profile": "iris"}], "planner": "boustrophedon"}));
    assert!(fleet.contains("landing_sites_for_fleet"), "{fleet}");
    let in_zone = {
        let z: Vec<[f64; 2]> = [(1400.0, 0.0), (1600.0, 0.0), (1600.0, 200.0), (1400.0, 200.0), (1400.0, 0.0)].iter().map(|&(x, y)| frame.to_wgs84(Coord { x, y })).collect();
        let zones = json!({"type": "Polygon", "coordinates": [z]});
        let params: PlanParams = serde_json::from_value(json!({"planner": "corridor", "line_spacing_m": 30, "vehicle": {"profile": "iris"}, "landing_sites": [site]})).unwrap();
        let mission = MissionGeometry { home, no_fly_zones: Some(&zones), ..MissionGeometry::area(&area) };
        plan(&mission, &params, &builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect_err("refused")
    };
    let in_zone = format!("{in_zone:?}");
    assert!(in_zone.contains("point_in_no_fly_zone") && in_zone.contains("/landing_sites/0"), "{in_zone}");
}
