//! World metres ↔ grid cells. The grid's cell (0, 0) has its lower corner at the origin; x
//! grows with the column, y with the row.

use crate::grid::{Cell, Grid};

/// Why a grid geometry is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// Origin or cell size not finite, cell size not positive, or an empty grid.
    #[error(
        "invalid map geometry: origin ({origin_x_m}, {origin_y_m}) m, cell {cell_size_m} m, {width_cells}x{height_cells} cells"
    )]
    Invalid {
        /// Origin x, metres.
        origin_x_m: f64,
        /// Origin y, metres.
        origin_y_m: f64,
        /// Cell edge, metres.
        cell_size_m: f64,
        /// Columns.
        width_cells: u32,
        /// Rows.
        height_cells: u32,
    },
}

/// Placement of the planning grid in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapGeometry {
    origin_x_m: f64,
    origin_y_m: f64,
    cell_size_m: f64,
    width_cells: u32,
    height_cells: u32,
}

impl MapGeometry {
    /// A grid of `width_cells × height_cells` cells of `cell_size_m` whose corner is at
    /// (`origin_x_m`, `origin_y_m`).
    pub fn new(
        origin_x_m: f64,
        origin_y_m: f64,
        cell_size_m: f64,
        width_cells: u32,
        height_cells: u32,
    ) -> Result<Self, GeometryError> {
        let valid = origin_x_m.is_finite()
            && origin_y_m.is_finite()
            && cell_size_m.is_finite()
            && cell_size_m > 0.0
            && width_cells > 0
            && height_cells > 0;
        if !valid {
            return Err(GeometryError::Invalid {
                origin_x_m,
                origin_y_m,
                cell_size_m,
                width_cells,
                height_cells,
            });
        }
        Ok(Self {
            origin_x_m,
            origin_y_m,
            cell_size_m,
            width_cells,
            height_cells,
        })
    }

    /// Cell edge, metres.
    pub fn cell_size_m(&self) -> f64 {
        self.cell_size_m
    }

    /// Columns.
    pub fn width_cells(&self) -> u32 {
        self.width_cells
    }

    /// Rows.
    pub fn height_cells(&self) -> u32 {
        self.height_cells
    }

    /// The cell containing `xy_m`, or `None` outside the grid (or for non-finite input).
    pub fn cell_of(&self, xy_m: [f64; 2]) -> Option<Cell> {
        let column = ((xy_m[0] - self.origin_x_m) / self.cell_size_m).floor();
        let row = ((xy_m[1] - self.origin_y_m) / self.cell_size_m).floor();
        let inside = column >= 0.0
            && row >= 0.0
            && column < f64::from(self.width_cells)
            && row < f64::from(self.height_cells);
        inside.then(|| Cell::new(column as u32, row as u32))
    }

    /// The cell nearest to `xy_m` inside the grid (clamped at the border); `None` only for
    /// non-finite input.
    pub fn nearest_cell(&self, xy_m: [f64; 2]) -> Option<Cell> {
        if !(xy_m[0].is_finite() && xy_m[1].is_finite()) {
            return None;
        }
        let clamp = |value_m: f64, origin_m: f64, cells: u32| {
            let index = ((value_m - origin_m) / self.cell_size_m).floor();
            index.clamp(0.0, f64::from(cells - 1)) as u32
        };
        Some(Cell::new(
            clamp(xy_m[0], self.origin_x_m, self.width_cells),
            clamp(xy_m[1], self.origin_y_m, self.height_cells),
        ))
    }

    /// World coordinates of the centre of `cell`, metres.
    pub fn center_of(&self, cell: Cell) -> [f64; 2] {
        [
            self.origin_x_m + (f64::from(cell.x) + 0.5) * self.cell_size_m,
            self.origin_y_m + (f64::from(cell.y) + 0.5) * self.cell_size_m,
        ]
    }

    /// True when every point of the segment (sampled at a quarter cell) lies in a traversable
    /// cell of `grid`: a straight drive from `from_m` to `to_m` crosses no obstacle cell.
    pub fn segment_is_clear(&self, grid: &Grid, from_m: [f64; 2], to_m: [f64; 2]) -> bool {
        let step_m = 0.25 * self.cell_size_m;
        let length_m = (to_m[0] - from_m[0]).hypot(to_m[1] - from_m[1]);
        let samples = (length_m / step_m).ceil().max(1.0) as usize;
        (0..=samples).all(|sample| {
            let t = sample as f64 / samples as f64;
            let point_m = [
                from_m[0] + t * (to_m[0] - from_m[0]),
                from_m[1] + t * (to_m[1] - from_m[1]),
            ];
            self.cell_of(point_m)
                .is_some_and(|cell| grid.is_traversable(cell))
        })
    }
}

