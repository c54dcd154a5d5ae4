//! What a resumed plan asks for: where the flight stopped, and how to go on (docs/api.md,
//! "Resume a plan").

use serde::{Deserialize, Serialize};

use crate::error::{InputError, check_range};

/// How far along the plan the flight got: a piece of its trajectory (the feature's `seq`) and
/// the share of that piece flown.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct CutAt {
    /// The `seq` of a flown piece (sweep, turn, transit, headland) of the plan's trajectory.
    pub seq: usize,
    /// 0 to 1: how much of that piece was flown.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1.0))]
    pub fraction: f64,
}

/// Where the resumed flight takes off from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum ResumeFrom {
    /// The mission's home (the aircraft landed; without a home, the first line's start).
    #[default]
    Home,
    /// The aircraft's `position`, still in the air: no take-off.
    Position,
}

/// `POST /api/v1/plans/{id}/resume`: exactly one of `at` and `position` says where the flight
/// stopped.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct ResumeParams {
    /// The piece of the trajectory the flight stopped on, and how far along it.
    pub at: Option<CutAt>,
    /// The aircraft's last position, `[lon, lat]`: the nearest point of the plan's path is
    /// where it stopped (at most [`MAX_CUT_OFF_PATH_M`] away).
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub position: Option<[f64; 2]>,
    /// With `position`: the aircraft's compass heading, degrees; only pieces flown within 60°
    /// of it are taken for the cut (where the path passes a place twice).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 360.0))]
    pub heading_deg: Option<f64>,
    /// How many trigger distances (the camera's photo spacing; without a camera, half the line
    /// spacing) before the cut the resumed line starts, 0 to 20 (default 2).
    #[cfg_attr(feature = "schema", schema(minimum = 0, maximum = 20))]
    pub photos_back: Option<u32>,
    /// `home` (default) or `position` (needs `position`).
    pub from: Option<ResumeFrom>,
    /// The battery left for the first sortie, 0 to 1 of its capacity (default: a fresh one).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1.0))]
    pub battery_remaining: Option<f64>,
}

/// Farthest the aircraft's position may lie from the plan's path, metres.
pub const MAX_CUT_OFF_PATH_M: f64 = 250.0;

/// Most photos back.
pub const MAX_PHOTOS_BACK: u32 = 20;

/// Where the flight stopped, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cut {
    At(CutAt),
    /// `[lon, lat]`, and the compass heading.
    Position([f64; 2], Option<f64>),
}

/// A resume request, checked and with its defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resume {
    pub cut: Cut,
    pub photos_back: u32,
    /// The aircraft's position when it takes off from there (`from: position`).
    pub airborne_at: Option<[f64; 2]>,
    pub battery_remaining: f64,
}

impl ResumeParams {
    /// The request checked: one cut, values in range, `from: position` with a position.
    pub fn check(&self) -> Result<Resume, InputError> {
        let cut = match (self.at, self.position) {
            (Some(at), None) => {
                check_range(at.fraction, 0.0, 1.0, "/at/fraction", "of the piece")?;
                if self.heading_deg.is_some() {
                    return Err(InputError::new("not_with_at", "/heading_deg", "heading_deg goes with position, not with at"));
                }
                Cut::At(at)
            }
            (None, Some(p)) => {
                check_range(p[0], -180.0, 180.0, "/position/0", "°")?;
                check_range(p[1], -90.0, 90.0, "/position/1", "°")?;
                if let Some(h) = self.heading_deg {
                    check_range(h, 0.0, 360.0, "/heading_deg", "°")?;
                }
                Cut::Position(p, self.heading_deg)
            }
            (Some(_), Some(_)) => return Err(InputError::new("cut_ambiguous", "/position", "give either at or position, not both")),
            (None, None) => {
                return Err(InputError::new("cut_missing", "/at", "say where the flight stopped: at {seq, fraction} (a piece of the trajectory) or position [lon, lat]"));
            }
        };
        let photos_back = self.photos_back.unwrap_or(2);
        if photos_back > MAX_PHOTOS_BACK {
            return Err(InputError::new("parameter_out_of_range", "/photos_back", format!("{photos_back} is more than the {MAX_PHOTOS_BACK} photos back accepted")));
        }
        let battery_remaining = self.battery_remaining.unwrap_or(1.0);
        check_range(battery_remaining, 0.0, 1.0, "/battery_remaining", "of the battery")?;
        let airborne_at = match (self.from.unwrap_or_default(), self.position) {
            (ResumeFrom::Home, _) => None,
            (ResumeFrom::Position, Some(p)) => Some(p),
            (ResumeFrom::Position, None) => {
                return Err(InputError::new("position_missing", "/from", "from position resumes from where the aircraft is: give its position"));
            }
        };
        Ok(Resume { cut, photos_back, airborne_at, battery_remaining })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn check(v: serde_json::Value) -> Result<Resume, InputError> {
        serde_json::from_value::<ResumeParams>(v).unwrap().check()
    }

    #[test]
    fn a_request_names_one_cut_in_range() {
        let ok = check(json!({"at": {"seq": 3, "fraction": 0.5}})).unwrap();
        assert_eq!((ok.photos_back, ok.airborne_at, ok.battery_remaining), (2, None, 1.0));
        let airborne = check(json!({"position": [8.5, 47.3], "heading_deg": 90, "from": "position", "battery_remaining": 0.4})).unwrap();
        assert_eq!(airborne.airborne_at, Some([8.5, 47.3]));
        for (bad, code, pointer) in [
            (json!({}), "cut_missing", "/at"),
            (json!({"at": {"seq": 1, "fraction": 0.2}, "position": [8.5, 47.3]}), "cut_ambiguous", "/position"),
            (json!({"at": {"seq": 1, "fraction": 1.5}}), "parameter_out_of_range", "/at/fraction"),
            (json!({"at": {"seq": 1, "fraction": 0.5}, "from": "position"}), "position_missing", "/from"),
            (json!({"position": [8.5, 97.0]}), "parameter_out_of_range", "/position/1"),
            (json!({"at": {"seq": 1, "fraction": 0.5}, "photos_back": 21}), "parameter_out_of_range", "/photos_back"),
            (json!({"at": {"seq": 1, "fraction": 0.5}, "battery_remaining": -0.1}), "parameter_out_of_range", "/battery_remaining"),
        ] {
            let e = check(bad.clone()).unwrap_err();
            assert_eq!((e.code, e.pointer.as_str()), (code, pointer), "{bad}: {e}");
        }
    }
}
