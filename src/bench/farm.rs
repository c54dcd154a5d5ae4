//! `coverplan bench --farm`: whole farms. First the scheduler alone on generated farms (fields
//! of 2 to 60 ha within 20 km of three depots, worked at 30 ha/h, 10-hour days), per class of
//! fields and machines: the makespan over its lower bound, the transit share, the time to
//! schedule. Then a farm plan end to end through the service (in process, SQLite, a worker per
//! core): `--farm-fields` generated fields with holes as missions, a 36 m sprayer's plans, four
//! machines over ten days: seconds from the request to the schedule, and peak memory.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use anyhow::Context;
use serde_json::{Value, json};

use super::{Stream, peak_mb, quantile, reset_peak};
use crate::config::Config;
use crate::planner::Stop;
use crate::planner::farm::{self, FieldWork, Machine, StraightLine, Window};

/// Metres per degree of latitude.
const M_PER_DEG: f64 = 111_195.0;
/// The farms' place: near Wageningen.
const ORIGIN: [f64; 2] = [5.66, 51.98];
/// The three depots, metres east and north of the origin.
const DEPOTS: [(f64, f64); 3] = [(0.0, 0.0), (24_000.0, 3_000.0), (11_000.0, 20_000.0)];
/// Fields lie within this many metres of a depot.
const FIELD_RADIUS_M: f64 = 20_000.0;
/// What a 36 m sprayer works an hour, turns included.
const HECTARES_PER_HOUR: f64 = 30.0;

fn lon_lat(east: f64, north: f64) -> [f64; 2] {
    [ORIGIN[0] + east / (M_PER_DEG * ORIGIN[1].to_radians().cos()), ORIGIN[1] + north / M_PER_DEG]
}

/// A generated field: its centre (metres from the origin) and area.
struct GeneratedField {
    centre: (f64, f64),
    hectares: f64,
}

fn generate(n: usize, seed: u64) -> Vec<GeneratedField> {
    let mut rng = Stream(seed.wrapping_mul(0x9E37).wrapping_add(51));
    (0..n)
        .map(|_| {
            let depot = DEPOTS[(rng.next() * 3.0) as usize % 3];
            let (r, a) = (FIELD_RADIUS_M * rng.next().sqrt(), rng.next() * std::f64::consts::TAU);
            GeneratedField { centre: (depot.0 + r * a.cos(), depot.1 + r * a.sin()), hectares: 2.0 + 58.0 * rng.next() }
        })
        .collect()
}

fn machines(n: usize) -> Vec<Machine> {
    (0..n)
        .map(|k| Machine {
            name: Some(format!("sprayer {}", k + 1)),
            depot: lon_lat(DEPOTS[k % 3].0, DEPOTS[k % 3].1),
            hours_per_day: None,
            road_speed_mps: Some(8.3),
            endurance_s: Some(3.0 * 3600.0),
            refill_s: Some(1_200.0),
        })
        .collect()
}

fn window(days: u32) -> Window {
    Window { start_date: "2027-04-12".into(), days, hours_per_day: Some(10.0), day_start: Some("07:00".into()) }
}

/// Runs both tables; `service_fields` fields go through the service (0: the scheduler only).
pub fn run(repeats: usize, service_fields: usize) -> anyhow::Result<String> {
    let mut out = String::new();
    writeln!(
        out,
        "Generated farms: fields of 2 to 60 ha within {} km of three depots, worked at {HECTARES_PER_HOUR} ha/h (entry and exit 300 m apart), 10-hour days, \
         machines at the depots in turn with a 3-hour tank and 20-minute refills, 30 km/h between fields in a straight line; {repeats} seeds a class. \
         Bound: the greatest of the total work over the machines, the longest field with its transits, and the bound that counts each field's nearest arrival, each day's drive home and the refills a day needs (docs/methods.md, farms §4). Idle: day ends left unused.\n",
        FIELD_RADIUS_M / 1000.0
    )?;
    writeln!(out, "| fields | machines | makespan / bound, median | max | transit share, median | idle share, median | days used, median | schedule ms, median | max |")?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|")?;
    for fields in [100, 400, 1000] {
        for machines_n in [2, 4, 8] {
            let (mut ratio, mut transit, mut idle, mut days, mut ms) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for seed in 0..repeats as u64 {
                let works: Vec<FieldWork> = generate(fields, seed)
                    .iter()
                    .map(|f| FieldWork { entry: lon_lat(f.centre.0, f.centre.1), exit: lon_lat(f.centre.0 + 300.0, f.centre.1), work_s: f.hectares / HECTARES_PER_HOUR * 3600.0 })
                    .collect();
                let started = Instant::now();
                let s = farm::schedule(&works, &machines(machines_n), &window(60), &StraightLine, &Stop::never())?;
                ms.push(started.elapsed().as_secs_f64() * 1000.0);
                ratio.push(s.makespan_over_bound);
                transit.push(s.transit_share);
                idle.push(s.idle_s / s.machines.iter().map(|m| m.working_time_s).sum::<f64>());
                days.push(f64::from(s.days_used));
            }
            let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
            writeln!(
                out,
                "| {fields} | {machines_n} | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} | {:.0} | {:.0} |",
                quantile(&mut ratio.clone(), 0.5),
                max(&ratio),
                quantile(&mut transit, 0.5),
                quantile(&mut idle, 0.5),
                quantile(&mut days, 0.5),
                quantile(&mut ms.clone(), 0.5),
                max(&ms)
            )?;
        }
    }
    if service_fields > 0 {
        out += &tokio::runtime::Runtime::new()?.block_on(through_the_service(service_fields))?;
    }
    Ok(out)
}

