//! The occupancy grid the planners search.
//!
//! Cells are free, obstacle or unknown; unknown cells are planned through as if free (the
//! optimistic assumption of D* Lite in unknown terrain). Every traversable cell may carry an
//! extra integer cost (obstacle inflation) that is added to each move *into* that cell.
//!
//! Coordinates follow MovingAI: `x` is the column, `y` the row, row 0 is the first map row.

use thiserror::Error;

/// Largest number of cells a grid may hold (bounds memory for untrusted map headers).
pub const MAX_CELLS: usize = 1 << 28;

/// A cell coordinate: `x` is the column, `y` the row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    /// Column, 0 at the left edge.
    pub x: u32,
    /// Row, 0 at the first (top) row.
    pub y: u32,
}

impl Cell {
    /// A cell at column `x`, row `y`.
    pub const fn new(x: u32, y: u32) -> Self {
        Self { x, y }
    }
}

impl std::fmt::Display for Cell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "({}, {})", self.x, self.y)
    }
}

/// What is known about a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CellState {
    /// Observed and traversable.
    Free,
    /// Observed and not traversable.
    Obstacle,
    /// Not observed yet; planned through as if free.
    #[default]
    Unknown,
}

impl CellState {
    /// Whether a planner may move into a cell in this state (unknown counts as free).
    pub const fn is_traversable(self) -> bool {
        !matches!(self, CellState::Obstacle)
    }
}

/// A new state and extra cost for one cell, as published by the mapper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CellChange {
    /// The cell that changed.
    pub cell: Cell,
    /// Its new state.
    pub state: CellState,
    /// Its new extra cost (added to every move into the cell; ignored for obstacles).
    pub extra_cost: u32,
}

impl CellChange {
    /// A change of `cell` to `state` with `extra_cost`.
    pub const fn new(cell: Cell, state: CellState, extra_cost: u32) -> Self {
        Self {
            cell,
            state,
            extra_cost,
        }
    }
}

