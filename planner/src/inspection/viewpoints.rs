//! Viewpoint sampling (spec `inspection.md` §5, §8): positions from a Halton sequence over
//! the volume around the targets, or near the current best path; the camera aimed at the
//! nearest point of interest, with Gaussian spread; kept when it sees enough.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use rayon::prelude::*;
use rstar::RTree;
use rstar::primitives::GeomWithData;

use super::poi::Poi;
use super::scene::{Point3, Scene};
use super::visibility::{Optics, Pose, visible};

/// Spread of the yaw and the pitch around the direction to the nearest point, degrees.
const YAW_SIGMA_DEG: f64 = 20.0;
const PITCH_SIGMA_DEG: f64 = 10.0;

/// Candidates checked at once (in parallel, then kept in order, so the result does not
/// depend on the thread count).
const BATCH: usize = 64;

#[derive(Debug, Clone, PartialEq)]
pub struct Viewpoint {
    pub pose: Pose,
    /// Points seen, ascending.
    pub sees: Vec<u32>,
}

/// Everything a candidate is judged against.
pub struct Sampler<'a> {
    pub scene: &'a Scene,
    pub pois: &'a [Poi],
    pub index: &'a RTree<GeomWithData<[f64; 3], u32>>,
    pub optics: Optics,
    /// Lowest and highest gimbal pitch, radians.
    pub pitch_range: [f64; 2],
    /// Least weight a viewpoint must see to be kept.
    pub threshold: f64,
    pub rng: ChaCha8Rng,
}

/// The i-th element of the van der Corput sequence in `base`.
fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= base as f64;
        r += f * (i % base) as f64;
        i /= base;
    }
    r
}

/// The 3D Halton point of index `i` in the unit cube.
pub fn halton(i: u64) -> [f64; 3] {
    [radical_inverse(i, 2), radical_inverse(i, 3), radical_inverse(i, 5)]
}

impl Sampler<'_> {
    pub fn new<'a>(scene: &'a Scene, pois: &'a [Poi], index: &'a RTree<GeomWithData<[f64; 3], u32>>, optics: Optics, pitch_range: [f64; 2], seed: u64) -> Sampler<'a> {
        let total: f64 = pois.iter().map(|p| p.weight).sum();
        // spec §5: max(10, 0.001 Σw), never more than a tenth of everything there is to see
        let threshold = (0.001 * total).max(10.0).min(0.1 * total);
        Sampler { scene, pois, index, optics, pitch_range, threshold, rng: ChaCha8Rng::seed_from_u64(seed) }
    }

    fn uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform index below `n` (at least 1).
    pub fn uniform_index(&mut self, n: usize) -> usize {
        (self.rng.next_u64() % n.max(1) as u64) as usize
    }

    /// A standard normal number (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = self.uniform().max(1e-300);
        let v = self.uniform();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }

    /// The camera aimed from `at` at the nearest point of interest, spread at random.
    fn aim(&mut self, at: Point3) -> Option<Pose> {
        let target = self.index.nearest_neighbor(&at)?.geom();
        let d = [target[0] - at[0], target[1] - at[1], target[2] - at[2]];
        let yaw = d[1].atan2(d[0]) + (YAW_SIGMA_DEG * self.normal()).to_radians();
        let pitch = (d[2].atan2(d[0].hypot(d[1])) + (PITCH_SIGMA_DEG * self.normal()).to_radians()).clamp(self.pitch_range[0], self.pitch_range[1]);
        Some(Pose { at, yaw, pitch })
    }

    /// Keeps the candidates (in order) that are free and see at least the threshold, up to
    /// `want`; `positions` yields candidate positions, `None` once it gives up.
    pub fn collect(&mut self, want: usize, max_tries: usize, mut positions: impl FnMut(&mut Self) -> Option<Point3>) -> (Vec<Viewpoint>, usize) {
        let mut kept = Vec::new();
        let mut tries = 0;
        while kept.len() < want && tries < max_tries {
            let mut poses = Vec::with_capacity(BATCH);
            while poses.len() < BATCH && tries < max_tries {
                tries += 1;
                let Some(at) = positions(self) else { break };
                if !self.scene.is_free(at, true) {
                    continue;
                }
                if let Some(pose) = self.aim(at) {
                    poses.push(pose);
                }
            }
            if poses.is_empty() {
                break;
            }
            let Sampler { scene, pois, index, optics, .. } = *self;
            let seen: Vec<Vec<u32>> = poses.par_iter().map(|pose| visible(scene, pois, index, &optics, pose)).collect();
            for (pose, sees) in poses.into_iter().zip(seen) {
                let weight: f64 = sees.iter().map(|&i| pois[i as usize].weight).sum();
                if weight >= self.threshold && kept.len() < want {
                    kept.push(Viewpoint { pose, sees });
                }
            }
        }
        (kept, tries)
    }

    /// A uniform point inside the ball of `radius` around `centre`.
    pub fn in_ball(&mut self, centre: Point3, radius: f64) -> Point3 {
        loop {
            let p = [2.0 * self.uniform() - 1.0, 2.0 * self.uniform() - 1.0, 2.0 * self.uniform() - 1.0];
            if p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0 {
                return [centre[0] + radius * p[0], centre[1] + radius * p[1], centre[2] + radius * p[2]];
            }
        }
    }

    /// A point on the prolate spheroid with foci `a` and `b` and major axis `1.2 |ab|`.
    pub fn on_spheroid(&mut self, a: Point3, b: Point3) -> Point3 {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let c = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / 2.0;
        let centre = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0];
        let semi_major = 1.2 * c;
        let semi_minor = (semi_major * semi_major - c * c).sqrt();
        // a direction on the unit sphere, stretched to the spheroid along the foci's axis
        let (z, phi) = (2.0 * self.uniform() - 1.0, std::f64::consts::TAU * self.uniform());
        let r = (1.0 - z * z).sqrt();
        let local = [semi_major * z, semi_minor * r * phi.cos(), semi_minor * r * phi.sin()];
        let axis = if c > 1e-9 { [d[0] / (2.0 * c), d[1] / (2.0 * c), d[2] / (2.0 * c)] } else { [1.0, 0.0, 0.0] };
        // two unit vectors across the axis
        let helper = if axis[2].abs() < 0.9 { [0.0, 0.0, 1.0] } else { [1.0, 0.0, 0.0] };
        let u = normalise(cross(axis, helper));
        let w = cross(axis, u);
        std::array::from_fn(|k| centre[k] + local[0] * axis[k] + local[1] * u[k] + local[2] * w[k])
    }
}

fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalise(a: Point3) -> Point3 {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_points_fill_the_cube_evenly() {
        let n = 4096;
        let mut octants = [0usize; 8];
        for i in 1..=n {
            let p = halton(i);
            assert!(p.iter().all(|c| (0.0..1.0).contains(c)));
            octants[(p[0] >= 0.5) as usize + 2 * (p[1] >= 0.5) as usize + 4 * (p[2] >= 0.5) as usize] += 1;
        }
        assert!(octants.iter().all(|&k| (k as f64 - 512.0).abs() < 10.0), "{octants:?}");
    }
}
