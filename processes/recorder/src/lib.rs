//! The `recorder` process (`hopnav launch --export-dataset DIR`): writes what the sensors
//! produced, in formats any external VO tool reads (DESIGN.md §6):
//!
//! - `jumper_cam/NNNNNN.pgm` + `jumper_cam/index.csv` (`frame,t_s,file`)
//! - `rover_left/…`, `rover_right/…` likewise for the stereo pair
//! - `cameras.json`: intrinsics (and stereo baseline) from the image headers
//! - `altimeter.csv`, `imu.csv`
//! - `groundtruth_jumper.tum`, `groundtruth_rover.tum` (`t tx ty tz qx qy qz qw`)
//!
//! It only reads shared memory; a sample that fails validation is counted, not written.
#![warn(missing_docs)]

pub mod formats;
mod recorder;
mod writers;

pub use recorder::Recorder;

/// Why the recorder failed.
#[derive(Debug, thiserror::Error)]
pub enum RecorderError {
    /// The configuration could not be loaded.
    #[error(transparent)]
    Config(#[from] hopnav_config::ConfigError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] hopnav_ipc::transport::OpenError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] hopnav_ipc::transport::ReceiveError),
    /// Writing the dataset failed.
    #[error("dataset {path}: {source}")]
    Io {
        /// File or folder.
        path: String,
        /// OS error.
        source: std::io::Error,
    },
    /// No output folder was configured.
    #[error("config key recorder.dir is empty: pass --export-dataset DIR")]
    NoDirectory,
}