/// Errors from building or editing a [`Grid`].
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum GridError {
    /// Width or height is zero.
    #[error("grid dimensions {width}x{height} are empty")]
    Empty {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// Width × height exceeds [`MAX_CELLS`].
    #[error("grid {width}x{height} has more than {MAX_CELLS} cells")]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// A cell lies outside the grid.
    #[error("cell {cell} is outside the {width}x{height} grid")]
    OutOfBounds {
        /// The offending cell.
        cell: Cell,
        /// Grid width.
        width: u32,
        /// Grid height.
        height: u32,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CellData {
    state: CellState,
    extra_cost: u32,
}

/// A width × height grid of cell states and extra costs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Grid {
    width: u32,
    height: u32,
    cells: Vec<CellData>,
}

impl Grid {
    /// A grid with every cell in `state` and no extra cost.
    pub fn new(width: u32, height: u32, state: CellState) -> Result<Self, GridError> {
        Self::filled(width, height, state, 0)
    }

    /// A grid with every cell in `state` at `extra_cost`.
    pub fn filled(
        width: u32,
        height: u32,
        state: CellState,
        extra_cost: u32,
    ) -> Result<Self, GridError> {
        if width == 0 || height == 0 {
            return Err(GridError::Empty { width, height });
        }
        let count = (width as usize)
            .checked_mul(height as usize)
            .filter(|&count| count <= MAX_CELLS)
            .ok_or(GridError::TooLarge { width, height })?;
        Ok(Self {
            width,
            height,
            cells: vec![CellData { state, extra_cost }; count],
        })
    }

    /// Number of columns.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Number of rows.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of cells (width × height).
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Whether `cell` lies inside the grid.
    pub fn contains(&self, cell: Cell) -> bool {
        cell.x < self.width && cell.y < self.height
    }

    /// The cell `dx` columns and `dy` rows from `cell`, or `None` outside the grid.
    pub fn offset(&self, cell: Cell, dx: i32, dy: i32) -> Option<Cell> {
        let moved = Cell::new(
            cell.x.checked_add_signed(dx)?,
            cell.y.checked_add_signed(dy)?,
        );
        self.contains(moved).then_some(moved)
    }

    /// Row-major index of `cell`, or `None` outside the grid.
    pub fn index_of(&self, cell: Cell) -> Option<usize> {
        self.contains(cell)
            .then(|| cell.y as usize * self.width as usize + cell.x as usize)
    }

    /// The cell at row-major `index`, or `None` past the end.
    pub fn cell_at(&self, index: usize) -> Option<Cell> {
        (index < self.cells.len()).then(|| {
            let width = self.width as usize;
            // Both quotient and remainder fit in u32 because index < width * height.
            Cell::new((index % width) as u32, (index / width) as u32)
        })
    }

    /// State of `cell`, or `None` outside the grid.
    pub fn state(&self, cell: Cell) -> Option<CellState> {
        self.index_of(cell).map(|index| self.cells[index].state)
    }

    /// Extra cost of `cell`, or `None` outside the grid.
    pub fn extra_cost(&self, cell: Cell) -> Option<u32> {
        self.index_of(cell)
            .map(|index| self.cells[index].extra_cost)
    }

    /// Whether `cell` is inside the grid and not an obstacle.
    pub fn is_traversable(&self, cell: Cell) -> bool {
        self.state(cell).is_some_and(CellState::is_traversable)
    }

    /// Whether the cell at row-major `index` exists and is not an obstacle.
    pub fn is_traversable_at(&self, index: usize) -> bool {
        self.cells
            .get(index)
            .is_some_and(|data| data.state.is_traversable())
    }

    /// Extra cost of the cell at row-major `index` (0 past the end).
    pub fn extra_cost_at(&self, index: usize) -> u32 {
        self.cells.get(index).map_or(0, |data| data.extra_cost)
    }

    /// Sets `cell`; returns whether any move cost changed (traversability, or the extra cost
    /// of a traversable cell). Unknown → free is not a cost change.
    pub fn set(
        &mut self,
        cell: Cell,
        state: CellState,
        extra_cost: u32,
    ) -> Result<bool, GridError> {
        let index = self.index_of(cell).ok_or(GridError::OutOfBounds {
            cell,
            width: self.width,
            height: self.height,
        })?;
        let new = CellData { state, extra_cost };
        let changes_cost = Self::differs_in_cost(self.cells[index], new);
        self.cells[index] = new;
        Ok(changes_cost)
    }

    /// Applies one [`CellChange`]; see [`Grid::set`].
    pub fn apply(&mut self, change: &CellChange) -> Result<bool, GridError> {
        self.set(change.cell, change.state, change.extra_cost)
    }

    /// Whether applying `change` would change any move cost (false outside the grid).
    pub fn would_change_cost(&self, change: &CellChange) -> bool {
        self.index_of(change.cell).is_some_and(|index| {
            Self::differs_in_cost(
                self.cells[index],
                CellData {
                    state: change.state,
                    extra_cost: change.extra_cost,
                },
            )
        })
    }

    fn differs_in_cost(old: CellData, new: CellData) -> bool {
        let old_open = old.state.is_traversable();
        let new_open = new.state.is_traversable();
        old_open != new_open || (new_open && old.extra_cost != new.extra_cost)
    }

    /// Fraction of cells that are obstacles.
    pub fn obstacle_fraction(&self) -> f64 {
        let blocked = self
            .cells
            .iter()
            .filter(|data| !data.state.is_traversable())
            .count();
        blocked as f64 / self.cells.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_empty_and_huge_grids() {
        assert!(matches!(
            Grid::new(0, 5, CellState::Free),
            Err(GridError::Empty { .. })
        ));
        assert!(matches!(
            Grid::new(u32::MAX, u32::MAX, CellState::Free),
            Err(GridError::TooLarge { .. })
        ));
    }

    #[test]
    fn index_round_trips() -> Result<(), GridError> {
        let grid = Grid::new(7, 3, CellState::Free)?;
        for index in 0..grid.cell_count() {
            let cell = grid.cell_at(index).ok_or(GridError::Empty {
                width: 0,
                height: 0,
            })?;
            assert_eq!(grid.index_of(cell), Some(index));
        }
        assert_eq!(grid.index_of(Cell::new(7, 0)), None);
        assert_eq!(grid.cell_at(21), None);
        Ok(())
    }

    #[test]
    fn unknown_to_free_is_not_a_cost_change() -> Result<(), GridError> {
        let mut grid = Grid::new(2, 2, CellState::Unknown)?;
        assert!(!grid.set(Cell::new(0, 0), CellState::Free, 0)?);
        assert!(grid.set(Cell::new(0, 0), CellState::Obstacle, 0)?);
        assert!(!grid.set(Cell::new(0, 0), CellState::Obstacle, 9)?);
        assert!(grid.set(Cell::new(1, 0), CellState::Free, 5)?);
        assert!(grid.set(Cell::new(5, 0), CellState::Free, 0).is_err());
        Ok(())
    }
}
