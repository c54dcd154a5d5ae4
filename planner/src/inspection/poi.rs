//! Points of interest: the target faces sampled on a regular grid, each point the centre of
//! the patch it stands for (spec `inspection.md` §3).

use geo::{BoundingRect, Contains, Coord};
use rstar::RTree;
use rstar::primitives::GeomWithData;

use super::scene::{Point3, Prism, outward_normal, ring_edges};
use crate::params::inspection::Face;

/// How far a point is moved off its face along the normal, so that its own face does not hide
/// it.
pub const OFFSET_M: f64 = 0.01;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Poi {
    pub at: Point3,
    /// Outward unit normal of its face.
    pub normal: Point3,
    /// Index of its target group (a structure's walls or roof).
    pub group: usize,
    pub weight: f64,
    pub area_m2: f64,
}

/// A structure's walls or roof, with the weight of its points.
#[derive(Debug, Clone, PartialEq)]
pub struct TargetGroup {
    pub prism: usize,
    pub face: Face,
    pub priority: f64,
}

/// The points of every group, skipping those inside another solid (a wall two buildings
/// share has nothing to see).
pub fn sample(prisms: &[Prism], groups: &[TargetGroup], spacing: f64) -> Vec<Poi> {
    let mut out = Vec::new();
    for (g, group) in groups.iter().enumerate() {
        let p = &prisms[group.prism];
        let mut push = |at: Point3, normal: Point3, area_m2: f64| {
            let at = [at[0] + normal[0] * OFFSET_M, at[1] + normal[1] * OFFSET_M, at[2] + normal[2] * OFFSET_M];
            if !prisms.iter().enumerate().any(|(i, q)| i != group.prism && inside(q, at)) {
                out.push(Poi { at, normal, group: g, weight: group.priority, area_m2 });
            }
        };
        if let Some(mesh) = &p.mesh {
            for t in mesh {
                sample_triangle(t, spacing, group.face, &mut push);
            }
            continue;
        }
        match group.face {
            Face::Walls => {
                let height = p.top_m - p.base_m;
                let rows = cells(height, spacing);
                for (a, b) in ring_edges(&p.footprint) {
                    let Some(n) = outward_normal(a, b) else { continue };
                    let len = (b.x - a.x).hypot(b.y - a.y);
                    let cols = cells(len, spacing);
                    let area = len / cols as f64 * height / rows as f64;
                    for i in 0..cols {
                        let t = (i as f64 + 0.5) / cols as f64;
                        for j in 0..rows {
                            let z = p.base_m + height * (j as f64 + 0.5) / rows as f64;
                            push([a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, z], [n.x, n.y, 0.0], area);
                        }
                    }
                }
            }
            Face::Roof => {
                let Some(bb) = p.footprint.bounding_rect() else { continue };
                let (cols, rows) = (cells(bb.width(), spacing), cells(bb.height(), spacing));
                for i in 0..cols {
                    for j in 0..rows {
                        let c = Coord { x: bb.min().x + (i as f64 + 0.5) * spacing, y: bb.min().y + (j as f64 + 0.5) * spacing };
                        if p.footprint.contains(&c) {
                            push([c.x, c.y, p.top_m], [0.0, 0.0, 1.0], spacing * spacing);
                        }
                    }
                }
            }
        }
    }
    out
}

/// Patches of about `spacing` across `len` (a length a rounding error over a whole number of
/// spacings counts as that number).
fn cells(len: f64, spacing: f64) -> usize {
    ((len / spacing) - 1e-6).ceil().max(1.0) as usize
}

