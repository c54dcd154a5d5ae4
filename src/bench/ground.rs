//! `coverplan bench --ground`: planner `headland` on the real fields at the configuration of
//! the Fields2Cover 2.1 figures measured on this machine (5 m wide, turning radius 3 m,
//! headland 10 m, its route planner with Dubins turns), and with a 6 m sprayer turning on 7 m
//! with two headland passes on the real and the generated fields, and on the real fields
//! with 3 passes forward, reversing, with slow steering and both: path length (and from the
//! first swath to the last: Fields2Cover's route drives no headland passes), turns and their shapes,
//! turns leaving the field or crossing a hole, mainland and headland coverage, planning time
//! (median of the runs) and peak memory; then the sprayer's refill trips against the operator's
//! rule, and two or three sprayers sharing a field.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{Value, json};

use super::{peak_mb, quantile, reset_peak};
use crate::planner::{self, FieldLimits, MissionGeometry, PlanOutput, PlanParams, Stop};

/// Fields2Cover 2.1 on this machine, process start included: (field, path m, turns, seconds).
const F2C: [(&str, f64, usize, f64); 5] = [
    ("nl-parcel-17ha", 32_316.0, 76, 1.6),
    ("nl-parcel-b", 6_220.0, 30, 0.5),
    ("us-field-two-cells", 26_202.0, 72, 1.5),
    ("us-field-two-cells-1", 45_642.0, 112, 2.6),
    ("ee-field-3-holes", 3_027.0, 44, 1.0),
];

fn params(width: f64, radius: f64, headland: Value) -> anyhow::Result<PlanParams> {
    let mut p = json!({"vehicle": {"kind": "ground", "working_width_m": width, "turn_radius_m": radius}});
    p.as_object_mut().context("object")?.extend(headland.as_object().context("object")?.clone());
    Ok(serde_json::from_value(p)?)
}

/// The plan of `mission` (median time over `repeats` runs, peak memory of the last), or the
/// reason it was refused.
fn plan(mission: &Value, params: &PlanParams, repeats: usize) -> Result<(PlanOutput, f64, f64), String> {
    let m = MissionGeometry::area(&mission["area"]);
    let profiles = planner::vehicle::builtin_profiles();
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..repeats {
        reset_peak();
        let started = Instant::now();
        let out = planner::plan(&m, params, &profiles, &FieldLimits::default(), &|_| true, &Stop::never()).map_err(|e| e.to_string())?;
        times.push(started.elapsed().as_secs_f64() * 1000.0);
        last = Some(out);
    }
    Ok((last.expect("one run"), quantile(&mut times, 0.5), peak_mb().unwrap_or(f64::NAN)))
}

/// The length from the first swath's start to the last swath's end: the swaths, the turns
/// and transits between them, not the headland passes nor the ways to and between them.
fn swath_to_swath_m(o: &PlanOutput) -> f64 {
    let pieces: Vec<(&str, f64)> = o
        .trajectory
        .features
        .iter()
        .filter_map(|f| {
            let p = f.properties.as_ref()?;
            Some((p.get("kind")?.as_str()?, p.get("length_m")?.as_f64()?))
        })
        .collect();
    let first = pieces.iter().position(|p| p.0 == "sweep");
    let last = pieces.iter().rposition(|p| p.0 == "sweep");
    match (first, last) {
        (Some(a), Some(b)) => pieces[a..=b].iter().map(|p| p.1).sum(),
        _ => 0.0,
    }
}

fn row(out: &mut String, name: &str, result: Result<(PlanOutput, f64, f64), String>, f2c: Option<(f64, usize, f64)>) {
    let (o, ms, mb) = match result {
        Ok(r) => r,
        Err(e) => {
            let _ = writeln!(out, "| {name} | refused: {e} |");
            return;
        }
    };
    let (s, g) = (&o.stats, o.stats.ground.clone().unwrap_or_default());
    let without = swath_to_swath_m(&o);
    let (theirs, ratio, their_turns, speedup) = match f2c {
        Some((len, turns, secs)) => (format!("{len:.0}"), format!("{:.3}", without / len), turns.to_string(), format!("{:.0}×", secs * 1000.0 / ms)),
        None => ("".into(), "".into(), "".into(), "".into()),
    };
    let _ = writeln!(
        out,
        "| {name} | {:.0} | {without:.0} | {theirs} | {ratio} | {} ({} U, {} Ω, {} fishtail) + {} along a pass + {} along a track + {} across | {their_turns} | {} | {} | {:.3} | {:.3} | {} | {:.3} | {ms:.0} | {speedup} | {mb:.0} |",
        s.length_m,
        // the corners' manoeuvres have a column of their own
        s.turns - g.corner_manoeuvres,
        g.u_turns,
        g.omega_turns,
        g.fishtail_turns,
        g.headland_drives,
        g.track_crossings,
        g.mainland_crossings,
        g.turns_leaving_field,
        g.turns_crossing_holes,
        g.mainland_coverage,
        g.headland_coverage,
        g.corner_manoeuvres,
        s.coverage_ratio
    );
}

