//! The `planner` node: [`PlannerProcess`] feeds the mapper's cells and the rover's pose to the
//! mission navigator of `hopnav-planner` and publishes drive commands, jump requests and the
//! path over iceoryx2. [`planner_section`] reads and checks `[planner]` as the process does.
//!
//! The planning itself has no IPC and lives in `hopnav-planner`; this crate only binds it.
#![warn(missing_docs)]

mod process;

pub use process::{PlannerProcess, PlannerProcessError, PlannerSection, planner_section};
