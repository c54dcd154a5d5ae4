//! The finished plan: its flights measured into the statistics (coverage, photos, energy,
//! a ground vehicle's, a fleet's and terrain figures), and its trajectory written as GeoJSON.

use geo::BooleanOps;

use super::compose::{self, FleetPlan, Flight, Prepared};
use super::error::PlanError;
use super::export;
use super::metrics::{self, Stats};
use super::params;
use super::path::FlightPath;

/// The statistics and the trajectory of `flights` (a fleet's when `fleet` says so); `terrain`:
/// the plan follows an elevation model.
pub(crate) fn finish(prepared: &Prepared, flights: &[Option<Flight>], fleet: Option<FleetPlan>, terrain: bool) -> Result<(Stats, geojson::FeatureCollection), PlanError> {
    let Prepared { resolved, field, region, keep_out, .. } = prepared;
    let flown: Vec<&Flight> = flights.iter().flatten().collect();
    let sorties: Vec<FlightPath> = flown.iter().flat_map(|f| f.sorties.iter().cloned()).collect();
    let estimates: Vec<crate::energy::PathEstimate> = flown.iter().flat_map(|f| f.estimates.iter().cloned()).collect();
    let usable_j: Vec<f64> = flown.iter().flat_map(|f| std::iter::repeat_n(f.vehicle.battery.usable_j(), f.sorties.len())).collect();
    let path = FlightPath { pieces: sorties.iter().flat_map(|s| s.pieces.iter().cloned()).collect() };
    let photos = resolved
        .camera
        .map(|c| flown.iter().flat_map(|f| f.sorties.iter().flat_map(move |s| metrics::photo_positions(s, &c.footprint(), Some(f.planned.sweep_angle)))).collect::<Vec<_>>());
    // measured by the planner when its one sortie is its path as planned
    let measured = match flown.as_slice() {
        [f] if f.sorties.len() == 1 && f.sorties[0] == f.planned.path => f.planned.swept.clone(),
        _ => None,
    };
    let (swept, strip_area_m2) = measured.unwrap_or_else(|| metrics::swept_and_strip_area(&path));
    let main = flown.first().ok_or_else(|| PlanError::Infeasible("no drone of the fleet has a part to fly".into()))?;
    let input = metrics::MeasureInput {
        path: &path,
        swept: &swept,
        strip_area_m2,
        sorties: &sorties,
        estimates: &estimates,
        usable_j: &usable_j,
        batteries_needed: flown.iter().map(|f| f.batteries_needed()).sum(),
        region,
        no_fly_zones: &field.no_fly_zones,
        spacing: resolved.line_spacing_m,
        sweep_heading_deg: params::math_to_bearing(main.planned.sweep_angle) % 180.0,
        cells: flown.iter().map(|f| f.planned.cells).sum(),
        photos: photos.as_ref().map(|p| (p.as_slice(), resolved.camera.expect("camera"))),
    };
    // three measures of the same swept ground, each a few set operations: side by side
    let ground_stats = || {
        prepared.ground.as_ref().map(|ground| {
            let h = &ground.headland;
            metrics::ground_stats(&path, &swept, &ground.spec, (&h.mainland, &h.band), &field.area, keep_out)
        })
    };
    let ((mut stats, uncovered), ground_stats) =
        rayon::join(|| rayon::join(|| metrics::measure(&input), || metrics::uncovered(&swept, &field.area.difference(&field.no_fly_zones))), ground_stats);
    stats.ground =
        ground_stats.map(|g| metrics::GroundStats { payload: crate::route::refill::PayloadStats::together(flown.iter().filter_map(|f| f.planned.payload.as_ref())), ..g });
    if fleet.is_none() {
        stats.begins_at = path.pieces.first().map(|p| field.frame.to_wgs84(p.start()));
        stats.ends_at = path.end().map(|c| field.frame.to_wgs84(c));
    }
    stats.wind = resolved.wind.map(|w| {
        let still_air: Option<Vec<(f64, f64)>> = flown.iter().map(|f| f.still_air_in_wind).collect();
        let total = |pick: fn(&(f64, f64)) -> f64| still_air.as_ref().map(|s| s.iter().map(pick).sum());
        metrics::WindStats { speed_mps: w.speed_mps, from_deg: w.from_deg, still_air_plan_duration_s: total(|s| s.0), still_air_plan_energy_j: total(|s| s.1) }
    });
    if terrain {
        compose::report_terrain(&flown, &mut stats);
    }
    let vehicle_flights: Vec<export::geojson::VehicleFlight<'_>> = flights
        .iter()
        .enumerate()
        .filter_map(|(k, f)| f.as_ref().map(|f| (k, f)))
        .map(|(k, f)| export::geojson::VehicleFlight {
            sorties: &f.sorties,
            estimates: &f.estimates,
            usable_j: f.vehicle.battery.usable_j(),
            battery_swaps: &f.battery_swaps,
            vehicle: fleet.is_some().then_some(k),
            laid: &f.laid,
        })
        .collect();
    let marks = export::geojson::Marks { photos: photos.as_deref(), uncovered: &uncovered };
    let trajectory = export::geojson::feature_collection(&field.frame, &vehicle_flights, resolved.altitude_m, &marks);
    for (k, f) in flights.iter().enumerate() {
        let Some(f) = f else { continue };
        if f.battery_swaps.is_empty() {
            continue;
        }
        let batteries = f.battery_swaps.len() + 1;
        let whose = if fleet.is_some() { format!("drone {k}'s part") } else { "this plan".to_string() };
        stats.warnings.push(format!(
            "{whose} needs {batteries} batteries ({:.0} kJ; {:.0} kJ usable per battery): without a home it is one route, with a battery_swap point where each \
             battery runs out; give the mission a home to fly it in sorties with return flights",
            f.needed_j / 1000.0,
            f.vehicle.battery.usable_j() / 1000.0
        ));
    }
    if let Some(fleet) = fleet {
        fleet.report(flights, &field.frame, &mut stats);
    }
    stats.lost_coverage_m = flown.iter().map(|f| f.lost_coverage_m).sum();
    stats.planner = main.planned.planner.unwrap_or(prepared.planner.id()).to_string();
    stats.alternatives = main.planned.alternatives.clone();
    stats.optimality = main.planned.optimality;
    Ok((stats, trajectory))
}
