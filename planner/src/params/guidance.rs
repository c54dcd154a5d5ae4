//! A farm's existing guidance line (`guidance`): swaths parallel to it and whole swath widths
//! from it, so that they fall on the rows and wheel tracks the farm already drives.

use geo::Coord;
use serde::{Deserialize, Serialize};

use super::{InputError, bearing_to_math, check_range};
use crate::frame::LocalFrame;

/// An AB line (points `a` and `b`) or an A+ line (point `a` and `bearing_deg`), as a
/// tractor's terminal or farm software keeps them.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Guidance {
    /// Point A, [longitude, latitude].
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub a: [f64; 2],
    /// Point B of an AB line, [longitude, latitude], at least a metre from A.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub b: Option<[f64; 2]>,
    /// The bearing of an A+ line, degrees clockwise from north, 0 to 360.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 360.0))]
    pub bearing_deg: Option<f64>,
}

/// Where the line runs, validated: through `a`, towards `b` or along a bearing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceLine {
    a: [f64; 2],
    towards: Towards,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Towards {
    Point([f64; 2]),
    /// A math angle, radians anticlockwise from east.
    Angle(f64),
}

/// Points A and B closer than this give no direction.
const SHORTEST_AB_M: f64 = 1.0;

fn position(p: [f64; 2], pointer: &str) -> Result<(), InputError> {
    let ok = p.iter().all(|v| v.is_finite()) && (-180.0..=180.0).contains(&p[0]) && (-90.0..=90.0).contains(&p[1]);
    if ok { Ok(()) } else { Err(InputError::new("invalid_position", pointer, format!("{p:?} is not a [longitude, latitude] position"))) }
}

impl Guidance {
    /// The line, or what is wrong with it.
    pub fn validate(&self) -> Result<GuidanceLine, InputError> {
        position(self.a, "/guidance/a")?;
        let towards = match (self.b, self.bearing_deg) {
            (Some(b), None) => {
                position(b, "/guidance/b")?;
                let apart = LocalFrame::new(self.a[0], self.a[1]).to_local(b[0], b[1]);
                if apart.x.hypot(apart.y) < SHORTEST_AB_M {
                    return Err(InputError::new("guidance_too_short", "/guidance/b", format!("points A and B are less than {SHORTEST_AB_M} m apart: they give no direction")));
                }
                Towards::Point(b)
            }
            (None, Some(bearing)) => {
                check_range(bearing, 0.0, 360.0, "/guidance/bearing_deg", "°")?;
                Towards::Angle(bearing_to_math(bearing))
            }
            (Some(_), Some(_)) => return Err(InputError::new("guidance_twice", "/guidance/bearing_deg", "give point b (an AB line) or bearing_deg (an A+ line), not both")),
            (None, None) => return Err(InputError::new("guidance_without_direction", "/guidance", "give point b (an AB line) or bearing_deg (an A+ line)")),
        };
        Ok(GuidanceLine { a: self.a, towards })
    }
}

impl GuidanceLine {
    /// Point A in `frame`, and the line's direction there (a math angle).
    pub fn in_frame(&self, frame: &LocalFrame) -> (Coord, f64) {
        let a = frame.to_local(self.a[0], self.a[1]);
        let angle = match self.towards {
            Towards::Point(b) => {
                let b = frame.to_local(b[0], b[1]);
                (b.y - a.y).atan2(b.x - a.x)
            }
            Towards::Angle(angle) => angle,
        };
        (a, angle)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ab_line_and_the_a_plus_line_of_its_bearing_run_the_same_way() {
        let frame = LocalFrame::new(5.0, 52.0);
        let ab = Guidance { a: [5.001, 52.001], b: Some([5.003, 52.001]), bearing_deg: None }.validate().unwrap();
        let a_plus = Guidance { a: [5.001, 52.001], b: None, bearing_deg: Some(90.0) }.validate().unwrap();
        let ((a1, t1), (a2, t2)) = (ab.in_frame(&frame), a_plus.in_frame(&frame));
        assert_eq!(a1, a2);
        // east in both, to the convergence of the meridians over 137 m
        assert!(t1.abs() < 1e-3 && t2.abs() < 1e-12, "{t1} {t2}");
    }

    #[test]
    fn lines_without_a_direction_are_refused_with_the_member() {
        let refused = |g: Guidance| g.validate().unwrap_err().pointer;
        assert_eq!(refused(Guidance { a: [5.0, 52.0], b: Some([5.000001, 52.0]), bearing_deg: None }), "/guidance/b");
        assert_eq!(refused(Guidance { a: [5.0, 52.0], b: None, bearing_deg: None }), "/guidance");
        assert_eq!(refused(Guidance { a: [5.0, 52.0], b: Some([5.1, 52.0]), bearing_deg: Some(3.0) }), "/guidance/bearing_deg");
        assert_eq!(refused(Guidance { a: [5.0, 52.0], b: None, bearing_deg: Some(361.0) }), "/guidance/bearing_deg");
        assert_eq!(refused(Guidance { a: [200.0, 52.0], b: None, bearing_deg: Some(1.0) }), "/guidance/a");
    }
}
