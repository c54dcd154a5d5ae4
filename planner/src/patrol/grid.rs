//! The patrol grid (patrolling spec §1): square cells in rows from the south-west corner; a cell
//! is free when its centre lies in the area and outside every no-fly zone.

use geo::{Contains, Coord, MultiPolygon, Point, Rect};

/// Most cells a patrol grid may have (200 × 200: the heat map is a polygon per cell, about 8 MB
/// of GeoJSON at this size).
pub const MAX_CELLS: usize = 40_000;

#[derive(Debug, Clone)]
pub struct CellGrid {
    pub cols: usize,
    pub rows: usize,
    pub free: Vec<bool>,
    /// Centre of cell (0, 0) in the local frame, and the cell's side, metres.
    pub origin: Coord,
    pub size: f64,
}

/// The four headings, in the order N, E, S, W, as (column, row) steps.
pub const STEPS: [(i64, i64); 4] = [(0, 1), (1, 0), (0, -1), (-1, 0)];

impl CellGrid {
    /// A `cols` × `rows` grid with every cell free (the reference set-up of seed 002).
    pub fn open(cols: usize, rows: usize) -> CellGrid {
        CellGrid { cols, rows, free: vec![true; cols * rows], origin: Coord { x: 0.0, y: 0.0 }, size: 1.0 }
    }

    /// Cells of side `size` over `area`'s bounding box; `None` when there would be more than
    /// [`MAX_CELLS`].
    pub fn over(area: &MultiPolygon, bounds: Rect, size: f64) -> Option<CellGrid> {
        let cols = (bounds.width() / size).ceil().max(1.0);
        let rows = (bounds.height() / size).ceil().max(1.0);
        if cols * rows > MAX_CELLS as f64 {
            return None;
        }
        let (cols, rows) = (cols as usize, rows as usize);
        let origin = Coord { x: bounds.min().x + size / 2.0, y: bounds.min().y + size / 2.0 };
        let mut grid = CellGrid { cols, rows, free: vec![false; cols * rows], origin, size };
        for cell in 0..cols * rows {
            grid.free[cell] = area.contains(&Point::from(grid.centre(cell)));
        }
        Some(grid)
    }

    pub fn len(&self) -> usize {
        self.free.len()
    }

    pub fn is_empty(&self) -> bool {
        self.free.is_empty()
    }

    pub fn index(&self, col: usize, row: usize) -> usize {
        row * self.cols + col
    }

    pub fn col_row(&self, cell: usize) -> (usize, usize) {
        (cell % self.cols, cell / self.cols)
    }

    pub fn centre(&self, cell: usize) -> Coord {
        let (c, r) = self.col_row(cell);
        Coord { x: self.origin.x + c as f64 * self.size, y: self.origin.y + r as f64 * self.size }
    }

    /// The free cell one step from `cell` in heading `h` (0 N, 1 E, 2 S, 3 W), if any.
    pub fn step(&self, cell: usize, h: usize) -> Option<usize> {
        let (c, r) = self.col_row(cell);
        let (dc, dr) = STEPS[h];
        let (c, r) = (c as i64 + dc, r as i64 + dr);
        if c < 0 || r < 0 || c >= self.cols as i64 || r >= self.rows as i64 {
            return None;
        }
        let next = self.index(c as usize, r as usize);
        self.free[next].then_some(next)
    }

    /// The heading (0 N, 1 E, 2 S, 3 W) of the step from `from` to its free neighbour `to`.
    pub fn heading(&self, from: usize, to: usize) -> Option<usize> {
        (0..4).find(|&h| self.step(from, h) == Some(to))
    }

    /// The free cell nearest to the south-west corner (row first, as the source's lower left).
    pub fn lower_left(&self) -> Option<usize> {
        (0..self.len()).filter(|&c| self.free[c]).min_by_key(|&c| {
            let (col, row) = self.col_row(c);
            (col + row, row)
        })
    }
}
