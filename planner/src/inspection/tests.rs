//! Properties of inspection plans over generated scenes: no leg comes nearer a structure,
//! obstacle or no-fly zone than the clearance, or leaves the area; the reward is the weighted
//! union of what the flown viewpoints see, recomputed afresh; the budget holds; the same seed
//! gives the same plan.

use geo::{Coord, Distance, Euclidean, MultiPolygon, Point, Polygon, Rotate, Translate, polygon};
use proptest::prelude::*;

use super::*;
use crate::field::Structure;
use crate::params::inspection::{BudgetLimit, Extension, InspectionSpec};
use crate::vehicle::builtin_profiles;

fn rectangle(w: f64, d: f64) -> Polygon {
    polygon![(x: -w / 2.0, y: -d / 2.0), (x: w / 2.0, y: -d / 2.0), (x: w / 2.0, y: d / 2.0), (x: -w / 2.0, y: d / 2.0)]
}

/// A building: footprint size, turn, place, height and base.
fn building() -> impl Strategy<Value = (f64, f64, f64, f64, f64, f64, f64)> {
    (4.0..14.0f64, 4.0..14.0f64, 0.0..90.0f64, -25.0..25.0f64, -25.0..25.0f64, 3.0..18.0f64, prop_oneof![3 => Just(0.0), 1 => 0.5..4.0f64])
}

struct Case {
    structures: Vec<Structure>,
    obstacles: Vec<(Polygon, f64)>,
    no_fly: MultiPolygon,
    fence: MultiPolygon,
    spec: InspectionSpec,
}

fn spec(budget: BudgetLimit, extension: Extension, seed: u64) -> InspectionSpec {
    InspectionSpec {
        targets: Vec::new(),
        budget,
        poi_spacing_m: 1.0,
        range_m: Some([0.5, 10.0]),
        max_incidence_deg: 75.0,
        gimbal_pitch_deg: [-90.0, 30.0],
        body_radius_m: 0.5,
        safety_margin_m: 1.5,
        altitude_range_m: None,
        viewpoints: 40,
        extension,
        extension_per_iteration: 5,
        capture_s: 1.0,
        show_unseen: false,
        seed,
        search_time: std::time::Duration::from_secs(30),
        start_altitude_m: 0.0,
        end_altitude_m: 0.0,
    }
}

fn run(case: &Case, iris: &Vehicle) -> InspectionPlan {
    let input = InspectionInput {
        structures: &case.structures,
        obstacles: &case.obstacles,
        no_fly_zones: &case.no_fly,
        geofence: &case.fence,
        vehicle: iris,
        spec: &case.spec,
        fov_deg: [70.0, 55.0],
        gsd_range_m: None,
        start: Coord { x: -45.0, y: -45.0 },
        end: Coord { x: 45.0, y: -45.0 },
    };
    plan(&input, &|_| true, &Stop::never()).expect("planned")
}

