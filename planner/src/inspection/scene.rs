//! The scene in 2.5D: every structure and obstacle an extruded prism, its triangles in a BVH
//! for line-of-sight tests (`parry3d`), and the volumes the drone keeps out of (spec
//! `inspection.md` §2).

use geo::algorithm::TriangulateEarcut;
use geo::{BoundingRect, Contains, Coord, LineString, MultiPolygon, Orient, Polygon, Rect, orient::Direction};
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::TriMesh;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

use crate::geom::{EdgeIndex, grow};

/// A point in the local frame: east, north, up (metres above ground).
pub type Point3 = [f64; 3];

/// A solid: its footprint from `base_m` to `top_m`.
#[derive(Debug, Clone)]
pub struct Prism {
    pub name: String,
    /// Counter-clockwise exterior, clockwise holes (a courtyard's walls face into it).
    pub footprint: Polygon,
    pub base_m: f64,
    pub top_m: f64,
    /// A structure that may be a target (obstacles only hide and block).
    pub is_structure: bool,
    /// A model's triangles: its faces instead of the footprint's walls and roof (the footprint,
    /// their hull, only bounds it).
    pub mesh: Option<Vec<[[f64; 3]; 3]>>,
}

/// The space a drone's centre may not enter around a prism: its footprint grown by the body's
/// radius and the margin, from the margin below its base to the margin above its top.
#[derive(Debug, Clone)]
pub struct KeepOut {
    pub footprint: Polygon,
    pub z: [f64; 2],
}

pub struct Scene {
    pub prisms: Vec<Prism>,
    pub keep_out: Vec<KeepOut>,
    keep_out_index: RTree<GeomWithData<Rectangle<[f64; 2]>, usize>>,
    /// No-fly zones grown by the body's radius and the margin: no height clears them.
    pub no_fly: MultiPolygon,
    /// Where the drone may fly: the mission's area.
    pub geofence: MultiPolygon,
    fence_edges: EdgeIndex,
    /// Every face as triangles, relative to `origin` (f32 keeps millimetres within kilometres
    /// of it).
    mesh: Option<TriMesh>,
    origin: Coord,
}

impl Scene {
    /// `clearance_m`: the body's radius plus the safety margin.
    pub fn new(prisms: Vec<Prism>, no_fly_zones: &MultiPolygon, geofence: MultiPolygon, body_radius_m: f64, margin_m: f64) -> Scene {
        let clearance = body_radius_m + margin_m;
        let prisms: Vec<Prism> = prisms.into_iter().map(|p| Prism { footprint: p.footprint.orient(Direction::Default), ..p }).collect();
        let keep_out: Vec<KeepOut> = prisms
            .iter()
            .map(|p| {
                let grown = grow(&MultiPolygon(vec![p.footprint.clone()]), clearance);
                // growing a polygon keeps one piece; the hull of its pieces is a safe stand-in
                let footprint = grown.0.into_iter().max_by(|a, b| geo::Area::unsigned_area(a).total_cmp(&geo::Area::unsigned_area(b))).unwrap_or_else(|| p.footprint.clone());
                KeepOut { footprint: Polygon::new(footprint.exterior().clone(), Vec::new()), z: [p.base_m - clearance, p.top_m + clearance] }
            })
            .collect();
        let keep_out_index = RTree::bulk_load(
            keep_out
                .iter()
                .enumerate()
                .filter_map(|(i, k)| k.footprint.bounding_rect().map(|r| GeomWithData::new(Rectangle::from_corners([r.min().x, r.min().y], [r.max().x, r.max().y]), i)))
                .collect(),
        );
        let origin = geofence.bounding_rect().map_or(Coord { x: 0.0, y: 0.0 }, |r| r.center());
        let mesh = triangles(&prisms, origin);
        let no_fly = if no_fly_zones.0.is_empty() { MultiPolygon(Vec::new()) } else { grow(no_fly_zones, clearance) };
        let fence_edges = EdgeIndex::new(&geofence);
        Scene { prisms, keep_out, keep_out_index, no_fly, geofence, fence_edges, mesh, origin }
    }

    /// The keep-out volumes whose footprint's box meets `rect`.
    pub fn keep_out_near(&self, rect: Rect) -> impl Iterator<Item = usize> + '_ {
        let aabb = AABB::from_corners([rect.min().x, rect.min().y], [rect.max().x, rect.max().y]);
        self.keep_out_index.locate_in_envelope_intersecting(&aabb).map(|g| g.data)
    }

    /// True where the drone's centre may be: outside every no-fly zone and every keep-out
    /// volume, and, when `fenced`, inside the geofence.
    pub fn is_free(&self, p: Point3, fenced: bool) -> bool {
        let c = Coord { x: p[0], y: p[1] };
        if p[2] < 0.0 || (fenced && !self.geofence.contains(&c)) || self.no_fly.contains(&c) {
            return false;
        }
        !self.keep_out_near(Rect::new(c, c)).any(|i| {
            let k = &self.keep_out[i];
            p[2] > k.z[0] && p[2] < k.z[1] && k.footprint.contains(&c)
        })
    }

    /// True when the segment stays in the geofence: its ends and middle inside (or on the
    /// edge), and no edge of the fence crossed.
    pub fn inside_fence(&self, a: Coord, b: Coord) -> bool {
        let mid = Coord { x: (a.x + b.x) / 2.0, y: (a.y + b.y) / 2.0 };
        let within = |c: Coord| geo::Intersects::intersects(&self.geofence, &c);
        within(a) && within(b) && within(mid) && !self.fence_edges.crossed(&[a, b])
    }

    /// True when a solid face lies strictly between `from` and `to` (`to` may sit on a face
    /// when it is moved off it first: see `poi`).
    pub fn occluded(&self, from: Point3, to: Point3) -> bool {
        let Some(mesh) = &self.mesh else { return false };
        let (o, t) = (self.relative(from), self.relative(to));
        let dir = t - o;
        // parameters along the segment: 0 at `from`, 1 at `to`
        mesh.cast_local_ray(&Ray::new(o, dir), 1.0 - 1e-6, false).is_some_and(|toi| toi > 1e-6)
    }

    fn relative(&self, p: Point3) -> Vector {
        Vector::new((p[0] - self.origin.x) as f32, (p[1] - self.origin.y) as f32, p[2] as f32)
    }
}

