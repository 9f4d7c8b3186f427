//! Physics configuration: serde types with defaults (paper Table 1) and `validate()`.
//!
//! Every struct is `#[serde(default, deny_unknown_fields)]`, so a TOML file lists only what it
//! changes and a misspelt key is an error. [`PhysicsConfig::validate`] rejects out-of-range
//! values with an error naming the dotted key (rooted at `physics.`) and the allowed range.
//!
//! ```
//! use hopnav_physics::PhysicsConfig;
//! let mut cfg = PhysicsConfig::default();
//! cfg.jumper.launch_speed_mps = 14.0;
//! let err = cfg.validate().unwrap_err().to_string();
//! assert!(err.starts_with("physics.jumper.launch_speed_mps = 14 is out of range: allowed [0.5, 12]"));
//! assert!(err.contains("physics.jumper.max_launch_speed_mps"));
//! ```

use serde::{Deserialize, Serialize};

use crate::error::ConfigError;

/// Root key of every config path in error messages.
pub const ROOT_KEY: &str = "physics";

/// Whole physics configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicsConfig {
    /// Length of one frame, seconds (10 fps → 0.1).
    pub frame_period_s: f64,
    /// Fixed physics substeps per frame.
    pub substeps: u32,
    /// Magnitude of gravity along world −z, m/s² (Mars: 3.711).
    pub gravity_mps2: f64,
    /// Rapier solver iterations per substep.
    pub solver_iterations: u32,
    /// Coulomb friction coefficient of the terrain.
    pub terrain_friction: f64,
    /// Coulomb friction coefficient of the rocks.
    pub rock_friction: f64,
    /// The jumping robot.
    pub jumper: JumperConfig,
    /// The four-wheel-steered rover.
    pub rover: RoverConfig,
    /// The jumper's barometric altimeter.
    pub altimeter: AltimeterConfig,
    /// The rover's IMU.
    pub imu: ImuConfig,
}

impl Default for PhysicsConfig {
    fn default() -> Self {
        Self {
            frame_period_s: 0.1,
            substeps: 10,
            gravity_mps2: 3.711,
            solver_iterations: 4,
            terrain_friction: 0.8,
            rock_friction: 0.8,
            jumper: JumperConfig::default(),
            rover: RoverConfig::default(),
            altimeter: AltimeterConfig::default(),
            imu: ImuConfig::default(),
        }
    }
}

