//! `coverplan bench --energy`: E-Spiral against E-BF on generated polygons as in seed 002
//! §5.1 (6 to 10 vertices, 200 to 600 m across, convex and concave), priced by the IRIS
//! model, lines 20 m apart and with the camera of its flights, with coverage and energy per
//! covered hectare; then EG-CPP's planning time, energy and optimality on rectangular grids of
//! 16 to 100 cells.

use std::fmt::Write;
use std::time::Instant;

use serde_json::{Value, json};

use crate::planner::{self, FieldLimits, MissionGeometry, PlanParams, Stop};

/// A small deterministic generator (xorshift64*), so that every run benches the same fields.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A star-shaped polygon of `n` vertices about `diameter` across, in metres: angles spread
/// with `irregularity` (0 = even), radii varied by `spikiness` (0 = convex, on a circle).
fn polygon(rng: &mut Rng, n: usize, diameter: f64, irregularity: f64, spikiness: f64) -> Vec<[f64; 2]> {
    let steps: Vec<f64> = (0..n).map(|_| 1.0 + irregularity * (2.0 * rng.next() - 1.0)).collect();
    let total: f64 = steps.iter().sum();
    let mut angle = rng.next() * std::f64::consts::TAU;
    (0..n)
        .map(|k| {
            angle += steps[k] / total * std::f64::consts::TAU;
            let r = diameter / 2.0 * (1.0 - spikiness * rng.next());
            [r * angle.cos(), r * angle.sin()]
        })
        .collect()
}

/// Metres around (10° E, 45° N) to a GeoJSON polygon.
fn geojson(points: &[[f64; 2]]) -> Value {
    let (lon0, lat0) = (10.0f64, 45.0f64);
    let mut ring: Vec<[f64; 2]> = points.iter().map(|p| [lon0 + p[0] / (111_320.0 * lat0.to_radians().cos()), lat0 + p[1] / 110_574.0]).collect();
    ring.push(ring[0]);
    json!({"type": "Polygon", "coordinates": [ring]})
}

