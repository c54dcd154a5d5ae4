//! `coverplan bench --patrol`: the patrolling experiments of seed 002 §5.3 (patrolling spec §7)
//! on our simulator: a 50 × 50 grid, 4 UAVs from the lower-left corner, 30 seeds per row, next
//! to the published means. Absolute values depend on tie details the source leaves open; the
//! orderings are what should carry over.

use std::fmt::Write as _;
use std::time::Instant;

use crate::planner::patrol::{CellGrid, Evaporation, PatrolMetrics, Sharing, Strategy, UpdateRule, Valleys, metrics_over_seeds, simulate, simulate_shared_cycle};

pub const SEEDS: u64 = 30;

/// Mean and population standard deviation.
fn mean_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    (mean, (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt())
}

/// The metrics of `strategy` over 30 seeds of the reference set-up, `cycles` long.
pub fn runs(strategy: &Strategy, cycles: u32) -> Vec<PatrolMetrics> {
    metrics_over_seeds(&CellGrid::open(50, 50), strategy, &[0; 4], cycles, 0..SEEDS)
}

/// (QMI mean, QMI SD, SDF mean, NTM mean) over 30 seeds.
pub fn summary(strategy: &Strategy, cycles: u32) -> (f64, f64, f64, f64) {
    let m = runs(strategy, cycles);
    let (qmi, qmi_sd) = mean_sd(&m.iter().map(|m| m.qmi).collect::<Vec<_>>());
    let (sdf, _) = mean_sd(&m.iter().map(|m| m.sdf).collect::<Vec<_>>());
    let (ntm, _) = mean_sd(&m.iter().map(|m| m.ntm as f64).collect::<Vec<_>>());
    (qmi, qmi_sd, sdf, ntm)
}

fn evaporation(interval: u32) -> Option<Evaporation> {
    Some(Evaporation { factor: 0.1, interval, continuous: false })
}

