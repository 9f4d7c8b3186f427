//! An independent Dijkstra oracle for tests.
//!
//! Deliberately shares no search or move code with the planners: it re-derives the move
//! rules (8-connected, 1000/1414 plus the extra cost of the entered cell, no corner cutting,
//! unknown = free) from the cell states, and searches forward from the start while D* Lite
//! searches backward from the goal.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::cost::{Cost, DIAGONAL_COST, STRAIGHT_COST};
use crate::grid::{Cell, CellState, Grid};

/// Cost of the cheapest path from `start` to `goal`, `None` when unreachable or either
/// cell is outside the grid. `start == goal` costs 0 whatever the cell holds.
pub fn dijkstra_cost(grid: &Grid, start: Cell, goal: Cell) -> Option<Cost> {
    if !grid.contains(start) || !grid.contains(goal) {
        return None;
    }
    if start == goal {
        return Some(0);
    }
    let width = i64::from(grid.width());
    let height = i64::from(grid.height());
    let open = |x: i64, y: i64| -> bool {
        x >= 0
            && y >= 0
            && x < width
            && y < height
            && grid.state(Cell::new(x as u32, y as u32)) != Some(CellState::Obstacle)
    };
    let mut best = vec![Cost::MAX; grid.cell_count()];
    let mut heap = BinaryHeap::new();
    let (sx, sy) = (i64::from(start.x), i64::from(start.y));
    if !open(sx, sy) {
        return None;
    }
    best[(sy * width + sx) as usize] = 0;
    heap.push(Reverse((0, sx, sy)));
    while let Some(Reverse((cost, x, y))) = heap.pop() {
        if cost > best[(y * width + x) as usize] {
            continue;
        }
        if x == i64::from(goal.x) && y == i64::from(goal.y) {
            return Some(cost);
        }
        for dy in -1..=1_i64 {
            for dx in -1..=1_i64 {
                if (dx, dy) == (0, 0) || !open(x + dx, y + dy) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal && (!open(x + dx, y) || !open(x, y + dy)) {
                    continue;
                }
                let entered = Cell::new((x + dx) as u32, (y + dy) as u32);
                let extra = Cost::from(grid.extra_cost(entered).unwrap_or(0));
                let base = if diagonal {
                    DIAGONAL_COST
                } else {
                    STRAIGHT_COST
                };
                let next_cost = cost + base + extra;
                let slot = &mut best[((y + dy) * width + x + dx) as usize];
                if next_cost < *slot {
                    *slot = next_cost;
                    heap.push(Reverse((next_cost, x + dx, y + dy)));
                }
            }
        }
    }
    None
}
