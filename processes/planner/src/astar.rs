//! A* over the same costs and heuristic as D* Lite: the repeated-A* baseline.
//!
//! Each [`AStar::search`] is a fresh search from scratch; only the buffers are reused
//! between searches (generation stamps instead of clearing), so repeated replanning does not
//! pay for allocation. By default ties in `f` go to the larger `g` (deeper node), the usual
//! tie-breaking that makes A* expand few nodes on octile grids, so the baseline is a strong
//! one; [`TieBreak::SmallerG`] mirrors the order D* Lite's second key component imposes.
//! [`SearchDirection::Backward`] searches from the goal to the start over reversed edges,
//! the direction D* Lite searches in.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::cost::{BASE_COSTS, Cost, INFINITE_COST, Neighbourhood, octile_distance};
use crate::grid::{Cell, Grid, GridError};
use crate::plan::{PlanError, PlanStats};

/// A path found by A*.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AStarResult {
    /// Cells from start to goal, both included.
    pub path: Vec<Cell>,
    /// Cost, expansions and pops of the search.
    pub stats: PlanStats,
}

const NO_PARENT: u32 = u32::MAX;

/// Which node A* expands first among nodes with equal `f = g + h`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TieBreak {
    /// The node farther from the start (larger `g`): few expansions on octile grids.
    #[default]
    LargerG,
    /// The node nearer the start (smaller `g`), like D* Lite's `k2 = min(g, rhs)`.
    SmallerG,
}

/// Which end A* searches from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SearchDirection {
    /// From the start towards the goal.
    #[default]
    Forward,
    /// From the goal towards the start over reversed edges (like D* Lite).
    Backward,
}

/// Reusable A* search state for grids of one size.
#[derive(Debug, Clone)]
pub struct AStar {
    g: Vec<Cost>,
    parent: Vec<u32>,
    seen_generation: Vec<u32>,
    closed_generation: Vec<u32>,
    generation: u32,
    tie_break: TieBreak,
    direction: SearchDirection,
    open: BinaryHeap<(Reverse<Cost>, Cost, u32)>,
}

impl AStar {
    /// Buffers for grids of `cell_count` cells (they grow if a larger grid is searched).
    pub fn new(cell_count: usize) -> Self {
        Self::with_tie_break(cell_count, TieBreak::default())
    }

    /// Like [`AStar::new`] with an explicit tie-breaking rule.
    pub fn with_tie_break(cell_count: usize, tie_break: TieBreak) -> Self {
        Self::configured(cell_count, tie_break, SearchDirection::Forward)
    }

    /// Like [`AStar::new`] with explicit tie-breaking and search direction.
    pub fn configured(cell_count: usize, tie_break: TieBreak, direction: SearchDirection) -> Self {
        Self {
            tie_break,
            direction,
            g: vec![INFINITE_COST; cell_count],
            parent: vec![NO_PARENT; cell_count],
            seen_generation: vec![0; cell_count],
            closed_generation: vec![0; cell_count],
            generation: 0,
            open: BinaryHeap::new(),
        }
    }

    /// Shortest path from `start` to `goal` on `grid`.
    pub fn search(
        &mut self,
        grid: &Grid,
        start: Cell,
        goal: Cell,
    ) -> Result<AStarResult, PlanError> {
        index_in(grid, start)?;
        index_in(grid, goal)?;
        let (source, target) = match self.direction {
            SearchDirection::Forward => (start, goal),
            SearchDirection::Backward => (goal, start),
        };
        let source_index = index_in(grid, source)?;
        let target_index = index_in(grid, target)?;
        self.prepare(grid.cell_count());
        let mut stats = PlanStats::default();
        self.open.clear();
        self.discover(source_index, 0, NO_PARENT);
        self.open.push((
            Reverse(octile_distance(source, target)),
            self.tie_value(0),
            source_index as u32,
        ));
        while let Some((_, _, node)) = self.open.pop() {
            stats.queue_pops += 1;
            let node = node as usize;
            // A node's better duplicate has a smaller f (same h), so it pops first and
            // closes the node; later duplicates are skipped here.
            if self.closed_generation[node] == self.generation {
                continue;
            }
            let node_g = self.g[node];
            self.closed_generation[node] = self.generation;
            if node == target_index {
                stats.cost = node_g;
                let mut path = self.trace_path(grid, target_index);
                if self.direction == SearchDirection::Backward {
                    path.reverse();
                }
                return Ok(AStarResult { path, stats });
            }
            stats.expansions += 1;
            let Some(cell) = grid.cell_at(node) else {
                continue;
            };
            let block = Neighbourhood::of(grid, cell);
            // Backward, the edge runs next → cell and pays the extra cost of `cell`.
            let entry_extra = Cost::from(grid.extra_cost_at(node));
            for (direction, base_cost) in BASE_COSTS.iter().enumerate() {
                if !block.allowed[direction] {
                    continue;
                }
                let (next, next_index) = (block.cells[direction], block.indices[direction]);
                let cost = match self.direction {
                    SearchDirection::Forward => block.out_cost(grid, direction),
                    SearchDirection::Backward => base_cost + entry_extra,
                };
                if self.closed_generation[next_index] == self.generation {
                    continue;
                }
                let next_g = node_g + cost;
                let known = if self.seen_generation[next_index] == self.generation {
                    self.g[next_index]
                } else {
                    INFINITE_COST
                };
                if next_g < known {
                    self.discover(next_index, next_g, node as u32);
                    let f = next_g + octile_distance(next, target);
                    self.open
                        .push((Reverse(f), self.tie_value(next_g), next_index as u32));
                }
            }
        }
        Err(PlanError::Unreachable)
    }

    fn tie_value(&self, g: Cost) -> Cost {
        match self.tie_break {
            TieBreak::LargerG => g,
            TieBreak::SmallerG => INFINITE_COST - g,
        }
    }

    fn prepare(&mut self, cell_count: usize) {
        if self.g.len() < cell_count {
            self.g.resize(cell_count, INFINITE_COST);
            self.parent.resize(cell_count, NO_PARENT);
            self.seen_generation.resize(cell_count, 0);
            self.closed_generation.resize(cell_count, 0);
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.seen_generation.fill(0);
            self.closed_generation.fill(0);
            self.generation = 1;
        }
    }

    fn discover(&mut self, index: usize, g: Cost, parent: u32) {
        self.g[index] = g;
        self.parent[index] = parent;
        self.seen_generation[index] = self.generation;
    }

    fn trace_path(&self, grid: &Grid, goal_index: usize) -> Vec<Cell> {
        let mut path = Vec::new();
        let mut current = goal_index as u32;
        while current != NO_PARENT && path.len() <= grid.cell_count() {
            if let Some(cell) = grid.cell_at(current as usize) {
                path.push(cell);
            }
            current = self.parent[current as usize];
        }
        path.reverse();
        path
    }
}

/// One-shot A* (allocates its buffers).
pub fn astar(grid: &Grid, start: Cell, goal: Cell) -> Result<AStarResult, PlanError> {
    AStar::new(grid.cell_count()).search(grid, start, goal)
}

fn index_in(grid: &Grid, cell: Cell) -> Result<usize, GridError> {
    grid.index_of(cell).ok_or(GridError::OutOfBounds {
        cell,
        width: grid.width(),
        height: grid.height(),
    })
}
