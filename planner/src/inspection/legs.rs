//! Collision-free legs between viewpoints in 2.5D, exact without sampling (spec
//! `inspection.md` §6): a leg flies around the keep-out footprints that reach into its
//! altitude band on their visibility graph, or climbs above the prisms in its way first; the
//! cheapest of the candidates under the budget's measure is kept. Every candidate is checked
//! segment by segment against the keep-out volumes before it is used.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use geo::{BoundingRect, Coord, LineString, MultiPolygon, Polygon, Rect};

use super::scene::{Point3, Scene};
use crate::energy::{EnergyModel, EnergyParams};
use crate::geom::{distance, grow, point_in_ring};
use crate::params::inspection::BudgetLimit;
use crate::path::{FlightPath, PieceKind};
use crate::route::visibility::TransitPlanner;
use crate::vehicle::Vehicle;

/// Extra distance of the graph's corners beyond the keep-out outline, so that a path along it
/// stays clear of it.
const CORNER_OFFSET_M: f64 = 0.2;

/// Yaw rate assumed for a profile whose energy model has none, degrees per second.
const DEFAULT_YAW_RATE_DEG_S: f64 = 36.0;

/// A flown leg: its points, and its figures from rest to rest.
#[derive(Debug, Clone, PartialEq)]
pub struct Leg {
    pub points: Vec<Point3>,
    pub length_m: f64,
    pub time_s: f64,
    pub energy_j: f64,
}

impl Leg {
    /// The leg's price under the budget's measure.
    pub fn cost(&self, budget: BudgetLimit) -> f64 {
        budget.measure(self.length_m, self.time_s, self.energy_j)
    }
}

/// What hovering and turning on the spot cost the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stationary {
    pub hover_w: f64,
    pub yaw_rate_deg_s: f64,
    pub yaw_w: f64,
}

impl Stationary {
    pub fn of(vehicle: &Vehicle) -> Stationary {
        match &vehicle.energy {
            EnergyParams::MultirotorIem(c) => Stationary { hover_w: c.hover_power_w(), yaw_rate_deg_s: c.yaw_rate_deg_s, yaw_w: c.yaw_power_w },
            EnergyParams::ConstantPower(p) => Stationary { hover_w: p.cruise_power_w, yaw_rate_deg_s: DEFAULT_YAW_RATE_DEG_S, yaw_w: p.cruise_power_w },
            // aircraft that cannot hover are refused before planning; these figures only keep
            // the function total
            EnergyParams::FixedWing(_) | EnergyParams::Ground(_) => Stationary { hover_w: 0.0, yaw_rate_deg_s: DEFAULT_YAW_RATE_DEG_S, yaw_w: 0.0 },
        }
    }

    /// Time and energy of hovering for `seconds` (to take a picture).
    pub fn hover(&self, seconds: f64) -> (f64, f64) {
        (seconds, seconds * self.hover_w)
    }

    /// Time and energy of turning on the spot by `degrees`.
    pub fn yaw(&self, degrees: f64) -> (f64, f64) {
        let t = degrees.abs() / self.yaw_rate_deg_s;
        (t, t * self.yaw_w)
    }
}

pub struct LegPlanner<'a> {
    scene: &'a Scene,
    vehicle: &'a Vehicle,
    /// Highest altitude a leg may climb to.
    ceiling_m: f64,
    /// Visibility graphs by the set of keep-out volumes a leg must go around.
    graphs: Mutex<HashMap<Vec<usize>, Arc<TransitPlanner>>>,
}

impl<'a> LegPlanner<'a> {
    pub fn new(scene: &'a Scene, vehicle: &'a Vehicle, ceiling_m: f64) -> Self {
        LegPlanner { scene, vehicle, ceiling_m, graphs: Mutex::new(HashMap::new()) }
    }

    pub fn vehicle(&self) -> &Vehicle {
        self.vehicle
    }

