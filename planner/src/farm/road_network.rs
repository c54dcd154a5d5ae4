//! Transits along the farm's roads: the shortest way over a network of GeoJSON LineStrings.
//!
//! Lines join where they share a point (to within [`JOIN_M`]). A place reaches the network at
//! its nearest road point, straight across the field; two places nearer each other than either
//! is to a road are joined directly, and so are places on roads that do not meet.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use geo::{Distance, Haversine, Point};
use geojson::{GeoJson, GeometryValue};
use rayon::prelude::*;
use rstar::RTree;
use rstar::primitives::GeomWithData;
use serde_json::Value;

use super::{LonLat, Transit};
use crate::error::InputError;
use crate::field::raw_positions;

/// Road points closer than this are one junction.
pub const JOIN_M: f64 = 0.5;
/// Most road points a network may have.
pub const MAX_ROAD_POINTS: usize = 200_000;

/// Degrees of latitude a metre spans (for keys and the index, not for distances).
const DEG_PER_M: f64 = 1.0 / 111_195.0;

/// The roads as a graph: points and the metres between neighbours.
#[derive(Debug, Clone)]
pub struct RoadNetwork {
    points: Vec<LonLat>,
    neighbours: Vec<Vec<(usize, f64)>>,
    index: RTree<GeomWithData<[f64; 2], usize>>,
}

impl RoadNetwork {
    /// Reads a FeatureCollection, Feature or geometry of LineStrings and MultiLineStrings;
    /// `pointer` is where the request holds it.
    pub fn from_geojson(roads: &Value, pointer: &str) -> Result<Self, InputError> {
        let parsed: GeoJson = serde_json::from_value(roads.clone()).map_err(|e| InputError::new("invalid_geojson", pointer, format!("the roads are not GeoJSON: {e}")))?;
        let mut lines: Vec<Vec<LonLat>> = Vec::new();
        let mut add = |value: &GeometryValue, at: String| -> Result<(), InputError> {
            match value {
                GeometryValue::LineString { coordinates } => lines.push(raw_positions(coordinates, &format!("{at}/coordinates"))?),
                GeometryValue::MultiLineString { coordinates } => {
                    for (i, line) in coordinates.iter().enumerate() {
                        lines.push(raw_positions(line, &format!("{at}/coordinates/{i}"))?);
                    }
                }
                _ => return Err(InputError::new("invalid_geojson", at, "a road is a LineString or MultiLineString")),
            }
            Ok(())
        };
        match &parsed {
            GeoJson::Geometry(g) => add(&g.value, pointer.to_owned())?,
            GeoJson::Feature(f) => add(&f.geometry.as_ref().ok_or_else(|| no_geometry(&format!("{pointer}/geometry")))?.value, format!("{pointer}/geometry"))?,
            GeoJson::FeatureCollection(c) => {
                for (k, f) in c.features.iter().enumerate() {
                    let at = format!("{pointer}/features/{k}/geometry");
                    add(&f.geometry.as_ref().ok_or_else(|| no_geometry(&at))?.value, at)?;
                }
            }
        }
        let total: usize = lines.iter().map(Vec::len).sum();
        if total > MAX_ROAD_POINTS {
            return Err(InputError::new("too_many_points", pointer, format!("the roads have {total} points; at most {MAX_ROAD_POINTS} are accepted")));
        }
        if lines.iter().all(|l| l.len() < 2) {
            return Err(InputError::new("invalid_geojson", pointer, "the roads hold no line of two points or more"));
        }
        Ok(Self::from_lines(&lines))
    }

    /// The network of these polylines.
    pub fn from_lines(lines: &[Vec<LonLat>]) -> Self {
        let mut points: Vec<LonLat> = Vec::new();
        let mut by_key: HashMap<(i64, i64), usize> = HashMap::new();
        let mut neighbours: Vec<Vec<(usize, f64)>> = Vec::new();
        let step = JOIN_M * DEG_PER_M;
        for line in lines {
            let mut previous: Option<usize> = None;
            for p in line {
                let key = ((p[0] / step).round() as i64, (p[1] / step).round() as i64);
                let id = *by_key.entry(key).or_insert_with(|| {
                    points.push(*p);
                    neighbours.push(Vec::new());
                    points.len() - 1
                });
                if let Some(q) = previous.filter(|&q| q != id) {
                    let metres = metres(points[q], points[id]);
                    neighbours[q].push((id, metres));
                    neighbours[id].push((q, metres));
                }
                previous = Some(id);
            }
        }
        let index = RTree::bulk_load(points.iter().enumerate().map(|(i, p)| GeomWithData::new(scaled(*p), i)).collect());
        RoadNetwork { points, neighbours, index }
    }

