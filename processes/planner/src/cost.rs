//! Integer move costs and the octile heuristic.
//!
//! Moves are 8-connected. A straight move costs [`STRAIGHT_COST`] (1000), a diagonal move
//! [`DIAGONAL_COST`] (1414), plus the extra cost of the cell moved *into*. There is no corner
//! cutting: a diagonal move is blocked when either orthogonal cell it passes is an obstacle.
//! Costs are integers so planners never compare floats for equality.
//!
//! [`octile_distance`] is consistent with these costs: it is exactly the cost of the cheapest
//! move sequence on an obstacle-free grid with no extra costs, and extra costs are never
//! negative.

use crate::grid::{Cell, Grid};

/// A path or move cost in thousandths of a cell edge.
pub type Cost = u64;

/// Cost of a horizontal or vertical move.
pub const STRAIGHT_COST: Cost = 1000;

/// Cost of a diagonal move (1000 × √2, rounded down).
pub const DIAGONAL_COST: Cost = 1414;

/// The cost of "no path"; every sum that reaches it saturates there.
pub const INFINITE_COST: Cost = Cost::MAX;

/// One of the eight moves of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Move {
    /// Column step, −1, 0 or 1.
    pub dx: i32,
    /// Row step, −1, 0 or 1.
    pub dy: i32,
}

impl Move {
    /// Whether the move changes both coordinates.
    pub const fn is_diagonal(self) -> bool {
        self.dx != 0 && self.dy != 0
    }

    /// Base cost of the move, without extra cell cost.
    pub const fn base_cost(self) -> Cost {
        if self.is_diagonal() {
            DIAGONAL_COST
        } else {
            STRAIGHT_COST
        }
    }

    /// The opposite move.
    pub const fn reversed(self) -> Self {
        Self {
            dx: -self.dx,
            dy: -self.dy,
        }
    }
}

/// The eight moves: four straight, then four diagonal.
pub const MOVES: [Move; 8] = [
    Move { dx: 1, dy: 0 },
    Move { dx: -1, dy: 0 },
    Move { dx: 0, dy: 1 },
    Move { dx: 0, dy: -1 },
    Move { dx: 1, dy: 1 },
    Move { dx: 1, dy: -1 },
    Move { dx: -1, dy: 1 },
    Move { dx: -1, dy: -1 },
];

/// Saturating cost addition: anything plus [`INFINITE_COST`] stays infinite.
pub const fn add_cost(a: Cost, b: Cost) -> Cost {
    a.saturating_add(b)
}

/// Octile distance between two cells in cost units.
pub fn octile_distance(a: Cell, b: Cell) -> Cost {
    let dx = Cost::from(a.x.abs_diff(b.x));
    let dy = Cost::from(a.y.abs_diff(b.y));
    let (long, short) = if dx > dy { (dx, dy) } else { (dy, dx) };
    STRAIGHT_COST * (long - short) + DIAGONAL_COST * short
}

/// The cell one `step` away from `cell`, or `None` outside the grid.
pub fn neighbour(grid: &Grid, cell: Cell, step: Move) -> Option<Cell> {
    grid.offset(cell, step.dx, step.dy)
}

/// The target and cost of moving from `from` by `step`, or `None` when the move is not
/// allowed (target outside the grid, either end an obstacle, or a cut corner).
pub fn move_cost(grid: &Grid, from: Cell, step: Move) -> Option<(Cell, Cost)> {
    let to = neighbour(grid, from, step)?;
    // Both cells are inside the grid, so these row-major indices are valid.
    let width = grid.width() as usize;
    let index = |x: u32, y: u32| y as usize * width + x as usize;
    let to_index = index(to.x, to.y);
    if !grid.is_traversable_at(index(from.x, from.y)) || !grid.is_traversable_at(to_index) {
        return None;
    }
    if step.is_diagonal()
        && (!grid.is_traversable_at(index(to.x, from.y))
            || !grid.is_traversable_at(index(from.x, to.y)))
    {
        return None;
    }
    let extra = Cost::from(grid.extra_cost_at(to_index));
    Some((to, step.base_cost() + extra))
}

