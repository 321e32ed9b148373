//! The cell grid: which discs are near which, so that a disc is only tested against discs in
//! its own and the adjacent cells.

pub mod grid;

pub use grid::{CellGrid, Visit, NONE};
