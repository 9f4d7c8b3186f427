//! Grid path planning for the hopnav rover.
//!
//! The planner process (`hopnav-planner-node`) replans whenever the mapper publishes changed
//! cells or the rover moves. This crate holds the algorithms only (no IPC), so tests and
//! benchmarks call them directly:
//!
//! - [`grid`]: the occupancy grid (free / obstacle / unknown, plus extra inflation cost).
//! - [`cost`]: integer move costs (1000 straight, 1414 diagonal, no corner cutting) and the
//!   octile heuristic.
//! - [`dstar_lite`]: the optimized D* Lite of Koenig & Likhachev (2002, Fig. 4).
//! - [`astar`]: A*, used as the repeated-A* baseline.
//! - [`dijkstra`]: an independent Dijkstra oracle for tests.
//! - [`movingai`]: MovingAI `.map` / `.scen` parsers; [`scenario`] solves their scenarios.
//! - [`dynamic`]: the "map starts unknown, revealed within radius R" traverse simulation.
//! - [`bench`]: own-harness benchmarks (expansion ratio, replan time p50/p99/max).
//!
//! # Example
//!
//! ```
//! use hopnav_planner::{Cell, CellChange, CellState, DStarLite, Grid};
//!
//! let grid = Grid::new(16, 16, CellState::Unknown)?;
//! let mut planner = DStarLite::new(grid, Cell::new(0, 0), Cell::new(15, 0))?;
//! let first = planner.compute_shortest_path()?;
//! assert_eq!(first.cost, 15 * 1000);
//!
//! // The mapper reports an obstacle on the straight line; replan incrementally.
//! planner.update_cells(&[CellChange::new(Cell::new(7, 0), CellState::Obstacle, 0)])?;
//! let replan = planner.compute_shortest_path()?;
//! assert_eq!(replan.cost, 13 * 1000 + 2 * 1414);
//! let path = planner.path().ok_or("no path")?;
//! assert_eq!(path.first(), Some(&Cell::new(0, 0)));
//! assert_eq!(path.last(), Some(&Cell::new(15, 0)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod astar;
pub mod bench;
pub mod cost;
pub mod dijkstra;
pub mod dstar_lite;
pub mod dynamic;
pub mod grid;
pub mod mission;
pub mod movingai;
pub mod plan;
pub mod queue;
pub mod random_map;
pub mod rng;
pub mod scenario;

pub use astar::{AStar, AStarResult, SearchDirection, TieBreak};
pub use cost::{Cost, DIAGONAL_COST, INFINITE_COST, STRAIGHT_COST, octile_distance};
pub use dijkstra::dijkstra_cost;
pub use dstar_lite::{DStarLite, KeyTieBreak};
pub use grid::{Cell, CellChange, CellState, Grid, GridError};
pub use plan::{PlanError, PlanStats, PlannerCounters};
