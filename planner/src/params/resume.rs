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
    #[cfg_attr(feature = "schema", schema(maximum = 1_000_000_000_u64))]
    pub seq: usize,
    /// 0 to 1: how much of that piece was flown.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1.0))]
    pub fraction: f64,
    /// Of a fleet's plan, the drone that stopped (the trajectory's `vehicle`, from 0): each
    /// drone's pieces are numbered on their own. The other drones' flights are not changed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schema(maximum = 63))]
    pub vehicle: Option<usize>,
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

/// What a flight log says of a flight: the server reads it from an uploaded log (`.tlog`,
/// `.ulg`, `.bin`); a client may send it as JSON instead.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Flown {
    /// The aircraft's positions in flight order, `[lon, lat]`, at least two.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 500000))]
    pub track: Vec<[f64; 2]>,
    /// Where the camera took its photos, `[lon, lat]`; empty (or a plan without a camera): the
    /// track within `tolerance_m` of a line is taken for its work.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(max_items = 100000))]
    pub photos: Vec<[f64; 2]>,
    /// The battery left at the log's end, 0 to 1.
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1.0))]
    pub battery_remaining: Option<f64>,
    /// Farthest across a line a photo (or the track) may lie to count as the line's, 0.1 to
    /// 100 m (default a quarter of the line spacing, at least 1 m).
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 100.0))]
    pub tolerance_m: Option<f64>,
}

/// Most positions of a flown track.
pub const MAX_TRACK_POINTS: usize = 500_000;

/// Most photos of a flight.
pub const MAX_FLOWN_PHOTOS: usize = 100_000;

/// `POST /api/v1/plans/{id}/resume`: exactly one of `at`, `position` and `flown` says where
/// the flight stopped.
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct ResumeParams {
    /// The piece of the trajectory the flight stopped on, and how far along it.
    pub at: Option<CutAt>,
    /// What the flight's log says (the body of an uploaded log fills it): the lines it did not
    /// image are left, wherever they lie.
    pub flown: Option<Flown>,
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
    /// `home` (default) or `position` (needs `position`, or `flown`: its track's last point).
    pub from: Option<ResumeFrom>,
    /// The battery left for the first sortie, 0 to 1 of its capacity (default: a fresh one; from
    /// a flown `position`, what the log says is left).
    #[cfg_attr(feature = "schema", schema(minimum = 0.0, maximum = 1.0))]
    pub battery_remaining: Option<f64>,
}

/// Farthest the aircraft's position may lie from the plan's path, metres.
pub const MAX_CUT_OFF_PATH_M: f64 = 250.0;

/// Most photos back.
pub const MAX_PHOTOS_BACK: u32 = 20;

/// Where the flight stopped, checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Cut {
    At(CutAt),
    /// `[lon, lat]`, and the compass heading.
    Position([f64; 2], Option<f64>),
    /// What the log says was flown.
    Flown(Flown),
}

/// A resume request, checked and with its defaults.
#[derive(Debug, Clone, PartialEq)]
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
        let given = [self.at.is_some(), self.position.is_some(), self.flown.is_some()];
        if given.iter().filter(|g| **g).count() > 1 {
            let second = ["/at", "/position", "/flown"].into_iter().zip(given).filter(|(_, g)| *g).nth(1).map_or("/position", |(p, _)| p);
            return Err(InputError::new("cut_ambiguous", second, "give one of at, position and flown"));
        }
        if self.heading_deg.is_some() && self.position.is_none() {
            return Err(InputError::new("not_with_at", "/heading_deg", "heading_deg goes with position, not with at or flown"));
        }
        let cut = if let Some(at) = self.at {
            check_range(at.fraction, 0.0, 1.0, "/at/fraction", "of the piece")?;
            Cut::At(at)
        } else if let Some(p) = self.position {
            check_position(p, "/position")?;
            if let Some(h) = self.heading_deg {
                check_range(h, 0.0, 360.0, "/heading_deg", "°")?;
            }
            Cut::Position(p, self.heading_deg)
        } else if let Some(flown) = &self.flown {
            flown.check()?;
            Cut::Flown(flown.clone())
        } else {
            return Err(InputError::new(
                "cut_missing",
                "/at",
                "say where the flight stopped: at {seq, fraction} (a piece of the trajectory), position [lon, lat], or the flight's log",
            ));
        };
        let photos_back = self.photos_back.unwrap_or(2);
        if photos_back > MAX_PHOTOS_BACK {
            return Err(InputError::new("parameter_out_of_range", "/photos_back", format!("{photos_back} is more than the {MAX_PHOTOS_BACK} photos back accepted")));
        }
        let last_tracked = self.flown.as_ref().and_then(|f| f.track.last().copied());
        let airborne_at = match (self.from.unwrap_or_default(), self.position.or(last_tracked)) {
            (ResumeFrom::Home, _) => None,
            (ResumeFrom::Position, Some(p)) => Some(p),
            (ResumeFrom::Position, None) => {
                return Err(InputError::new("position_missing", "/from", "from position resumes from where the aircraft is: give its position"));
            }
        };
        // still in the air, the aircraft flies on the battery its log says it has
        let logged = self.flown.as_ref().and_then(|f| f.battery_remaining).filter(|_| airborne_at.is_some());
        let battery_remaining = self.battery_remaining.or(logged).unwrap_or(1.0);
        check_range(battery_remaining, 0.0, 1.0, "/battery_remaining", "of the battery")?;
        Ok(Resume { cut, photos_back, airborne_at, battery_remaining })
    }
}

fn check_position(p: [f64; 2], pointer: &str) -> Result<(), InputError> {
    check_range(p[0], -180.0, 180.0, &format!("{pointer}/0"), "°")?;
    check_range(p[1], -90.0, 90.0, &format!("{pointer}/1"), "°")
}

impl Flown {
    fn check(&self) -> Result<(), InputError> {
        if self.track.len() < 2 {
            return Err(InputError::new("log_without_position", "/flown/track", "the log has fewer than two positions of the aircraft: was its GPS on?"));
        }
        if self.track.len() > MAX_TRACK_POINTS {
            return Err(InputError::new("too_many_points", "/flown/track", format!("{} positions; at most {MAX_TRACK_POINTS} are read", self.track.len())));
        }
        if self.photos.len() > MAX_FLOWN_PHOTOS {
            return Err(InputError::new("too_many_points", "/flown/photos", format!("{} photos; at most {MAX_FLOWN_PHOTOS} are read", self.photos.len())));
        }
        for (k, p) in self.track.iter().enumerate() {
            check_position(*p, &format!("/flown/track/{k}"))?;
        }
        for (k, p) in self.photos.iter().enumerate() {
            check_position(*p, &format!("/flown/photos/{k}"))?;
        }
        if let Some(b) = self.battery_remaining {
            check_range(b, 0.0, 1.0, "/flown/battery_remaining", "of the battery")?;
        }
        if let Some(t) = self.tolerance_m {
            check_range(t, 0.1, 100.0, "/flown/tolerance_m", "m")?;
        }
        Ok(())
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
