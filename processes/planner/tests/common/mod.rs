//! Helpers shared by the integration tests.
#![allow(dead_code)]

use hopnav_planner::cost::{Cost, edge_cost};
use hopnav_planner::{Cell, CellState, Grid};

/// Builds a grid from rows: `.` free, `#` obstacle, `?` unknown, digits = free with extra
/// cost digit × 100.
pub fn grid_from_rows(rows: &[&str]) -> Grid {
    let height = rows.len() as u32;
    let width = rows.first().map_or(0, |row| row.len()) as u32;
    let mut grid = Grid::new(width, height, CellState::Free).expect("valid grid size");
    for (y, row) in rows.iter().enumerate() {
        assert_eq!(row.len() as u32, width, "ragged test grid");
        for (x, symbol) in row.chars().enumerate() {
            let cell = Cell::new(x as u32, y as u32);
            let (state, extra) = match symbol {
                '.' => (CellState::Free, 0),
                '#' => (CellState::Obstacle, 0),
                '?' => (CellState::Unknown, 0),
                digit @ '0'..='9' => (CellState::Free, digit.to_digit(10).unwrap_or(0) * 100),
                other => panic!("unknown test grid symbol {other:?}"),
            };
            grid.set(cell, state, extra).expect("cell in grid");
        }
    }
    grid
}

/// Asserts `path` runs from `start` to `goal` through allowed moves only (adjacent cells,
/// no obstacles, no cut corners) and returns its cost.
pub fn assert_valid_path(grid: &Grid, path: &[Cell], start: Cell, goal: Cell) -> Cost {
    assert_eq!(path.first(), Some(&start), "path must begin at the start");
    assert_eq!(path.last(), Some(&goal), "path must end at the goal");
    let mut total = 0;
    for pair in path.windows(2) {
        let (from, to) = (pair[0], pair[1]);
        assert!(grid.is_traversable(to), "path enters obstacle {to}");
        if from.x != to.x && from.y != to.y {
            assert!(
                grid.is_traversable(Cell::new(to.x, from.y))
                    && grid.is_traversable(Cell::new(from.x, to.y)),
                "path cuts a corner between {from} and {to}"
            );
        }
        total += edge_cost(grid, from, to).unwrap_or_else(|| panic!("illegal move {from} -> {to}"));
    }
    total
}
