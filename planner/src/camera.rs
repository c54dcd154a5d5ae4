//! Camera stage: from a sensor and quality targets to altitude, footprint, line spacing and
//! photo spacing (docs/methods.md, camera §1–§3, §6).
//!
//! The ground sample distance comes from the sensor width and is used for both image axes, as
//! QGroundControl's `CameraCalc` does, so the figures match its survey calculator exactly
//! (for square pixels this is the pinhole footprint of both axes).

use serde::{Deserialize, Serialize};

use super::error::{InputError, check_range};
use super::sweep::Footprint;

/// How the camera is mounted: `landscape` puts the image width across the track.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    #[default]
    Landscape,
    Portrait,
}

/// A camera: a preset, or its figures (which override the preset's).
#[serde_with::skip_serializing_none]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// A camera from `GET /api/v1/cameras`.
    pub preset: Option<String>,
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 200.0))]
    pub sensor_width_mm: Option<f64>,
    pub sensor_height_mm: Option<f64>,
    #[cfg_attr(feature = "schema", schema(minimum = 0.1, maximum = 2000.0))]
    pub focal_length_mm: Option<f64>,
    /// Horizontal field of view (across the image width), instead of sensor and lens.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 170.0))]
    pub hfov_deg: Option<f64>,
    /// Diagonal field of view, as data sheets usually quote it.
    #[cfg_attr(feature = "schema", schema(minimum = 1.0, maximum = 170.0))]
    pub dfov_deg: Option<f64>,
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 1000000))]
    pub image_width_px: Option<u32>,
    #[cfg_attr(feature = "schema", schema(minimum = 1, maximum = 1000000))]
    pub image_height_px: Option<u32>,
    pub orientation: Option<Orientation>,
}

/// A camera that survey users own, with its data sheet figures.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct CameraPreset {
    pub id: &'static str,
    pub name: &'static str,
    pub sensor_width_mm: f64,
    pub sensor_height_mm: f64,
    pub focal_length_mm: f64,
    pub image_width_px: u32,
    pub image_height_px: u32,
}

const fn preset(id: &'static str, name: &'static str, sensor: (f64, f64), focal_length_mm: f64, image: (u32, u32)) -> CameraPreset {
    CameraPreset { id, name, sensor_width_mm: sensor.0, sensor_height_mm: sensor.1, focal_length_mm, image_width_px: image.0, image_height_px: image.1 }
}

/// The camera presets (manufacturers' data sheets: sensor size, real focal length, image size).
pub const PRESETS: &[CameraPreset] = &[
    preset("dji_phantom4_pro", "DJI Phantom 4 Pro / Pro V2.0 / RTK (1-inch, 20 MP)", (13.2, 8.8), 8.8, (5472, 3648)),
    preset("dji_mavic2_pro", "DJI Mavic 2 Pro (Hasselblad L1D-20c)", (13.2, 8.8), 10.26, (5472, 3648)),
    preset("dji_mavic3_enterprise", "DJI Mavic 3 Enterprise, wide camera (4/3, 20 MP)", (17.3, 13.0), 12.29, (5280, 3956)),
    preset("dji_zenmuse_p1_35mm", "DJI Zenmuse P1 with the 35 mm lens (full frame, 45 MP)", (35.9, 24.0), 35.0, (8192, 5460)),
    preset("sensefly_soda", "senseFly S.O.D.A. (1-inch, 20 MP)", (13.2, 8.8), 10.6, (5472, 3648)),
    preset("micasense_rededge_mx", "MicaSense RedEdge-MX (multispectral, per band)", (4.8, 3.6), 5.4, (1280, 960)),
];

/// What a camera and its targets imply for the flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPlan {
    pub altitude_m: f64,
    pub gsd_cm: f64,
    pub footprint_across_m: f64,
    pub footprint_along_m: f64,
    /// Largest distance between lines for the side overlap.
    pub line_spacing_m: f64,
    /// Largest distance between photos for the front overlap.
    pub photo_spacing_m: f64,
}

impl CameraPlan {
    /// What one photo images and how far apart photos are taken, for laying lines.
    pub fn footprint(&self) -> Footprint {
        Footprint { across_m: self.footprint_across_m, along_m: self.footprint_along_m, photo_spacing_m: self.photo_spacing_m }
    }
}

