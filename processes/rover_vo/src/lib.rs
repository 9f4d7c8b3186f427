//! Rover stereo visual odometry (issue #5) as plain library modules, without IPC:
//! sparse stereo matching ([`stereo`]), KLT tracking of world-anchored map points, 2-point
//! (IMU roll/pitch) or 3-point RANSAC with Gauss–Newton refinement of the reprojection error
//! ([`motion`]), keyframes and world-frame feature clouds with heights above the local ground
//! ([`ground`], [`pipeline`]). `hopnav-rover-vo-node` wraps it as the `rover_vo` process.
//!
//! Entry points for the CLI:
//! - `hopnav run rover_vo`: `hopnav_rover_vo_node::RoverVoProcess`; config check:
//!   `hopnav_rover_vo_node::rover_vo_section`.
//! - `hopnav eval rover-vo`: `hopnav_eval::rover_vo::run` (TUM files, ATE/RPE, drift %,
//!   top-view PNG), over [`run::run_traverse`].
//! - `hopnav bench rover-vo`: [`bench::run`] (p50/p99/max ms per stereo frame).
#![warn(missing_docs)]

pub mod bench;
pub mod config;
pub mod ground;
pub mod motion;
pub mod pipeline;
pub mod run;
pub mod simulate;
pub mod stereo;
mod stereo_edge;
mod stereo_patch;
