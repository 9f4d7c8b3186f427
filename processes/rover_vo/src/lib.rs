//! Rover stereo visual odometry (issue #5) as plain library modules, without IPC:
//! sparse stereo matching, KLT tracking, 2-point (IMU roll/pitch) or 3-point RANSAC motion with
//! Gauss–Newton refinement of the reprojection error, keyframes, and world-frame feature
//! clouds with heights above the local ground. [`process`] wraps it as the `rover_vo` process.
#![warn(missing_docs)]

pub mod bench;
pub mod config;
pub mod eval;
pub mod ground;
pub mod motion;
pub mod pipeline;
pub mod process;
pub mod simulate;
pub mod stereo;
