//! Planner `inspection` through the public entry point, from WGS84 GeoJSON: seed 001's first
//! scene rebuilt (spec `inspection.md` §11): one 8 × 8 m building of 4 floors (12 m), points
//! of interest every 0.5 m on its walls and roof, the source's camera (57° × 44.3°, 160 × 120
//! px) and range (0.3–5.5 m), a 0.5 m body.

use coverplan_planner::frame::LocalFrame;
use coverplan_planner::{FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop, plan};
use geo::Coord;
use serde_json::{Value, json};

/// The building's corner at the frame's origin; the area a 60 m square around it.
pub fn scene_one() -> (Value, Value, [f64; 2]) {
    let frame = LocalFrame::new(10.0, 52.0);
    let at = |x: f64, y: f64| {
        let [lon, lat] = frame.to_wgs84(Coord { x, y });
        json!([lon, lat])
    };
    let ring = |pts: &[(f64, f64)]| {
        let mut r: Vec<Value> = pts.iter().map(|&(x, y)| at(x, y)).collect();
        r.push(r[0].clone());
        json!([r])
    };
    let area = json!({"type": "Polygon", "coordinates": ring(&[(-26.0, -26.0), (34.0, -26.0), (34.0, 34.0), (-26.0, 34.0)])});
    let structures = json!({"type": "FeatureCollection", "features": [{
        "type": "Feature",
        "properties": {"name": "scene-1", "height_m": 12.0},
        "geometry": {"type": "Polygon", "coordinates": ring(&[(0.0, 0.0), (8.0, 0.0), (8.0, 8.0), (0.0, 8.0)])},
    }]});
    let home = frame.to_wgs84(Coord { x: -12.0, y: 4.0 });
    (area, structures, home)
}

pub fn scene_one_params(budget_m: f64, extension: &str, seed: u64) -> PlanParams {
    serde_json::from_value(json!({
        "planner": "inspection",
        "camera": {"hfov_deg": 57.0, "image_width_px": 160, "image_height_px": 120},
        "budget": {"max_length_m": budget_m},
        "inspection": {"range_m": [0.3, 5.5], "body_radius_m": 0.5, "safety_margin_m": 0.5, "viewpoints": 300, "extension": extension},
        "seed": seed,
        "time_limit_s": 120,
    }))
    .unwrap()
}

pub fn plan_scene_one(params: &PlanParams) -> PlanOutput {
    let (area, structures, home) = scene_one();
    let mission = MissionGeometry { structures: Some(&structures), home: Some(home), ..MissionGeometry::area(&area) };
    plan(&mission, params, &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned")
}

#[test]
fn scene_one_reaches_the_reference_shares() {
    for (extension, least) in [("none", 0.84), ("sphere", 0.95)] {
        let out = plan_scene_one(&scene_one_params(200.0, extension, 1));
        let st = &out.stats;
        let ins = st.inspection.as_ref().unwrap();
        eprintln!(
            "scene 1, 200 m, extension {extension}: {:.4} of {} points seen, {} viewpoints ({} sampled), {:.1} m, {} iterations ({}), {:.0} ms",
            st.inspection_coverage.unwrap(),
            ins.pois,
            ins.viewpoints,
            ins.viewpoints_sampled,
            st.length_m,
            ins.iterations,
            ins.search_end,
            st.planning_time_ms
        );
        assert_eq!(ins.pois, 4 * 16 * 24 + 16 * 16);
        assert!(st.length_m <= 200.0 + 1e-6 && (ins.budget_used - st.length_m).abs() < 1e-6);
        assert!(st.inspection_coverage.unwrap() >= least, "extension {extension}: {:?} below {least}", st.inspection_coverage);
    }
}

#[test]
fn the_share_seen_rises_with_the_budget() {
    let shares: Vec<f64> = [50.0, 100.0, 200.0].iter().map(|&b| plan_scene_one(&scene_one_params(b, "none", 2)).stats.inspection_coverage.unwrap()).collect();
    eprintln!("scene 1 without extension at 50, 100, 200 m: {shares:?}");
    assert!(shares.windows(2).all(|w| w[1] > w[0]), "{shares:?}");
}

/// Spec §9: raising one target's weight must not lower its seen share. Two buildings 30 m
/// apart, a budget that cannot see both whole.
#[test]
fn a_higher_priority_is_seen_at_least_as_much() {
    let frame = LocalFrame::new(10.0, 52.0);
    let at = |x: f64, y: f64| {
        let [lon, lat] = frame.to_wgs84(Coord { x, y });
        json!([lon, lat])
    };
    let square = |x0: f64| {
        let mut r: Vec<Value> = [(x0, 0.0), (x0 + 8.0, 0.0), (x0 + 8.0, 8.0), (x0, 8.0)].iter().map(|&(x, y)| at(x, y)).collect();
        r.push(r[0].clone());
        json!([r])
    };
    let area = {
        let mut r: Vec<Value> = [(-40.0, -30.0), (60.0, -30.0), (60.0, 40.0), (-40.0, 40.0)].iter().map(|&(x, y)| at(x, y)).collect();
        r.push(r[0].clone());
        json!({"type": "Polygon", "coordinates": [r]})
    };
    let structures = json!({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "west", "height_m": 8.0}, "geometry": {"type": "Polygon", "coordinates": square(-15.0)}},
        {"type": "Feature", "properties": {"name": "east", "height_m": 8.0}, "geometry": {"type": "Polygon", "coordinates": square(15.0)}},
    ]});
    let home = frame.to_wgs84(Coord { x: 4.0, y: -20.0 });
    let mission = MissionGeometry { structures: Some(&structures), home: Some(home), ..MissionGeometry::area(&area) };
    let share_of_east = |priority: f64| {
        let params: PlanParams = serde_json::from_value(json!({
            "planner": "inspection",
            "budget": {"max_length_m": 150},
            "targets": [{"name": "west"}, {"name": "east", "priority": priority}],
            "inspection": {"range_m": [0.5, 8], "extension": "none", "viewpoints": 200},
            "seed": 4,
        }))
        .unwrap();
        let out = plan(&mission, &params, &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned");
        let targets = out.stats.inspection.unwrap().targets;
        let seen: usize = targets.iter().filter(|t| t.name == "east").map(|t| t.seen).sum();
        let total: usize = targets.iter().filter(|t| t.name == "east").map(|t| t.total).sum();
        seen as f64 / total as f64
    };
    let (even, raised) = (share_of_east(1.0), share_of_east(5.0));
    eprintln!("east seen at priority 1: {even:.3}, at 5: {raised:.3}");
    assert!(raised >= even, "{raised} < {even}");
    assert!(raised > 0.0);
}

