//! A machine's working day on a farm as flight files: the sorties its fields' plans fly that
//! day, one after another, in one flight plan (docs/api.md, farm plans).
//!
//! A field worked over several days is flown sortie by sortie: a sortie belongs to the day in
//! whose share of the field's work the middle of its flown length falls, so each sortie is flown
//! on exactly one day.

use std::collections::BTreeMap;

use geo::{Distance, Euclidean, Line, Point};
use geojson::{Feature, FeatureCollection, GeometryValue};
use serde_json::{Value, json};

use super::{ExportRequest, MissionGeometry, written};
use crate::error::InputError;
use crate::farm::Stretch;
use crate::frame::LocalFrame;

/// A stretch of the day on one field: the field's plan, and the share of its work done then.
pub struct DayStretch<'a> {
    pub request: ExportRequest<'a>,
    pub share: Stretch,
}

/// Writes one machine's day in `format`, as files named from `stem`: the day's sorties in one
/// flight plan (a file per sortie in the formats that describe one flight). Fields planned with
/// other parameters or another home than the one before them begin a new plan (`-run-2`, …).
pub fn export_day(format: &str, stem: &str, stretches: &[DayStretch<'_>]) -> Result<Vec<(String, Vec<u8>)>, InputError> {
    let mut runs: Vec<&[DayStretch<'_>]> = Vec::new();
    let mut begun = 0;
    for k in 1..=stretches.len() {
        if k == stretches.len() || !alike(&stretches[k - 1].request, &stretches[k].request) {
            runs.push(&stretches[begun..k]);
            begun = k;
        }
    }
    let plans: Vec<(&DayStretch<'_>, Merged)> = runs.iter().filter_map(|run| Some((&run[0], Merged::of(run)?))).collect();
    let mut files = Vec::new();
    for (k, (first, merged)) in plans.iter().enumerate() {
        let name = if plans.len() > 1 { format!("{stem}-run-{}", k + 1) } else { stem.to_owned() };
        let first = &first.request;
        let mission = MissionGeometry {
            area: &merged.area,
            no_fly_zones: merged.no_fly_zones.as_ref(),
            obstacles: None,
            structures: None,
            home: first.mission.home,
            terrain: first.mission.terrain,
        };
        let request = ExportRequest { name: &name, mission, params: first.params, profiles: first.profiles, trajectory: &merged.trajectory, options: first.options };
        files.extend(written(format, &request, &super::file_stem(&name))?.files);
    }
    Ok(files)
}

/// Two fields flown in one plan: planned alike, from the same home.
fn alike(a: &ExportRequest<'_>, b: &ExportRequest<'_>) -> bool {
    a.mission.home == b.mission.home && serde_json::to_value(a.params).ok() == serde_json::to_value(b.params).ok()
}

/// A run of stretches as one plan: the fields' areas and zones, and their sorties of the day
/// renumbered one after another.
struct Merged {
    area: Value,
    no_fly_zones: Option<Value>,
    trajectory: FeatureCollection,
}

impl Merged {
    /// `None` when no sortie of the run is flown that day.
    fn of(run: &[DayStretch<'_>]) -> Option<Merged> {
        let (mut areas, mut zones, mut features) = (Vec::new(), Vec::new(), Vec::new());
        let mut sorties_before = 0;
        for stretch in run {
            let trajectory = stretch.request.trajectory;
            let lengths = sortie_lengths(trajectory);
            let chosen = flown_in(&lengths, stretch.share);
            if chosen.is_empty() {
                continue;
            }
            areas.extend(as_features(stretch.request.mission.area));
            zones.extend(stretch.request.mission.no_fly_zones.map(as_features).unwrap_or_default());
            let whole = chosen.len() == lengths.len();
            let mut sweeps = Vec::new();
            for feature in &trajectory.features {
                match (kind_of(feature), sortie_of(feature)) {
                    (Some("photos"), _) => continue,
                    (Some(_), Some(sortie)) if chosen.contains(&sortie) => {
                        let mut f = feature.clone();
                        let rank = chosen.iter().position(|&s| s == sortie).expect("chosen") as u64;
                        f.set_property("sortie", sorties_before + rank + 1);
                        f.remove_property("vehicle");
                        if kind_of(&f) == Some("sweep") {
                            sweeps.push(f.clone());
                        }
                        features.push(f);
                    }
                    _ => {}
                }
            }
            // the photos of the sorties flown: all of them, or those on the day's sweeps
            for feature in trajectory.features.iter().filter(|f| kind_of(f) == Some("photos")) {
                features.push(if whole { feature.clone() } else { photos_on(feature, &sweeps) });
            }
            sorties_before += chosen.len() as u64;
        }
        if features.is_empty() {
            return None;
        }
        for (seq, f) in features.iter_mut().filter(|f| kind_of(f) != Some("photos")).enumerate() {
            f.set_property("seq", seq);
        }
        let collection = |features: Vec<Value>| json!({"type": "FeatureCollection", "features": features});
        Some(Merged {
            area: collection(areas),
            no_fly_zones: (!zones.is_empty()).then(|| collection(zones)),
            trajectory: FeatureCollection { bbox: None, features, foreign_members: None },
        })
    }
}

fn kind_of(f: &Feature) -> Option<&str> {
    f.property("kind").and_then(Value::as_str)
}

fn sortie_of(f: &Feature) -> Option<u64> {
    f.property("sortie").and_then(Value::as_u64)
}

/// Each sortie's flown length, m, by its number.
fn sortie_lengths(trajectory: &FeatureCollection) -> BTreeMap<u64, f64> {
    let mut lengths = BTreeMap::new();
    for f in &trajectory.features {
        if let Some(sortie) = sortie_of(f) {
            *lengths.entry(sortie).or_insert(0.0) += f.property("length_m").and_then(Value::as_f64).unwrap_or(0.0);
        }
    }
    lengths
}

/// The sorties flown in `share` of the work: those the middle of whose length lies in it.
fn flown_in(lengths: &BTreeMap<u64, f64>, share: Stretch) -> Vec<u64> {
    let total: f64 = lengths.values().sum();
    let mut before = 0.0;
    let mut chosen = Vec::new();
    for (&sortie, &length) in lengths {
        let middle = if total > 0.0 { (before + length / 2.0) / total } else { 0.5 };
        before += length;
        if share.from <= middle && (middle < share.to || share.to >= 1.0) {
            chosen.push(sortie);
        }
    }
    chosen
}

/// A mission's area or zones (a geometry, Feature or FeatureCollection) as Features.
fn as_features(value: &Value) -> Vec<Value> {
    match value["type"].as_str() {
        Some("FeatureCollection") => value["features"].as_array().cloned().unwrap_or_default(),
        Some("Feature") => vec![value.clone()],
        Some(_) => vec![json!({"type": "Feature", "properties": {}, "geometry": value})],
        None => Vec::new(),
    }
}

/// The photos of `photos` (a MultiPoint) that lie on one of `sweeps` (within a metre).
fn photos_on(photos: &Feature, sweeps: &[Feature]) -> Feature {
    let mut kept = photos.clone();
    let Some(GeometryValue::MultiPoint { coordinates }) = photos.geometry.as_ref().map(|g| &g.value) else { return kept };
    let Some(origin) = coordinates.first() else { return kept };
    let frame = LocalFrame::new(origin[0], origin[1]);
    let local = |p: &geojson::Position| frame.to_local(p[0], p[1]);
    let segments: Vec<Line> = sweeps
        .iter()
        .filter_map(|s| match s.geometry.as_ref().map(|g| &g.value) {
            Some(GeometryValue::LineString { coordinates }) => Some(coordinates.windows(2).map(|w| Line::new(local(&w[0]), local(&w[1]))).collect::<Vec<_>>()),
            _ => None,
        })
        .flatten()
        .collect();
    let on_a_sweep = |p: &geojson::Position| {
        let q = Point::from(local(p));
        segments.iter().any(|segment| Euclidean.distance(&q, segment) < 1.0)
    };
    let taken: Vec<geojson::Position> = coordinates.iter().filter(|p| on_a_sweep(p)).cloned().collect();
    kept.set_property("count", taken.len());
    kept.geometry = Some(geojson::Geometry::new(GeometryValue::MultiPoint { coordinates: taken }));
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lengths(l: &[f64]) -> BTreeMap<u64, f64> {
        l.iter().enumerate().map(|(k, &v)| (k as u64 + 1, v)).collect()
    }

    #[test]
    fn each_sortie_is_flown_on_one_day() {
        let l = lengths(&[100.0, 300.0, 100.0, 500.0]);
        let days = [(0.0, 0.25), (0.25, 0.6), (0.6, 1.0)].map(|(from, to)| flown_in(&l, Stretch { field: 0, from, to }));
        assert_eq!(days, [vec![1], vec![2, 3], vec![4]]);
        assert_eq!(flown_in(&l, Stretch { field: 0, from: 0.0, to: 1.0 }), [1, 2, 3, 4]);
    }

    #[test]
    fn a_photo_is_on_a_sweep_within_a_metre() {
        // a sweep 10 m east from (5°E, 52°N); photos 0.5 m and 5 m north of its middle
        let frame = LocalFrame::new(5.0, 52.0);
        let at = |x: f64, y: f64| {
            let p = frame.to_wgs84(geo::Coord { x, y });
            geojson::Position::from(vec![p[0], p[1]])
        };
        let sweep = Feature::from(geojson::Geometry::new(GeometryValue::LineString { coordinates: vec![at(0.0, 0.0), at(10.0, 0.0)] }));
        let photos = Feature::from(geojson::Geometry::new(GeometryValue::MultiPoint { coordinates: vec![at(5.0, 0.5), at(5.0, 5.0)] }));
        let kept = photos_on(&photos, &[sweep]);
        let Some(GeometryValue::MultiPoint { coordinates }) = kept.geometry.map(|g| g.value) else { panic!("photos are a MultiPoint") };
        assert_eq!(coordinates, vec![at(5.0, 0.5)]);
    }
}
