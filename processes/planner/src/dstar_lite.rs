//! D* Lite, the optimized version (Koenig & Likhachev 2002, Fig. 4).
//!
//! The search runs backwards from the goal: `g(s)` estimates the cost from `s` to the goal
//! and `rhs(s) = min over successors s'` of `c(s, s') + g(s')`. Vertices with `g ≠ rhs` are
//! queued with key `[min(g, rhs) + h(start, s) + k_m; min(g, rhs)]`. When the start moves,
//! `k_m` grows by `h(last_start, start)` (lazily, right before keys are next computed) so
//! queued keys stay lower bounds without re-keying the queue.
//!
//! A changed cell changes the cost of every directed edge into and out of it, and also the
//! diagonal edges that pass its corner (no corner cutting). All those edges start at the cell
//! or one of its 8 neighbours, so an update re-evaluates exactly those 9 vertices, edge by
//! edge, with the optimized rules of Fig. 4 (cheaper edge: `rhs = min(rhs, c + g)`; dearer
//! edge that supported `rhs`: recompute `rhs` from all successors).
//!
//! One deliberate difference to Fig. 4: `ComputeShortestPath` loops while
//! `TopKey < Key(start) OR rhs(start) ≠ g(start)` (Fig. 4 has `>`). With `>`, a start that
//! is overconsistent with a key equal to the top key may end with a stale `g(start)` (only
//! `rhs(start)` exact; the oracle test catches this, e.g. `g(start) = ∞` on a reachable goal
//! after a start jump). With `≠` it costs at most a few extra pops and `g(start)` is always
//! the exact cost to the goal on return, which is what the oracle test checks.
//!
//! # Tie-breaking extension
//!
//! The paper's second key component `min(g, rhs)` makes ties in `k1` go to the vertex
//! nearest the goal (the search root). On octile grids in open or unknown terrain many
//! vertices share `k1 = g*(start)`, and this order expands all of them before it stops,
//! where A* with the usual "deeper node first" tie-breaking expands few.
//! [`KeyTieBreak::TowardStart`] (opt-in, default is [`KeyTieBreak::Paper`]) orders equal-`k1`
//! vertices as: underconsistent first by ascending `g` (the order the paper's correctness
//! argument needs for them), then overconsistent/consistent ones by descending `rhs`
//! (nearest the start first). An overconsistent vertex popped with minimal `k1` has an exact
//! `rhs` whatever the order among equal keys (a vertex with a too-high `rhs` has a strictly
//! larger `k1` than the first inconsistent vertex on its optimal path); a too-low `rhs`
//! traces back to an underconsistent vertex of no larger `k1`, which the class order pops
//! first. The oracle property test runs both modes.
//!
//! # Example
//!
//! ```
//! use hopnav_planner::{Cell, CellState, DStarLite, Grid, PlanError};
//!
//! let mut grid = Grid::new(3, 3, CellState::Free)?;
//! for y in 0..3 {
//!     grid.set(Cell::new(1, y), CellState::Obstacle, 0)?;
//! }
//! let mut planner = DStarLite::new(grid, Cell::new(0, 0), Cell::new(2, 2))?;
//! assert_eq!(planner.compute_shortest_path(), Err(PlanError::Unreachable));
//! assert_eq!(planner.path(), None);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::cost::{Cost, INFINITE_COST, Neighbourhood, add_cost, octile_distance};
use crate::grid::{Cell, CellChange, Grid, GridError};
use crate::plan::{PlanError, PlanStats, PlannerCounters};
use crate::queue::{Key, KeyedQueue};

/// How D* Lite orders queued vertices whose first key components are equal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum KeyTieBreak {
    /// Fig. 4 keys: second component `min(g, rhs)`, ascending.
    #[default]
    Paper,
    /// Underconsistent vertices first (ascending `g`), then the others by descending
    /// `min(g, rhs)`: like A*'s "deeper node first". See the module docs.
    TowardStart,
}

/// Second key component of [`KeyTieBreak::TowardStart`] for consistent/overconsistent
/// vertices starts here, above every underconsistent one.
const OVERCONSISTENT_CLASS: Cost = 1 << 62;

/// Incremental shortest-path planner over a [`Grid`] (optimized D* Lite).
#[derive(Debug, Clone)]
pub struct DStarLite {
    tie_break: KeyTieBreak,
    grid: Grid,
    start: Cell,
    last_start: Cell,
    goal: Cell,
    key_modifier: Cost,
    g: Vec<Cost>,
    rhs: Vec<Cost>,
    queue: KeyedQueue,
    counters: PlannerCounters,
    affected: Vec<(Cell, [Cost; 8])>,
    affected_mark: Vec<u32>,
    mark_generation: u32,
}