/// A model's faces count as roof where they face up by more than 45°, else as walls.
const ROOF_NORMAL_Z: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The centres of a triangle cut into m² equal triangles (m the longest edge over the
/// spacing), when the triangle is of `face`'s kind; its normal from its winding.
fn sample_triangle(t: &[[f64; 3]; 3], spacing: f64, face: Face, push: &mut impl FnMut(Point3, Point3, f64)) {
    let [a, b, c] = *t;
    let (u, v) = (sub(b, a), sub(c, a));
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let twice_area = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if twice_area < 1e-12 {
        return;
    }
    let normal = n.map(|x| x / twice_area);
    if (normal[2] >= ROOF_NORMAL_Z) != (face == Face::Roof) {
        return;
    }
    // a floor on the ground is never seen
    if normal[2] <= -ROOF_NORMAL_Z && [a, b, c].iter().all(|p| p[2] <= 0.05) {
        return;
    }
    let longest = [u, v, sub(c, b)].iter().map(|e| (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()).fold(0.0, f64::max);
    let m = cells(longest, spacing);
    let area = twice_area / 2.0 / (m * m) as f64;
    let at = |i: f64, j: f64| std::array::from_fn(|k| a[k] + u[k] * i / m as f64 + v[k] * j / m as f64);
    for i in 0..m {
        for j in 0..m - i {
            // the upright small triangle's centre, and the inverted one beside it
            push(at(i as f64 + 1.0 / 3.0, j as f64 + 1.0 / 3.0), normal, area);
            if i + j + 1 < m {
                push(at(i as f64 + 2.0 / 3.0, j as f64 + 2.0 / 3.0), normal, area);
            }
        }
    }
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Inside a prism's solid (a model's hull is not a solid: it is not asked).
fn inside(q: &Prism, at: Point3) -> bool {
    q.mesh.is_none() && at[2] > q.base_m && at[2] < q.top_m && q.footprint.contains(&Coord { x: at[0], y: at[1] })
}

/// The points in an R-tree by position, with their index.
pub fn index(pois: &[Poi]) -> RTree<GeomWithData<[f64; 3], u32>> {
    RTree::bulk_load(pois.iter().enumerate().map(|(i, p)| GeomWithData::new(p.at, i as u32)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    #[test]
    fn a_box_gives_a_point_per_patch_with_normals_pointing_out() {
        let footprint = polygon![(x: 0.0, y: 0.0), (x: 8.0, y: 0.0), (x: 8.0, y: 8.0), (x: 0.0, y: 8.0)];
        let prisms = vec![Prism { name: "b".into(), footprint, base_m: 0.0, top_m: 12.0, is_structure: true, mesh: None }];
        let groups = vec![TargetGroup { prism: 0, face: Face::Walls, priority: 1.0 }, TargetGroup { prism: 0, face: Face::Roof, priority: 2.0 }];
        let pois = sample(&prisms, &groups, 0.5);
        let walls = pois.iter().filter(|p| p.group == 0).count();
        assert_eq!(walls, 4 * 16 * 24);
        assert_eq!(pois.len() - walls, 16 * 16);
        let area: f64 = pois.iter().map(|p| p.area_m2).sum();
        assert!((area - (4.0 * 8.0 * 12.0 + 64.0)).abs() < 1e-9);
        for p in &pois {
            // the normal points away from the centre of the box
            let out = (p.at[0] - 4.0) * p.normal[0] + (p.at[1] - 4.0) * p.normal[1] + (p.at[2] - 6.0) * p.normal[2];
            assert!(out > 0.0, "{p:?}");
        }
        assert!(pois.iter().all(|p| (p.group == 1) == (p.weight == 2.0)));
    }

    #[test]
    fn a_model_is_sampled_on_its_faces_by_their_normals() {
        // a 4 × 4 m square roof at 3 m and one wall, wound counter-clockwise seen from outside
        let roof = [[[0.0, 0.0, 3.0], [4.0, 0.0, 3.0], [4.0, 4.0, 3.0]], [[0.0, 0.0, 3.0], [4.0, 4.0, 3.0], [0.0, 4.0, 3.0]]];
        let wall = [[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 0.0, 3.0]], [[0.0, 0.0, 0.0], [4.0, 0.0, 3.0], [0.0, 0.0, 3.0]]];
        let footprint = polygon![(x: 0.0, y: 0.0), (x: 4.0, y: 0.0), (x: 4.0, y: 4.0), (x: 0.0, y: 4.0)];
        let mesh: Vec<[[f64; 3]; 3]> = roof.into_iter().chain(wall).collect();
        let prisms = vec![Prism { name: "m".into(), footprint, base_m: 0.0, top_m: 3.0, is_structure: true, mesh: Some(mesh) }];
        let groups = [TargetGroup { prism: 0, face: Face::Walls, priority: 1.0 }, TargetGroup { prism: 0, face: Face::Roof, priority: 1.0 }];
        let pois = sample(&prisms, &groups, 0.5);
        let area = |g: usize| pois.iter().filter(|p| p.group == g).map(|p| p.area_m2).sum::<f64>();
        assert!((area(0) - 12.0).abs() < 1e-9 && (area(1) - 16.0).abs() < 1e-9, "{} {}", area(0), area(1));
        assert!(pois.iter().filter(|p| p.group == 0).all(|p| p.normal == [0.0, -1.0, 0.0] && p.at[1] < 0.0));
        assert!(pois.iter().filter(|p| p.group == 1).all(|p| (0.0..4.0).contains(&p.at[0]) && (0.0..4.0).contains(&p.at[1])));
    }

    #[test]
    fn a_wall_shared_with_a_neighbour_has_no_points() {
        let a = polygon![(x: 0.0, y: 0.0), (x: 4.0, y: 0.0), (x: 4.0, y: 4.0), (x: 0.0, y: 4.0)];
        let b = polygon![(x: 4.0, y: 0.0), (x: 8.0, y: 0.0), (x: 8.0, y: 4.0), (x: 4.0, y: 4.0)];
        let prism = |footprint| Prism { name: "x".into(), footprint, base_m: 0.0, top_m: 4.0, is_structure: true, mesh: None };
        let pois = sample(&[prism(a), prism(b)], &[TargetGroup { prism: 0, face: Face::Walls, priority: 1.0 }], 1.0);
        assert_eq!(pois.len(), 3 * 4 * 4);
        assert!(pois.iter().all(|p| p.at[0] < 4.0));
    }
}