    /// The cheapest free leg from `a` to `b` under `budget`'s measure, with its time and
    /// energy, or `None` when none is found; `fenced`: it stays in the geofence (legs between
    /// viewpoints; the legs from the start and to the end may come from outside).
    pub fn leg(&self, a: Point3, b: Point3, budget: BudgetLimit, fenced: bool) -> Option<Leg> {
        let leg = self.way(a, b, budget, fenced)?;
        Some(if leg.time_s.is_nan() { price(leg.points, self.vehicle.energy_model().as_ref()) } else { leg })
    }

    /// As [`Self::leg`], but a leg chosen by its length is not priced in time and energy
    /// (they are NaN): the search under a length budget needs only lengths.
    pub fn way(&self, a: Point3, b: Point3, budget: BudgetLimit, fenced: bool) -> Option<Leg> {
        let model = self.vehicle.energy_model();
        let hi = a[2].max(b[2]);
        let (a_hi, b_hi) = ([a[0], a[1], hi], [b[0], b[1], hi]);
        let mut best: Option<Leg> = None;
        let mut consider = |points: Vec<Point3>| {
            if points.windows(2).all(|w| self.scene.segment_free(w[0], w[1], fenced)) {
                let leg = match budget {
                    BudgetLimit::LengthM(_) => Leg { length_m: length_3d(&points), points, time_s: f64::NAN, energy_j: f64::NAN },
                    _ => price(points, model.as_ref()),
                };
                if best.as_ref().is_none_or(|b| leg.cost(budget) < b.cost(budget)) {
                    best = Some(leg);
                }
            }
        };
        // around what reaches into the band between the two altitudes
        if let Some(p) = self.around(a, b) {
            consider(p);
        }
        // up (or down) to the higher altitude first, then around at it
        if a[2] < hi
            && let Some(mut p) = self.around(a_hi, b)
        {
            p.insert(0, a);
            consider(p);
        } else if b[2] < hi
            && let Some(mut p) = self.around(a, b_hi)
        {
            p.push(b);
            consider(p);
        }
        // straight over everything in the way
        let over = self.scene.crossing_tops([a[0], a[1]], [b[0], b[1]]).fold(hi, f64::max);
        if over <= self.ceiling_m {
            consider(vec![a, [a[0], a[1], over], [b[0], b[1], over], b]);
        }
        best
    }

    /// A path in the plane around the keep-out footprints that reach into the band between
    /// the two altitudes, its altitude changing evenly along it.
    fn around(&self, a: Point3, b: Point3) -> Option<Vec<Point3>> {
        let (lo, hi) = (a[2].min(b[2]), a[2].max(b[2]));
        let (pa, pb) = (Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] });
        let area = Rect::new(pa, pb);
        let near_line = |i: &usize| self.scene.keep_out[*i].z[0] < hi && self.scene.keep_out[*i].z[1] > lo;
        // the graph covers every volume in the band, not only those near the line: a way around
        // may lead far from it
        let active: Vec<usize> = (0..self.scene.keep_out.len()).filter(near_line).collect();
        let nothing_near = !self.scene.keep_out_near(area).any(|i| near_line(&i)) && !self.scene.no_fly.bounding_rect().is_some_and(|r| geo::Intersects::intersects(&r, &area));
        let flat = if nothing_near {
            vec![pa, pb]
        } else {
            let graph = self.graph(active);
            graph.path(pa, pb)?
        };
        let total: f64 = flat.windows(2).map(|w| distance(w[0], w[1])).sum();
        let mut run = 0.0;
        let mut out = Vec::with_capacity(flat.len());
        for (k, c) in flat.iter().enumerate() {
            if k > 0 {
                run += distance(flat[k - 1], *c);
            }
            let t = if total > 0.0 { run / total } else { 0.0 };
            out.push([c.x, c.y, a[2] + (b[2] - a[2]) * t]);
        }
        // the ends exactly, so that legs join
        out[0] = a;
        *out.last_mut().expect("two points at least") = b;
        Some(out)
    }

    fn graph(&self, active: Vec<usize>) -> Arc<TransitPlanner> {
        if let Some(g) = self.graphs.lock().expect("graphs").get(&active) {
            return g.clone();
        }
        let mut walls: Vec<Polygon> = active.iter().map(|&i| self.scene.keep_out[i].footprint.clone()).collect();
        walls.extend(self.scene.no_fly.0.iter().cloned());
        let walls = MultiPolygon(walls);
        let graph = Arc::new(TransitPlanner::new(&grow(&walls, CORNER_OFFSET_M), &walls));
        self.graphs.lock().expect("graphs").insert(active, graph.clone());
        graph
    }
}

