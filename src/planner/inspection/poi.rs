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

fn inside(q: &Prism, at: Point3) -> bool {
    at[2] > q.base_m && at[2] < q.top_m && q.footprint.contains(&Coord { x: at[0], y: at[1] })
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
        let prisms = vec![Prism { name: "b".into(), footprint, base_m: 0.0, top_m: 12.0, is_structure: true }];
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
    fn a_wall_shared_with_a_neighbour_has_no_points() {
        let a = polygon![(x: 0.0, y: 0.0), (x: 4.0, y: 0.0), (x: 4.0, y: 4.0), (x: 0.0, y: 4.0)];
        let b = polygon![(x: 4.0, y: 0.0), (x: 8.0, y: 0.0), (x: 8.0, y: 4.0), (x: 4.0, y: 4.0)];
        let prism = |footprint| Prism { name: "x".into(), footprint, base_m: 0.0, top_m: 4.0, is_structure: true };
        let pois = sample(&[prism(a), prism(b)], &[TargetGroup { prism: 0, face: Face::Walls, priority: 1.0 }], 1.0);
        assert_eq!(pois.len(), 3 * 4 * 4);
        assert!(pois.iter().all(|p| p.at[0] < 4.0));
    }
}
