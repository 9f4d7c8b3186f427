//! The `jumper_vo` node: [`JumperVoProcess`] runs the pipeline of `hopnav-jumper-vo` on the
//! jumper's camera stream and publishes the pose every frame and a feature cloud per keyframe
//! over iceoryx2. [`jumper_vo_section`] reads and checks `[jumper_vo]` as the process does.
//!
//! The visual odometry itself has no IPC and lives in `hopnav-jumper-vo`; this crate only
//! binds it.
#![warn(missing_docs)]

mod process;

pub use process::{JumperVoProcess, JumperVoProcessError, jumper_vo_section};