/// The same way flown backwards, priced afresh (a climb becomes a descent).
pub fn reversed(leg: &Leg, vehicle: &Vehicle) -> Leg {
    let mut points = leg.points.clone();
    points.reverse();
    price(points, vehicle.energy_model().as_ref())
}

/// Length, time and energy of a leg flown from rest to rest.
pub fn length_3d(points: &[Point3]) -> f64 {
    points.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2) + (w[1][2] - w[0][2]).powi(2)).sqrt()).sum()
}

fn price(points: Vec<Point3>, model: &dyn EnergyModel) -> Leg {
    let length_m = length_3d(&points);
    let flat: Vec<Coord> = points.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    let (time_s, energy_j) = if flat.windows(2).all(|w| w[0] == w[1]) {
        let dz = points[points.len() - 1][2] - points[0][2];
        model.takeoff_landing(dz.max(0.0), (-dz).max(0.0))
    } else {
        let mut path = FlightPath::default();
        path.push(PieceKind::Transit, flat, 0.0);
        path.pieces[0].z = points.iter().map(|p| p[2]).collect();
        model.pieces(&path).iter().fold((0.0, 0.0), |(t, e), p| (t + p.duration_s, e + p.energy_j))
    };
    Leg { points, length_m, time_s, energy_j }
}

impl Scene {
    /// True when the straight segment from `p` to `q` stays out of the no-fly zones and out of
    /// every keep-out volume (touching its outline is allowed), and, when `fenced`, in the
    /// geofence.
    pub fn segment_free(&self, p: Point3, q: Point3, fenced: bool) -> bool {
        let (a, b) = (Coord { x: p[0], y: p[1] }, Coord { x: q[0], y: q[1] });
        if p[2] < 0.0 || q[2] < 0.0 {
            return false;
        }
        if (fenced && !self.inside_fence(a, b)) || self.no_fly.0.iter().any(|z| inside_intervals(z, a, b).next().is_some()) {
            return false;
        }
        self.keep_out_near(Rect::new(a, b)).all(|i| {
            let k = &self.keep_out[i];
            inside_intervals(&k.footprint, a, b).all(|(t0, t1)| {
                let (z0, z1) = (p[2] + (q[2] - p[2]) * t0, p[2] + (q[2] - p[2]) * t1);
                z0.max(z1) <= k.z[0] + 1e-6 || z0.min(z1) >= k.z[1] - 1e-6
            })
        })
    }

    /// The tops of the keep-out volumes whose footprint the segment `a`–`b` passes through.
    pub fn crossing_tops(&self, a: [f64; 2], b: [f64; 2]) -> impl Iterator<Item = f64> + '_ {
        let (a, b) = (Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] });
        self.keep_out_near(Rect::new(a, b)).filter(move |&i| inside_intervals(&self.keep_out[i].footprint, a, b).next().is_some()).map(|i| self.keep_out[i].z[1])
    }
}

