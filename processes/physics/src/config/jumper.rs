//! The jumping robot's launch limits, body and settling.

use hopnav_config::range::Interval;
use serde::{Deserialize, Serialize};

use super::{HALF_PI, Keys};
use crate::error::ConfigError;

/// The jumping robot: a small cube launched ballistically (paper Table 1 defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JumperConfig {
    /// Start position (x, y), metres; z follows from the terrain.
    pub start_xy_m: [f64; 2],
    /// Start heading about world z, radians (0 = +x).
    pub start_yaw_rad: f64,
    /// Launch the first hop automatically at frame 0, along `start_yaw_rad`, with
    /// `launch_speed_mps` at `launch_angle_rad` (the paper's single hop).
    pub initial_hop: bool,
    /// Launch speed of the initial hop, m/s (Table 1: 10).
    pub launch_speed_mps: f64,
    /// Launch elevation angle, radians (Table 1: 60°); planned hops keep this angle.
    pub launch_angle_rad: f64,
    /// Angular velocity applied at launch, body frame (x forward, y left, z up), rad/s.
    /// Table 1: 0.1 rad/s about the pitch axis; positive y pitches the nose down.
    pub launch_angular_velocity_body_radps: [f64; 3],
    /// Smallest launch speed a hop may use, m/s.
    pub min_launch_speed_mps: f64,
    /// Largest launch speed a hop may use, m/s.
    pub max_launch_speed_mps: f64,
    /// Smallest launch angle, radians.
    pub min_launch_angle_rad: f64,
    /// Largest launch angle, radians.
    pub max_launch_angle_rad: f64,
    /// Half the edge length of the cube body, metres.
    pub half_extent_m: f64,
    /// Mass, kilograms.
    pub mass_kg: f64,
    /// Coulomb friction coefficient of the body.
    pub friction: f64,
    /// Restitution of the body (0 = no bounce).
    pub restitution: f64,
    /// A contact point closer than this counts as ground contact, metres.
    pub contact_distance_m: f64,
    /// The body is at rest when its speed stays below this, m/s …
    pub settle_speed_mps: f64,
    /// … and its angular speed below this, rad/s …
    pub settle_angular_speed_radps: f64,
    /// … for this many consecutive frames.
    pub settle_frames: u32,
    /// After landing, the jumper counts as settled after this long even if still moving, seconds.
    pub settle_timeout_s: f64,
    /// Linear damping while landing, 1/s: the landing cage absorbs the impact, so the body
    /// stops within a metre or so instead of rolling on (0 = a bare cube that rolls for metres).
    pub landing_linear_damping_per_s: f64,
    /// Angular damping while landing, 1/s.
    pub landing_angular_damping_per_s: f64,
    /// Evaluation only: tell the jumper VO the true launch point of every hop, not only the
    /// first. Each hop's VO error then starts at zero: the bound on what relocalizing the
    /// jumper at rest could give a mission (off in every real mission).
    pub oracle_launch_position: bool,
}

impl Default for JumperConfig {
    fn default() -> Self {
        Self {
            start_xy_m: [-12.0, 1.5],
            start_yaw_rad: 0.0,
            initial_hop: true,
            launch_speed_mps: 10.0,
            launch_angle_rad: std::f64::consts::FRAC_PI_3,
            launch_angular_velocity_body_radps: [0.0, 0.1, 0.0],
            min_launch_speed_mps: 0.5,
            max_launch_speed_mps: 12.0,
            min_launch_angle_rad: 20f64.to_radians(),
            max_launch_angle_rad: 80f64.to_radians(),
            half_extent_m: 0.1,
            mass_kg: 2.0,
            friction: 0.8,
            restitution: 0.1,
            contact_distance_m: 0.005,
            settle_speed_mps: 0.05,
            settle_angular_speed_radps: 0.1,
            settle_frames: 5,
            settle_timeout_s: 20.0,
            landing_linear_damping_per_s: 8.0,
            landing_angular_damping_per_s: 12.0,
            oracle_launch_position: false,
        }
    }
}

impl JumperConfig {
    /// Checks the values under `keys`: the start and the launch, then the body and landing.
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.start_pose(self.start_xy_m, self.start_yaw_rad)?;
        k.real(
            "max_launch_speed_mps",
            self.max_launch_speed_mps,
            Interval::left_open(0.0, 50.0),
        )?;
        k.real_bounded(
            "min_launch_speed_mps",
            self.min_launch_speed_mps,
            Interval::left_open(0.0, self.max_launch_speed_mps),
            &["max_launch_speed_mps"],
        )?;
        k.real_bounded(
            "launch_speed_mps",
            self.launch_speed_mps,
            Interval::closed(self.min_launch_speed_mps, self.max_launch_speed_mps),
            &["min_launch_speed_mps", "max_launch_speed_mps"],
        )?;
        k.real(
            "max_launch_angle_rad",
            self.max_launch_angle_rad,
            Interval::open(0.0, HALF_PI),
        )?;
        k.real_bounded(
            "min_launch_angle_rad",
            self.min_launch_angle_rad,
            Interval::left_open(0.0, self.max_launch_angle_rad),
            &["max_launch_angle_rad"],
        )?;
        k.real_bounded(
            "launch_angle_rad",
            self.launch_angle_rad,
            Interval::closed(self.min_launch_angle_rad, self.max_launch_angle_rad),
            &["min_launch_angle_rad", "max_launch_angle_rad"],
        )?;
        for (i, w) in self.launch_angular_velocity_body_radps.iter().enumerate() {
            k.real(
                &format!("launch_angular_velocity_body_radps[{i}]"),
                *w,
                Interval::closed(-10.0, 10.0),
            )?;
        }
        self.validate_body_and_landing(k)
    }

    /// Checks the cube's body and contact values and when it counts as landed.
    fn validate_body_and_landing(&self, k: &Keys) -> Result<(), ConfigError> {
        k.real(
            "half_extent_m",
            self.half_extent_m,
            Interval::closed(0.02, 1.0),
        )?;
        k.real("mass_kg", self.mass_kg, Interval::left_open(0.0, 1000.0))?;
        k.real("friction", self.friction, Interval::closed(0.0, 2.0))?;
        k.real("restitution", self.restitution, Interval::closed(0.0, 1.0))?;
        k.real(
            "contact_distance_m",
            self.contact_distance_m,
            Interval::closed(0.0, 0.1),
        )?;
        k.real(
            "settle_speed_mps",
            self.settle_speed_mps,
            Interval::left_open(0.0, 10.0),
        )?;
        k.real(
            "settle_angular_speed_radps",
            self.settle_angular_speed_radps,
            Interval::left_open(0.0, 10.0),
        )?;
        k.int("settle_frames", self.settle_frames.into(), 1, 10_000)?;
        k.real(
            "settle_timeout_s",
            self.settle_timeout_s,
            Interval::left_open(0.0, 3600.0),
        )?;
        k.real(
            "landing_linear_damping_per_s",
            self.landing_linear_damping_per_s,
            Interval::closed(0.0, 1000.0),
        )?;
        k.real(
            "landing_angular_damping_per_s",
            self.landing_angular_damping_per_s,
            Interval::closed(0.0, 1000.0),
        )
    }
}
