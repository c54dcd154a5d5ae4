//! The flown path: pieces of kind sweep, headland, turn or transit, joined end to start.

use geo::Coord;

use crate::geom::{distance, polyline_length};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum PieceKind {
    /// A coverage line, flown at survey altitude with the sensor on.
    Sweep,
    /// A ground vehicle's working pass around the field's edge or a hole, in the headland.
    Headland,
    /// The connection between two lines of the same cell.
    Turn,
    /// Any other connection: from the start, between cells or fields, to the end.
    Transit,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    pub kind: PieceKind,
    pub points: Vec<Coord>,
    /// Width covered on each side of a sweep (half the swath); 0 for other kinds.
    pub half_swath_m: f64,
    /// Altitude of each point where the piece climbs over obstacles; empty: flown at the
    /// plan's altitude.
    pub z: Vec<f64>,
    /// A ground vehicle's turn between swaths: its shape.
    pub shape: Option<TurnShape>,
    /// A ground vehicle's swath left as a tramline (controlled traffic).
    pub tramline: bool,
    /// A ground vehicle's tank is refilled (or unloaded) where this piece ends (`payload`),
    /// standing there this many seconds.
    pub refill_s: Option<f64>,
    /// The camera's pose on a pass of an oblique plan; `None`: pointed down, facing the way
    /// the vehicle flies.
    pub look: Option<Look>,
}

/// Where the camera points on one pass of an oblique plan, and what its photos image there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// 1 for the nadir pass, 2 to 5 for the oblique ones.
    pub pass: usize,
    /// As a gimbal says it: 0 level, −90 straight down.
    pub gimbal_pitch_deg: f64,
    /// The direction the camera faces (math radians), held however the lines are flown;
    /// `None`: the way the vehicle flies.
    pub heading: Option<f64>,
    /// Where the image centre lies on the ground, from the point under the vehicle.
    pub centre_offset: Coord,
    /// The ground a photo surely images (a rectangle round its centre): across the line and
    /// along it; and the largest step between photos along the line.
    pub across_m: f64,
    pub along_m: f64,
    pub photo_spacing_m: f64,
}

/// The shape of a ground vehicle's turn at the end of a swath.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum TurnShape {
    /// Turns joined by a straight (CSC): the swaths are at least a turning diameter apart,
    /// or one end lies further out than the other.
    U,
    /// Three turns, the middle one bulging out (CCC): the swaths are closer than a turning
    /// diameter and the vehicle cannot reverse.
    Omega,
    /// Any turn with a part driven in reverse: the three-point turn or a Reeds–Shepp word with
    /// cusps.
    Fishtail,
    /// A headland pass's corner worked by a vehicle that may reverse: driven into, then
    /// backed out of to the next edge (without working).
    Corner,
}

impl PieceKind {
    /// True for the pieces that work the ground: sweeps and headland passes.
    pub fn works(self) -> bool {
        matches!(self, PieceKind::Sweep | PieceKind::Headland)
    }
}

impl Piece {
    /// Length along the path, climbs included.
    pub fn length(&self) -> f64 {
        if self.z.is_empty() {
            return polyline_length(&self.points);
        }
        self.points.windows(2).zip(self.z.windows(2)).map(|(p, z)| distance(p[0], p[1]).hypot(z[1] - z[0])).sum()
    }

    pub fn start(&self) -> Coord {
        self.points[0]
    }

    pub fn end(&self) -> Coord {
        *self.points.last().expect("a piece has points")
    }
}

impl Piece {
    /// A piece of `kind` along `points`, covering `half_swath_m` each side (0 for connections),
    /// at the plan's altitude, with nothing else said of it.
    pub fn new(kind: PieceKind, points: Vec<Coord>, half_swath_m: f64) -> Piece {
        Piece { kind, points, half_swath_m, z: Vec::new(), shape: None, tramline: false, refill_s: None, look: None }
    }
}

/// A path in flight order. Consecutive pieces share their end points exactly.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlightPath {
    pub pieces: Vec<Piece>,
}

impl FlightPath {
    /// Appends a piece; a connection of zero length is dropped.
    pub fn push(&mut self, kind: PieceKind, points: Vec<Coord>, half_swath_m: f64) {
        debug_assert!(points.len() >= 2);
        if !kind.works() && polyline_length(&points) == 0.0 {
            return;
        }
        if let Some(last) = self.pieces.last() {
            debug_assert_eq!(last.end(), points[0], "pieces must join exactly");
        }
        self.pieces.push(Piece::new(kind, points, half_swath_m));
    }

    /// Appends a ground vehicle's turn of `shape`.
    pub fn push_turn(&mut self, shape: TurnShape, points: Vec<Coord>) {
        let before = self.pieces.len();
        self.push(PieceKind::Turn, points, 0.0);
        if self.pieces.len() > before {
            self.pieces[before].shape = Some(shape);
        }
    }

    pub fn end(&self) -> Option<Coord> {
        self.pieces.last().map(Piece::end)
    }

    /// True when piece `k` is a sweep that leaves the sweep before it at an angle, with no turn
    /// between (a spiral ring's corner, a spur's tip): the camera keeps triggering through it.
    pub fn bends_into(&self, k: usize) -> bool {
        let (Some(before), Some(piece)) = (k.checked_sub(1).and_then(|j| self.pieces.get(j)), self.pieces.get(k)) else { return false };
        if before.kind != PieceKind::Sweep || piece.kind != PieceKind::Sweep {
            return false;
        }
        let [.., a0, a1] = before.points[..] else { return false };
        let [b0, b1, ..] = piece.points[..] else { return false };
        let (a, b) = (a1 - a0, b1 - b0);
        let (cross, dot) = (a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y);
        cross.abs() > 1e-6 * a.x.hypot(a.y) * b.x.hypot(b.y) || dot < 0.0
    }

    pub fn length(&self) -> f64 {
        self.pieces.iter().map(Piece::length).sum()
    }
}