    /// The road point nearest `place` (by the index's scaled degrees: exact enough at farm scale).
    fn nearest(&self, place: LonLat) -> usize {
        self.index.nearest_neighbor(&scaled(place)).map(|g| g.data).expect("a network has points")
    }

    /// Metres from road point `from` to every road point (infinite where no road leads).
    fn shortest_from(&self, from: usize) -> Vec<f64> {
        let mut metres = vec![f64::INFINITY; self.points.len()];
        let mut heap = BinaryHeap::new();
        metres[from] = 0.0;
        heap.push(Reached(0.0, from));
        while let Some(Reached(d, u)) = heap.pop() {
            if d > metres[u] {
                continue;
            }
            for &(v, w) in &self.neighbours[u] {
                if d + w < metres[v] {
                    metres[v] = d + w;
                    heap.push(Reached(d + w, v));
                }
            }
        }
        metres
    }
}

impl Transit for RoadNetwork {
    fn distances(&self, places: &[LonLat]) -> Vec<f64> {
        let n = places.len();
        let access: Vec<(usize, f64)> = places.iter().map(|p| self.nearest(*p)).zip(places).map(|(r, p)| (r, metres(*p, self.points[r]))).collect();
        (0..n)
            .into_par_iter()
            .flat_map_iter(|i| {
                let along = self.shortest_from(access[i].0);
                let access = &access;
                (0..n).map(move |j| {
                    let straight = metres(places[i], places[j]);
                    let by_road = access[i].1 + along[access[j].0] + access[j].1;
                    if straight <= access[i].1 + access[j].1 || !by_road.is_finite() { straight } else { by_road }
                })
            })
            .collect()
    }
}

fn no_geometry(at: &str) -> InputError {
    InputError::new("invalid_geojson", at, "a road needs a geometry")
}

fn metres(a: LonLat, b: LonLat) -> f64 {
    Haversine.distance(Point::from(a), Point::from(b))
}

/// Longitude shrunk by the latitude's cosine, so that the index's nearest is nearly the nearest.
fn scaled(p: LonLat) -> [f64; 2] {
    [p[0] * p[1].to_radians().cos(), p[1]]
}

/// A road point reached after so many metres; the heap pops the nearest first.
#[derive(PartialEq)]
struct Reached(f64, usize);

impl Eq for Reached {}

impl Ord for Reached {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Reached {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transit_follows_the_roads_round_a_corner() {
        // an L of roads: (0,0) → (0,0.01) → (0.01,0.01); places at its two ends
        let roads = RoadNetwork::from_lines(&[vec![[0.0, 0.0], [0.0, 0.01]], vec![[0.0, 0.01], [0.01, 0.01]]]);
        let d = roads.distances(&[[0.0, 0.0], [0.01, 0.01]]);
        let leg = metres([0.0, 0.0], [0.0, 0.01]);
        assert!((d[1] - 2.0 * leg).abs() < 5.0, "{} m, expected about {} m", d[1], 2.0 * leg);
        assert!(d[1] > metres([0.0, 0.0], [0.01, 0.01]) * 1.3);
        assert_eq!(d[0], 0.0);
    }

    #[test]
    fn places_nearer_each_other_than_the_roads_are_joined_directly() {
        let roads = RoadNetwork::from_lines(&[vec![[0.1, 0.0], [0.1, 0.01]]]);
        let d = roads.distances(&[[0.0, 0.0], [0.0, 0.001]]);
        assert!((d[1] - metres([0.0, 0.0], [0.0, 0.001])).abs() < 1e-6);
    }

    #[test]
    fn roads_that_are_not_geojson_lines_are_refused_where_they_are() {
        let point = serde_json::json!({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [0, 0]}}]});
        let e = RoadNetwork::from_geojson(&point, "/transit/roads").unwrap_err();
        assert_eq!((e.code, e.pointer.as_str()), ("invalid_geojson", "/transit/roads/features/0/geometry"));
    }
}
