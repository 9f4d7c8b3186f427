//! VO → mapper: world-frame feature clouds, a `[FeaturePoint]` slice with a [`CloudHeader`].

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, Robot, SampleStamp};

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

impl CloudHeader {
    /// The header of a keyframe cloud: `robot` saw `point_count` points from
    /// `world_from_camera`, in the frame `frame` stamps (its index and simulated time; the
    /// transport adds the sequence and the publish time).
    pub fn keyframe(
        robot: Robot,
        frame: &SampleStamp,
        world_from_camera: Pose3,
        point_count: usize,
        keyframe_index: u64,
    ) -> Self {
        Self {
            stamp: frame.for_same_frame(),
            world_from_camera,
            point_count: point_count as u32,
            robot: robot.code(),
            keyframe_index,
        }
    }
}

impl FeaturePoint {
    /// A point from a VO's double-precision estimate, narrowed to the wire's `f32`; an
    /// unknown height (`None`) is sent as NaN.
    pub fn from_estimate(
        position_m: [f64; 3],
        height_above_ground_m: Option<f64>,
        track_id: u32,
        depth_sigma_m: f64,
    ) -> Self {
        Self {
            position_m: position_m.map(|coordinate| coordinate as f32),
            height_above_ground_m: height_above_ground_m.map_or(f32::NAN, |h| h as f32),
            track_id,
            depth_sigma_m: depth_sigma_m as f32,
        }
    }

    /// True when the position and sigma are finite (height may be NaN = unknown).
    pub fn is_valid(&self) -> bool {
        self.position_m.iter().all(|value| value.is_finite())
            && self.depth_sigma_m.is_finite()
            && !self.height_above_ground_m.is_infinite()
    }
}

const _: () = assert!(size_of::<CloudHeader>() == 104);
const _: () = assert!(size_of::<FeaturePoint>() == 24);
