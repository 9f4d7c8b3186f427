//! The rover's body, drive limits and steering.

use hopnav_config::range::Interval;
use serde::{Deserialize, Serialize};

use super::{HALF_PI, Keys, PI};
use crate::error::ConfigError;

/// The rover: rigid chassis on four independently driven and steered wheels.
///
/// Body frame: x forward, y left, z up; wheel centres at `(±wheelbase/2, ±track/2)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RoverConfig {
    /// Start position (x, y), metres; z follows from the terrain.
    pub start_xy_m: [f64; 2],
    /// Start heading about world z, radians (0 = +x).
    pub start_yaw_rad: f64,
    /// Distance between front and rear axles, metres.
    pub wheelbase_m: f64,
    /// Distance between left and right wheel centres, metres.
    pub track_m: f64,
    /// Wheel radius, metres.
    pub wheel_radius_m: f64,
    /// Wheel width, metres.
    pub wheel_width_m: f64,
    /// Chassis box half extents (x, y, z), metres.
    pub chassis_half_extents_m: [f64; 3],
    /// Height of the chassis belly above the wheel contact plane, metres.
    pub ground_clearance_m: f64,
    /// Rocks taller than this block the rover; smaller ones are driven over, metres.
    pub max_climbable_height_m: f64,
    /// Largest pitch or roll the rover accepts before it refuses to move on, radians.
    pub max_tilt_rad: f64,
    /// Top speed, m/s.
    pub max_speed_mps: f64,
    /// Largest linear acceleration, m/s².
    pub max_accel_mps2: f64,
    /// Top yaw rate, rad/s.
    pub max_yaw_rate_radps: f64,
    /// Largest yaw acceleration, rad/s².
    pub max_yaw_accel_radps2: f64,
    /// Steering rate of each wheel, rad/s.
    pub max_steer_rate_radps: f64,
    /// The chassis moves only when every wheel is steered within this of its target, radians.
    pub steer_tolerance_rad: f64,
    /// Heading errors above this make the rover turn on the spot, radians.
    pub turn_in_place_enter_rad: f64,
    /// A turn on the spot ends when the heading error falls below this, radians.
    pub turn_in_place_exit_rad: f64,
    /// Proportional heading gain: yaw rate per radian of heading error, 1/s.
    pub heading_gain_per_s: f64,
    /// The waypoint counts as reached within this horizontal distance, metres.
    pub arrive_tolerance_m: f64,
}

impl Default for RoverConfig {
    fn default() -> Self {
        // The body's dimensions are defined once, in hopnav-robot, for every crate.
        let body = hopnav_robot::RoverBody::default();
        Self {
            start_xy_m: [-12.0, -1.5],
            start_yaw_rad: 0.0,
            wheelbase_m: body.wheelbase_m,
            track_m: body.track_m,
            wheel_radius_m: body.wheel_radius_m,
            wheel_width_m: body.wheel_width_m,
            chassis_half_extents_m: body.chassis_half_extents_m,
            ground_clearance_m: body.ground_clearance_m,
            max_climbable_height_m: body.max_climbable_height_m,
            max_tilt_rad: body.max_tilt_rad,
            max_speed_mps: 0.5,
            max_accel_mps2: 0.5,
            max_yaw_rate_radps: 0.6,
            max_yaw_accel_radps2: 1.2,
            max_steer_rate_radps: 2.0,
            steer_tolerance_rad: 0.05,
            turn_in_place_enter_rad: 0.35,
            turn_in_place_exit_rad: 0.03,
            heading_gain_per_s: 1.5,
            arrive_tolerance_m: 0.1,
        }
    }
}

impl RoverConfig {
    /// The body's dimensions, as the mapper, the planner and the evaluation read them.
    pub fn body(&self) -> hopnav_robot::RoverBody {
        hopnav_robot::RoverBody {
            wheelbase_m: self.wheelbase_m,
            track_m: self.track_m,
            wheel_radius_m: self.wheel_radius_m,
            wheel_width_m: self.wheel_width_m,
            chassis_half_extents_m: self.chassis_half_extents_m,
            ground_clearance_m: self.ground_clearance_m,
            max_climbable_height_m: self.max_climbable_height_m,
            max_tilt_rad: self.max_tilt_rad,
        }
    }

    /// Checks the values under `keys`: the start, the body's geometry, then the motion.
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.start_pose(self.start_xy_m, self.start_yaw_rad)?;
        k.real("wheelbase_m", self.wheelbase_m, Interval::closed(0.1, 10.0))?;
        k.real("track_m", self.track_m, Interval::closed(0.1, 10.0))?;
        k.real(
            "wheel_radius_m",
            self.wheel_radius_m,
            Interval::closed(0.02, 2.0),
        )?;
        k.real(
            "wheel_width_m",
            self.wheel_width_m,
            Interval::closed(0.01, 2.0),
        )?;
        for (i, h) in self.chassis_half_extents_m.iter().enumerate() {
            k.real(
                &format!("chassis_half_extents_m[{i}]"),
                *h,
                Interval::closed(0.02, 5.0),
            )?;
        }
        k.real(
            "ground_clearance_m",
            self.ground_clearance_m,
            Interval::closed(0.0, 3.0),
        )?;
        k.real_bounded(
            "max_climbable_height_m",
            self.max_climbable_height_m,
            Interval::closed(0.0, self.ground_clearance_m),
            &["ground_clearance_m"],
        )?;
        self.validate_motion(k)
    }

    /// Checks the drive's limits and how it steers and arrives.
    fn validate_motion(&self, k: &Keys) -> Result<(), ConfigError> {
        k.real(
            "max_tilt_rad",
            self.max_tilt_rad,
            Interval::left_open(0.0, HALF_PI),
        )?;
        k.real(
            "max_speed_mps",
            self.max_speed_mps,
            Interval::left_open(0.0, 10.0),
        )?;
        k.real(
            "max_accel_mps2",
            self.max_accel_mps2,
            Interval::left_open(0.0, 50.0),
        )?;
        k.real(
            "max_yaw_rate_radps",
            self.max_yaw_rate_radps,
            Interval::left_open(0.0, 10.0),
        )?;
        k.real(
            "max_yaw_accel_radps2",
            self.max_yaw_accel_radps2,
            Interval::left_open(0.0, 100.0),
        )?;
        k.real(
            "max_steer_rate_radps",
            self.max_steer_rate_radps,
            Interval::left_open(0.0, 100.0),
        )?;
        k.real(
            "steer_tolerance_rad",
            self.steer_tolerance_rad,
            Interval::left_open(0.0, 1.0),
        )?;
        k.real(
            "turn_in_place_enter_rad",
            self.turn_in_place_enter_rad,
            Interval::left_open(0.0, PI),
        )?;
        k.real_bounded(
            "turn_in_place_exit_rad",
            self.turn_in_place_exit_rad,
            Interval::left_open(0.0, self.turn_in_place_enter_rad),
            &["turn_in_place_enter_rad"],
        )?;
        k.real(
            "heading_gain_per_s",
            self.heading_gain_per_s,
            Interval::left_open(0.0, 100.0),
        )?;
        k.real(
            "arrive_tolerance_m",
            self.arrive_tolerance_m,
            Interval::left_open(0.0, 10.0),
        )
    }

    /// Wheel centre positions (x, y) in the body frame: front-left, front-right, rear-left,
    /// rear-right.
    pub fn wheel_positions_body_m(&self) -> [[f64; 2]; 4] {
        let (hx, hy) = (self.wheelbase_m / 2.0, self.track_m / 2.0);
        [[hx, hy], [hx, -hy], [-hx, hy], [-hx, -hy]]
    }
}
