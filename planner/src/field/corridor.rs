//! Corridors: LineString features of the mission's area with a `width_m` property (a road, a
//! river, a pipeline). The area to cover is the centre line buffered by half the width, round
//! at the bends and the ends; planner `corridor` flies lines along the centre line.

use geo::algorithm::buffer::{BufferStyle, LineCap, LineJoin};
use geo::{Buffer, Coord, LineString, MultiPolygon, Orient, orient::Direction};
use geojson::GeometryValue;
use serde_json::Value;

use super::{FieldLimits, raw_positions};
use crate::error::InputError;
use crate::frame::LocalFrame;

/// Widest corridor accepted, metres: wider strips are areas.
pub const MAX_CORRIDOR_WIDTH_M: f64 = 2_000.0;

/// Angle between the points of a buffer's round bends and ends (radians): 5°, within 0.1 % of
/// the width of a true arc.
const ROUND_STEP_RAD: f64 = 0.087;

/// A corridor in the local frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Corridor {
    /// At least two points, none repeated.
    pub centre: Vec<Coord>,
    pub width_m: f64,
    /// Its feature's JSON pointer in the mission.
    pub pointer: String,
}

impl Corridor {
    /// The corridor's ground: every point within half the width of the centre line.
    pub fn outline(&self) -> MultiPolygon {
        let style = BufferStyle::new(self.width_m / 2.0).line_join(LineJoin::Round(ROUND_STEP_RAD)).line_cap(LineCap::Round(ROUND_STEP_RAD));
        LineString::new(self.centre.clone()).buffer_with_style(style).orient(Direction::Default)
    }
}

/// A corridor as sent.
pub(super) struct RawCorridor {
    pointer: String,
    positions: Vec<[f64; 2]>,
    width_m: f64,
}

impl RawCorridor {
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }
}

/// The corridors of a feature of the area; `None` when its geometry is no line (a field).
pub(super) fn of_feature(f: &geojson::Feature, pointer: &str) -> Result<Option<Vec<RawCorridor>>, InputError> {
    let lines: Vec<(&Vec<geojson::Position>, String)> = match f.geometry.as_ref().map(|g| &g.value) {
        Some(GeometryValue::LineString { coordinates }) => vec![(coordinates, format!("{pointer}/geometry/coordinates"))],
        Some(GeometryValue::MultiLineString { coordinates }) => coordinates.iter().enumerate().map(|(i, c)| (c, format!("{pointer}/geometry/coordinates/{i}"))).collect(),
        _ => return Ok(None),
    };
    let wp = format!("{pointer}/properties/width_m");
    let width_m = f
        .property("width_m")
        .and_then(Value::as_f64)
        .ok_or_else(|| InputError::new("corridor_width_missing", wp.clone(), "a line of the area is a corridor: give its width in metres as the feature's `width_m` property"))?;
    if !(width_m > 0.0 && width_m <= MAX_CORRIDOR_WIDTH_M) {
        return Err(InputError::new("parameter_out_of_range", wp, format!("{width_m} is outside the accepted range (0, {MAX_CORRIDOR_WIDTH_M}] m")));
    }
    let mut out = Vec::with_capacity(lines.len());
    for (coordinates, pointer) in lines {
        let positions = raw_positions(coordinates, &pointer)?;
        out.push(RawCorridor { pointer, positions, width_m });
    }
    Ok(Some(out))
}

/// The refusal of a bare line geometry, which has no properties to hold a width.
pub(super) fn bare_line(pointer: &str) -> InputError {
    InputError::new("corridor_width_missing", pointer, "a corridor is a LineString Feature with its width in metres as the `width_m` property; a bare geometry has none")
}

/// The corridor in the local frame, its repeated points dropped.
pub(super) fn local(frame: &LocalFrame, raw: &RawCorridor, limits: &FieldLimits) -> Result<Corridor, InputError> {
    let max_r = limits.max_radius_km * 1000.0;
    let mut centre: Vec<Coord> = Vec::with_capacity(raw.positions.len());
    for (k, p) in raw.positions.iter().enumerate() {
        let c = frame.to_local(p[0], p[1]);
        if c.x.hypot(c.y) > max_r {
            return Err(InputError::new(
                "mission_too_wide",
                format!("{}/{k}", raw.pointer),
                format!("this position is more than {} km from the mission's centre", limits.max_radius_km),
            ));
        }
        if !centre.last().is_some_and(|l| (l.x - c.x).hypot(l.y - c.y) < 1e-3) {
            centre.push(c);
        }
    }
    if centre.len() < 2 {
        return Err(InputError::new("degenerate_corridor", raw.pointer.clone(), "a corridor's centre line needs at least two distinct positions"));
    }
    Ok(Corridor { centre, width_m: raw.width_m, pointer: raw.pointer.clone() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Area;

    #[test]
    fn a_corridors_outline_is_its_centre_line_grown_by_half_its_width() {
        let c = Corridor { centre: vec![Coord { x: 0.0, y: 0.0 }, Coord { x: 1000.0, y: 0.0 }, Coord { x: 1000.0, y: 500.0 }], width_m: 60.0, pointer: String::new() };
        let area = c.outline().unsigned_area();
        // two rectangles, a quarter disc at the bend (outside) less a square (inside), two half discs
        let r: f64 = 30.0;
        let expected = 1500.0 * 60.0 + std::f64::consts::PI * r * r + std::f64::consts::PI * r * r / 4.0 - r * r;
        assert!((area - expected).abs() < 2e-3 * expected, "{area} against {expected}");
    }
}
