//! Decompose stage: split the sweep lines of a region into cells that can each be flown back
//! and forth without leaving them.

pub mod boustrophedon;

use super::sweep::{SweepPattern, SweepSegment};

/// A cell: one segment on each of a run of consecutive lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub segments: Vec<SweepSegment>,
}

/// A decomposition method.
pub trait Decomposition {
    fn cells(&self, pattern: &SweepPattern) -> Vec<Cell>;
}
