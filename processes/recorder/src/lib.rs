//! The `recorder` process. `hopnav launch --record FILE.mcap` writes every topic into one MCAP
//! file in hopnav's own encoding ([`recording`]). `hopnav launch --export-dataset DIR` writes
//! what the sensors produced, in formats any external VO tool reads (DESIGN.md §6):
//!
//! - `jumper_cam/NNNNNN.pgm` + `jumper_cam/index.csv` (`frame,t_s,file`)
//! - `rover_left/…`, `rover_right/…` likewise for the stereo pair
//! - `cameras.json`: intrinsics (and stereo baseline) from the image headers
//! - `altimeter.csv`, `imu.csv`
//! - `groundtruth_jumper.tum`, `groundtruth_rover.tum` (`t tx ty tz qx qy qz qw`)
//!
//! `hopnav launch --viewer [ADDR]` serves the recording's Foxglove channels live ([`viewer`]).
//!
//! It only reads shared memory; a sample that fails validation is counted, not written. It runs
//! in the last stage of the frame, so in lockstep it reads every sample of every frame.
#![warn(missing_docs)]

mod dataset;
mod error_chain;
pub mod formats;
mod foxglove_out;
mod recorder;
pub mod recording;
mod taps;
pub mod viewer;
mod views;
mod writers;

pub use recorder::Recorder;
pub use recording::{RecordingSummary, check_writable};
pub use viewer::{DEFAULT_VIEWER_ADDRESS, ViewerError, check_viewer_address};

/// Why the recorder failed: a failure every node shares (its config, its ports), or one of
/// its own ([`RecordingError`]).
pub type RecorderError = hopnav_ipc::node_error::NodeError<RecordingError>;

/// The recorder's own failures: where and how it writes what it records.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// Writing the dataset failed.
    #[error("dataset {path}: {source}")]
    Io {
        /// File or folder.
        path: String,
        /// OS error.
        source: std::io::Error,
    },
    /// Neither a dataset folder, a recording file nor a viewer address was configured.
    #[error(
        "config keys recorder.dir, recorder.mcap and recorder.viewer are empty: pass --export-dataset DIR, --record FILE.mcap or --viewer"
    )]
    NoOutput,
    /// The live view could not start.
    #[error(transparent)]
    Viewer(#[from] ViewerError),
    /// The recording file cannot be created or written.
    #[error("cannot write the recording {path}: {source}")]
    Unwritable {
        /// The file.
        path: String,
        /// OS error.
        source: std::io::Error,
    },
    /// The MCAP writer refused a record.
    #[error("recording {path}: {reason}")]
    Mcap {
        /// The file.
        path: String,
        /// The writer's error.
        reason: String,
    },
}
