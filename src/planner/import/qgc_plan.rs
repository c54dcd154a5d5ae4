//! QGroundControl `.plan`: survey polygons (`ComplexItem`s) are fields; exclusion fences are
//! no-fly zones; inclusion fences are fields when the plan has no survey; the planned home is
//! home. Positions are `[lat, lon]` in this format.

use geo::Polygon;
use serde_json::Value;

use super::{Collected, Importer, Kind, ring};
use crate::error::InputError;

pub struct QgcPlan;

fn lat_lon_ring(value: &Value, pointer: &str) -> Result<Polygon, InputError> {
    let points = value.as_array().ok_or_else(|| InputError::new("invalid_plan", pointer, "a polygon must be a list of [lat, lon]"))?;
    let points = points
        .iter()
        .enumerate()
        .map(|(i, p)| match (p.get(0).and_then(Value::as_f64), p.get(1).and_then(Value::as_f64)) {
            (Some(lat), Some(lon)) => Ok([lon, lat]),
            _ => Err(InputError::new("invalid_plan", format!("{pointer}/{i}"), "a point must be [lat, lon]")),
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Polygon::new(ring(points, pointer)?, vec![]))
}

impl Importer for QgcPlan {
    fn id(&self) -> &'static str {
        "plan"
    }

    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        let plan: Value = serde_json::from_slice(bytes).map_err(|e| InputError::new("invalid_plan", "/", format!("not valid JSON: {e}")))?;
        if plan.get("fileType").and_then(Value::as_str) != Some("Plan") {
            return Err(InputError::new("invalid_plan", "/fileType", "a QGroundControl plan has `fileType: \"Plan\"`"));
        }
        let mut out = Collected::default();
        let items = plan.pointer("/mission/items").and_then(Value::as_array).cloned().unwrap_or_default();
        let mut simple = 0;
        for (i, item) in items.iter().enumerate() {
            match (item.get("type").and_then(Value::as_str), item.get("complexItemType").and_then(Value::as_str)) {
                (Some("ComplexItem"), Some("survey")) => {
                    let pointer = format!("/mission/items/{i}/polygon");
                    out.add(Kind::Field, lat_lon_ring(item.get("polygon").unwrap_or(&Value::Null), &pointer)?, None, &pointer);
                }
                (Some("ComplexItem"), other) => out.warnings.push(format!("/mission/items/{i}: a {} item was dropped", other.unwrap_or("complex"))),
                _ => simple += 1,
            }
        }
        if simple > 0 {
            out.warnings.push(format!("/mission/items: {simple} simple mission items were not read: coverplan plans the route anew"));
        }
        let fences = plan.pointer("/geoFence/polygons").and_then(Value::as_array).cloned().unwrap_or_default();
        let surveyed = !out.fields.is_empty();
        for (i, fence) in fences.iter().enumerate() {
            let pointer = format!("/geoFence/polygons/{i}/polygon");
            let polygon = lat_lon_ring(fence.get("polygon").unwrap_or(&Value::Null), &pointer)?;
            match (fence.get("inclusion").and_then(Value::as_bool).unwrap_or(true), surveyed) {
                (false, _) => out.add(Kind::NoFlyZone, polygon, None, &pointer),
                (true, false) => out.add(Kind::Field, polygon, None, &pointer),
                (true, true) => out.warnings.push(format!("{pointer}: an inclusion fence was dropped (the survey polygons are the fields)")),
            }
        }
        if plan.pointer("/geoFence/circles").and_then(Value::as_array).is_some_and(|c| !c.is_empty()) {
            out.warnings.push("/geoFence/circles: circular fences were dropped".to_owned());
        }
        if let Some(home) = plan.pointer("/mission/plannedHomePosition").and_then(Value::as_array)
            && let (Some(lat), Some(lon)) = (home.first().and_then(Value::as_f64), home.get(1).and_then(Value::as_f64))
        {
            out.home = Some([lon, lat]);
        }
        Ok(out)
    }
}
