//! QGroundControl `.plan`: survey polygons (`ComplexItem`s) are fields; exclusion fences are
//! no-fly zones; inclusion fences are fields when the plan has no survey; the planned home is
//! home. Positions are `[lat, lon]` in this format.

use geo::Polygon;
use serde_json::Value;

use super::{Collected, Glimpse, Importer, Kind, ring};
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
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        matches!(glimpse, Glimpse::Json(v) if v.get("fileType").and_then(Value::as_str) == Some("Plan"))
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
                    out.add(Kind::Field, lat_lon_ring(item.get("polygon").unwrap_or(&Value::Null), &pointer)?, None, None, &pointer);
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
                (false, _) => out.add(Kind::NoFlyZone, polygon, None, None, &pointer),
                (true, false) => out.add(Kind::Field, polygon, None, None, &pointer),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn survey_polygons_are_fields_and_exclusion_fences_zones() {
        let plan = br#"{"fileType": "Plan", "version": 1,
            "mission": {"plannedHomePosition": [47.3, 8.5, 420], "items": [
                {"type": "SimpleItem", "command": 22},
                {"type": "ComplexItem", "complexItemType": "survey", "polygon": [[47.30, 8.50], [47.30, 8.51], [47.31, 8.51], [47.31, 8.50]]}]},
            "geoFence": {"polygons": [
                {"inclusion": true, "polygon": [[47.2, 8.4], [47.2, 8.6], [47.4, 8.6]]},
                {"inclusion": false, "polygon": [[47.302, 8.502], [47.302, 8.503], [47.303, 8.503]]}], "circles": []}}"#;
        let out = QgcPlan.read(plan).unwrap();
        assert_eq!((out.fields.len(), out.no_fly_zones.len()), (1, 1));
        // [lat, lon] in the file, x = longitude here
        assert_eq!(out.fields[0].exterior().0[1], geo::Coord { x: 8.51, y: 47.30 });
        assert_eq!(out.home, Some([8.5, 47.3]));
        assert_eq!(out.warnings.len(), 2, "{:?}", out.warnings);
    }
}