/// What a camera pitched below the horizon images of flat ground `h` below it
/// (docs/methods.md, camera §8): a trapezoid ahead of the vehicle, narrowest at its near edge,
/// which with the image centre bounds the rectangle the lines are laid for. Distances are along
/// the look direction, from the point under the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObliqueView {
    /// The gimbal's pitch, as gimbals say it (−90 straight down).
    pub gimbal_pitch_deg: f64,
    /// Where the image centre meets the ground: h / tan(pitch).
    pub centre_m: f64,
    /// The near edge: how far ahead, and how wide.
    pub near_m: f64,
    pub near_width_m: f64,
    /// The overlaps asked for, as the shares of a footprint neighbouring lines and photos
    /// step: 1 − side overlap, 1 − front overlap.
    pub line_step: f64,
    pub photo_step: f64,
}

/// Least angle between the top of an oblique image and the horizon: beyond it the far edge
/// runs off towards the horizon.
pub const OBLIQUE_HORIZON_MARGIN_DEG: f64 = 5.0;

impl CameraPlan {
    /// The view with the gimbal at `gimbal_pitch_deg` (−90 < pitch < 0); `Err` with the
    /// steepest pitch whose image stays [`OBLIQUE_HORIZON_MARGIN_DEG`] below the horizon.
    pub fn oblique(&self, gimbal_pitch_deg: f64) -> Result<ObliqueView, f64> {
        let h = self.altitude_m;
        let pitch = (-gimbal_pitch_deg).to_radians();
        let (tan_a, tan_b) = (self.footprint_across_m / (2.0 * h), self.footprint_along_m / (2.0 * h));
        let half_v = tan_b.atan();
        if pitch - half_v < OBLIQUE_HORIZON_MARGIN_DEG.to_radians() {
            return Err(-(half_v.to_degrees() + OBLIQUE_HORIZON_MARGIN_DEG));
        }
        let (s, c) = pitch.sin_cos();
        Ok(ObliqueView {
            gimbal_pitch_deg,
            centre_m: h / pitch.tan(),
            near_m: h / (pitch + half_v).tan(),
            near_width_m: 2.0 * h * tan_a / (s + tan_b * c),
            line_step: self.line_spacing_m / self.footprint_across_m,
            photo_step: self.photo_spacing_m / self.footprint_along_m,
        })
    }
}

impl ObliqueView {
    /// The rectangle centred on the image centre that the trapezoid holds: as deep as twice
    /// the near edge's distance to the centre, as wide as the near edge. Laid as a footprint
    /// on lines the camera looks along (`across_lines` false) or across: the lines' spacing
    /// and the photos' step follow the overlaps asked for.
    pub fn footprint(&self, across_lines: bool) -> Footprint {
        let (depth, width) = (2.0 * (self.centre_m - self.near_m), self.near_width_m);
        let (across_m, along_m) = if across_lines { (depth, width) } else { (width, depth) };
        Footprint { across_m, along_m, photo_spacing_m: along_m * self.photo_step }
    }
}

/// Horizontal field of view from a diagonal one, for an image of `w` × `h` pixels.
pub fn hfov_from_dfov(dfov_deg: f64, w: f64, h: f64) -> f64 {
    2.0 * ((dfov_deg.to_radians() / 2.0).tan() * w / w.hypot(h)).atan().to_degrees()
}

impl Camera {
    /// The camera with its preset's figures filled in where it gives none.
    fn complete(&self) -> Result<Camera, InputError> {
        let Some(id) = &self.preset else { return Ok(self.clone()) };
        let p = PRESETS.iter().find(|p| p.id == id).ok_or_else(|| {
            let known: Vec<&str> = PRESETS.iter().map(|p| p.id).collect();
            InputError::new("unknown_camera", "/camera/preset", format!("no camera preset `{id}`; known: {}", known.join(", ")))
        })?;
        let lens_given = self.hfov_deg.is_some() || self.dfov_deg.is_some();
        Ok(Camera {
            preset: None,
            sensor_width_mm: self.sensor_width_mm.or((!lens_given).then_some(p.sensor_width_mm)),
            sensor_height_mm: self.sensor_height_mm.or((!lens_given).then_some(p.sensor_height_mm)),
            focal_length_mm: self.focal_length_mm.or((!lens_given).then_some(p.focal_length_mm)),
            image_width_px: self.image_width_px.or(Some(p.image_width_px)),
            image_height_px: self.image_height_px.or(Some(p.image_height_px)),
            ..self.clone()
        })
    }

