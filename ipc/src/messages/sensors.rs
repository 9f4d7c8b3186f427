//! physics → camera, VO and evaluation: body states, altimeter, IMU.

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, SampleStamp, Vec3};

/// Ground-truth state of one rigid body. Evaluation and rendering only: VO, mapper and planner
/// never read it.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::BodyState")]
pub struct BodyState {
    /// `world_from_body`.
    pub world_from_body: Pose3,
    /// Linear velocity in the world frame, m/s.
    pub linear_velocity_mps: Vec3,
    /// Angular velocity in the world frame, rad/s.
    pub angular_velocity_radps: Vec3,
    /// 1 while the body touches the ground, else 0.
    pub in_contact: u32,
    /// Collisions so far with rocks the body cannot climb (the rover; 0 for the jumper).
    pub collisions: u32,
}

/// Ground truth of both robots for one frame.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::BodyStates")]
pub struct BodyStates {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// The jumping robot.
    pub jumper: BodyState,
    /// The ground rover.
    pub rover: BodyState,
}

/// The jumper's barometric altimeter.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::AltimeterSample")]
pub struct AltimeterSample {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Measured static pressure, pascal.
    pub pressure_pa: f64,
    /// Altitude derived from pressure (noisy), metres above the datum.
    pub altitude_m: f64,
    /// One-sigma noise of `altitude_m`, metres.
    pub altitude_sigma_m: f64,
}

/// The rover's inertial measurement unit.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::ImuSample")]
pub struct ImuSample {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Attitude estimate `world_from_imu` as a unit quaternion `[x, y, z, w]` (yaw drifts).
    pub attitude_xyzw: [f64; 4],
    /// Angular rate in the IMU frame, rad/s.
    pub angular_rate_radps: Vec3,
    /// Specific force in the IMU frame, m/s².
    pub specific_force_mps2: Vec3,
}

impl Default for ImuSample {
    fn default() -> Self {
        Self {
            stamp: SampleStamp::default(),
            attitude_xyzw: [0.0, 0.0, 0.0, 1.0],
            angular_rate_radps: [0.0; 3],
            specific_force_mps2: [0.0; 3],
        }
    }
}

const _: () = assert!(size_of::<BodyState>() == 112);
const _: () = assert!(size_of::<BodyStates>() == 256);
const _: () = assert!(size_of::<AltimeterSample>() == 56);
const _: () = assert!(size_of::<ImuSample>() == 112);