pub fn run() -> String {
    let started = Instant::now();
    let nd = Strategy::nc_drone();
    let own = |sharing| Strategy { sharing, ..nd };
    let methods: [(&str, Strategy, [f64; 3], [&str; 3]); 8] = [
        ("centralised NC-Drone", nd, [768.55, 770.34, 773.48], ["0.73 / 5.8k", "0.75 / 9.9k", "0.76 / 14.5k"]),
        ("NC", Strategy::classic(UpdateRule::Nc), [806.62, 826.70, 829.54], ["0.84 / 23.7k", "0.84 / 35.6k", "0.83 / 47.5k"]),
        ("LRTA*", Strategy::classic(UpdateRule::Lrta), [805.73, 820.97, 828.07], ["0.83 / 24.2k", "0.78 / 36.3k", "0.84 / 48.4k"]),
        ("TVUR", Strategy::classic(UpdateRule::Tvur), [791.89, 808.93, 813.12], ["0.87 / 24.0k", "0.84 / 36.0k", "0.84 / 48.1k"]),
        ("WVUR", Strategy::classic(UpdateRule::Wvur), [816.55, 831.88, 840.48], ["0.77 / 23.8k", "0.76 / 35.7k", "0.76 / 47.6k"]),
        ("decentralised MULTI", own(Sharing::Multi), [849.80, 884.63, 895.21], ["1.14 / 7.9k", "1.14 / 13.8k", "1.16 / 20.0k"]),
        ("decentralised MAX", own(Sharing::Max), [797.58, 816.81, 825.43], ["2.10 / 6.5k", "2.50 / 11.1k", "2.92 / 15.5k"]),
        ("decentralised AVG", own(Sharing::Avg), [795.57, 813.00, 823.67], ["2.21 / 6.4k", "2.77 / 10.8k", "3.14 / 15.8k"]),
    ];
    let mut out = format!(
        "Patrolling (seed 002 §5.3): 50 × 50 cells, 4 UAVs from the lower-left corner, {SEEDS} seeds per row; ours against the published means\n\n\
         | method | cycles | QMI ours | QMI published | SDF ours | NTM ours | SDF / NTM published |\n|:---|---:|---:|---:|---:|---:|:---|\n"
    );
    for (name, strategy, qmi_published, rest) in &methods {
        for (k, cycles) in [10_000, 15_000, 20_000].into_iter().enumerate() {
            let (qmi, sd, sdf, ntm) = summary(strategy, cycles);
            let _ = writeln!(out, "| {name} | {cycles} | {qmi:.2} ± {sd:.2} | {:.2} | {sdf:.2} | {:.1}k | {} |", qmi_published[k], ntm / 1000.0, rest[k]);
        }
    }
    let strategies: Vec<(String, Strategy, &str)> = vec![
        ("centralised-WS".into(), Strategy { watershed: Some(Valleys::Visits), ..nd }, "745.87 ± 7.96 / 7.4k"),
        ("centralised-TS".into(), Strategy { time_ties: true, ..nd }, "752.39 ± 29.74 / 5.4k"),
        ("centralised-WSTS".into(), Strategy { watershed: Some(Valleys::LastVisit), ..nd }, "747.30 ± 4.12 / 8.1k"),
        ("centralised-ES-100".into(), Strategy { evaporation: evaporation(100), ..nd }, "700.97 / ≈3× baseline"),
        ("centralised-ES-250".into(), Strategy { evaporation: evaporation(250), ..nd }, "702.49 / ≈3× baseline"),
        ("centralised-ES-500".into(), Strategy { evaporation: evaporation(500), ..nd }, "706.60 / ≈3× baseline"),
        ("centralised-ES-1000".into(), Strategy { evaporation: evaporation(1000), ..nd }, "705.69 / ≈3× baseline"),
        ("MULTI-ES-100".into(), Strategy { evaporation: evaporation(100), ..own(Sharing::Multi) }, "806.84 ± 14.18"),
        ("MAX-ES-100".into(), Strategy { evaporation: evaporation(100), ..own(Sharing::Max) }, "789.98 ± 10.59"),
        ("AVG-ES-100".into(), Strategy { evaporation: evaporation(100), ..own(Sharing::Avg) }, "791.13–794.95"),
        ("CFS-50".into(), Strategy { sync_interval: 50, ..own(Sharing::Periodic) }, "= centralised"),
        ("CFS-100".into(), Strategy { sync_interval: 100, ..own(Sharing::Periodic) }, "+7–8 % per doubling"),
        ("CFS-250".into(), Strategy { sync_interval: 250, ..own(Sharing::Periodic) }, ""),
        (
            "CFS-WS-ES-Time-50".into(),
            Strategy { sync_interval: 50, watershed: Some(Valleys::Visits), evaporation: evaporation(100), time_ties: true, ..own(Sharing::Periodic) },
            "742.64 / 0.85 / 8.9k",
        ),
        (
            "CFS-WSTS-ES-Time-50".into(),
            Strategy { sync_interval: 50, watershed: Some(Valleys::LastVisit), evaporation: evaporation(100), time_ties: true, ..own(Sharing::Periodic) },
            "739.40 / 1.02 / 9.6k",
        ),
    ];
    out.push_str("\nStrategies at 20 000 cycles (the source does not state the length of these runs; its baseline: QMI 772.33 ± 33.24, NTM 5.7k)\n\n| strategy | QMI ours | SDF ours | NTM ours | published |\n|:---|---:|---:|---:|:---|\n");
    for (name, strategy, published) in &strategies {
        let (qmi, sd, sdf, ntm) = summary(strategy, 20_000);
        let _ = writeln!(out, "| {name} | {qmi:.2} ± {sd:.2} | {sdf:.2} | {:.1}k | {published} |", ntm / 1000.0);
    }
    let grid = CellGrid::open(50, 50);
    let fixed = simulate_shared_cycle(&grid, 0, 4, 20_000).metrics;
    let _ = writeln!(out, "| shared cycle (predictable, one run: no randomness) | {:.2} | {:.2} | {:.1}k | not in the source |", fixed.qmi, fixed.sdf, fixed.ntm as f64 / 1000.0);
    let one = Instant::now();
    simulate(&grid, &nd, &[0; 4], 20_000, 0, &|| false).expect("not stopped");
    let one_ms = one.elapsed().as_secs_f64() * 1000.0;
    let thirty = Instant::now();
    runs(&nd, 20_000);
    let _ = writeln!(
        out,
        "\nTime: one centralised NC-Drone patrol of 4 UAVs × 20 000 cycles on 50 × 50 cells {one_ms:.1} ms; 30 seeds of it {:.0} ms; this whole table {:.1} s.",
        thirty.elapsed().as_secs_f64() * 1000.0,
        started.elapsed().as_secs_f64()
    );
    out
}
