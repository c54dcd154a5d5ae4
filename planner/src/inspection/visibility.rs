//! What a camera at a viewpoint sees: the points inside its frustum and range, facing it
//! closely enough, with nothing solid in between (spec `inspection.md` §4).

use rstar::RTree;
use rstar::primitives::GeomWithData;

use super::poi::Poi;
use super::scene::{Point3, Scene};

/// The camera's reach.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Optics {
    pub hfov_deg: f64,
    pub vfov_deg: f64,
    pub min_range_m: f64,
    pub max_range_m: f64,
    pub max_incidence_deg: f64,
}

/// Where the camera is and where it looks: yaw as a math angle (radians counter-clockwise
/// from east) and gimbal pitch (radians, negative down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub at: Point3,
    pub yaw: f64,
    pub pitch: f64,
}

/// The camera's axes in the local frame: forward (the optical axis), left and up.
fn axes(pose: &Pose) -> [Point3; 3] {
    let (sy, cy) = pose.yaw.sin_cos();
    let (sp, cp) = pose.pitch.sin_cos();
    [[cp * cy, cp * sy, sp], [-sy, cy, 0.0], [-sp * cy, -sp * sy, cp]]
}

fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Indices of the points seen from `pose`, ascending.
pub fn visible(scene: &Scene, pois: &[Poi], index: &RTree<GeomWithData<[f64; 3], u32>>, optics: &Optics, pose: &Pose) -> Vec<u32> {
    let [fwd, left, up] = axes(pose);
    let (tan_h, tan_v) = ((optics.hfov_deg / 2.0).to_radians().tan(), (optics.vfov_deg / 2.0).to_radians().tan());
    let cos_inc = optics.max_incidence_deg.to_radians().cos();
    let v = pose.at;
    let mut seen: Vec<u32> = index
        .locate_within_distance(v, optics.max_range_m * optics.max_range_m)
        .map(|g| g.data)
        .filter(|&i| {
            let p = &pois[i as usize];
            let d = [p.at[0] - v[0], p.at[1] - v[1], p.at[2] - v[2]];
            let range = dot(d, d).sqrt();
            let x = dot(d, fwd);
            if range < optics.min_range_m || x <= 0.0 {
                return false;
            }
            let (y, z) = (dot(d, left), dot(d, up));
            // |atan2(y, x)| ≤ hfov/2 with x > 0
            if y.abs() > x * tan_h || z.abs() > x * tan_v {
                return false;
            }
            // the face turned towards the camera, no more than the incidence limit away
            if -dot(p.normal, d) < cos_inc * range {
                return false;
            }
            !scene.occluded(v, p.at)
        })
        .collect();
    seen.sort_unstable();
    seen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspection::poi::{self, TargetGroup};
    use crate::inspection::scene::Prism;
    use crate::params::inspection::Face;
    use geo::{MultiPolygon, polygon};

    fn setup() -> (Scene, Vec<Poi>) {
        let footprint = polygon![(x: 0.0, y: 0.0), (x: 8.0, y: 0.0), (x: 8.0, y: 8.0), (x: 0.0, y: 8.0)];
        let prisms = vec![Prism { name: "b".into(), footprint, base_m: 0.0, top_m: 8.0, is_structure: true, mesh: None }];
        let pois = poi::sample(&prisms, &[TargetGroup { prism: 0, face: Face::Walls, priority: 1.0 }, TargetGroup { prism: 0, face: Face::Roof, priority: 1.0 }], 0.5);
        let fence = MultiPolygon(vec![polygon![(x: -50.0, y: -50.0), (x: 60.0, y: -50.0), (x: 60.0, y: 60.0), (x: -50.0, y: 60.0)]]);
        (Scene::new(prisms, &MultiPolygon(Vec::new()), fence, 0.5, 2.0), pois)
    }

    const OPTICS: Optics = Optics { hfov_deg: 60.0, vfov_deg: 45.0, min_range_m: 0.3, max_range_m: 10.0, max_incidence_deg: 75.0 };

    #[test]
    fn a_camera_facing_the_west_wall_sees_only_that_wall_within_its_frustum() {
        let (scene, pois) = setup();
        let index = poi::index(&pois);
        let pose = Pose { at: [-5.0, 4.0, 4.0], yaw: 0.0, pitch: 0.0 };
        let seen = visible(&scene, &pois, &index, &OPTICS, &pose);
        assert!(!seen.is_empty());
        for &i in &seen {
            let p = &pois[i as usize];
            assert_eq!(p.normal, [-1.0, 0.0, 0.0]);
            // within ±30° across and ±22.5° up and down at 5 m
            assert!((p.at[1] - 4.0).abs() <= 5.01 * 30f64.to_radians().tan() && (p.at[2] - 4.0).abs() <= 5.01 * 22.5f64.to_radians().tan());
        }
        // facing away: nothing
        assert!(visible(&scene, &pois, &index, &OPTICS, &Pose { yaw: std::f64::consts::PI, ..pose }).is_empty());
        // looking down from above the roof: roof points only
        let down = visible(&scene, &pois, &index, &OPTICS, &Pose { at: [4.0, 4.0, 14.0], yaw: 0.0, pitch: -std::f64::consts::FRAC_PI_2 });
        assert!(!down.is_empty() && down.iter().all(|&i| pois[i as usize].normal == [0.0, 0.0, 1.0]));
    }

    #[test]
    fn grazing_faces_and_far_points_are_not_seen() {
        let (scene, pois) = setup();
        let index = poi::index(&pois);
        // along the west wall's plane: every point of it is seen at more than 75° from its normal
        let pose = Pose { at: [-0.5, -6.0, 4.0], yaw: std::f64::consts::FRAC_PI_2, pitch: 0.0 };
        let seen = visible(&scene, &pois, &index, &OPTICS, &pose);
        assert!(seen.iter().all(|&i| pois[i as usize].normal != [-1.0, 0.0, 0.0]));
        let far = Pose { at: [-20.0, 4.0, 4.0], yaw: 0.0, pitch: 0.0 };
        assert!(visible(&scene, &pois, &index, &OPTICS, &far).is_empty());
    }
}
