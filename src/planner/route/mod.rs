//! Route stage: transits that avoid no-fly zones, and the order in which cells are flown.

pub mod nearest_cell;
pub mod visibility;
