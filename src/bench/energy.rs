//! `coverplan bench --energy`: E-Spiral against E-BF on generated polygons as in seed 002
//! §5.1 (6 to 10 vertices, 200 to 600 m across, convex and concave), priced by the IRIS
//! model; then EG-CPP's planning time on rectangular grids of 16 to 48 cells.

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

fn plan(area: &Value, planner: &str, profiles: &[planner::vehicle::Vehicle]) -> Result<planner::PlanOutput, planner::PlanError> {
    let params: PlanParams = serde_json::from_value(json!({"planner": planner, "line_spacing_m": 20, "vehicle": {"profile": "iris"}})).expect("params");
    let mission = MissionGeometry { area, no_fly_zones: None, obstacles: None, home: None };
    planner::plan(&mission, &params, profiles, &FieldLimits::default(), &|_| true, &Stop::never())
}

pub fn run(fields_per_row: usize) -> String {
    let mut profiles = planner::vehicle::builtin_profiles();
    profiles.iter_mut().for_each(|v| v.battery.energy_wh = 1e5); // no sorties
    let mut out = format!(
        "E-Spiral against E-BF: IRIS model, lines 20 m apart, {fields_per_row} generated polygons per row, irregularity 0..0.5\n\n\
         | vertices | shape | diameter m | fields | E-BF kJ | E-Spiral kJ | spiral saves | spiral cheaper | E-BF s | E-Spiral s | spiral coverage |\n\
         |---------:|:------|-----------:|-------:|--------:|------------:|-------------:|---------------:|-------:|-----------:|----------------:|\n"
    );
    let mut rng = Rng(0x5eed_0002);
    for n in 6..=10 {
        for (shape, spikiness) in [("convex", 0.0), ("concave", 0.4)] {
            for diameter in [200.0, 600.0] {
                let (mut bf, mut sp, mut bf_t, mut sp_t, mut wins, mut cov, mut count) = (0.0, 0.0, 0.0, 0.0, 0, f64::INFINITY, 0);
                for _ in 0..fields_per_row {
                    let irregularity = 0.5 * rng.next();
                    let area = geojson(&polygon(&mut rng, n, diameter, irregularity, spikiness));
                    let (Ok(b), Ok(s)) = (plan(&area, "e_bf", &profiles), plan(&area, "e_spiral", &profiles)) else { continue };
                    bf += b.stats.energy_j;
                    sp += s.stats.energy_j;
                    bf_t += b.stats.duration_s;
                    sp_t += s.stats.duration_s;
                    wins += usize::from(s.stats.energy_j < b.stats.energy_j);
                    cov = f64::min(cov, s.stats.coverage_ratio);
                    count += 1;
                }
                let k = count.max(1) as f64;
                let _ = writeln!(
                    out,
                    "| {n:8} | {shape:5} | {diameter:10.0} | {count:6} | {:7.1} | {:11.1} | {:10.1} % | {wins:>8} of {count:<3} | {:6.0} | {:10.0} | {cov:15.4} |",
                    bf / k / 1000.0,
                    sp / k / 1000.0,
                    100.0 * (1.0 - sp / bf),
                    bf_t / k,
                    sp_t / k,
                );
            }
        }
    }
    out.push_str(
        "\nEG-CPP: rectangles of n × 4 cells 20 m apart, every start cell searched (IRIS)\n\n| cells | plan ms | energy kJ | result | gap |\n|------:|--------:|----------:|:-------|----:|\n",
    );
    for cells in [16, 20, 24, 28, 32, 36, 40, 48, 60, 80, 100] {
        // half a cell short of n × 4 cells of 20 m: the frame's rounding adds no row or column
        let (w, h) = (20.0 * (cells / 4) as f64 - 10.0, 70.0);
        let area = geojson(&[[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]);
        let t = Instant::now();
        let result = plan(&area, "eg_cpp", &profiles);
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