    /// Ground sample distance per metre of altitude (m/px per m), and the image size.
    fn gsd_per_m(&self) -> Result<(f64, f64, f64), InputError> {
        let c = self.complete()?;
        let (Some(w), Some(h)) = (c.image_width_px, c.image_height_px) else {
            return Err(InputError::new("camera_incomplete", "/camera", "give image_width_px and image_height_px, or a preset"));
        };
        let (w, h) = (w as f64, h as f64);
        check_range(w, 1.0, 1e6, "/camera/image_width_px", "px")?;
        check_range(h, 1.0, 1e6, "/camera/image_height_px", "px")?;
        let per_m = match (c.sensor_width_mm, c.focal_length_mm, c.hfov_deg, c.dfov_deg) {
            (Some(sw), Some(f), None, None) => {
                check_range(sw, 0.1, 200.0, "/camera/sensor_width_mm", "mm")?;
                check_range(f, 0.1, 2_000.0, "/camera/focal_length_mm", "mm")?;
                sw / (f * w)
            }
            (None, None, Some(fov), None) => {
                check_range(fov, 1.0, 170.0, "/camera/hfov_deg", "°")?;
                2.0 * (fov.to_radians() / 2.0).tan() / w
            }
            (None, None, None, Some(fov)) => {
                check_range(fov, 1.0, 170.0, "/camera/dfov_deg", "°")?;
                2.0 * (hfov_from_dfov(fov, w, h).to_radians() / 2.0).tan() / w
            }
            _ => {
                return Err(InputError::new("camera_incomplete", "/camera", "describe the lens one way: sensor_width_mm with focal_length_mm, or hfov_deg, or dfov_deg"));
            }
        };
        Ok((per_m, w, h))
    }

    /// Horizontal and vertical fields of view in degrees (square pixels), and the ground
    /// sample distance per metre of distance at the image centre.
    pub fn field_of_view(&self) -> Result<([f64; 2], f64), InputError> {
        let (per_m, w, h) = self.gsd_per_m()?;
        let fov = |px: f64| 2.0 * (per_m * px / 2.0).atan().to_degrees();
        Ok(([fov(w), fov(h)], per_m))
    }

    /// Resolves the altitude (given, or from a wanted ground sample distance) and the spacings.
    pub fn plan(&self, altitude_m: Option<f64>, gsd_cm: Option<f64>, side_overlap: f64, front_overlap: f64) -> Result<CameraPlan, InputError> {
        let (per_m, w, h) = self.gsd_per_m()?;
        let altitude_m = match (altitude_m, gsd_cm) {
            (Some(_), Some(_)) => return Err(InputError::new("camera_altitude_twice", "/gsd_cm", "give altitude_m or gsd_cm, not both")),
            (Some(a), None) => a,
            (None, Some(g)) => {
                check_range(g, 0.01, 1_000.0, "/gsd_cm", "cm/px")?;
                g / 100.0 / per_m
            }
            (None, None) => return Err(InputError::new("camera_needs_altitude", "/altitude_m", "with a camera, give altitude_m or gsd_cm")),
        };
        if gsd_cm.is_some() && !(1.0..=5_000.0).contains(&altitude_m) {
            return Err(InputError::new("gsd_out_of_reach", "/gsd_cm", format!("this camera takes that GSD from {altitude_m:.1} m; the altitude is 1 to 5 000 m")));
        }
        check_range(altitude_m, 1.0, 5_000.0, "/altitude_m", "m")?;
        let gsd = altitude_m * per_m;
        let (across, along) = match self.orientation.unwrap_or_default() {
            Orientation::Landscape => (w * gsd, h * gsd),
            Orientation::Portrait => (h * gsd, w * gsd),
        };
        Ok(CameraPlan {
            altitude_m,
            gsd_cm: gsd * 100.0,
            footprint_across_m: across,
            footprint_along_m: along,
            line_spacing_m: across * (1.0 - side_overlap),
            photo_spacing_m: along * (1.0 - front_overlap),
        })
    }
}

