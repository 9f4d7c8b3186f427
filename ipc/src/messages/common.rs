//! Building blocks shared by many messages.

use iceoryx2::prelude::ZeroCopySend;

use super::coded_enum;

/// Identity and timing of one sample; the first field of every message.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::SampleStamp")]
pub struct SampleStamp {
    /// Frame of the 10 fps clock this sample belongs to.
    pub frame_index: u64,
    /// Per-publisher counter, strictly increasing; consumers reject repeats and regressions.
    pub sequence: u64,
    /// Simulated time of the frame, nanoseconds since mission start.
    pub sim_time_ns: u64,
    /// CLOCK_MONOTONIC when the sample was published.
    pub publish_stamp_ns: u64,
}

impl SampleStamp {
    /// A stamp for a sample about the same frame as this one: its frame index and simulated
    /// time; the transport adds the sequence and the publish time.
    pub fn for_same_frame(&self) -> Self {
        Self {
            frame_index: self.frame_index,
            sim_time_ns: self.sim_time_ns,
            ..Self::default()
        }
    }
}

/// A 3-vector in metres, metres per second, or radians per second as the field name says.
pub type Vec3 = [f64; 3];

/// A rigid transform `parent_from_body`: position of the body origin in the parent frame and
/// the body orientation as a unit quaternion `[x, y, z, w]`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::Pose3")]
pub struct Pose3 {
    /// Position of the body origin in the parent frame, metres.
    pub position_m: Vec3,
    /// Orientation as a unit quaternion `[x, y, z, w]`.
    pub orientation_xyzw: [f64; 4],
}

impl Default for Pose3 {
    fn default() -> Self {
        Self {
            position_m: [0.0; 3],
            orientation_xyzw: [0.0, 0.0, 0.0, 1.0],
        }
    }
}

impl Pose3 {
    /// True when every number is finite and the quaternion is unit length within 1e-3.
    pub fn is_valid(&self) -> bool {
        let finite = self
            .position_m
            .iter()
            .chain(self.orientation_xyzw.iter())
            .all(|value| value.is_finite());
        let norm_sq: f64 = self.orientation_xyzw.iter().map(|q| q * q).sum();
        finite && (norm_sq - 1.0).abs() < 2e-3
    }

    /// The pose as an isometry (the quaternion is renormalized).
    pub fn to_isometry(&self) -> nalgebra::Isometry3<f64> {
        let [x, y, z, w] = self.orientation_xyzw;
        let [px, py, pz] = self.position_m;
        nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::new(px, py, pz),
            nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)),
        )
    }

    /// The pose of an isometry.
    pub fn from_isometry(isometry: &nalgebra::Isometry3<f64>) -> Self {
        let q = isometry.rotation.coords;
        Self {
            position_m: isometry.translation.vector.into(),
            orientation_xyzw: [q.x, q.y, q.z, q.w],
        }
    }
}

coded_enum! {
    /// Which robot a sample is about.
    Robot {
        /// The hopping scout with the rear-facing mono camera and the altimeter.
        Jumper = 1,
        /// The ground rover with the stereo camera and the IMU.
        Rover = 2,
    }
}

const _: () = assert!(size_of::<SampleStamp>() == 32);
const _: () = assert!(size_of::<Pose3>() == 56);
