//! The hopnav supervisor: spawns the process graph by re-executing the hopnav binary, drives
//! the 10 fps frame clock (wall clock or lockstep), checks budgets from heartbeats, restarts
//! what fails, and writes a report.
//!
//! The pure parts, [`restart`] and [`scheduler`], are tested without processes; the system
//! tests in the workspace's `tests/` launch the real binary.
#![warn(missing_docs)]

mod child;
pub mod contact_log;
mod error;
pub mod fault_injector;
mod frame_loop;
mod hang_verdict;
pub mod hop_counter;
mod janitor;
mod launch;
pub mod mission;
pub mod mission_record;
pub mod mission_report;
mod progress;
pub mod relay;
pub mod report;
pub mod restart;
pub mod rover_motion;
pub mod scheduler;
pub mod signals;
mod slot;
mod status_line;
pub mod vo_pairs;

pub use error::LaunchError;
pub use launch::{LaunchOptions, LaunchOutcome, launch};
pub use mission_record::{Evaluation, MissionEvaluator, MissionRecord};
