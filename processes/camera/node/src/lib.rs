//! The `camera` node: each frame [`CameraProcess`] takes the ground-truth poses physics
//! published, renders the jumper's rear-facing mono camera and the rover's stereo pair with the
//! world crate's rasterizer, drawing straight into loaned iceoryx2 samples, and publishes them
//! with their intrinsics, mount and frame index.
//!
//! Configuration lives in the `[camera]` table (`hopnav_camera::CameraSection`); the terrain in
//! `[world]`.
#![warn(missing_docs)]

mod process;

pub use process::CameraProcess;

/// Why the camera process failed: the shared node plumbing, or the world could not be made.
pub type CameraError = hopnav_ipc::node_error::NodeError<WorldUnavailable>;

/// The world (or its render scene) could not be generated.
#[derive(Debug, thiserror::Error)]
#[error("world: {0}")]
pub struct WorldUnavailable(#[from] pub hopnav_world::WorldError);
