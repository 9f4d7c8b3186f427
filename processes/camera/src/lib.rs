//! The cameras of hopnav, without IPC: the `[camera]` table ([`CameraSection`]: both cameras'
//! intrinsics and mounts, defined in `hopnav_robot::camera`, and the rendering options). The
//! `camera` process (`hopnav-camera-node`) renders with them each frame, straight into shared
//! memory.
//!
//! Configuration lives in the `[camera]` table ([`CameraSection`]); the terrain in `[world]`.
#![warn(missing_docs)]

mod config;

pub use config::{CameraSection, check_world_section, from_world_error};