impl PhysicsConfig {
    /// Checks every value; the error names the first offending key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let p = Keys::new(ROOT_KEY);
        p.real(
            "frame_period_s",
            self.frame_period_s,
            Range::left_open(0.0, 1.0),
        )?;
        p.int("substeps", self.substeps.into(), 1, 1000)?;
        p.real(
            "gravity_mps2",
            self.gravity_mps2,
            Range::left_open(0.0, 30.0),
        )?;
        p.int("solver_iterations", self.solver_iterations.into(), 1, 64)?;
        p.real(
            "terrain_friction",
            self.terrain_friction,
            Range::closed(0.0, 2.0),
        )?;
        p.real("rock_friction", self.rock_friction, Range::closed(0.0, 2.0))?;
        self.jumper.validate(&p.child("jumper"))?;
        self.rover.validate(&p.child("rover"))?;
        self.altimeter.validate(&p.child("altimeter"))?;
        self.imu.validate(&p.child("imu"))
    }

    /// Length of one substep, seconds.
    pub fn substep_s(&self) -> f64 {
        self.frame_period_s / f64::from(self.substeps.max(1))
    }
}

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
    /// Checks the values under `keys`.
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.xy("start_xy_m", self.start_xy_m)?;
        k.real(
            "start_yaw_rad",
            self.start_yaw_rad,
            Range::closed(-TAU, TAU),
        )?;
        k.real(
            "max_launch_speed_mps",
            self.max_launch_speed_mps,
            Range::left_open(0.0, 50.0),
        )?;
        k.real_bounded(
            "min_launch_speed_mps",
            self.min_launch_speed_mps,
            Range::left_open(0.0, self.max_launch_speed_mps),
            &["max_launch_speed_mps"],
        )?;
        k.real_bounded(
            "launch_speed_mps",
            self.launch_speed_mps,
            Range::closed(self.min_launch_speed_mps, self.max_launch_speed_mps),
            &["min_launch_speed_mps", "max_launch_speed_mps"],
        )?;
        k.real(
            "max_launch_angle_rad",
            self.max_launch_angle_rad,
            Range::open(0.0, HALF_PI),
        )?;
        k.real_bounded(
            "min_launch_angle_rad",
            self.min_launch_angle_rad,
            Range::left_open(0.0, self.max_launch_angle_rad),
            &["max_launch_angle_rad"],
        )?;
        k.real_bounded(
            "launch_angle_rad",
            self.launch_angle_rad,
            Range::closed(self.min_launch_angle_rad, self.max_launch_angle_rad),
            &["min_launch_angle_rad", "max_launch_angle_rad"],
        )?;
        for (i, w) in self.launch_angular_velocity_body_radps.iter().enumerate() {
            k.real(
                &format!("launch_angular_velocity_body_radps[{i}]"),
                *w,
                Range::closed(-10.0, 10.0),
            )?;
        }
        k.real(
            "half_extent_m",
            self.half_extent_m,
            Range::closed(0.02, 1.0),
        )?;
        k.real("mass_kg", self.mass_kg, Range::left_open(0.0, 1000.0))?;
        k.real("friction", self.friction, Range::closed(0.0, 2.0))?;
        k.real("restitution", self.restitution, Range::closed(0.0, 1.0))?;
        k.real(
            "contact_distance_m",
            self.contact_distance_m,
            Range::closed(0.0, 0.1),
        )?;
        k.real(
            "settle_speed_mps",
            self.settle_speed_mps,
            Range::left_open(0.0, 10.0),
        )?;
        k.real(
            "settle_angular_speed_radps",
            self.settle_angular_speed_radps,
            Range::left_open(0.0, 10.0),
        )?;
        k.int("settle_frames", self.settle_frames.into(), 1, 10_000)?;
        k.real(
            "settle_timeout_s",
            self.settle_timeout_s,
            Range::left_open(0.0, 3600.0),
        )?;
        k.real(
            "landing_linear_damping_per_s",
            self.landing_linear_damping_per_s,
            Range::closed(0.0, 1000.0),
        )?;
        k.real(
            "landing_angular_damping_per_s",
            self.landing_angular_damping_per_s,
            Range::closed(0.0, 1000.0),
        )
    }
}

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
            max_tilt_rad: 30f64.to_radians(),
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
        }
    }

    /// Checks the values under `keys`.
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.xy("start_xy_m", self.start_xy_m)?;
        k.real(
            "start_yaw_rad",
            self.start_yaw_rad,
            Range::closed(-TAU, TAU),
        )?;
        k.real("wheelbase_m", self.wheelbase_m, Range::closed(0.1, 10.0))?;
        k.real("track_m", self.track_m, Range::closed(0.1, 10.0))?;
        k.real(
            "wheel_radius_m",
            self.wheel_radius_m,
            Range::closed(0.02, 2.0),
        )?;
        k.real(
            "wheel_width_m",
            self.wheel_width_m,
            Range::closed(0.01, 2.0),
        )?;
        for (i, h) in self.chassis_half_extents_m.iter().enumerate() {
            k.real(
                &format!("chassis_half_extents_m[{i}]"),
                *h,
                Range::closed(0.02, 5.0),
            )?;
        }
        k.real(
            "ground_clearance_m",
            self.ground_clearance_m,
            Range::closed(0.0, 3.0),
        )?;
        k.real_bounded(
            "max_climbable_height_m",
            self.max_climbable_height_m,
            Range::closed(0.0, self.ground_clearance_m),
            &["ground_clearance_m"],
        )?;
        k.real(
            "max_tilt_rad",
            self.max_tilt_rad,
            Range::left_open(0.0, HALF_PI),
        )?;
        k.real(
            "max_speed_mps",
            self.max_speed_mps,
            Range::left_open(0.0, 10.0),
        )?;
        k.real(
            "max_accel_mps2",
            self.max_accel_mps2,
            Range::left_open(0.0, 50.0),
        )?;
        k.real(
            "max_yaw_rate_radps",
            self.max_yaw_rate_radps,
            Range::left_open(0.0, 10.0),
        )?;
        k.real(
            "max_yaw_accel_radps2",
            self.max_yaw_accel_radps2,
            Range::left_open(0.0, 100.0),
        )?;
        k.real(
            "max_steer_rate_radps",
            self.max_steer_rate_radps,
            Range::left_open(0.0, 100.0),
        )?;
        k.real(
            "steer_tolerance_rad",
            self.steer_tolerance_rad,
            Range::left_open(0.0, 1.0),
        )?;
        k.real(
            "turn_in_place_enter_rad",
            self.turn_in_place_enter_rad,
            Range::left_open(0.0, PI),
        )?;
        k.real_bounded(
            "turn_in_place_exit_rad",
            self.turn_in_place_exit_rad,
            Range::left_open(0.0, self.turn_in_place_enter_rad),
            &["turn_in_place_enter_rad"],
        )?;
        k.real(
            "heading_gain_per_s",
            self.heading_gain_per_s,
            Range::left_open(0.0, 100.0),
        )?;
        k.real(
            "arrive_tolerance_m",
            self.arrive_tolerance_m,
            Range::left_open(0.0, 10.0),
        )
    }

    /// Wheel centre positions (x, y) in the body frame: front-left, front-right, rear-left,
    /// rear-right.
    pub fn wheel_positions_body_m(&self) -> [[f64; 2]; 4] {
        let (hx, hy) = (self.wheelbase_m / 2.0, self.track_m / 2.0);
        [[hx, hy], [hx, -hy], [-hx, hy], [-hx, -hy]]
    }
}