/// 3D distance from `p` to the prism of `footprint` between `lo` and `hi`.
fn distance_to_prism(p: [f64; 3], footprint: &Polygon, lo: f64, hi: f64) -> f64 {
    let flat = Euclidean.distance(&Point::new(p[0], p[1]), footprint);
    let dz = (lo - p[2]).max(p[2] - hi).max(0.0);
    flat.hypot(dz)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

    #[test]
    fn inspection_plans_keep_clear_see_what_they_claim_and_fit_the_budget(
        buildings in prop::collection::vec(building(), 1..4),
        tree in prop::option::of((-30.0..30.0f64, -30.0..30.0f64, 1.0..3.0f64, 4.0..12.0f64)),
        zone in prop::option::of((-30.0..30.0f64, -30.0..30.0f64, 3.0..10.0f64)),
        budget_kind in 0..3usize,
        budget_scale in 0.2..1.5f64,
        extension in prop_oneof![Just(Extension::None), Just(Extension::Sphere), Just(Extension::Ellipse)],
        seed in 0..1000u64,
    ) {
        let structures: Vec<Structure> = buildings.iter().enumerate().map(|(i, &(w, d, turn, x, y, h, base))| Structure {
            name: format!("b{i}"),
            footprint: rectangle(w, d).rotate_around_point(turn, Point::new(0.0, 0.0)).translate(x, y),
            base_m: base,
            height_m: h,
            pointer: String::new(),
            mesh: None,
        }).collect();
        let obstacles: Vec<(Polygon, f64)> = tree.map(|(x, y, r, h)| {
            let ring: Vec<Coord> = (0..16).map(|k| { let a = std::f64::consts::TAU * k as f64 / 16.0; Coord { x: x + r * a.cos(), y: y + r * a.sin() } }).collect();
            (Polygon::new(ring.into(), Vec::new()), h)
        }).into_iter().collect();
        let no_fly = MultiPolygon(zone.map(|(x, y, s)| rectangle(s, s).translate(x, y)).into_iter().collect());
        let budget = match budget_kind {
            0 => BudgetLimit::LengthM(400.0 * budget_scale),
            1 => BudgetLimit::TimeS(300.0 * budget_scale),
            _ => BudgetLimit::EnergyJ(60_000.0 * budget_scale),
        };
        let case = Case { structures, obstacles, no_fly, fence: MultiPolygon(vec![rectangle(100.0, 100.0)]), spec: spec(budget, extension, seed) };
        let iris = builtin_profiles().into_iter().find(|v| v.profile == "iris").unwrap();
        let input = InspectionInput {
            structures: &case.structures, obstacles: &case.obstacles, no_fly_zones: &case.no_fly, geofence: &case.fence, vehicle: &iris,
            spec: &case.spec, fov_deg: [70.0, 55.0], gsd_range_m: None, start: Coord { x: -45.0, y: -45.0 }, end: Coord { x: 45.0, y: -45.0 },
        };
        let planned = match plan(&input, &|_| true, &Stop::never()) {
            Ok(p) => p,
            // a start or end that the generated scene blocks is refused, not planned
            Err(PlanError::Input(e)) if e.code == "position_not_free" || e.code == "budget_too_small" => return Ok(()),
            Err(PlanError::Infeasible(why)) if why.contains("no free way") || why.contains("no viewpoint") => return Ok(()),
            Err(e) => panic!("{e:?}"),
        };
        let clearance = case.spec.body_radius_m + case.spec.safety_margin_m;

        // the path: from the start to the end, legs joined
        let points: Vec<[f64; 3]> = planned.legs.iter().flat_map(|l| l.points.iter().copied()).collect();
        prop_assert_eq!(points[0], [-45.0, -45.0, 0.0]);
        prop_assert_eq!(*points.last().unwrap(), [45.0, -45.0, 0.0]);
        for w in planned.legs.windows(2) {
            prop_assert_eq!(w[0].points.last(), w[1].points.first());
        }
        // clear of every solid and zone, inside the area, sampled every 5 cm
        let solids: Vec<(&Polygon, f64, f64)> = case.structures.iter().map(|s| (&s.footprint, s.base_m, s.base_m + s.height_m))
            .chain(case.obstacles.iter().map(|(p, h)| (p, 0.0, *h))).collect();
        let last = planned.legs.len() - 1;
        for (i, leg) in planned.legs.iter().enumerate() {
            // the legs from the start and to the end may come from outside the area
            let fenced = i != 0 && i != last;
            for w in leg.points.windows(2) {
                let len = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2) + (w[1][2] - w[0][2]).powi(2)).sqrt();
                let steps = (len / 0.05).ceil().max(1.0) as usize;
                for k in 0..=steps {
                    let t = k as f64 / steps as f64;
                    let p: [f64; 3] = std::array::from_fn(|i| w[0][i] + (w[1][i] - w[0][i]) * t);
                    prop_assert!(p[2] >= -1e-9);
                    for (footprint, lo, hi) in &solids {
                        let d = distance_to_prism(p, footprint, *lo, *hi);
                        prop_assert!(d >= clearance - 1e-6, "{p:?} is {d} m from a solid");
                    }
                    for z in &case.no_fly {
                        prop_assert!(Euclidean.distance(&Point::new(p[0], p[1]), z) >= clearance - 1e-6, "{p:?} near a no-fly zone");
                    }
                    prop_assert!(!fenced || geo::Intersects::intersects(&case.fence, &Point::new(p[0], p[1])), "{p:?} outside the area");
                }
            }
        }
        // the reward: the union of what the flown viewpoints see, recomputed
        let prisms: Vec<Prism> = case.structures.iter().map(|s| Prism { name: s.name.clone(), footprint: s.footprint.clone(), base_m: s.base_m, top_m: s.base_m + s.height_m, is_structure: true, mesh: None })
            .chain(case.obstacles.iter().map(|(p, h)| Prism { name: "o".into(), footprint: p.clone(), base_m: 0.0, top_m: *h, is_structure: false, mesh: None })).collect();
        let scene = Scene::new(prisms, &case.no_fly, case.fence.clone(), case.spec.body_radius_m, case.spec.safety_margin_m);
        let index = poi::index(&planned.pois);
        let mut seen = vec![false; planned.pois.len()];
        for v in &planned.viewpoints {
            for i in visibility::visible(&scene, &planned.pois, &index, &planned.optics, &v.pose) {
                seen[i as usize] = true;
            }
        }
        prop_assert_eq!(&seen, &planned.seen);
        let weighted: f64 = planned.pois.iter().zip(&seen).filter(|(_, s)| **s).map(|(p, _)| p.weight).sum();
        let stats = planned.stats();
        let ins = stats.inspection.as_ref().unwrap();
        prop_assert!((weighted - ins.weighted_seen).abs() <= 1e-9 * weighted.max(1.0));
        prop_assert_eq!(ins.pois_seen, seen.iter().filter(|s| **s).count());
        prop_assert_eq!(planned.viewpoints.iter().map(|v| v.new_pois).sum::<usize>(), ins.pois_seen);
        // the budget
        prop_assert!(planned.budget_used <= case.spec.budget.value() * (1.0 + 1e-9), "{} over {:?}", planned.budget_used, case.spec.budget);
        let measured = case.spec.budget.measure(stats.length_m, stats.duration_s, stats.energy_j);
        prop_assert!((measured - planned.budget_used).abs() <= 1e-6 * measured.max(1.0), "{measured} vs {}", planned.budget_used);
        // the same seed, the same plan (when both searches ended on their counts, not the
        // clock: a debug build under load can take the second run past the time limit)
        if planned.search_end != SearchEnd::TimeLimit {
            let again = run(&case, &iris);
            if again.search_end != SearchEnd::TimeLimit {
                prop_assert_eq!(&again.legs, &planned.legs);
                prop_assert_eq!(&again.viewpoints, &planned.viewpoints);
            }
        }
    }
}
