//! Camera stage: from sensor and quality targets to line spacing and photo spacing.
//!
//! Landscape mounting: the image width lies across the track.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::error::InputError;
use super::vehicle::check_range;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor_width_mm: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor_height_mm: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_length_mm: Option<f64>,
    /// Horizontal field of view, instead of sensor size and focal length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hfov_deg: Option<f64>,
    pub image_width_px: u32,
    pub image_height_px: u32,
}

/// What a camera and its targets imply for the flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPlan {
    pub altitude_m: f64,
    pub gsd_cm: f64,
    pub footprint_across_m: f64,
    pub footprint_along_m: f64,
    pub line_spacing_m: f64,
    pub photo_spacing_m: f64,
}

impl Camera {
    /// Ground footprint width per metre of altitude, across and along track.
    fn footprint_per_m(&self) -> Result<(f64, f64), InputError> {
        check_range(self.image_width_px as f64, 1.0, 1e6, "/camera/image_width_px", "px")?;
        check_range(self.image_height_px as f64, 1.0, 1e6, "/camera/image_height_px", "px")?;
        let aspect = self.image_height_px as f64 / self.image_width_px as f64;
        match (self.sensor_width_mm, self.focal_length_mm, self.hfov_deg) {
            (Some(w), Some(f), _) => {
                check_range(w, 0.1, 200.0, "/camera/sensor_width_mm", "mm")?;
                check_range(f, 0.1, 2_000.0, "/camera/focal_length_mm", "mm")?;
                let h = match self.sensor_height_mm {
                    Some(h) => {
                        check_range(h, 0.1, 200.0, "/camera/sensor_height_mm", "mm")?;
                        h
                    }
                    None => w * aspect,
                };
                Ok((w / f, h / f))
            }
            (_, _, Some(fov)) => {
                check_range(fov, 1.0, 170.0, "/camera/hfov_deg", "°")?;
                let across = 2.0 * (fov.to_radians() / 2.0).tan();
                Ok((across, across * aspect))
            }
            _ => Err(InputError::new(
                "camera_incomplete",
                "/camera",
                "give sensor_width_mm and focal_length_mm, or hfov_deg",
            )),
        }
    }

    /// Resolves altitude (given, or from a wanted ground sample distance) and the spacings.
    pub fn plan(&self, altitude_m: Option<f64>, gsd_cm: Option<f64>, side_overlap: f64, front_overlap: f64) -> Result<CameraPlan, InputError> {
        let (across, along) = self.footprint_per_m()?;
        let px = self.image_width_px as f64;
        let altitude_m = match (altitude_m, gsd_cm) {
            (Some(a), _) => a,
            (None, Some(g)) => {
                check_range(g, 0.01, 1_000.0, "/gsd_cm", "cm/px")?;
                g / 100.0 * px / across
            }
            (None, None) => return Err(InputError::new("camera_needs_altitude", "/altitude_m", "with a camera, give altitude_m or gsd_cm")),
        };
        check_range(altitude_m, 1.0, 5_000.0, "/altitude_m", "m")?;
        let footprint_across_m = altitude_m * across;
        let footprint_along_m = altitude_m * along;
        Ok(CameraPlan {
            altitude_m,
            gsd_cm: footprint_across_m / px * 100.0,
            footprint_across_m,
            footprint_along_m,
            line_spacing_m: footprint_across_m * (1.0 - side_overlap),
            photo_spacing_m: footprint_along_m * (1.0 - front_overlap),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sensor_and_hfov_agree() {
        // 13.2 × 8.8 mm sensor, 8.8 mm lens, 5472 × 3648 px (a common 1-inch 20 MP camera)
        let cam = Camera { sensor_width_mm: Some(13.2), sensor_height_mm: Some(8.8), focal_length_mm: Some(8.8), hfov_deg: None, image_width_px: 5472, image_height_px: 3648 };
        let p = cam.plan(Some(100.0), None, 0.7, 0.8).unwrap();
        assert!((p.footprint_across_m - 150.0).abs() < 1e-9);
        assert!((p.footprint_along_m - 100.0).abs() < 1e-9);
        assert!((p.line_spacing_m - 45.0).abs() < 1e-9);
        assert!((p.photo_spacing_m - 20.0).abs() < 1e-9);
        assert!((p.gsd_cm - 2.7412).abs() < 1e-3);
        // the same camera described by its field of view
        let fov = 2.0 * (13.2f64 / 2.0 / 8.8).atan().to_degrees();
        let cam2 = Camera { sensor_width_mm: None, sensor_height_mm: None, focal_length_mm: None, hfov_deg: Some(fov), ..cam.clone() };
        let q = cam2.plan(None, Some(p.gsd_cm), 0.7, 0.8).unwrap();
        assert!((q.altitude_m - 100.0).abs() < 1e-6 && (q.footprint_along_m - 100.0).abs() < 1e-6);
    }
}
