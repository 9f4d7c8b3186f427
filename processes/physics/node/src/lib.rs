//! The `physics` node: [`PhysicsProcess`] wires the simulation of `hopnav-physics` to its
//! iceoryx2 topics (stage 0 of every frame: drive commands and jump requests in; ground truth,
//! altimeter, IMU, hop launches and the resumable state out). [`physics_section`] reads and
//! checks `[physics]` as the process does.
//!
//! The simulation itself has no IPC and lives in `hopnav-physics`; this crate only binds it.
#![warn(missing_docs)]

mod process;

pub use process::{BuildError, PhysicsProcess, PhysicsProcessError, physics_section};