/// Walls, roofs and (for raised prisms) floors, as one triangle mesh.
fn triangles(prisms: &[Prism], origin: Coord) -> Option<TriMesh> {
    let mut vertices: Vec<Vector> = Vec::new();
    let mut indices: Vec<[u32; 3]> = Vec::new();
    let push = |corners: &[(Coord, f64)], vertices: &mut Vec<Vector>| {
        let at = vertices.len() as u32;
        vertices.extend(corners.iter().map(|(c, z)| Vector::new((c.x - origin.x) as f32, (c.y - origin.y) as f32, *z as f32)));
        at
    };
    for p in prisms {
        if let Some(mesh) = &p.mesh {
            for t in mesh {
                let i = push(&t.map(|c| (Coord { x: c[0], y: c[1] }, c[2])), &mut vertices);
                indices.push([i, i + 1, i + 2]);
            }
            continue;
        }
        let rings = std::iter::once(p.footprint.exterior()).chain(p.footprint.interiors());
        for ring in rings {
            for w in ring.0.windows(2) {
                let i = push(&[(w[0], p.base_m), (w[1], p.base_m), (w[1], p.top_m), (w[0], p.top_m)], &mut vertices);
                indices.push([i, i + 1, i + 2]);
                indices.push([i, i + 2, i + 3]);
            }
        }
        let mut caps = vec![p.top_m];
        if p.base_m > 0.0 {
            caps.push(p.base_m);
        }
        for z in caps {
            for t in p.footprint.earcut_triangles() {
                let i = push(&[(t.v1(), z), (t.v2(), z), (t.v3(), z)], &mut vertices);
                indices.push([i, i + 1, i + 2]);
            }
        }
    }
    if indices.is_empty() {
        return None;
    }
    TriMesh::new(vertices, indices).ok()
}

/// The ring's outward normals: for each edge of a counter-clockwise exterior or a clockwise
/// hole, the unit vector to its right points away from the solid.
pub fn outward_normal(a: Coord, b: Coord) -> Option<Coord> {
    let d = b - a;
    let len = d.x.hypot(d.y);
    (len > 1e-9).then(|| Coord { x: d.y / len, y: -d.x / len })
}

/// Every edge of a polygon's rings.
pub fn ring_edges(p: &Polygon) -> impl Iterator<Item = (Coord, Coord)> + '_ {
    std::iter::once(p.exterior()).chain(p.interiors()).flat_map(|r: &LineString| r.0.windows(2).map(|w| (w[0], w[1])))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use geo::polygon;

    /// A 10 m cube at the origin in a 110 m square, a 0.5 m body with a 2 m margin.
    pub fn cube() -> Scene {
        let footprint = polygon![(x: 0.0, y: 0.0), (x: 10.0, y: 0.0), (x: 10.0, y: 10.0), (x: 0.0, y: 10.0)];
        let prism = Prism { name: "b".into(), footprint, base_m: 0.0, top_m: 10.0, is_structure: true, mesh: None };
        let fence = MultiPolygon(vec![polygon![(x: -50.0, y: -50.0), (x: 60.0, y: -50.0), (x: 60.0, y: 60.0), (x: -50.0, y: 60.0)]]);
        Scene::new(vec![prism], &MultiPolygon(Vec::new()), fence, 0.5, 2.0)
    }

    #[test]
    fn a_solid_hides_what_is_behind_it_and_not_what_is_above() {
        let s = cube();
        assert!(s.occluded([-5.0, 5.0, 5.0], [15.0, 5.0, 5.0]));
        assert!(!s.occluded([-5.0, 5.0, 12.0], [15.0, 5.0, 12.0]));
        // a point on the near wall, moved off it, is seen; on the far wall it is not
        assert!(!s.occluded([-5.0, 5.0, 5.0], [-0.01, 5.0, 5.0]));
        assert!(s.occluded([-5.0, 5.0, 5.0], [10.01, 5.0, 5.0]));
    }

    #[test]
    fn keep_out_is_the_clearance_around_the_solid() {
        let s = cube();
        assert!(!s.is_free([-2.0, 5.0, 5.0], true) && s.is_free([-3.0, 5.0, 5.0], true));
        assert!(!s.is_free([5.0, 5.0, 12.0], true) && s.is_free([5.0, 5.0, 12.6], true));
        assert!(!s.is_free([100.0, 5.0, 5.0], true) && s.is_free([100.0, 5.0, 5.0], false), "outside the geofence");
    }
}
