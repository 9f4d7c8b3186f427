//! Result and error types shared by the planners.

use thiserror::Error;

use crate::cost::Cost;
use crate::grid::{Cell, GridError};

/// Why a plan could not be produced.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PlanError {
    /// No path exists from the start to the goal on the currently known map.
    #[error("goal is unreachable from the start on the known map")]
    Unreachable,
    /// A start, goal or changed cell lies outside the grid.
    #[error(transparent)]
    OutOfBounds(#[from] GridError),
    /// The search exceeded its iteration bound. This is a planner bug guard: the loop stops
    /// instead of hanging.
    #[error("search exceeded {limit} queue pops without converging at start {start}")]
    IterationLimit {
        /// The bound that was exceeded.
        limit: u64,
        /// The start cell of the search.
        start: Cell,
    },
}

/// What one search or replan did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PlanStats {
    /// Cost of the shortest path from the start to the goal.
    pub cost: Cost,
    /// Vertices expanded by this call (g-value set, for D* Lite over- or underconsistent).
    pub expansions: u64,
    /// Priority-queue pops by this call, including D* Lite key refreshes.
    pub queue_pops: u64,
}

/// Lifetime counters of a planner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PlannerCounters {
    /// Vertex expansions over all searches.
    pub expansions: u64,
    /// Priority-queue pops over all searches.
    pub queue_pops: u64,
    /// Number of searches (calls that computed a path).
    pub searches: u64,
    /// Directed edges whose cost changed through map updates.
    pub changed_edges: u64,
}
