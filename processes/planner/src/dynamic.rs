//! Traverse simulation in initially unknown terrain (`hopnav plan --dynamic R`).
//!
//! The agent knows nothing at the start (every cell unknown, planned through as free). Each
//! step it senses the true state of every cell within Euclidean radius `R` (and always its 8
//! neighbours, so it never steps into an unseen obstacle), hands the changed cells to the
//! planner, replans if any move cost changed, and moves one cell along its path.
//!
//! The same traverse runs with D* Lite (incremental) and with repeated A* (fresh search),
//! the latter under two replanning policies (and two tie-breaking rules, see
//! [`TieBreak`]):
//! - [`ReplanPolicy::EveryChange`]: search again whenever any cost changed (the naive baseline);
//! - [`ReplanPolicy::WhenPathBlocked`]: search again only when the rest of the current path
//!   got dearer. Revealing terrain only raises costs (unknown → obstacle or inflated), so an
//!   untouched path is still optimal: this is the fair, equally optimal baseline.

use std::time::{Duration, Instant};

use thiserror::Error;

use crate::astar::{AStar, SearchDirection, TieBreak};
use crate::cost::{Cost, edge_cost, path_cost};
use crate::dstar_lite::{DStarLite, KeyTieBreak};
use crate::grid::{Cell, CellChange, CellState, Grid, GridError};
use crate::plan::PlanError;

/// When repeated A* searches again.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReplanPolicy {
    /// After every step that changed any move cost.
    EveryChange,
    /// Only when the remaining path is blocked or got dearer.
    WhenPathBlocked,
}

/// Which planner drives the traverse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Algorithm {
    /// Incremental D* Lite.
    DStarLite {
        /// Key tie-breaking rule.
        tie_break: KeyTieBreak,
    },
    /// A fresh A* search per replan.
    RepeatedAStar {
        /// When to search again.
        policy: ReplanPolicy,
        /// Order of nodes with equal `f`.
        tie_break: TieBreak,
        /// Which end the search starts from.
        direction: SearchDirection,
    },
}

/// The planners [`compare`] runs, in order.
pub const COMPARED_ALGORITHMS: [Algorithm; 6] = [
    Algorithm::DStarLite {
        tie_break: KeyTieBreak::Paper,
    },
    Algorithm::DStarLite {
        tie_break: KeyTieBreak::TowardStart,
    },
    Algorithm::RepeatedAStar {
        policy: ReplanPolicy::EveryChange,
        tie_break: TieBreak::LargerG,
        direction: SearchDirection::Forward,
    },
    Algorithm::RepeatedAStar {
        policy: ReplanPolicy::WhenPathBlocked,
        tie_break: TieBreak::LargerG,
        direction: SearchDirection::Forward,
    },
    Algorithm::RepeatedAStar {
        policy: ReplanPolicy::EveryChange,
        tie_break: TieBreak::LargerG,
        direction: SearchDirection::Backward,
    },
    Algorithm::RepeatedAStar {
        policy: ReplanPolicy::EveryChange,
        tie_break: TieBreak::SmallerG,
        direction: SearchDirection::Forward,
    },
];

impl std::fmt::Display for Algorithm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (policy, tie_break, direction) = match self {
            Algorithm::DStarLite {
                tie_break: KeyTieBreak::Paper,
            } => return write!(f, "D* Lite"),
            Algorithm::DStarLite {
                tie_break: KeyTieBreak::TowardStart,
            } => return write!(f, "D* Lite (toward-start ties)"),
            Algorithm::RepeatedAStar {
                policy,
                tie_break,
                direction,
            } => (policy, tie_break, direction),
        };
        let policy = match policy {
            ReplanPolicy::EveryChange => "every change",
            ReplanPolicy::WhenPathBlocked => "path blocked",
        };
        let ties = match tie_break {
            TieBreak::LargerG => "",
            TieBreak::SmallerG => ", small-g ties",
        };
        let backward = match direction {
            SearchDirection::Forward => "",
            SearchDirection::Backward => ", backward",
        };
        write!(f, "A* ({policy}{ties}{backward})")
    }
}

/// Traverse parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DynamicConfig {
    /// Sensing radius in cells.
    pub sensor_radius_cells: u32,
    /// Step bound (the traverse fails past it); `None` means 4 × cell count.
    pub max_steps: Option<usize>,
}

