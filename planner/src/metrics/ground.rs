//! A ground plan's figures: the headland, the mainland and the turns.

use geo::{Area, BooleanOps, Buffer, Distance, Euclidean, Length, Line, LineString, MultiLineString, MultiPolygon, Point, Polygon};
use serde::{Deserialize, Serialize};

use super::coverage::under;
use crate::params::HeadlandSpec;
use crate::path::{FlightPath, Piece, PieceKind, TurnShape};

/// How near a swath's track a leg of a crossing lies to be in its wheel marks.
const ON_TRACK_M: f64 = 0.05;
/// How far into the mainland a connection must run to cross the crop: its edge is smoothed
/// (the rings and swath ends round it to centimetres), and a wheel on it is on the headland.
const INTO_CROP_M: f64 = 0.5;

/// A ground plan's figures: how much of the mainland and of the headland is worked, and how
/// the vehicle turns.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct GroundStats {
    pub headland_width_m: f64,
    pub headland_passes: usize,
    pub headland_length_m: f64,
    pub mainland_area_m2: f64,
    pub headland_area_m2: f64,
    /// Shares of the mainland and of the headland band the implement works.
    pub mainland_coverage: f64,
    pub headland_coverage: f64,
    pub u_turns: usize,
    pub omega_turns: usize,
    pub fishtail_turns: usize,
    /// Corners of the headland passes worked by a manoeuvre into them (a vehicle that may
    /// reverse): turns of their own, beside the U, Ω and fishtail turns between swaths.
    #[serde(default)]
    pub corner_manoeuvres: usize,
    /// Connections between two swaths driven along a headland pass (where no turn fits), those
    /// that cross the mainland in a swath's wheel marks (where nothing in the headland joins
    /// the swaths), and those that cross it off every swath's and pass's track, across the crop.
    pub headland_drives: usize,
    #[serde(default)]
    pub track_crossings: usize,
    pub mainland_crossings: usize,
    /// Turns that leave the field or enter a hole or no-fly zone: 0 unless the planner is wrong.
    pub turns_leaving_field: usize,
    pub turns_crossing_holes: usize,
    /// Swaths left as tramlines (`tramline_every`).
    pub tramlines: usize,
    /// The refill (or unloading) trips of a vehicle with a `payload`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload: Option<crate::route::refill::PayloadStats>,
}

/// The ground figures of `path`, worked as `swept`, with the headland `spec` over its
/// `(mainland, band)`; `field` is the fields with their holes, `keep_out` the no-fly zones
/// grown by the margin.
pub fn ground_stats(
    path: &FlightPath,
    swept: &MultiPolygon,
    spec: &HeadlandSpec,
    (mainland, band): (&MultiPolygon, &MultiPolygon),
    field: &MultiPolygon,
    keep_out: &MultiPolygon,
) -> GroundStats {
    let turns: Vec<&Piece> = path.pieces.iter().filter(|p| p.kind == PieceKind::Turn).collect();
    let crop = mainland.buffer(-INTO_CROP_M);
    let shaped = |shape: TurnShape| turns.iter().filter(|p| p.shape == Some(shape)).count();
    let pieces = &path.pieces;
    let between_swaths =
        (1..pieces.len().saturating_sub(1)).filter(|&i| pieces[i].kind == PieceKind::Transit && pieces[i - 1].kind == PieceKind::Sweep && pieces[i + 1].kind == PieceKind::Sweep);
    let outer = MultiPolygon(field.iter().map(|p| Polygon::new(p.exterior().clone(), vec![])).collect());
    let holes = MultiPolygon(field.iter().flat_map(|p| p.interiors().iter().map(|r| Polygon::new(r.clone(), vec![]))).chain(keep_out.iter().cloned()).collect());
    let inside = |zones: &MultiPolygon, p: &Piece| zones.clip(&MultiLineString(vec![LineString::from(p.points.clone())]), false);
    let inside_length = |zones: &MultiPolygon, p: &Piece| inside(zones, p).0.iter().map(|l| Euclidean.length(l)).sum::<f64>();
    // the wheel marks of the swaths and of the headland passes (a pass rounds a corner sharper
    // than the turning circle over the mainland's tip)
    let marks = |kind: PieceKind| -> Vec<Line> { pieces.iter().filter(|p| p.kind == kind).flat_map(|p| p.points.windows(2).map(|w| Line::new(w[0], w[1]))).collect() };
    let (swath_marks, pass_marks) = (marks(PieceKind::Sweep), marks(PieceKind::Headland));
    // a piece's metres in the mainland: all, in a swath's wheel marks, and off every swath's and
    // pass's (legs not on one track from end to end)
    let over_mainland = |p: &Piece| {
        let on =
            |marks: &[Line], l: &Line| marks.iter().any(|t| Euclidean.distance(&Point::from(l.start), t) < ON_TRACK_M && Euclidean.distance(&Point::from(l.end), t) < ON_TRACK_M);
        let legs: Vec<Line> = inside(&crop, p).0.into_iter().flat_map(|l| l.lines().collect::<Vec<_>>()).collect();
        let length = |keep: &dyn Fn(&Line) -> bool| legs.iter().filter(|l| keep(l)).map(|l| Euclidean.length(l)).sum::<f64>();
        (length(&|_| true), length(&|l| on(&swath_marks, l)), length(&|l| !on(&swath_marks, l) && !on(&pass_marks, l)))
    };
    let share = |part: &MultiPolygon| {
        let area = part.unsigned_area();
        if area > 0.0 { (under(swept, part).0 / area).min(1.0) } else { 1.0 }
    };
    let (mut along_tracks, mut crossings) = (0, 0);
    for i in between_swaths.clone() {
        match over_mainland(&pieces[i]) {
            (all, ..) if all <= 1.0 => {}
            (_, _, off) if off > 1.0 => crossings += 1,
            (_, on_swaths, _) if on_swaths > 1.0 => along_tracks += 1,
            _ => {}
        }
    }
    GroundStats {
        headland_width_m: spec.width_m,
        headland_passes: spec.passes,
        headland_length_m: path.pieces.iter().filter(|p| p.kind == PieceKind::Headland).map(|p| p.length()).sum(),
        mainland_area_m2: mainland.unsigned_area(),
        headland_area_m2: band.unsigned_area(),
        mainland_coverage: share(mainland),
        headland_coverage: share(band),
        u_turns: shaped(TurnShape::U),
        omega_turns: shaped(TurnShape::Omega),
        fishtail_turns: shaped(TurnShape::Fishtail),
        corner_manoeuvres: shaped(TurnShape::Corner),
        mainland_crossings: crossings,
        track_crossings: along_tracks,
        headland_drives: between_swaths.count() - along_tracks - crossings,
        // a centimetre of slack: the turns' arcs are sampled
        turns_leaving_field: turns.iter().filter(|p| inside_length(&outer, p) < p.length() - 0.01).count(),
        turns_crossing_holes: turns.iter().filter(|p| inside_length(&holes, p) > 0.01).count(),
        tramlines: pieces.iter().filter(|p| p.tramline).count(),
        payload: None,
    }
}