/// A field's polygon: a jittered octagon of `hectares` round `centre`, with a pond in the
/// middle of every second field.
fn field_geometry(f: &GeneratedField, k: usize, rng: &mut Stream) -> Value {
    let radius = (f.hectares * 10_000.0 / (2.0 * 2f64.sqrt())).sqrt();
    let ring = |r: f64, jitter: f64, rng: &mut Stream| -> Vec<[f64; 2]> {
        let mut ring: Vec<[f64; 2]> = (0..8)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 8.0;
                let r = r * (1.0 - jitter + 2.0 * jitter * rng.next());
                lon_lat(f.centre.0 + r * a.cos(), f.centre.1 + r * a.sin())
            })
            .collect();
        ring.push(ring[0]);
        ring
    };
    let mut rings = vec![ring(radius, 0.15, rng)];
    if k.is_multiple_of(2) {
        let mut pond = ring(radius * 0.12, 0.0, rng);
        pond.reverse();
        rings.push(pond);
    }
    json!({"type": "Polygon", "coordinates": rings})
}

async fn through_the_service(n: usize) -> anyhow::Result<String> {
    let dir = std::env::temp_dir().join(format!("coverplan-bench-farm-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await?;
    let base = format!("http://{}", listener.local_addr()?);
    let mut config = Config::new(listener.local_addr()?, format!("sqlite://{}?mode=rwc", dir.join("bench.db").display()));
    config.workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    let workers = config.workers;
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(crate::server::serve(listener, config, async move {
        let _ = stopped.await;
    }));
    let client = reqwest::Client::new();
    let ready = async {
        for _ in 0..400 {
            if client.get(format!("{base}/readyz")).send().await.is_ok_and(|r| r.status() == 200) {
                return true;
            }
            tokio::time::sleep(Duration::from_millis(25)).await;
        }
        false
    };
    anyhow::ensure!(ready.await, "the server did not become ready");
    let mut rng = Stream(7);
    let mut ids = Vec::with_capacity(n);
    for (k, f) in generate(n, 1).iter().enumerate() {
        let body = json!({"name": format!("field {k}"), "area": field_geometry(f, k, &mut rng)});
        let made: Value = client.post(format!("{base}/api/v1/missions")).json(&body).send().await?.json().await?;
        ids.push(made["id"].as_str().with_context(|| format!("field {k} refused: {made}"))?.to_owned());
    }
    reset_peak();
    let request = json!({
        "name": "bench farm", "missions": ids, "machines": machines(4), "window": window(10),
        "params": {"vehicle": {"profile": "tractor_sprayer", "working_width_m": 36, "min_turn_radius_m": 8}, "headland_passes": 1},
    });
    let started = Instant::now();
    let posted: Value = client.post(format!("{base}/api/v1/farm-plans")).json(&request).send().await?.json().await?;
    let id = posted["id"].as_str().with_context(|| format!("the farm plan was refused: {posted}"))?.to_owned();
    let farm = loop {
        let farm: Value = client.get(format!("{base}/api/v1/farm-plans/{id}")).send().await?.json().await?;
        if farm["status"] != "planning" {
            break farm;
        }
        anyhow::ensure!(started.elapsed() < Duration::from_secs(1_800), "the farm plan took more than 30 minutes");
        tokio::time::sleep(Duration::from_millis(250)).await;
    };
    let seconds = started.elapsed().as_secs_f64();
    let peak = peak_mb().unwrap_or(f64::NAN);
    let _ = stop.send(());
    let _ = server.await;
    let _ = std::fs::remove_dir_all(&dir);
    let s = &farm["schedule"];
    let planned = farm["fields"].as_array().map_or(0, |f| f.iter().filter(|f| f["status"] == "succeeded").count());
    let hours = |v: &Value| v.as_f64().unwrap_or(f64::NAN) / 3600.0;
    let mut out = String::new();
    writeln!(out, "\n### A farm plan through the service\n")?;
    writeln!(
        out,
        "{n} generated fields (every second one with a pond) as missions, planned for a 36 m sprayer turning on 8 m with one headland pass; four machines at the three depots, \
         ten 10-hour days from 2027-04-12; in process on SQLite with {workers} workers; time from the request to the schedule, peak memory of the whole process.\n"
    )?;
    writeln!(out, "| fields | planned | s | peak MB | makespan h | bound h | makespan / bound | transit share | days used | fits the window |")?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|---|")?;
    writeln!(
        out,
        "| {n} | {planned} | {seconds:.1} | {peak:.0} | {:.1} | {:.1} | {:.3} | {:.3} | {} | {} |",
        hours(&s["makespan_s"]),
        hours(&s["lower_bound_s"]),
        s["makespan_over_bound"].as_f64().unwrap_or(f64::NAN),
        s["transit_share"].as_f64().unwrap_or(f64::NAN),
        s["days_used"],
        s["fits_window"]
    )?;
    Ok(out)
}