impl DStarLite {
    /// A planner on `grid` from `start` to `goal`. Allocates all per-cell state here; the
    /// first [`compute_shortest_path`](Self::compute_shortest_path) does the initial search.
    pub fn new(grid: Grid, start: Cell, goal: Cell) -> Result<Self, PlanError> {
        Self::with_tie_break(grid, start, goal, KeyTieBreak::Paper)
    }

    /// Like [`DStarLite::new`] with an explicit key tie-breaking rule.
    pub fn with_tie_break(
        grid: Grid,
        start: Cell,
        goal: Cell,
        tie_break: KeyTieBreak,
    ) -> Result<Self, PlanError> {
        check_in_bounds(&grid, start)?;
        check_in_bounds(&grid, goal)?;
        let cell_count = grid.cell_count();
        let mut planner = Self {
            tie_break,
            grid,
            start,
            last_start: start,
            goal,
            key_modifier: 0,
            g: vec![INFINITE_COST; cell_count],
            rhs: vec![INFINITE_COST; cell_count],
            queue: KeyedQueue::new(cell_count),
            counters: PlannerCounters::default(),
            affected: Vec::new(),
            affected_mark: vec![0; cell_count],
            mark_generation: 0,
        };
        let goal_index = planner.index(goal);
        planner.rhs[goal_index] = 0;
        let goal_key = planner.calculate_key(goal, goal_index);
        planner.queue.insert_or_update(goal_index, goal_key);
        Ok(planner)
    }

    /// The map the planner currently believes.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The current start (the robot's cell).
    pub fn start(&self) -> Cell {
        self.start
    }

    /// The goal.
    pub fn goal(&self) -> Cell {
        self.goal
    }

    /// Lifetime counters (expansions, pops, searches, changed edges).
    pub fn counters(&self) -> PlannerCounters {
        self.counters
    }

    /// Number of vertices currently in the priority queue.
    pub fn queue_len(&self) -> usize {
        self.queue.len()
    }

    /// `g(cell)`, or `None` outside the grid. [`INFINITE_COST`] means "no path known".
    pub fn g_value(&self, cell: Cell) -> Option<Cost> {
        self.grid.index_of(cell).map(|index| self.g[index])
    }

    /// `rhs(cell)`, or `None` outside the grid.
    pub fn rhs_value(&self, cell: Cell) -> Option<Cost> {
        self.grid.index_of(cell).map(|index| self.rhs[index])
    }

    /// `g(start)` if finite: the cost to the goal after the last
    /// [`compute_shortest_path`](Self::compute_shortest_path).
    pub fn cost_to_goal(&self) -> Option<Cost> {
        let cost = self.g[self.index(self.start)];
        (cost != INFINITE_COST).then_some(cost)
    }

    /// Moves the start to `new_start` (the robot moved). `k_m` is updated lazily, before
    /// keys are next computed. Call [`compute_shortest_path`](Self::compute_shortest_path)
    /// afterwards unless the robot followed [`next_step`](Self::next_step) and no cells
    /// changed (then the g-values stay valid, as in the paper's main loop).
    pub fn move_start(&mut self, new_start: Cell) -> Result<(), PlanError> {
        check_in_bounds(&self.grid, new_start)?;
        self.start = new_start;
        Ok(())
    }

    /// Applies map changes and re-evaluates every edge they touch. Returns how many of the
    /// changes altered a move cost. Validates all cells before applying any: on error the
    /// planner is unchanged.
    pub fn update_cells(&mut self, changes: &[CellChange]) -> Result<usize, PlanError> {
        for change in changes {
            check_in_bounds(&self.grid, change.cell)?;
        }
        let mut cost_changes = 0;
        self.next_mark_generation();
        let mut affected = std::mem::take(&mut self.affected);
        affected.clear();
        for change in changes {
            if !self.grid.would_change_cost(change) {
                continue;
            }
            cost_changes += 1;
            self.mark_affected(change.cell, &mut affected);
            let block = Neighbourhood::of(&self.grid, change.cell);
            for (&index, &next) in block.indices.iter().zip(&block.cells) {
                if index != usize::MAX {
                    self.mark_affected(next, &mut affected);
                }
            }
        }
        if cost_changes == 0 {
            self.affected = affected;
            return Ok(0);
        }
        for change in changes {
            self.grid.apply(change)?;
        }
        self.sync_key_modifier();
        for (vertex, old_costs) in &affected {
            self.reevaluate_out_edges(*vertex, old_costs);
        }
        self.affected = affected;
        Ok(cost_changes)
    }