/// Why a traverse could not be simulated.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum DynamicError {
    /// Start or goal outside the map.
    #[error(transparent)]
    Grid(#[from] GridError),
    /// The planner failed for a reason other than an unreachable goal.
    #[error(transparent)]
    Planner(#[from] PlanError),
    /// The planner asked for a move that is not allowed on the true map.
    #[error("planner moved from {from} to {to}, which the true map forbids")]
    IllegalMove {
        /// Cell moved from.
        from: Cell,
        /// Cell moved to.
        to: Cell,
    },
}

/// What one traverse did.
#[derive(Debug, Clone, PartialEq)]
pub struct TraverseResult {
    /// Planner used.
    pub algorithm: Algorithm,
    /// Whether the agent reached the goal.
    pub reached_goal: bool,
    /// Cells visited, start and end included.
    pub executed_path: Vec<Cell>,
    /// Cost of the executed path on the true map.
    pub executed_cost: Cost,
    /// Searches after the initial one.
    pub replans: u64,
    /// Expansions over all searches, initial included.
    pub expansions: u64,
    /// Time of the initial search.
    pub initial_plan_time: Duration,
    /// Time of each replan (D* Lite: cell update + ComputeShortestPath; A*: the search).
    pub replan_times: Vec<Duration>,
}

impl TraverseResult {
    /// Initial plan time plus all replan times.
    pub fn total_plan_time(&self) -> Duration {
        self.initial_plan_time + self.replan_times.iter().sum::<Duration>()
    }
}

/// Every planner of [`COMPARED_ALGORITHMS`] on the same traverse problem.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicComparison {
    /// One traverse per entry of [`COMPARED_ALGORITHMS`], same order.
    pub runs: Vec<TraverseResult>,
}

impl DynamicComparison {
    /// The traverse of `algorithm`, if it was run.
    pub fn run(&self, algorithm: Algorithm) -> Option<&TraverseResult> {
        self.runs.iter().find(|run| run.algorithm == algorithm)
    }
}

/// Runs every planner of [`COMPARED_ALGORITHMS`] from `start` to `goal` on the hidden map
/// `truth`.
pub fn compare(
    truth: &Grid,
    start: Cell,
    goal: Cell,
    config: &DynamicConfig,
) -> Result<DynamicComparison, DynamicError> {
    let runs = COMPARED_ALGORITHMS
        .iter()
        .map(|&algorithm| simulate(truth, start, goal, algorithm, config))
        .collect::<Result<_, _>>()?;
    Ok(DynamicComparison { runs })
}

/// Runs one traverse with `algorithm` from `start` to `goal` on the hidden map `truth`.
pub fn simulate(
    truth: &Grid,
    start: Cell,
    goal: Cell,
    algorithm: Algorithm,
    config: &DynamicConfig,
) -> Result<TraverseResult, DynamicError> {
    for cell in [start, goal] {
        if !truth.contains(cell) {
            return Err(GridError::OutOfBounds {
                cell,
                width: truth.width(),
                height: truth.height(),
            }
            .into());
        }
    }
    let unknown = Grid::new(truth.width(), truth.height(), CellState::Unknown)?;
    let mut traverse = Traverse::new(truth, start, algorithm, config);
    match algorithm {
        Algorithm::DStarLite { tie_break } => traverse.run_dstar(unknown, goal, tie_break)?,
        Algorithm::RepeatedAStar {
            policy,
            tie_break,
            direction,
        } => traverse.run_astar(
            unknown,
            goal,
            policy,
            AStar::configured(0, tie_break, direction),
        )?,
    }
    Ok(traverse.result)
}

struct Traverse<'a> {
    truth: &'a Grid,
    radius: u32,
    max_steps: usize,
    position: Cell,
    changes: Vec<CellChange>,
    result: TraverseResult,
}

impl<'a> Traverse<'a> {
    fn new(truth: &'a Grid, start: Cell, algorithm: Algorithm, config: &DynamicConfig) -> Self {
        Self {
            truth,
            radius: config.sensor_radius_cells,
            max_steps: config
                .max_steps
                .unwrap_or_else(|| truth.cell_count().saturating_mul(4)),
            position: start,
            changes: Vec::new(),
            result: TraverseResult {
                algorithm,
                reached_goal: false,
                executed_path: vec![start],
                executed_cost: 0,
                replans: 0,
                expansions: 0,
                initial_plan_time: Duration::ZERO,
                replan_times: Vec::new(),
            },
        }
    }

    fn run_dstar(
        &mut self,
        unknown: Grid,
        goal: Cell,
        tie_break: KeyTieBreak,
    ) -> Result<(), DynamicError> {
        let mut planner = DStarLite::with_tie_break(unknown, self.position, goal, tie_break)?;
        self.sense(planner.grid());
        let began = Instant::now();
        planner.update_cells(&self.changes)?;
        let initial = planner.compute_shortest_path();
        self.result.initial_plan_time = began.elapsed();
        let mut reachable = accept_unreachable(initial)?;
        while reachable && self.position != goal && self.steps() < self.max_steps {
            let Some(next) = planner.next_step() else {
                break;
            };
            self.step_to(next)?;
            planner.move_start(next)?;
            self.sense(planner.grid());
            if self.changes.is_empty() {
                continue;
            }
            let began = Instant::now();
            if planner.update_cells(&self.changes)? > 0 {
                let outcome = planner.compute_shortest_path();
                self.result.replan_times.push(began.elapsed());
                self.result.replans += 1;
                reachable = accept_unreachable(outcome)?;
            }
        }
        self.result.expansions = planner.counters().expansions;
        self.result.reached_goal = self.position == goal;
        Ok(())
    }

