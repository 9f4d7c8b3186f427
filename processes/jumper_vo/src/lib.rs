//! Jumper visual odometry (paper §2) as plain library modules, without IPC.
#![warn(missing_docs)]

pub mod ballistic;
pub mod bench;
pub mod cloud;
pub mod config;
pub mod flight_ba;
pub mod frames;
pub mod output;
pub mod pipeline;
pub mod rng;
pub mod run;
pub mod scale;
pub mod simulate;
pub mod spin;
pub mod tracks;
pub mod trajectory;
