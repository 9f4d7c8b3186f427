//! Solving MovingAI scenarios on a known map with D* Lite and A* (for `hopnav plan`).

use std::time::{Duration, Instant};

use thiserror::Error;

use crate::astar::AStar;
use crate::cost::Cost;
use crate::dstar_lite::DStarLite;
use crate::grid::{Cell, Grid};
use crate::movingai::{Scenario, cost_matches_optimal_length};
use crate::plan::PlanError;

/// Why a scenario could not be run on a map.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ScenarioError {
    /// The scenario was made for a map of another size.
    #[error("scenario is for a {expected_width}x{expected_height} map, map is {width}x{height}")]
    MapSizeMismatch {
        /// Width stated by the scenario.
        expected_width: u32,
        /// Height stated by the scenario.
        expected_height: u32,
        /// Actual map width.
        width: u32,
        /// Actual map height.
        height: u32,
    },
    /// A planner failed for a reason other than an unreachable goal.
    #[error(transparent)]
    Planner(#[from] PlanError),
}

/// Result of one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioOutcome {
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// D* Lite cost, `None` if unreachable.
    pub cost: Option<Cost>,
    /// The scenario's optimal length (1 / √2 units).
    pub optimal_length: f64,
    /// Whether `cost` matches `optimal_length` within rounding.
    pub matches_optimal: bool,
    /// Whether D* Lite and A* found the same cost.
    pub planners_agree: bool,
    /// D* Lite vertex expansions (initial search).
    pub dstar_expansions: u64,
    /// D* Lite search time (excluding allocation).
    pub dstar_time: Duration,
    /// A* node expansions.
    pub astar_expansions: u64,
    /// A* search time.
    pub astar_time: Duration,
}

/// Solves `scenario` on `grid` with a fresh D* Lite and with `astar`.
pub fn solve_scenario(
    grid: &Grid,
    scenario: &Scenario,
    astar: &mut AStar,
) -> Result<ScenarioOutcome, ScenarioError> {
    if (scenario.map_width, scenario.map_height) != (grid.width(), grid.height()) {
        return Err(ScenarioError::MapSizeMismatch {
            expected_width: scenario.map_width,
            expected_height: scenario.map_height,
            width: grid.width(),
            height: grid.height(),
        });
    }
    let mut planner = DStarLite::new(grid.clone(), scenario.start, scenario.goal)?;
    let began = Instant::now();
    let dstar = planner.compute_shortest_path();
    let dstar_time = began.elapsed();
    let dstar_cost = match dstar {
        Ok(stats) => Some(stats.cost),
        Err(PlanError::Unreachable) => None,
        Err(other) => return Err(other.into()),
    };
    let began = Instant::now();
    let astar_result = astar.search(grid, scenario.start, scenario.goal);
    let astar_time = began.elapsed();
    let (astar_cost, astar_expansions) = match astar_result {
        Ok(result) => (Some(result.stats.cost), result.stats.expansions),
        Err(PlanError::Unreachable) => (None, 0),
        Err(other) => return Err(other.into()),
    };
    Ok(ScenarioOutcome {
        start: scenario.start,
        goal: scenario.goal,
        cost: dstar_cost,
        optimal_length: scenario.optimal_length,
        matches_optimal: dstar_cost
            .is_some_and(|cost| cost_matches_optimal_length(cost, scenario.optimal_length)),
        planners_agree: dstar_cost == astar_cost,
        dstar_expansions: planner.counters().expansions,
        dstar_time,
        astar_expansions,
        astar_time,
    })
}
