//! Measuring a plan: its lengths, time, energy, coverage and intrusions.

use geo::{Area, MultiPolygon};

use super::coverage::{covered_by, length_inside, under};
use super::photos::{Photo, pass_strips, photo_strips};
use super::{PassStats, Stats};
use crate::camera::CameraPlan;
use crate::energy::PathEstimate;
use crate::params::math_to_bearing;
use crate::path::{FlightPath, Look, Piece, PieceKind};
use crate::sortie::SortieTotals;

pub struct MeasureInput<'a> {
    /// The whole flight: its sorties one after another.
    pub path: &'a FlightPath,
    pub sorties: &'a [FlightPath],
    /// One per sortie.
    pub estimates: &'a [PathEstimate],
    /// Energy one battery gives above its reserve, for each sortie (a fleet's drones differ).
    pub usable_j: &'a [f64],
    /// Batteries the flights need (see [`Stats::batteries_needed`]), counted per vehicle.
    pub batteries_needed: usize,
    pub region: &'a MultiPolygon,
    /// [`swept`] of `path`.
    pub swept: &'a MultiPolygon,
    /// The swaths' areas summed ([`swept_and_strip_area`]).
    pub strip_area_m2: f64,
    pub no_fly_zones: &'a MultiPolygon,
    pub spacing: f64,
    pub sweep_heading_deg: f64,
    pub cells: usize,
    pub photos: Option<(&'a [Photo], CameraPlan)>,
}

pub fn measure(m: &MeasureInput<'_>) -> Stats {
    // from +0: an empty sum is -0.0, which the stats would show as "-0.0"
    let by_kind = |k: PieceKind| m.path.pieces.iter().filter(|p| p.kind == k).fold(0.0, |sum, p| sum + p.length());
    let length_m = m.path.length();
    let energy_j: f64 = m.estimates.iter().map(PathEstimate::energy_j).sum();
    let area = m.region.unsigned_area();
    let lower_bound_m = area / m.spacing;
    let (covered, swept) = under(m.swept, m.region);
    let share = |imaged: &[geo::Polygon]| if area > 0.0 { (covered_by(imaged, m.region).0 / area).min(1.0) } else { 0.0 };
    let passes = m.photos.map_or_else(Vec::new, |(photos, _)| passes(m.path, photos, &share));
    // an oblique plan's: its nadir pass's, measured with the passes
    let photo_coverage_ratio = m.photos.map(|(photos, cam)| match passes.first() {
        Some(nadir) => nadir.photo_coverage_ratio,
        None => share(&photo_strips(photos, cam.footprint_across_m, cam.footprint_along_m)),
    });
    Stats {
        length_m,
        sweep_length_m: by_kind(PieceKind::Sweep),
        turn_length_m: by_kind(PieceKind::Turn),
        transit_length_m: by_kind(PieceKind::Transit),
        duration_s: m.estimates.iter().map(PathEstimate::duration_s).sum(),
        energy_j,
        energy_wh: energy_j / 3600.0,
        takeoff_landing_energy_j: m.estimates.iter().map(|e| e.takeoff_landing_j()).sum(),
        sorties: m.sorties.len(),
        sortie_totals: m
            .sorties
            .iter()
            .zip(m.estimates)
            .zip(m.usable_j)
            .enumerate()
            .map(|(k, ((s, e), usable_j))| SortieTotals {
                sortie: k + 1,
                vehicle: None,
                sweep_lines: s.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count(),
                length_m: s.length(),
                duration_s: e.duration_s(),
                energy_j: e.energy_j(),
                battery_used: e.energy_j() / usable_j,
            })
            .collect(),
        batteries_needed: m.batteries_needed,
        warnings: Vec::new(),
        planner: String::new(),
        alternatives: Vec::new(),
        coverage_ratio: if area > 0.0 { (covered / area).min(1.0) } else { 0.0 },
        photo_coverage_ratio,
        overlap_ratio: if swept > 0.0 { (m.strip_area_m2 / swept - 1.0).max(0.0) } else { 0.0 },
        area_to_cover_m2: area,
        turns: m.path.pieces.iter().filter(|p| p.kind == PieceKind::Turn).count(),
        nfz_intrusion_m: length_inside(m.path, m.no_fly_zones),
        sweep_lines: m.path.pieces.iter().filter(|p| p.kind == PieceKind::Sweep).count(),
        cells: m.cells,
        photos: m.photos.map_or(0, |(p, _)| p.len()),
        line_spacing_m: m.spacing,
        sweep_heading_deg: m.sweep_heading_deg,
        lower_bound_m,
        efficiency: if length_m > 0.0 { lower_bound_m / length_m } else { 0.0 },
        planning_time_ms: 0.0,
        lost_coverage_m: 0.0,
        optimality: None,
        makespan_s: None,
        vehicles: Vec::new(),
        conflicts: None,
        ground: None,
        inspection_coverage: None,
        inspection: None,
        terrain: None,
        resume: None,
        wind: None,
        begins_at: None,
        ends_at: None,
        passes,
    }
}

/// Each pass of an oblique plan (none for another plan).
fn passes(path: &FlightPath, photos: &[Photo], share: &dyn Fn(&[geo::Polygon]) -> f64) -> Vec<PassStats> {
    let mut looks: Vec<Look> = path.pieces.iter().filter_map(|p| p.look).collect();
    looks.sort_by_key(|l| l.pass);
    looks.dedup_by_key(|l| l.pass);
    looks
        .into_iter()
        .map(|look| {
            let on_pass = || path.pieces.iter().filter(move |p| p.look.is_some_and(|l| l.pass == look.pass));
            PassStats {
                pass: look.pass,
                gimbal_pitch_deg: look.gimbal_pitch_deg,
                camera_heading_deg: look.heading.map(math_to_bearing),
                photos: photos.iter().filter(|p| p.look.is_some_and(|l| l.pass == look.pass)).count(),
                length_m: on_pass().map(Piece::length).sum(),
                sweep_length_m: on_pass().filter(|p| p.kind == PieceKind::Sweep).map(Piece::length).sum(),
                photo_coverage_ratio: share(&pass_strips(photos, look.pass)),
            }
        })
        .collect()
}
