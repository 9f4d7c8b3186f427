//! The `rover_vo` node: [`RoverVoProcess`] runs the stereo pipeline of `hopnav-rover-vo` on the
//! rover's stereo stream and publishes the pose every frame and a feature cloud per keyframe
//! over iceoryx2. [`rover_vo_section`] reads and checks `[rover_vo]` as the process does;
//! [`rig_from_header`] turns a stereo image header into the pipeline's rig.
//!
//! The visual odometry itself has no IPC and lives in `hopnav-rover-vo`; this crate only binds
//! it.
#![warn(missing_docs)]

mod process;

pub use process::{RoverVoProcess, RoverVoProcessError, rig_from_header, rover_vo_section};
