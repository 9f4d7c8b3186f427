//! What the rover is doing, as its true velocities show it, and how its mission time splits
//! between driving, reversing, turning on the spot and standing still.

use hopnav_ipc::messages::BodyState;
use serde::{Deserialize, Serialize};

/// A forward or backward ground speed above this is driving, metres per second.
const MOVING_MPS: f64 = 0.02;
/// Below `MOVING_MPS`, a yaw rate above this is a turn on the spot, radians per second.
const TURNING_RADPS: f64 = 0.02;

/// The rover's motion over a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoverMotion {
    /// Driving front first.
    Driving,
    /// Driving rear first (backing away from something).
    Reversing,
    /// Turning on the spot.
    Turning,
    /// Neither moving nor turning.
    Still,
    /// Not seen moving yet.
    #[default]
    Unknown,
}

impl RoverMotion {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Driving => "driving",
            Self::Reversing => "reversing",
            Self::Turning => "turning",
            Self::Still => "still",
            Self::Unknown => "unknown",
        }
    }
}

/// The rover's motion in this frame, and its heading (radians).
pub fn motion_of(rover: &BodyState) -> (RoverMotion, f64) {
    let world_from_body = rover.world_from_body.to_isometry();
    let (_, _, yaw_rad) = world_from_body.rotation.euler_angles();
    let [vx, vy, _] = rover.linear_velocity_mps;
    let forward_mps = vx * yaw_rad.cos() + vy * yaw_rad.sin();
    let yaw_rate_radps = rover.angular_velocity_radps[2];
    let motion = if forward_mps > MOVING_MPS {
        RoverMotion::Driving
    } else if forward_mps < -MOVING_MPS {
        RoverMotion::Reversing
    } else if yaw_rate_radps.abs() > TURNING_RADPS {
        RoverMotion::Turning
    } else {
        RoverMotion::Still
    };
    (motion, yaw_rad)
}

/// Seconds of the mission the rover spent in each motion (the frames up to B, or to the end).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct MotionTimes {
    /// Driving front first, seconds.
    pub driving_s: f64,
    /// Driving rear first, seconds.
    pub reversing_s: f64,
    /// Turning on the spot, seconds.
    pub turning_s: f64,
    /// Neither moving nor turning, seconds.
    pub still_s: f64,
}

impl MotionTimes {
    /// Adds `dt_s` to the bucket of `motion` (an unknown motion counts as still).
    pub fn add(&mut self, motion: RoverMotion, dt_s: f64) {
        let bucket = match motion {
            RoverMotion::Driving => &mut self.driving_s,
            RoverMotion::Reversing => &mut self.reversing_s,
            RoverMotion::Turning => &mut self.turning_s,
            RoverMotion::Still | RoverMotion::Unknown => &mut self.still_s,
        };
        *bucket += dt_s;
    }

    /// All four, seconds.
    pub fn total_s(&self) -> f64 {
        self.driving_s + self.reversing_s + self.turning_s + self.still_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopnav_ipc::messages::Pose3;

    fn rover(heading_rad: f64, velocity_mps: [f64; 2], yaw_rate_radps: f64) -> BodyState {
        let half = 0.5 * heading_rad;
        BodyState {
            world_from_body: Pose3 {
                position_m: [0.0; 3],
                orientation_xyzw: [0.0, 0.0, half.sin(), half.cos()],
            },
            linear_velocity_mps: [velocity_mps[0], velocity_mps[1], 0.0],
            angular_velocity_radps: [0.0, 0.0, yaw_rate_radps],
            in_contact: 1,
            collisions: 0,
        }
    }

    #[test]
    fn the_motion_follows_the_speed_along_the_heading_then_the_yaw_rate() {
        let north = std::f64::consts::FRAC_PI_2;
        assert_eq!(
            motion_of(&rover(north, [0.0, 0.3], 0.5)).0,
            RoverMotion::Driving
        );
        assert_eq!(
            motion_of(&rover(north, [0.0, -0.3], 0.0)).0,
            RoverMotion::Reversing
        );
        // Sliding sideways is not driving.
        assert_eq!(
            motion_of(&rover(north, [0.3, 0.0], 0.0)).0,
            RoverMotion::Still
        );
        assert_eq!(
            motion_of(&rover(north, [0.0, 0.0], -0.3)).0,
            RoverMotion::Turning
        );
        assert!((motion_of(&rover(north, [0.0; 2], 0.0)).1 - north).abs() < 1e-9);
    }

    #[test]
    fn the_times_add_up_per_motion() {
        let mut times = MotionTimes::default();
        for motion in [
            RoverMotion::Driving,
            RoverMotion::Turning,
            RoverMotion::Unknown,
        ] {
            times.add(motion, 0.1);
        }
        assert!((times.driving_s - 0.1).abs() < 1e-12);
        assert!((times.turning_s - 0.1).abs() < 1e-12);
        assert!((times.still_s - 0.1).abs() < 1e-12);
        assert!((times.total_s() - 0.3).abs() < 1e-12);
    }
}