/// The eight moves of one cell, read from its 3 × 3 block in one go: the fast path the
/// planners use in their inner loops (equivalent to [`move_cost`] for each move).
///
/// Move existence is symmetric (`a → b` is allowed exactly when `b → a` is), so one mask
/// serves successors and predecessors; only the extra cost differs (paid on entry).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Neighbourhood {
    /// Row-major index of the neighbour in each [`MOVES`] direction (`usize::MAX` outside).
    pub indices: [usize; 8],
    /// The neighbour cell in each direction (meaningless where `allowed` is false).
    pub cells: [Cell; 8],
    /// Whether the move in each direction is allowed.
    pub allowed: [bool; 8],
}

impl Neighbourhood {
    /// Reads the neighbourhood of `cell` (which must lie inside `grid`; outside, no move is
    /// allowed).
    pub fn of(grid: &Grid, cell: Cell) -> Self {
        let width = grid.width() as usize;
        let mut open = [[false; 3]; 3];
        let mut block_index = [[usize::MAX; 3]; 3];
        for (row, dy) in [-1_i32, 0, 1].into_iter().enumerate() {
            let Some(y) = cell.y.checked_add_signed(dy).filter(|&y| y < grid.height()) else {
                continue;
            };
            for (column, dx) in [-1_i32, 0, 1].into_iter().enumerate() {
                let Some(x) = cell.x.checked_add_signed(dx).filter(|&x| x < grid.width()) else {
                    continue;
                };
                let index = y as usize * width + x as usize;
                block_index[row][column] = index;
                open[row][column] = grid.is_traversable_at(index);
            }
        }
        let mut neighbourhood = Self {
            indices: [usize::MAX; 8],
            cells: [cell; 8],
            allowed: [false; 8],
        };
        for (direction, step) in MOVES.iter().enumerate() {
            let row = (step.dy + 1) as usize;
            let column = (step.dx + 1) as usize;
            let index = block_index[row][column];
            neighbourhood.indices[direction] = index;
            if index == usize::MAX {
                continue;
            }
            neighbourhood.cells[direction] = Cell::new(
                cell.x.wrapping_add_signed(step.dx),
                cell.y.wrapping_add_signed(step.dy),
            );
            neighbourhood.allowed[direction] = open[1][1]
                && open[row][column]
                && (!step.is_diagonal() || (open[1][column] && open[row][1]));
        }
        neighbourhood
    }

    /// The neighbours that may move into the centre cell, as `(cell, row-major index, cost of
    /// that move)`; entering the centre costs `entry_extra` on top of the move's base cost.
    pub fn predecessors(&self, entry_extra: Cost) -> impl Iterator<Item = (Cell, usize, Cost)> {
        (0..8)
            .filter(|&direction| self.allowed[direction])
            .map(move |direction| {
                (
                    self.cells[direction],
                    self.indices[direction],
                    BASE_COSTS[direction] + entry_extra,
                )
            })
    }

    /// Cost of the move in `direction` out of the centre cell, [`INFINITE_COST`] if not
    /// allowed.
    pub fn out_cost(&self, grid: &Grid, direction: usize) -> Cost {
        if self.allowed[direction] {
            MOVES[direction].base_cost() + Cost::from(grid.extra_cost_at(self.indices[direction]))
        } else {
            INFINITE_COST
        }
    }
}

/// Base cost of each [`MOVES`] direction.
pub const BASE_COSTS: [Cost; 8] = [
    STRAIGHT_COST,
    STRAIGHT_COST,
    STRAIGHT_COST,
    STRAIGHT_COST,
    DIAGONAL_COST,
    DIAGONAL_COST,
    DIAGONAL_COST,
    DIAGONAL_COST,
];