/// Barometric altimeter: `p = p0 · exp(−(z − z_datum) / H)`, noise defined in altitude.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AltimeterConfig {
    /// Standard deviation of the Gaussian altitude noise, metres (Table 1: 1).
    pub sigma_m: f64,
    /// Pressure at the datum, pascals (Mars surface ≈ 610).
    pub surface_pressure_pa: f64,
    /// Atmospheric scale height, metres (Mars ≈ 11 100).
    pub scale_height_m: f64,
    /// World z of the datum (altitude 0), metres.
    pub datum_z_m: f64,
    /// Pressure quantisation step, pascals (0 = none).
    pub pressure_resolution_pa: f64,
}

impl Default for AltimeterConfig {
    fn default() -> Self {
        Self {
            sigma_m: 1.0,
            surface_pressure_pa: 610.0,
            scale_height_m: 11_100.0,
            datum_z_m: 0.0,
            pressure_resolution_pa: 0.0,
        }
    }
}

impl AltimeterConfig {
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.real("sigma_m", self.sigma_m, Range::closed(0.0, 100.0))?;
        k.real(
            "surface_pressure_pa",
            self.surface_pressure_pa,
            Range::left_open(0.0, 1e6),
        )?;
        k.real(
            "scale_height_m",
            self.scale_height_m,
            Range::closed(100.0, 1e6),
        )?;
        k.real("datum_z_m", self.datum_z_m, Range::closed(-1e4, 1e4))?;
        k.real(
            "pressure_resolution_pa",
            self.pressure_resolution_pa,
            Range::closed(0.0, 100.0),
        )
    }
}

/// Rover IMU noise: white noise per frame sample, constant biases drawn at start, yaw drift.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ImuConfig {
    /// Gyro white noise per sample, rad/s.
    pub gyro_noise_radps: f64,
    /// Standard deviation of the constant gyro bias (per axis), rad/s.
    pub gyro_bias_sigma_radps: f64,
    /// Accelerometer white noise per sample, m/s².
    pub accel_noise_mps2: f64,
    /// Standard deviation of the constant accelerometer bias (per axis), m/s².
    pub accel_bias_sigma_mps2: f64,
    /// White noise on the reported roll and pitch, radians.
    pub attitude_noise_rad: f64,
    /// Deterministic yaw drift rate of the reported attitude, rad/s.
    pub yaw_drift_radps: f64,
    /// Yaw random walk of the reported attitude, rad/√s.
    pub yaw_random_walk_rad_per_sqrt_s: f64,
}

impl Default for ImuConfig {
    fn default() -> Self {
        Self {
            gyro_noise_radps: 0.002,
            gyro_bias_sigma_radps: 0.0005,
            accel_noise_mps2: 0.02,
            accel_bias_sigma_mps2: 0.005,
            attitude_noise_rad: 0.002,
            yaw_drift_radps: 1e-4,
            yaw_random_walk_rad_per_sqrt_s: 5e-4,
        }
    }
}