/// How the polygons are flown: lines 20 m apart (seed 002 §5.1's simulations), or the camera
/// and overlaps of its flights (§5.1.2: 10 m up, a 100° lens of 2386 × 2386 px, 10 % side
/// overlap, none in front), where coverage is what the photos image.
const SET_UPS: [(&str, &str); 2] = [
    ("lines 20 m apart", r#"{"line_spacing_m": 20}"#),
    (
        "the flights' camera (10 m, 100°, 2386 × 2386 px, side overlap 0.1, front 0)",
        r#"{"camera": {"hfov_deg": 100, "image_width_px": 2386, "image_height_px": 2386}, "altitude_m": 10, "side_overlap": 0.1, "front_overlap": 0}"#,
    ),
];

fn plan(area: &Value, planner: &str, set_up: &Value, profiles: &[planner::vehicle::Vehicle]) -> Result<planner::PlanOutput, planner::PlanError> {
    let mut params = json!({"planner": planner, "vehicle": {"profile": "iris"}});
    params.as_object_mut().expect("an object").extend(set_up.as_object().expect("an object").clone());
    let params: PlanParams = serde_json::from_value(params).expect("params");
    let mission = MissionGeometry::area(area);
    planner::plan(&mission, &params, profiles, &FieldLimits::default(), &|_| true, &Stop::never())
}

/// Shoelace area of a ring in metres.
fn area_m2(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    (0..n).map(|i| points[i][0] * points[(i + 1) % n][1] - points[(i + 1) % n][0] * points[i][1]).sum::<f64>().abs() / 2.0
}

/// Share of the area a plan covers: what its photos image, with a camera.
fn coverage(p: &planner::PlanOutput) -> f64 {
    p.stats.photo_coverage_ratio.unwrap_or(p.stats.coverage_ratio)
}

/// One planner's results over a row of fields.
#[derive(Default)]
struct Tally {
    planned: usize,
    energy_j: f64,
    duration_s: f64,
    covered_ha: f64,
    least_coverage: Option<f64>,
    /// The first refusal, to say why a field was not planned.
    refusal: Option<String>,
}

impl Tally {
    fn add(&mut self, result: &Result<planner::PlanOutput, planner::PlanError>, area_m2: f64) {
        match result {
            Ok(p) => {
                self.planned += 1;
                self.energy_j += p.stats.energy_j;
                self.duration_s += p.stats.duration_s;
                self.covered_ha += coverage(p) * area_m2 / 1e4;
                self.least_coverage = Some(self.least_coverage.map_or(coverage(p), |c| c.min(coverage(p))));
            }
            Err(e) => {
                self.refusal.get_or_insert_with(|| e.to_string());
            }
        }
    }

    fn kj_per_ha(&self) -> f64 {
        self.energy_j / 1000.0 / self.covered_ha
    }
}

pub fn run(fields_per_row: usize, seed: u64) -> String {
    let mut profiles = planner::vehicle::builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5); // no sorties
    let mut out = String::new();
    let mut refusals = Vec::new();
    for (name, set_up) in SET_UPS {
        let set_up: Value = serde_json::from_str(set_up).expect("a set-up");
        let _ = write!(
            out,
            "E-Spiral against E-BF: IRIS model, {name}, {fields_per_row} generated polygons per row (seed {seed}), irregularity 0..0.5; \
             energy and time are means over the fields both planned, kJ/ha is energy per hectare covered\n\n\
             | vertices | shape | diameter m | planned E-BF | planned E-Spiral | E-BF kJ | E-Spiral kJ | E-BF kJ/ha | E-Spiral kJ/ha | spiral saves per ha | spiral cheaper per ha | E-BF s | E-Spiral s | least coverage E-BF | least coverage E-Spiral |\n\
             |---------:|:------|-----------:|-------------:|-----------------:|--------:|------------:|-----------:|---------------:|--------------------:|----------------------:|-------:|-----------:|-----------------:|--------------------:|\n"
        );
        // the same polygons for every set-up (xorshift needs a seed other than 0)
        let mut rng = Rng(seed.max(1));
        for n in 6..=10 {
            for (shape, spikiness) in [("convex", 0.0), ("concave", 0.4)] {
                for diameter in [200.0, 600.0] {
                    let (mut bf, mut sp) = (Tally::default(), Tally::default());
                    // over the fields both planned
                    let (mut both_bf, mut both_sp) = (Tally::default(), Tally::default());
                    let mut cheaper = 0;
                    for _ in 0..fields_per_row {
                        let irregularity = 0.5 * rng.next();
                        let points = polygon(&mut rng, n, diameter, irregularity, spikiness);
                        let (area, m2) = (geojson(&points), area_m2(&points));
                        let (b, s) = (plan(&area, "e_bf", &set_up, &profiles), plan(&area, "e_spiral", &set_up, &profiles));
                        bf.add(&b, m2);
                        sp.add(&s, m2);
                        if let (Ok(bo), Ok(so)) = (&b, &s) {
                            both_bf.add(&b, m2);
                            both_sp.add(&s, m2);
                            let per_ha = |o: &planner::PlanOutput| o.stats.energy_j / (coverage(o) * m2);
                            cheaper += usize::from(per_ha(so) < per_ha(bo));
                        }
                    }
                    let both = both_bf.planned.max(1) as f64;
                    let least = |t: &Tally| t.least_coverage.map_or("-".to_string(), |c| format!("{c:.4}"));
                    let _ = writeln!(
                        out,
                        "| {n:8} | {shape:7} | {diameter:10.0} | {:>6} of {fields_per_row:<3} | {:>8} of {fields_per_row:<5} | {:7.1} | {:11.1} | {:10.1} | {:14.1} | {:18.1} % | {cheaper:>10} of {:<8} | {:6.0} | {:10.0} | {:>16} | {:>19} |",
                        bf.planned,
                        sp.planned,
                        both_bf.energy_j / both / 1000.0,
                        both_sp.energy_j / both / 1000.0,
                        both_bf.kj_per_ha(),
                        both_sp.kj_per_ha(),
                        100.0 * (1.0 - both_sp.kj_per_ha() / both_bf.kj_per_ha()),
                        both_bf.planned,
                        both_bf.duration_s / both,
                        both_sp.duration_s / both,
                        least(&bf),
                        least(&sp),
                    );
                    for (planner, t) in [("e_bf", &bf), ("e_spiral", &sp)] {
                        if let Some(why) = &t.refusal {
                            refusals.push(format!("- {name}: {planner}, {n} vertices, {shape}, {diameter:.0} m: {why}"));
                        }
                    }
                }
            }
        }
        out.push('\n');
    }
    if !refusals.is_empty() {
        out.push_str("\nFirst refusal per row and planner:\n\n");
        out.push_str(&refusals.join("\n"));
        out.push('\n');
    }
    out.push_str(
        "\nEG-CPP: rectangles of n × 4 cells 20 m apart, every start cell searched (IRIS)\n\n| cells | plan ms | energy kJ | result | gap |\n|------:|--------:|----------:|:-------|----:|\n",
    );
    for cells in [16, 20, 24, 28, 32, 36, 40, 48, 60, 80, 100] {
        // half a cell short of n × 4 cells of 20 m: the frame's rounding adds no row or column
        let (w, h) = (20.0 * (cells / 4) as f64 - 10.0, 70.0);
        let area = geojson(&[[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]);
        let t = Instant::now();
        let result = plan(&area, "eg_cpp", &json!({"line_spacing_m": 20}), &profiles);
        let ms = t.elapsed().as_secs_f64() * 1000.0;
        let (energy, note, gap) = match result.as_ref().map(|p| (&p.stats, p.stats.optimality)) {
            Ok((st, Some(o))) => (format!("{:.1}", st.energy_j / 1000.0), format!("{} ({} cells)", o.status.as_str(), st.cells), format!("{:.1} %", 100.0 * o.gap)),
            Ok((st, None)) => (format!("{:.1}", st.energy_j / 1000.0), "planned".into(), "-".into()),
            Err(e) => ("-".into(), format!("refused: {e}"), "-".into()),
        };
        let _ = writeln!(out, "| {cells:5} | {ms:7.0} | {energy:>9} | {note} | {gap} |");
    }
    out
}