/// The cost of the single move `from` → `to`, or `None` when they are not adjacent or the
/// move is not allowed.
pub fn edge_cost(grid: &Grid, from: Cell, to: Cell) -> Option<Cost> {
    let dx = i64::from(to.x) - i64::from(from.x);
    let dy = i64::from(to.y) - i64::from(from.y);
    if (dx, dy) == (0, 0) || dx.abs() > 1 || dy.abs() > 1 {
        return None;
    }
    let step = Move {
        dx: dx as i32,
        dy: dy as i32,
    };
    move_cost(grid, from, step).map(|(_, cost)| cost)
}

/// Total cost of `path`, or `None` if it is empty or any step is not an allowed move.
pub fn path_cost(grid: &Grid, path: &[Cell]) -> Option<Cost> {
    let first = path.first()?;
    if !grid.contains(*first) {
        return None;
    }
    path.windows(2).try_fold(0, |total: Cost, pair| {
        edge_cost(grid, pair[0], pair[1]).map(|cost| total + cost)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{CellState, GridError};

    #[test]
    fn octile_matches_move_costs() {
        assert_eq!(octile_distance(Cell::new(0, 0), Cell::new(3, 0)), 3000);
        assert_eq!(octile_distance(Cell::new(0, 0), Cell::new(2, 2)), 2828);
        assert_eq!(
            octile_distance(Cell::new(5, 1), Cell::new(0, 3)),
            3000 + 2828
        );
    }

    #[test]
    fn diagonal_blocked_by_either_corner() -> Result<(), GridError> {
        let mut grid = Grid::new(2, 2, CellState::Free)?;
        let diagonal = Move { dx: 1, dy: 1 };
        assert_eq!(
            move_cost(&grid, Cell::new(0, 0), diagonal),
            Some((Cell::new(1, 1), 1414))
        );
        grid.set(Cell::new(1, 0), CellState::Obstacle, 0)?;
        assert_eq!(move_cost(&grid, Cell::new(0, 0), diagonal), None);
        grid.set(Cell::new(1, 0), CellState::Free, 0)?;
        grid.set(Cell::new(0, 1), CellState::Obstacle, 0)?;
        assert_eq!(move_cost(&grid, Cell::new(0, 0), diagonal), None);
        Ok(())
    }

    #[test]
    fn neighbourhood_agrees_with_move_cost() -> Result<(), GridError> {
        let mut grid = Grid::new(5, 4, CellState::Free)?;
        let mut rng = crate::rng::SplitMix64::new(3);
        for _ in 0..200 {
            let cell = Cell::new(rng.below_u32(5), rng.below_u32(4));
            let state = if rng.chance(1, 3) {
                CellState::Obstacle
            } else {
                CellState::Unknown
            };
            grid.set(cell, state, rng.below_u32(500))?;
            for index in 0..grid.cell_count() {
                let center = grid.cell_at(index).ok_or(GridError::Empty {
                    width: 0,
                    height: 0,
                })?;
                let block = Neighbourhood::of(&grid, center);
                for (direction, step) in MOVES.iter().enumerate() {
                    let expected = move_cost(&grid, center, *step);
                    let fast = block.allowed[direction]
                        .then(|| (block.cells[direction], block.out_cost(&grid, direction)));
                    assert_eq!(fast, expected);
                    assert_eq!(BASE_COSTS[direction], step.base_cost());
                }
            }
        }
        Ok(())
    }

    #[test]
    fn extra_cost_is_paid_on_entry() -> Result<(), GridError> {
        let mut grid = Grid::new(2, 1, CellState::Free)?;
        grid.set(Cell::new(1, 0), CellState::Free, 250)?;
        assert_eq!(
            edge_cost(&grid, Cell::new(0, 0), Cell::new(1, 0)),
            Some(1250)
        );
        assert_eq!(
            edge_cost(&grid, Cell::new(1, 0), Cell::new(0, 0)),
            Some(1000)
        );
        assert_eq!(edge_cost(&grid, Cell::new(0, 0), Cell::new(0, 0)), None);
        Ok(())
    }
}