impl ImuConfig {
    pub(crate) fn validate(&self, k: &Keys) -> Result<(), ConfigError> {
        k.real(
            "gyro_noise_radps",
            self.gyro_noise_radps,
            Range::closed(0.0, 1.0),
        )?;
        k.real(
            "gyro_bias_sigma_radps",
            self.gyro_bias_sigma_radps,
            Range::closed(0.0, 1.0),
        )?;
        k.real(
            "accel_noise_mps2",
            self.accel_noise_mps2,
            Range::closed(0.0, 10.0),
        )?;
        k.real(
            "accel_bias_sigma_mps2",
            self.accel_bias_sigma_mps2,
            Range::closed(0.0, 10.0),
        )?;
        k.real(
            "attitude_noise_rad",
            self.attitude_noise_rad,
            Range::closed(0.0, 1.0),
        )?;
        k.real(
            "yaw_drift_radps",
            self.yaw_drift_radps,
            Range::closed(-1.0, 1.0),
        )?;
        k.real(
            "yaw_random_walk_rad_per_sqrt_s",
            self.yaw_random_walk_rad_per_sqrt_s,
            Range::closed(0.0, 1.0),
        )
    }
}

const PI: f64 = std::f64::consts::PI;
const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;
const TAU: f64 = std::f64::consts::TAU;

/// An interval used to check and describe a value.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Range {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Range {
    const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }
    const fn left_open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }
    const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: true,
        }
    }
    fn contains(&self, v: f64) -> bool {
        let lo_ok = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        let hi_ok = if self.hi_open {
            v < self.hi
        } else {
            v <= self.hi
        };
        v.is_finite() && lo_ok && hi_ok
    }
    fn describe(&self) -> String {
        format!(
            "{}{}, {}{}",
            if self.lo_open { '(' } else { '[' },
            self.lo,
            self.hi,
            if self.hi_open { ')' } else { ']' }
        )
    }
}

/// A dotted key prefix with checking helpers.
#[derive(Debug, Clone)]
pub(crate) struct Keys {
    prefix: String,
}

impl Keys {
    pub(crate) fn new(prefix: &str) -> Self {
        Self {
            prefix: prefix.to_string(),
        }
    }
    fn key(&self, field: &str) -> String {
        format!("{}.{field}", self.prefix)
    }
    fn child(&self, field: &str) -> Self {
        Self {
            prefix: self.key(field),
        }
    }
    fn real(&self, field: &str, v: f64, r: Range) -> Result<(), ConfigError> {
        self.real_bounded(field, v, r, &[])
    }
    fn real_bounded(
        &self,
        field: &str,
        v: f64,
        r: Range,
        bounds: &[&str],
    ) -> Result<(), ConfigError> {
        if r.contains(v) {
            return Ok(());
        }
        Err(ConfigError::OutOfRange {
            key: self.key(field),
            value: format!("{v}"),
            range: r.describe(),
            bound_keys: bounds.iter().map(|b| self.key(b)).collect(),
        })
    }
    fn int(&self, field: &str, v: u64, lo: u64, hi: u64) -> Result<(), ConfigError> {
        if (lo..=hi).contains(&v) {
            return Ok(());
        }
        Err(ConfigError::OutOfRange {
            key: self.key(field),
            value: v.to_string(),
            range: format!("[{lo}, {hi}]"),
            bound_keys: Vec::new(),
        })
    }
    fn xy(&self, field: &str, v: [f64; 2]) -> Result<(), ConfigError> {
        self.real(&format!("{field}[0]"), v[0], Range::closed(-1e4, 1e4))?;
        self.real(&format!("{field}[1]"), v[1], Range::closed(-1e4, 1e4))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate() {
        assert_eq!(PhysicsConfig::default().validate(), Ok(()));
    }

    #[test]
    fn nan_is_rejected() {
        let mut cfg = PhysicsConfig::default();
        cfg.altimeter.sigma_m = f64::NAN;
        let err = cfg.validate().unwrap_err().to_string();
        assert!(
            err.starts_with("physics.altimeter.sigma_m = NaN is out of range"),
            "{err}"
        );
    }
}