    fn run_astar(
        &mut self,
        mut known: Grid,
        goal: Cell,
        policy: ReplanPolicy,
        mut astar: AStar,
    ) -> Result<(), DynamicError> {
        self.sense(&known);
        self.apply_changes(&mut known)?;
        let began = Instant::now();
        let initial = astar.search(&known, self.position, goal);
        self.result.initial_plan_time = began.elapsed();
        let mut plan = match initial {
            Ok(found) => {
                self.result.expansions += found.stats.expansions;
                Some((found.path, found.stats.cost, 0_usize))
            }
            Err(PlanError::Unreachable) => None,
            Err(other) => return Err(other.into()),
        };
        while let Some((path, remaining_cost, index)) = plan.as_mut() {
            if self.position == goal || self.steps() >= self.max_steps {
                break;
            }
            let Some(&next) = path.get(*index + 1) else {
                break;
            };
            let step_cost = self.step_to(next)?;
            *index += 1;
            *remaining_cost = remaining_cost.saturating_sub(step_cost);
            self.sense(&known);
            if self.apply_changes(&mut known)? == 0 {
                continue;
            }
            let must_replan = match policy {
                ReplanPolicy::EveryChange => true,
                ReplanPolicy::WhenPathBlocked => {
                    path_cost(&known, &path[*index..]) != Some(*remaining_cost)
                }
            };
            if !must_replan {
                continue;
            }
            let began = Instant::now();
            let outcome = astar.search(&known, self.position, goal);
            self.result.replan_times.push(began.elapsed());
            self.result.replans += 1;
            plan = match outcome {
                Ok(found) => {
                    self.result.expansions += found.stats.expansions;
                    Some((found.path, found.stats.cost, 0))
                }
                Err(PlanError::Unreachable) => None,
                Err(other) => return Err(other.into()),
            };
        }
        self.result.reached_goal = self.position == goal;
        Ok(())
    }

    fn steps(&self) -> usize {
        self.result.executed_path.len() - 1
    }

    /// Moves the agent, checking the move against the true map.
    fn step_to(&mut self, next: Cell) -> Result<Cost, DynamicError> {
        let cost = edge_cost(self.truth, self.position, next).ok_or(DynamicError::IllegalMove {
            from: self.position,
            to: next,
        })?;
        self.result.executed_cost += cost;
        self.result.executed_path.push(next);
        self.position = next;
        Ok(cost)
    }

    /// Fills `self.changes` with every sensed cell whose known state differs from the truth.
    fn sense(&mut self, known: &Grid) {
        self.changes.clear();
        let reach = self.radius.max(1);
        let radius_squared = u64::from(self.radius) * u64::from(self.radius);
        let (cx, cy) = (self.position.x, self.position.y);
        let y_range = cy.saturating_sub(reach)..=cy.saturating_add(reach).min(known.height() - 1);
        for y in y_range {
            let x_range =
                cx.saturating_sub(reach)..=cx.saturating_add(reach).min(known.width() - 1);
            for x in x_range {
                let dx = u64::from(x.abs_diff(cx));
                let dy = u64::from(y.abs_diff(cy));
                let adjacent = dx <= 1 && dy <= 1;
                if !adjacent && dx * dx + dy * dy > radius_squared {
                    continue;
                }
                let cell = Cell::new(x, y);
                let (Some(state), Some(extra_cost)) =
                    (self.truth.state(cell), self.truth.extra_cost(cell))
                else {
                    continue;
                };
                if known.state(cell) != Some(state) || known.extra_cost(cell) != Some(extra_cost) {
                    self.changes.push(CellChange::new(cell, state, extra_cost));
                }
            }
        }
    }

    /// Applies `self.changes` to `known`; returns how many changed a move cost.
    fn apply_changes(&self, known: &mut Grid) -> Result<usize, GridError> {
        let mut cost_changes = 0;
        for change in &self.changes {
            if known.apply(change)? {
                cost_changes += 1;
            }
        }
        Ok(cost_changes)
    }
}

/// `Ok(true)` for a found path, `Ok(false)` for an unreachable goal, `Err` otherwise.
fn accept_unreachable<T>(outcome: Result<T, PlanError>) -> Result<bool, PlanError> {
    match outcome {
        Ok(_) => Ok(true),
        Err(PlanError::Unreachable) => Ok(false),
        Err(other) => Err(other),
    }
}
