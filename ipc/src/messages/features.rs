//! VO → mapper: world-frame feature clouds, a `[FeaturePoint]` slice with a [`CloudHeader`].

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, SampleStamp};

/// User header of a feature cloud sample.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::CloudHeader")]
pub struct CloudHeader {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// The producer's viewpoint, from which the mapper takes the direction of each point's
    /// depth error: the camera at the keyframe (for the jumper, the keyframe that closed the
    /// triangulation, shared by every point of the cloud; their depth sigmas are ranges from
    /// it).
    pub world_from_camera: Pose3,
    /// Points in the slice.
    pub point_count: u32,
    /// A [`Robot`](super::Robot) code: who observed the points.
    pub robot: u32,
    /// Keyframe counter of the producer.
    pub keyframe_index: u64,
}

/// One triangulated feature in the world frame.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::FeaturePoint")]
pub struct FeaturePoint {
    /// Position in the world frame, metres.
    pub position_m: [f32; 3],
    /// Height above the local ground estimate, metres (NaN if unknown).
    pub height_above_ground_m: f32,
    /// Track identifier, stable while the feature is tracked.
    pub track_id: u32,
    /// Standard deviation of the depth estimate, metres.
    pub depth_sigma_m: f32,
}

impl FeaturePoint {
    /// True when the position and sigma are finite (height may be NaN = unknown).
    pub fn is_valid(&self) -> bool {
        self.position_m.iter().all(|value| value.is_finite())
            && self.depth_sigma_m.is_finite()
            && !self.height_above_ground_m.is_infinite()
    }
}

const _: () = assert!(size_of::<CloudHeader>() == 104);
const _: () = assert!(size_of::<FeaturePoint>() == 24);
