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

/// Why the camera process failed.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// The configuration could not be loaded or is invalid.
    #[error(transparent)]
    Config(#[from] hopnav_config::ConfigError),
    /// The world could not be generated.
    #[error("world: {0}")]
    World(#[from] hopnav_world::WorldError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] hopnav_ipc::transport::OpenError),
    /// A sample could not be sent.
    #[error(transparent)]
    Send(#[from] hopnav_ipc::transport::SendError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] hopnav_ipc::transport::ReceiveError),
}