const HEADER: &str = "| field | length m | first to last swath m | F2C m | ratio | swath to swath: turns, drives along a pass, crossings along a swath's track, across the crop | F2C turns | leaving field | crossing holes | mainland cov | headland cov | corners worked | field cov | ms | vs F2C | peak MB |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// `only`: the fields (real or generated) to plan, all when empty.
pub fn run(random_dir: &Path, repeats: usize, only: &[String]) -> anyhow::Result<String> {
    let wanted = |name: &str| only.is_empty() || only.iter().any(|f| f == name);
    let real_dir = random_dir.parent().context("the fields' folder")?.join("real-fields");
    let read = |path: &Path| -> anyhow::Result<Value> { Ok(serde_json::from_str(&std::fs::read_to_string(path).with_context(|| path.display().to_string())?)?) };
    let repeats = repeats.max(1);
    let mut out = String::new();
    let _ = writeln!(out, "release build, median of {repeats} runs, process start not included (Fields2Cover's times include it)\n");
    let _ = writeln!(
        out,
        "Fields2Cover's configuration: 5 m wide, turning radius 3 m, headland 10 m (2 passes), forward only; our swaths with balanced ends (the default), with full-width ends, then ending with their centre line as Fields2Cover's do\n"
    );
    out.push_str(HEADER);
    // our default swath ends, the longest, then Fields2Cover's rule (centre-line ends)
    for (ends, label) in [("balanced", ""), ("full_width", ", full-width ends"), ("centre_line", ", centre-line ends")] {
        let f2c = params(5.0, 3.0, json!({"headland_width_m": 10, "swath_ends": ends}))?;
        for (name, length, turns, secs) in F2C.into_iter().filter(|f| wanted(f.0)) {
            let mission = read(&real_dir.join(format!("{name}.json")))?;
            row(&mut out, &format!("{name}{label}"), plan(&mission, &f2c, repeats), Some((length, turns, secs)));
        }
    }
    let _ = writeln!(out, "\nA 6 m sprayer turning on 7 m, 2 headland passes (12 m), forward only; generated fields: the `_00` of each hole count\n");
    out.push_str(HEADER);
    let sprayer = params(6.0, 7.0, json!({"headland_passes": 2}))?;
    // the real fields, then the generated ones
    let fields = || -> anyhow::Result<Vec<(String, Value)>> {
        let real = F2C.into_iter().filter(|f| wanted(f.0)).map(|(name, ..)| Ok((name.to_owned(), read(&real_dir.join(format!("{name}.json")))?)));
        let generated = (0..16).map(|holes| format!("h{holes:02}_00")).filter(|n| wanted(n)).map(|name| Ok((name.clone(), read(&random_dir.join(format!("{name}.json")))?)));
        real.chain(generated).collect()
    };
    for (name, mission) in fields()? {
        row(&mut out, &name, plan(&mission, &sprayer, repeats), None);
    }
    let _ = writeln!(
        out,
        "\nThe same sprayer allowed to reverse: turns may be Reeds–Shepp words and fishtails, and a corner sharper than it turns is worked by driving into it and backing out to the next edge (`corners worked`)\n"
    );
    out.push_str(HEADER);
    let mut reversing = sprayer.clone();
    reversing.vehicle.reverse_allowed = Some(true);
    for (name, mission) in fields()? {
        row(&mut out, &name, plan(&mission, &reversing, repeats), None);
    }
    let _ = writeln!(
        out,
        "\nThe same sprayer by steering, 3 headland passes (18 m: a continuous-curvature turn reaches 10.6 m past the swath's end): forward, reversing (Reeds–Shepp words, fishtails), slow steering (curvature rate 0.02 /m²: clothoids of 7.1 m), both\n"
    );
    out.push_str(HEADER);
    // (label, may reverse, curvature rate)
    let steerings = [("forward", false, None), ("reversing", true, None), ("slow steering", false, Some(0.02)), ("both", true, Some(0.02))];
    for (label, reverse, rate) in steerings {
        let mut params = params(6.0, 7.0, json!({"headland_passes": 3}))?;
        params.vehicle.reverse_allowed = Some(reverse);
        params.vehicle.max_curvature_rate = rate;
        for (name, ..) in F2C.into_iter().filter(|f| wanted(f.0)) {
            let mission = read(&real_dir.join(format!("{name}.json")))?;
            row(&mut out, &format!("{name}, {label}"), plan(&mission, &params, repeats), None);
        }
    }
    let _ = writeln!(
        out,
        "\nThe 2-pass sprayer with a 3 000 l tank, refilled at the first corner of the field's edge, standing there 900 s a trip (the default, weighed as 1 350 m on the headland when the trips are chosen): its trips (inside a swath or pass), their non-working metres (stands left out) and legs across the mainland, beside the operator's rule (back only at a swath's end, when what is left cannot finish the next)\n"
    );
    out.push_str(TRIPS_HEADER);
    let names = F2C.iter().map(|f| (f.0.to_string(), real_dir.clone())).chain((0..16).map(|holes| (format!("h{holes:02}_00"), random_dir.to_path_buf())));
    for (name, dir) in names.filter(|(n, _)| wanted(n)) {
        let mission = read(&dir.join(format!("{name}.json")))?;
        let corner = mission["area"]["coordinates"][0].get(0).filter(|c| c[0].is_number()).or_else(|| mission["area"]["coordinates"][0][0].get(0)).cloned().context("a corner")?;
        for rate in [200.0, 1000.0] {
            let tank = params(6.0, 7.0, json!({"headland_passes": 2, "payload": {"capacity": 3000, "rate_per_ha": rate, "refill_points": [corner]}}))?;
            trips_row(&mut out, &name, rate, plan(&mission, &tank, repeats));
        }
    }
    let _ = writeln!(out, "\nThe 2-pass sprayer alone and as 2 and 3 machines sharing the field: when the last is done, against one alone, and the longest wait to set off\n");
    out.push_str("| field | machines | done s | of one alone | longest wait s | mainland cov | conflicts | ms |\n|---|---|---|---|---|---|---|---|\n");
    for (name, dir) in F2C
        .iter()
        .map(|f| (f.0.to_string(), real_dir.clone()))
        .chain((0..16).step_by(3).map(|holes| (format!("h{holes:02}_00"), random_dir.to_path_buf())))
        .filter(|(n, _)| wanted(n))
    {
        let mission = read(&dir.join(format!("{name}.json")))?;
        let mut alone_s = None;
        for machines in [1u32, 2, 3] {
            let mut fleet = params(6.0, 7.0, json!({"headland_passes": 2}))?;
            fleet.vehicles = (machines > 1).then_some(machines);
            match plan(&mission, &fleet, repeats) {
                Ok((o, ms, _)) => {
                    let s = &o.stats;
                    let done = s.makespan_s.unwrap_or(s.duration_s);
                    let alone = *alone_s.get_or_insert(done);
                    let wait = s.vehicles.iter().map(|v| v.departure_s).fold(0.0, f64::max);
                    let cov = s.ground.as_ref().map_or(0.0, |g| g.mainland_coverage);
                    let conflicts = s.conflicts.as_ref().map_or(0, Vec::len);
                    let _ = writeln!(out, "| {name} | {machines} | {done:.0} | {:.3} | {wait:.0} | {cov:.3} | {conflicts} | {ms:.0} |", done / alone);
                }
                Err(e) => {
                    let _ = writeln!(out, "| {name} | {machines} | refused: {e} |");
                }
            }
        }
    }
    Ok(out)
}

const TRIPS_HEADER: &str = "| field | l/ha | applied l | trips (inside) | non-working m | crossings | rule's trips | rule's m | rule's crossings | saving | ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n";

fn trips_row(out: &mut String, name: &str, rate: f64, result: Result<(PlanOutput, f64, f64), String>) {
    let (o, ms, _) = match result {
        Ok(r) => r,
        Err(e) => {
            let _ = writeln!(out, "| {name} | {rate:.0} | refused: {e} |");
            return;
        }
    };
    let p = o.stats.ground.and_then(|g| g.payload).unwrap_or_default();
    let _ = writeln!(
        out,
        "| {name} | {rate:.0} | {:.0} | {} ({}) | {:.0} | {} | {} | {} | {} | {:.1} % | {ms:.0} |",
        p.amount,
        p.trips,
        p.trips_inside_pieces,
        p.trip_distance_m,
        p.trip_crossings,
        p.rule_trips,
        p.rule_trip_distance_m.map_or_else(|| "no way".to_string(), |m| format!("{m:.0}")),
        p.rule_trip_crossings,
        100.0 * p.saving
    );
}
