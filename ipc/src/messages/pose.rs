//! VO → mapper, planner, evaluation: estimated poses.

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, Robot, SampleStamp};

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

impl PoseEstimate {
    /// A VO's estimate of `robot`'s pose on the frame `frame` stamps (its index and simulated
    /// time; the transport adds the sequence and the publish time).
    pub fn from_vo(
        robot: Robot,
        frame: &SampleStamp,
        world_from_body: Pose3,
        confidence: f64,
        scale: f64,
        tracked_features: usize,
        is_keyframe: bool,
    ) -> Self {
        Self {
            stamp: frame.for_same_frame(),
            world_from_body,
            confidence,
            scale,
            tracked_features: tracked_features as u32,
            robot: robot.code(),
            is_keyframe: u32::from(is_keyframe),
            reserved: 0,
        }
    }
}