/// The parameter intervals of the segment `a`–`b` (0 at `a`, 1 at `b`) that lie strictly
/// inside the polygon; a segment of no length is one interval when its point is inside.
fn inside_intervals(poly: &Polygon, a: Coord, b: Coord) -> impl Iterator<Item = (f64, f64)> {
    let rings: Vec<&LineString> = std::iter::once(poly.exterior()).chain(poly.interiors()).collect();
    let d = b - a;
    let mut ts = vec![0.0, 1.0];
    for ring in &rings {
        for w in ring.0.windows(2) {
            let (p, e) = (w[0], w[1] - w[0]);
            let denom = d.x * e.y - d.y * e.x;
            if denom.abs() < 1e-15 {
                continue;
            }
            let ap = p - a;
            let t = (ap.x * e.y - ap.y * e.x) / denom;
            let u = (ap.x * d.y - ap.y * d.x) / denom;
            if (0.0..=1.0).contains(&t) && (-1e-12..=1.0 + 1e-12).contains(&u) {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
    let strictly_inside = move |c: Coord| {
        let in_exterior = point_in_ring(c, &rings[0].0);
        in_exterior && !rings[1..].iter().any(|r| point_in_ring(c, &r.0)) && !on_outline(&rings, c)
    };
    let pieces: Vec<(f64, f64)> = if ts.len() == 2 && d.x == 0.0 && d.y == 0.0 {
        if strictly_inside(a) { vec![(0.0, 1.0)] } else { Vec::new() }
    } else {
        ts.windows(2)
            .filter(|w| w[1] - w[0] > 1e-12)
            .filter(|w| {
                let t = (w[0] + w[1]) / 2.0;
                strictly_inside(Coord { x: a.x + d.x * t, y: a.y + d.y * t })
            })
            .map(|w| (w[0], w[1]))
            .collect()
    };
    pieces.into_iter()
}

/// Within a micrometre of a ring's outline.
fn on_outline(rings: &[&LineString], c: Coord) -> bool {
    rings.iter().any(|r| {
        r.0.windows(2).any(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let len2 = ab.x * ab.x + ab.y * ab.y;
            let t = if len2 > 0.0 { (((c.x - a.x) * ab.x + (c.y - a.y) * ab.y) / len2).clamp(0.0, 1.0) } else { 0.0 };
            distance(c, Coord { x: a.x + ab.x * t, y: a.y + ab.y * t }) < 1e-6
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspection::scene::tests::cube;
    use crate::vehicle::builtin_profiles;

    #[test]
    fn a_leg_goes_around_low_and_over_when_that_is_shorter() {
        let s = cube();
        let iris = builtin_profiles().into_iter().find(|v| v.profile == "iris").unwrap();
        let legs = LegPlanner::new(&s, &iris, 100.0);
        let budget = BudgetLimit::LengthM(1e9);
        // low across the building: around it (2 × hypot(5.3, 7.7) + 15.4 ≈ 34 m, less than climbing 9.5 m and back)
        let low = legs.leg([-8.0, 5.0, 3.0], [18.0, 5.0, 3.0], budget, true).unwrap();
        assert!(low.points.iter().all(|p| (p[2] - 3.0).abs() < 1e-9) && low.length_m > 33.0 && low.length_m < 35.0, "{low:?}");
        // just under the keep-out's top: over it
        let high = legs.leg([-8.0, 5.0, 12.0], [18.0, 5.0, 12.0], budget, true).unwrap();
        assert!((high.length_m - (26.0 + 2.0 * 0.5)).abs() < 1e-9, "{high:?}");
        for leg in [&low, &high] {
            assert!(leg.points.windows(2).all(|w| s.segment_free(w[0], w[1], true)));
            assert!(leg.time_s > 0.0 && leg.energy_j > 0.0);
        }
        // a clear leg is straight
        let clear = legs.leg([-8.0, -8.0, 3.0], [18.0, -8.0, 5.0], budget, true).unwrap();
        assert_eq!(clear.points.len(), 2);
    }

    #[test]
    fn segments_through_the_volume_are_refused_and_along_its_outline_are_not() {
        let s = cube();
        assert!(!s.segment_free([-5.0, 5.0, 5.0], [15.0, 5.0, 5.0], true));
        assert!(s.segment_free([-5.0, 5.0, 12.5], [15.0, 5.0, 12.5], true));
        // descending into the roof's clearance
        assert!(!s.segment_free([5.0, 5.0, 20.0], [5.0, 5.0, 11.0], true));
        assert!(s.segment_free([5.0, 5.0, 20.0], [5.0, 5.0, 12.6], true));
        // outside the geofence
        assert!(!s.segment_free([-40.0, 0.0, 5.0], [-70.0, 0.0, 5.0], true));
        assert!(s.segment_free([-40.0, 0.0, 5.0], [-70.0, 0.0, 5.0], false));
    }
}
