//! VO → mapper, planner, evaluation: estimated poses.

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, SampleStamp};

/// A 6-DOF pose estimate of one robot.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::PoseEstimate")]
pub struct PoseEstimate {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Estimated `world_from_body`.
    pub world_from_body: Pose3,
    /// Confidence in [0, 1]; below 0.5 the pose is propagated, not measured.
    pub confidence: f64,
    /// Metric scale factor applied to the monocular translation (1 for stereo).
    pub scale: f64,
    /// Tracked features used for this estimate.
    pub tracked_features: u32,
    /// A [`Robot`](super::Robot) code.
    pub robot: u32,
    /// 1 if this frame became a keyframe.
    pub is_keyframe: u32,
    /// Reserved, zero.
    pub reserved: u32,
}

const _: () = assert!(size_of::<PoseEstimate>() == 120);