impl MapGeometry {
    /// Whether a rover footprint of `half_extents_m` (half length along its heading, half
    /// width), driven straight from `from_m` to `to_m` facing along the segment, stays clear
    /// of every cell `blocked` says is a rock. Sampled every quarter cell; a cell counts as
    /// touched when any part of its square may lie inside the footprint.
    pub fn footprint_is_clear(
        &self,
        from_m: [f64; 2],
        to_m: [f64; 2],
        half_extents_m: [f64; 2],
        blocked: impl Fn(Cell) -> bool,
    ) -> bool {
        let (dx, dy) = (to_m[0] - from_m[0], to_m[1] - from_m[1]);
        let length_m = dx.hypot(dy);
        if !length_m.is_finite() {
            return false;
        }
        let (cos, sin) = if length_m > 1e-9 {
            (dx / length_m, dy / length_m)
        } else {
            (1.0, 0.0)
        };
        let [half_length_m, half_width_m] = half_extents_m;
        // A cell touches the footprint when its centre is within half a cell diagonal of it.
        let grow_m = 0.5 * std::f64::consts::SQRT_2 * self.cell_size_m;
        let reach_m = half_length_m.hypot(half_width_m) + grow_m;
        let samples = (length_m / (0.25 * self.cell_size_m)).ceil().max(1.0) as usize;
        (0..=samples).all(|sample| {
            let t = sample as f64 / samples as f64;
            let centre_m = [from_m[0] + t * dx, from_m[1] + t * dy];
            let Some(lo) = self.nearest_cell([centre_m[0] - reach_m, centre_m[1] - reach_m]) else {
                return false;
            };
            let Some(hi) = self.nearest_cell([centre_m[0] + reach_m, centre_m[1] + reach_m]) else {
                return false;
            };
            (lo.y..=hi.y).all(|y| {
                (lo.x..=hi.x).all(|x| {
                    let cell = Cell::new(x, y);
                    let [cx, cy] = self.center_of(cell);
                    let (rx, ry) = (cx - centre_m[0], cy - centre_m[1]);
                    let along_m = (rx * cos + ry * sin).abs();
                    let across_m = (-rx * sin + ry * cos).abs();
                    let inside =
                        along_m <= half_length_m + grow_m && across_m <= half_width_m + grow_m;
                    !inside || !blocked(cell)
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_and_centre_round_trip() {
        let geometry = MapGeometry::new(-32.0, -32.0, 0.5, 128, 128).unwrap();
        let cell = geometry.cell_of([0.1, -0.1]).unwrap();
        assert_eq!(cell, Cell::new(64, 63));
        assert_eq!(geometry.center_of(cell), [0.25, -0.25]);
        assert_eq!(geometry.cell_of([40.0, 0.0]), None);
        assert_eq!(geometry.nearest_cell([40.0, 0.0]), Some(Cell::new(127, 64)));
        assert_eq!(geometry.cell_of([f64::NAN, 0.0]), None);
    }

    #[test]
    fn rejects_bad_geometry() {
        assert!(MapGeometry::new(0.0, 0.0, 0.0, 4, 4).is_err());
        assert!(MapGeometry::new(f64::NAN, 0.0, 0.5, 4, 4).is_err());
        assert!(MapGeometry::new(0.0, 0.0, 0.5, 0, 4).is_err());
    }

    #[test]
    fn the_footprint_sweep_sees_a_rock_beside_the_centre_line() {
        let geometry = MapGeometry::new(-8.0, -8.0, 0.25, 64, 64).unwrap();
        let rock = geometry.cell_of([2.0, 0.45]).unwrap();
        let blocked = |cell: Cell| cell == rock;
        // The centre line (y = 0) passes 0.45 m from the rock: the 0.8 m wide body hits it…
        assert!(!geometry.footprint_is_clear([0.0, 0.0], [4.0, 0.0], [0.55, 0.4], blocked));
        // … a line 1 m away clears it, and so does a drive that stops short of it.
        assert!(geometry.footprint_is_clear([0.0, -1.0], [4.0, -1.0], [0.55, 0.4], blocked));
        assert!(geometry.footprint_is_clear([-3.0, 0.0], [0.5, 0.0], [0.55, 0.4], blocked));
        assert!(!geometry.footprint_is_clear([f64::NAN, 0.0], [1.0, 0.0], [0.55, 0.4], blocked));
    }
}
