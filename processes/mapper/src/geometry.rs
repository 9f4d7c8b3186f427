//! The fixed grid of the mission area: world metres ↔ cell indices.
//!
//! Cell `(x, y)` covers `[origin_x_m + x·cell_size_m, origin_x_m + (x+1)·cell_size_m)` along
//! world x and likewise along world y; `x` is the column, `y` the row (the planner's
//! convention). The geometry never changes during a mission and travels in every `MapHeader`.

use serde::{Deserialize, Serialize};

/// Largest number of cells a map may hold (bounds memory: see [`crate::cell::CellStats`]).
pub const MAX_CELLS: u64 = 1 << 21;

/// Origin, cell size and dimensions of the map grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridGeometry {
    /// World x of the corner of cell (0, 0), metres.
    pub origin_x_m: f64,
    /// World y of the corner of cell (0, 0), metres.
    pub origin_y_m: f64,
    /// Edge length of a cell, metres.
    pub cell_size_m: f64,
    /// Cells along x.
    pub width_cells: u32,
    /// Cells along y.
    pub height_cells: u32,
}

impl GridGeometry {
    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.width_cells as usize * self.height_cells as usize
    }

    /// The `(x, y)` cell holding world point `(x_m, y_m)`, `None` outside the grid.
    pub fn cell_of(&self, x_m: f64, y_m: f64) -> Option<(u32, u32)> {
        let fx = ((x_m - self.origin_x_m) / self.cell_size_m).floor();
        let fy = ((y_m - self.origin_y_m) / self.cell_size_m).floor();
        let inside = fx >= 0.0
            && fy >= 0.0
            && fx < f64::from(self.width_cells)
            && fy < f64::from(self.height_cells);
        inside.then_some((fx as u32, fy as u32))
    }

    /// Linear index of cell `(x, y)` (row-major); the caller ensures it is inside.
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width_cells as usize + x as usize
    }

    /// Cell `(x, y)` of a linear index.
    pub fn coords(&self, index: usize) -> (u32, u32) {
        let width = self.width_cells.max(1) as usize;
        ((index % width) as u32, (index / width) as u32)
    }

    /// World `(x, y)` of the centre of cell `(x, y)`, metres.
    pub fn centre_m(&self, x: u32, y: u32) -> (f64, f64) {
        (
            self.origin_x_m + (f64::from(x) + 0.5) * self.cell_size_m,
            self.origin_y_m + (f64::from(y) + 0.5) * self.cell_size_m,
        )
    }

    /// Cells within `radius_cells` of `(x, y)` (a clipped square), as inclusive index ranges.
    pub fn window(&self, x: u32, y: u32, radius_cells: u32) -> (u32, u32, u32, u32) {
        let x0 = x.saturating_sub(radius_cells);
        let y0 = y.saturating_sub(radius_cells);
        let x1 = x.saturating_add(radius_cells).min(self.width_cells - 1);
        let y1 = y.saturating_add(radius_cells).min(self.height_cells - 1);
        (x0, y0, x1, y1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> GridGeometry {
        GridGeometry {
            origin_x_m: -32.0,
            origin_y_m: -32.0,
            cell_size_m: 0.5,
            width_cells: 128,
            height_cells: 128,
        }
    }

    #[test]
    fn cells_round_down_and_edges_are_outside() {
        let g = geometry();
        assert_eq!(g.cell_of(-32.0, -32.0), Some((0, 0)));
        assert_eq!(g.cell_of(0.0, 0.25), Some((64, 64)));
        assert_eq!(g.cell_of(31.99, -31.99), Some((127, 0)));
        assert_eq!(g.cell_of(32.0, 0.0), None);
        assert_eq!(g.cell_of(-32.01, 0.0), None);
        assert_eq!(g.cell_of(f64::NAN, 0.0), None);
        assert_eq!(g.cell_of(1e300, 0.0), None);
        let (cx, cy) = g.centre_m(64, 64);
        assert_eq!((cx, cy), (0.25, 0.25));
        assert_eq!(g.coords(g.index(5, 7)), (5, 7));
    }
}
