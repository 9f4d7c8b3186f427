//! The cameras of hopnav, without IPC: the `[camera]` table ([`CameraSection`]: both cameras'
//! intrinsics, mounts and rendering options) and where each camera sits on its robot
//! ([`body_from_camera`]). The `camera` process (`hopnav-camera-node`) renders with them each
//! frame, straight into shared memory.
//!
//! Configuration lives in the `[camera]` table ([`CameraSection`]); the terrain in `[world]`.
#![warn(missing_docs)]

mod config;
mod mount;

pub use config::{CameraSection, MountConfig, check_world_section, from_world_error};
pub use mount::body_from_camera;
