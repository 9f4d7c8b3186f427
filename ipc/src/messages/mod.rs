//! Every message of the process graph (DESIGN.md §2), split by direction of flow.
//!
//! All types are `#[repr(C)]`, [`ZeroCopySend`](iceoryx2::prelude::ZeroCopySend) with an explicit
//! type name, and hold no pointers, so they live in shared memory as they are. Enumerations
//! travel as `u32` codes with checked conversions: an invalid discriminant read from shared
//! memory would be undefined behaviour, an unknown code is just a rejected sample.
//! Each file asserts its types' sizes at compile time, so a layout change is a deliberate edit.
//! Such an edit also bumps the type's layout version in [`crate::wire`], which names it in
//! recordings.

mod clock;
mod commands;
mod common;
mod features;
mod heartbeat;
mod image;
mod map;
mod path;
mod physics_state;
mod pose;
mod sensors;

pub use clock::{ClockMode, FrameCommand, FrameTick};
pub use commands::{Control, ControlKind, DriveCommand, DriveDirection, HopLaunch, JumpRequest};
pub use common::{Pose3, Robot, SampleStamp, Vec3};
pub use features::{CloudHeader, FeaturePoint};
pub use heartbeat::{Heartbeat, NO_FRAME, ProcessState};
pub use image::{CameraIntrinsics, ImageHeader, PixelFormat};
pub use map::{CellClass, CellUpdate, MapHeader};
pub use path::{MissionState, PathHeader, PathPoint};
pub use physics_state::{BlockCode, HopPhase, JumperCycle, NoiseState, PhysicsState, RoverDrive};
pub use pose::{PoseEstimate, PoseQuality};
pub use sensors::{AltimeterSample, BodyState, BodyStates, ImuSample};

/// Declares a `u32`-coded enumeration with a checked `from_code`.
macro_rules! coded_enum {
    ($(#[$meta:meta])* $name:ident { $($(#[$vmeta:meta])* $variant:ident = $code:expr),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vmeta])* $variant = $code),+
        }

        impl $name {
            /// The wire code of this value.
            pub const fn code(self) -> u32 {
                self as u32
            }

            /// The value of a wire code, `None` for an unknown code.
            pub const fn from_code(code: u32) -> Option<Self> {
                match code {
                    $($code => Some(Self::$variant),)+
                    _ => None,
                }
            }
        }
    };
}
pub(crate) use coded_enum;