    /// ComputeShortestPath: makes `g(start)` the exact cost to the goal on the known map.
    /// Returns [`PlanError::Unreachable`] when no path exists (after exhausting the queue;
    /// never hangs).
    pub fn compute_shortest_path(&mut self) -> Result<PlanStats, PlanError> {
        self.sync_key_modifier();
        let start_index = self.index(self.start);
        let pop_limit = 16 * self.grid.cell_count() as u64 + 1024;
        let mut stats = PlanStats::default();
        loop {
            let top = self.queue.top();
            let top_key = top.map_or(Key::INFINITE, |(_, key)| key);
            let start_key = self.calculate_key(self.start, start_index);
            let start_inconsistent = self.rhs[start_index] != self.g[start_index];
            if top_key >= start_key && !start_inconsistent {
                break;
            }
            let Some((vertex_index, old_key)) = top else {
                break;
            };
            stats.queue_pops += 1;
            if stats.queue_pops > pop_limit {
                self.record(&stats);
                return Err(PlanError::IterationLimit {
                    limit: pop_limit,
                    start: self.start,
                });
            }
            let vertex = self.cell_of(vertex_index);
            let new_key = self.calculate_key(vertex, vertex_index);
            if old_key < new_key {
                self.queue.insert_or_update(vertex_index, new_key);
            } else if self.g[vertex_index] > self.rhs[vertex_index] {
                stats.expansions += 1;
                self.g[vertex_index] = self.rhs[vertex_index];
                self.queue.remove(vertex_index);
                self.lower_predecessors(vertex, vertex_index);
            } else {
                stats.expansions += 1;
                let old_g = self.g[vertex_index];
                self.g[vertex_index] = INFINITE_COST;
                self.raise_predecessors(vertex, vertex_index, old_g);
                self.update_vertex(vertex, vertex_index);
            }
        }
        self.record(&stats);
        let cost = self.g[start_index];
        if cost == INFINITE_COST {
            return Err(PlanError::Unreachable);
        }
        stats.cost = cost;
        Ok(stats)
    }

    /// The best next cell from the start: `argmin c(start, s') + g(s')`. `None` at the goal or
    /// when no path is known.
    pub fn next_step(&self) -> Option<Cell> {
        if self.start == self.goal {
            return None;
        }
        self.best_successor(self.start).map(|(cell, _)| cell)
    }

    /// The path from the start to the goal by greedy descent over `c + g`, including both
    /// ends. `None` when no path is known. Bounded by the cell count, so it never loops.
    pub fn path(&self) -> Option<Vec<Cell>> {
        if self.g[self.index(self.start)] == INFINITE_COST {
            return None;
        }
        let mut path = vec![self.start];
        let mut current = self.start;
        while current != self.goal {
            if path.len() > self.grid.cell_count() {
                return None;
            }
            let (next, _) = self.best_successor(current)?;
            path.push(next);
            current = next;
        }
        Some(path)
    }

    fn best_successor(&self, cell: Cell) -> Option<(Cell, Cost)> {
        let block = Neighbourhood::of(&self.grid, cell);
        let mut best: Option<(Cell, Cost)> = None;
        for direction in 0..8 {
            if !block.allowed[direction] {
                continue;
            }
            let total = add_cost(
                block.out_cost(&self.grid, direction),
                self.g[block.indices[direction]],
            );
            if total != INFINITE_COST && best.is_none_or(|(_, best_total)| total < best_total) {
                best = Some((block.cells[direction], total));
            }
        }
        best
    }

    fn record(&mut self, stats: &PlanStats) {
        self.counters.expansions += stats.expansions;
        self.counters.queue_pops += stats.queue_pops;
        self.counters.searches += 1;
    }

    /// g(vertex) just dropped to rhs(vertex): predecessors may now route through it.
    fn lower_predecessors(&mut self, vertex: Cell, vertex_index: usize) {
        let vertex_g = self.g[vertex_index];
        let entry_extra = Cost::from(self.grid.extra_cost_at(vertex_index));
        let block = Neighbourhood::of(&self.grid, vertex);
        for (predecessor, predecessor_index, edge_cost) in block.predecessors(entry_extra) {
            if predecessor != self.goal {
                let via_vertex = add_cost(edge_cost, vertex_g);
                if via_vertex < self.rhs[predecessor_index] {
                    self.rhs[predecessor_index] = via_vertex;
                }
            }
            self.update_vertex(predecessor, predecessor_index);
        }
    }

    /// g(vertex) was raised to infinity from `old_g`: predecessors whose rhs used it recompute.
    fn raise_predecessors(&mut self, vertex: Cell, vertex_index: usize, old_g: Cost) {
        let entry_extra = Cost::from(self.grid.extra_cost_at(vertex_index));
        let block = Neighbourhood::of(&self.grid, vertex);
        for (predecessor, predecessor_index, edge_cost) in block.predecessors(entry_extra) {
            let via_vertex = add_cost(edge_cost, old_g);
            if predecessor != self.goal && self.rhs[predecessor_index] == via_vertex {
                self.rhs[predecessor_index] = self.min_successor_cost(predecessor);
            }
            self.update_vertex(predecessor, predecessor_index);
        }
    }

