//! The schedule as CSV: a row per leg, for spreadsheets and farm office software.

use super::schedule::{LegKind, Schedule};

/// The columns, in order.
pub const COLUMNS: [&str; 10] = ["machine", "day", "date", "start", "end", "kind", "field_index", "field", "distance_m", "finishes_field"];

/// One row per leg of every machine's days; `field_labels[i]` names field `i` in the `field`
/// column (the service writes its mission's name and plan id).
///
/// ```
/// use coverplan_planner::farm::{FieldWork, Machine, StraightLine, Window, schedule, schedule_csv};
/// use coverplan_planner::Stop;
///
/// let field = FieldWork { entry: [5.0, 50.0], exit: [5.001, 50.0], work_s: 3_600.0 };
/// let machine = Machine { name: Some("tractor".into()), depot: [5.0, 50.01], hours_per_day: None, road_speed_mps: None, endurance_s: None, refill_s: None };
/// let window = Window { start_date: "2027-04-12".into(), days: 5, hours_per_day: None, day_start: None };
/// let plan = schedule(&[field], &[machine], &window, &StraightLine, &Stop::never()).unwrap();
/// let csv = String::from_utf8(schedule_csv(&plan, &["north field".to_owned()])).unwrap();
/// let rows: Vec<&str> = csv.lines().collect();
/// assert_eq!(rows[0], "machine,day,date,start,end,kind,field_index,field,distance_m,finishes_field");
/// assert!(rows[2].starts_with("tractor,1,2027-04-12,07:02:14,08:02:14,work,0,north field,,true"), "{}", rows[2]);
/// assert_eq!(rows.len(), 4); // there, the work, back
/// ```
pub fn schedule_csv(schedule: &Schedule, field_labels: &[String]) -> Vec<u8> {
    let mut out = csv::Writer::from_writer(Vec::new());
    out.write_record(COLUMNS).expect("writing to memory");
    for machine in &schedule.machines {
        for day in &machine.days {
            for leg in &day.legs {
                let kind = match leg.kind {
                    LegKind::Transit => "transit",
                    LegKind::Work => "work",
                    LegKind::Refill => "refill",
                };
                let field = leg.field.map(|i| field_labels.get(i).cloned().unwrap_or_default()).unwrap_or_default();
                out.write_record([
                    machine.machine.clone(),
                    day.day.to_string(),
                    day.date.clone(),
                    leg.start.clone(),
                    leg.end.clone(),
                    kind.to_owned(),
                    leg.field.map(|i| i.to_string()).unwrap_or_default(),
                    field,
                    leg.distance_m.map(|d| format!("{d:.0}")).unwrap_or_default(),
                    leg.finishes_field.map(|f| f.to_string()).unwrap_or_default(),
                ])
                .expect("writing to memory");
            }
        }
    }
    out.into_inner().expect("writing to memory")
}