/// Scene 1's building as a Wavefront OBJ model (a box without a floor, faces wound outwards,
/// y up as modelling tools write it) placed at the same corner: seen as well as the prism.
#[test]
fn a_model_is_inspected_like_its_prism() {
    let obj = "o scene-1\nv 0 0 0\nv 8 0 0\nv 8 0 -8\nv 0 0 -8\nv 0 12 0\nv 8 12 0\nv 8 12 -8\nv 0 12 -8\n\
               f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\nf 5 6 7 8\n";
    let (area, _, home) = scene_one();
    let frame = LocalFrame::new(10.0, 52.0);
    let corner = frame.to_wgs84(Coord { x: 0.0, y: 0.0 });
    let structures = json!({"type": "FeatureCollection", "features": [{
        "type": "Feature", "properties": {"name": "model", "obj": obj, "up": "y"}, "geometry": {"type": "Point", "coordinates": corner},
    }]});
    let mission = MissionGeometry { structures: Some(&structures), home: Some(home), ..MissionGeometry::area(&area) };
    let out =
        plan(&mission, &scene_one_params(200.0, "none", 1), &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).expect("planned");
    let ins = out.stats.inspection.unwrap();
    let area_seen: Vec<(String, String, usize)> = ins.targets.iter().map(|t| (t.name.clone(), t.face.clone(), t.total)).collect();
    eprintln!("scene 1 as a model: {:.4} seen, {area_seen:?}", out.stats.inspection_coverage.unwrap());
    assert_eq!(ins.targets.len(), 2);
    assert!(out.stats.inspection_coverage.unwrap() >= 0.84, "{:?}", out.stats.inspection_coverage);
    assert!(out.stats.length_m <= 200.0 + 1e-6);
    // a model reaching below the ground is refused with its place
    let low = json!({"type": "FeatureCollection", "features": [{
        "type": "Feature", "properties": {"obj": "v 0 0 -1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}, "geometry": {"type": "Point", "coordinates": corner},
    }]});
    let mission = MissionGeometry { structures: Some(&low), ..mission };
    let refused =
        plan(&mission, &scene_one_params(200.0, "none", 1), &coverplan_planner::vehicle::builtin_profiles(), &FieldLimits::default(), &|_| true, &Stop::never()).unwrap_err();
    assert!(refused.to_string().contains("below the ground"), "{refused}");
}