    /// Applies the Fig. 4 edge-change rules to every out-edge of `vertex` whose cost moved
    /// from `old_costs`, then UpdateVertex once.
    fn reevaluate_out_edges(&mut self, vertex: Cell, old_costs: &[Cost; 8]) {
        let vertex_index = self.index(vertex);
        let block = Neighbourhood::of(&self.grid, vertex);
        for (direction, &old_cost) in old_costs.iter().enumerate() {
            let new_cost = block.out_cost(&self.grid, direction);
            if new_cost == old_cost {
                continue;
            }
            self.counters.changed_edges += 1;
            if vertex == self.goal {
                continue;
            }
            // One of the costs is finite, so the neighbour is inside the grid.
            let successor_g = self.g[block.indices[direction]];
            if old_cost > new_cost {
                let via_successor = add_cost(new_cost, successor_g);
                if via_successor < self.rhs[vertex_index] {
                    self.rhs[vertex_index] = via_successor;
                }
            } else if self.rhs[vertex_index] == add_cost(old_cost, successor_g) {
                self.rhs[vertex_index] = self.min_successor_cost(vertex);
            }
        }
        self.update_vertex(vertex, vertex_index);
    }

    fn min_successor_cost(&self, cell: Cell) -> Cost {
        let block = Neighbourhood::of(&self.grid, cell);
        let mut best = INFINITE_COST;
        for direction in 0..8 {
            if block.allowed[direction] {
                let total = add_cost(
                    block.out_cost(&self.grid, direction),
                    self.g[block.indices[direction]],
                );
                best = best.min(total);
            }
        }
        best
    }

    fn update_vertex(&mut self, cell: Cell, index: usize) {
        if self.g[index] != self.rhs[index] {
            let key = self.calculate_key(cell, index);
            self.queue.insert_or_update(index, key);
        } else {
            self.queue.remove(index);
        }
    }

    fn calculate_key(&self, cell: Cell, index: usize) -> Key {
        let (g, rhs) = (self.g[index], self.rhs[index]);
        let best = g.min(rhs);
        let secondary = match self.tie_break {
            KeyTieBreak::Paper => best,
            KeyTieBreak::TowardStart if best == INFINITE_COST => INFINITE_COST,
            // Path costs stay far below 2^62 (at most 2^28 cells × (1414 + u32::MAX)).
            KeyTieBreak::TowardStart if g < rhs => best.min(OVERCONSISTENT_CLASS - 1),
            KeyTieBreak::TowardStart => {
                OVERCONSISTENT_CLASS
                    + (OVERCONSISTENT_CLASS - 1 - best.min(OVERCONSISTENT_CLASS - 1))
            }
        };
        Key {
            primary: add_cost(
                add_cost(best, octile_distance(self.start, cell)),
                self.key_modifier,
            ),
            secondary,
        }
    }

    fn sync_key_modifier(&mut self) {
        if self.start != self.last_start {
            self.key_modifier = add_cost(
                self.key_modifier,
                octile_distance(self.last_start, self.start),
            );
            self.last_start = self.start;
        }
    }

    fn mark_affected(&mut self, cell: Cell, affected: &mut Vec<(Cell, [Cost; 8])>) {
        let index = self.index(cell);
        if self.affected_mark[index] == self.mark_generation {
            return;
        }
        self.affected_mark[index] = self.mark_generation;
        let block = Neighbourhood::of(&self.grid, cell);
        let old_costs: [Cost; 8] =
            std::array::from_fn(|direction| block.out_cost(&self.grid, direction));
        affected.push((cell, old_costs));
    }

    fn next_mark_generation(&mut self) {
        self.mark_generation = self.mark_generation.wrapping_add(1);
        if self.mark_generation == 0 {
            self.affected_mark.fill(0);
            self.mark_generation = 1;
        }
    }

    /// Row-major index of a cell already known to be inside the grid.
    fn index(&self, cell: Cell) -> usize {
        cell.y as usize * self.grid.width() as usize + cell.x as usize
    }

    fn cell_of(&self, index: usize) -> Cell {
        let width = self.grid.width() as usize;
        Cell::new((index % width) as u32, (index / width) as u32)
    }
}

fn check_in_bounds(grid: &Grid, cell: Cell) -> Result<(), GridError> {
    if grid.contains(cell) {
        Ok(())
    } else {
        Err(GridError::OutOfBounds {
            cell,
            width: grid.width(),
            height: grid.height(),
        })
    }
}
