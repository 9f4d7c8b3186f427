//! # hopnav-physics
//!
//! The physics of the hopnav simulation, as plain modules without IPC (the `physics` process,
//! `hopnav-physics-node`, wraps them):
//!
//! - [`PhysicsConfig`]: serde configuration (paper Table 1 defaults) with `validate()`;
//! - [`colliders`]: terrain heightfield and rock convex hulls from a [`hopnav_world::World`];
//! - [`jumper`]: the jumping robot (dynamic rapier cube) and its hop cycle;
//! - [`hop_planner`]: launch parameters toward a target within the configured limits;
//! - [`rover`]: the four-wheel-steered rover (kinematic chassis, wheel-contact queries);
//! - [`sensors`]: barometric altimeter and IMU; [`noise`]: seeded PRNG and Box–Muller;
//! - [`PhysicsSim`] ([`sim`]): one 100 ms frame per [`PhysicsSim::step_frame`];
//! - [`SimSnapshot`] and [`PhysicsSim::resume_from`]: a restarted physics continues the
//!   simulation; [`wire`] turns it into the message it resumes from and back;
//! - [`bench`]: an own-harness step-time benchmark.
//!
//! # Conventions
//! World: metres, **z up** (as in `hopnav-world`), gravity along −z. Body frames: x forward,
//! y left, z up. Quaternions `[x, y, z, w]`, `world_from_body`. Angles in radians. Rapier runs
//! in f32; state and outputs are f64.
//!
//! # Determinism
//! Same world, config, seed and inputs → bitwise-identical [`FrameOutputs`] (tested).

#![warn(missing_docs)]

pub mod bench;
pub mod colliders;
pub mod config;
pub mod error;
pub mod frame;
pub mod hop_planner;
pub mod jumper;
pub mod math;
pub mod noise;
pub mod rover;
pub mod sensors;
pub mod sim;
pub mod wire;

pub use config::PhysicsConfig;
pub use error::{ConfigError, PhysicsError};
pub use frame::{
    AltimeterSample, BlockReason, BodyState, DriveCommand, FrameInputs, FrameOutputs, HopRecord,
    HopRequest, HopState, ImuSample, JumperStatus, RoverMode, RoverStatus,
};
pub use sim::{PhysicsSim, ResumeError, SimSnapshot};