/// Photo positions along a line of length `len`, from its start (docs/methods.md, camera §6, fitted mode):
/// the fewest photos no farther apart than `max_step` whose footprints (`footprint` long)
/// are flush with both ends; one photo in the middle of a line shorter than a footprint.
pub fn fitted_photo_offsets(len: f64, footprint: f64, max_step: f64) -> Vec<f64> {
    let n = (((len - (footprint - max_step)) / max_step) - 1e-9).ceil().max(1.0) as usize;
    if n == 1 {
        return vec![len / 2.0];
    }
    let step = (len - footprint) / (n - 1) as f64;
    (0..n).map(|i| footprint / 2.0 + i as f64 * step).collect()
}

/// Photo positions along a straight piece of a line that bends (a spiral's ring, a spur), where
/// the camera keeps triggering through the bends: the photo at a bend is the next piece's first,
/// taken at the bend and facing the next piece, so that its footprint reaches over the corner
/// (seed 002 §4.1: a photo at each ring vertex images the field's corner). `after_bend`: the
/// piece starts at a bend (else its first footprint is flush with its start); `before_bend`: it
/// ends at one (its last photo is a step before the bend; else its last footprint is flush with
/// its end). Both false: [`fitted_photo_offsets`].
pub fn photo_offsets_through_bends(len: f64, footprint: f64, max_step: f64, after_bend: bool, before_bend: bool) -> Vec<f64> {
    let first = if after_bend { 0.0 } else { (footprint / 2.0).min(len / 2.0) };
    let steps = |span: f64| ((span / max_step) - 1e-9).ceil().max(1.0) as usize;
    match (after_bend, before_bend) {
        (false, false) => fitted_photo_offsets(len, footprint, max_step),
        // photos up to the bend, the bend's own left to the next piece
        (_, true) => {
            let n = steps(len - first);
            (0..n).map(|i| first + i as f64 * (len - first) / n as f64).collect()
        }
        // from the bend to a footprint flush with the end
        (true, false) => {
            let last = len - footprint / 2.0;
            if last <= 0.0 {
                return vec![0.0];
            }
            let n = steps(last);
            (0..=n).map(|i| i as f64 * last / n as f64).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Through bends, photos stay a step apart at most; a bend's photo is the piece's
        /// first and never its last (the next piece takes it); an end without a bend keeps its
        /// footprint flush with the end.
        #[test]
        fn photos_through_bends_image_the_whole_piece(len in 0.5..400.0f64, footprint in 5.0..60.0f64, overlap in 0.0..0.9f64, after in any::<bool>(), before in any::<bool>()) {
            let step = footprint * (1.0 - overlap);
            let offsets = photo_offsets_through_bends(len, footprint, step, after, before);
            prop_assert!(!offsets.is_empty());
            prop_assert!(offsets.windows(2).all(|w| w[1] > w[0] && w[1] - w[0] <= step + 1e-9), "{offsets:?}");
            let (first, last) = (offsets[0], offsets[offsets.len() - 1]);
            prop_assert!(first >= 0.0 && last <= len);
            if after {
                prop_assert_eq!(first, 0.0);
            } else {
                prop_assert!(first <= footprint / 2.0 + 1e-9);
            }
            if before {
                prop_assert!(last < len && len - last <= step + 1e-9, "{offsets:?}");
            } else {
                prop_assert!(last + footprint / 2.0 >= len - 1e-9, "{offsets:?}");
            }
        }
    }

    fn sensor(w: f64, h: f64, f: f64, px: (u32, u32)) -> Camera {
        Camera { sensor_width_mm: Some(w), sensor_height_mm: Some(h), focal_length_mm: Some(f), image_width_px: Some(px.0), image_height_px: Some(px.1), ..Camera::default() }
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-12)
    }

    #[test]
    fn qgroundcontrol_parity() {
        // docs/methods.md, camera §7 E1: QGroundControl's documentation camera at 25 cm/px, overlaps 70/70 %
        let p = sensor(23.2, 15.4, 16.0, (5456, 3632)).plan(None, Some(25.0), 0.7, 0.7).unwrap();
        assert!(close(p.altitude_m, 940.6896551724138, 1e-9));
        assert!(close(p.footprint_across_m, 1364.0, 1e-9) && close(p.footprint_along_m, 908.0, 1e-9));
        assert!(close(p.line_spacing_m, 409.2, 1e-9) && close(p.photo_spacing_m, 272.4, 1e-9));
    }

    #[test]
    fn one_inch_camera_vectors() {
        // E2: 1-inch 20 MP camera
        let cam = sensor(13.2, 8.8, 8.8, (5472, 3648));
        let p = cam.plan(None, Some(2.0), 0.7, 0.8).unwrap();
        assert!(close(p.altitude_m, 72.96, 1e-6) && close(p.footprint_across_m, 109.44, 1e-6) && close(p.footprint_along_m, 72.96, 1e-6));
        assert!(close(p.line_spacing_m, 32.832, 1e-6) && close(p.photo_spacing_m, 14.592, 1e-6));
        let q = cam.plan(Some(100.0), None, 0.7, 0.8).unwrap();
        assert!(close(q.gsd_cm, 2.7412, 1e-4) && close(q.footprint_across_m, 150.0, 1e-9) && close(q.line_spacing_m, 45.0, 1e-9));
        // a 300 m line, fitted photos: 17 photos 14.19 m apart
        let photos = fitted_photo_offsets(300.0, p.footprint_along_m, p.photo_spacing_m);
        assert_eq!(photos.len(), 17);
        assert!((photos[1] - photos[0] - 14.19).abs() < 1e-2);
        assert!(close(photos[0], 72.96 / 2.0, 1e-9) && close(photos[16], 300.0 - 72.96 / 2.0, 1e-9));
        // the same camera by its preset, and portrait mounting swaps the footprint
        let preset = Camera { preset: Some("dji_phantom4_pro".into()), ..Camera::default() };
        assert_eq!(preset.plan(Some(100.0), None, 0.7, 0.8).unwrap(), q);
        let portrait = Camera { orientation: Some(Orientation::Portrait), ..preset };
        assert!(close(portrait.plan(Some(100.0), None, 0.7, 0.8).unwrap().footprint_across_m, 100.0, 1e-9));
    }

    #[test]
    fn field_of_view_vectors() {
        // E3: seed 000's camera, hfov 94.4° over 3000 × 2250 px at 50 m
        let cam = Camera { hfov_deg: Some(94.4), image_width_px: Some(3000), image_height_px: Some(2250), ..Camera::default() };
        let p = cam.plan(Some(50.0), None, 0.2, 0.6).unwrap();
        assert!((p.footprint_across_m - 107.990).abs() < 1e-3 && (p.footprint_along_m - 80.993).abs() < 1e-3);
        assert!((p.gsd_cm - 3.5997).abs() < 1e-4 && (p.line_spacing_m - 86.392).abs() < 1e-3 && (p.photo_spacing_m - 32.397).abs() < 1e-3);
        // E4: seed 002's camera
        let cam = Camera { hfov_deg: Some(100.0), image_width_px: Some(2386), image_height_px: Some(2386), ..Camera::default() };
        let p = cam.plan(Some(10.0), None, 0.1, 0.1).unwrap();
        assert!((p.footprint_across_m - 23.835).abs() < 1e-3 && (p.line_spacing_m - 21.452).abs() < 1e-3);
        // a diagonal 84° over 5472 × 3648 px is 73.68° across
        assert!((hfov_from_dfov(84.0, 5472.0, 3648.0) - 73.68).abs() < 0.01);
    }

    #[test]
    fn incomplete_or_unknown_cameras_are_refused() {
        let c = Camera { image_width_px: Some(100), image_height_px: Some(100), ..Camera::default() };
        assert_eq!(c.plan(Some(50.0), None, 0.7, 0.8).unwrap_err().code, "camera_incomplete");
        let c = Camera { preset: Some("box_brownie".into()), ..Camera::default() };
        assert_eq!(c.plan(Some(50.0), None, 0.7, 0.8).unwrap_err().pointer, "/camera/preset");
        let c = sensor(13.2, 8.8, 8.8, (5472, 3648));
        assert_eq!(c.plan(Some(50.0), Some(2.0), 0.7, 0.8).unwrap_err().code, "camera_altitude_twice");
    }
}
