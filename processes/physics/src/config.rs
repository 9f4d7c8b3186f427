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
mod jumper;
mod rover;
mod sensors;

use hopnav_config::range::{Interval, OutOfRange, check_int, dotted_key};
use serde::{Deserialize, Serialize};

pub use jumper::JumperConfig;
pub use rover::RoverConfig;
pub use sensors::{AltimeterConfig, ImuConfig};

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
            Interval::left_open(0.0, 1.0),
        )?;
        p.int("substeps", self.substeps.into(), 1, 1000)?;
        p.real(
            "gravity_mps2",
            self.gravity_mps2,
            Interval::left_open(0.0, 30.0),
        )?;
        p.int("solver_iterations", self.solver_iterations.into(), 1, 64)?;
        p.real(
            "terrain_friction",
            self.terrain_friction,
            Interval::closed(0.0, 2.0),
        )?;
        p.real(
            "rock_friction",
            self.rock_friction,
            Interval::closed(0.0, 2.0),
        )?;
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
const PI: f64 = std::f64::consts::PI;
const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;
const TAU: f64 = std::f64::consts::TAU;
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
        dotted_key(&self.prefix, field)
    }
    fn child(&self, field: &str) -> Self {
        Self {
            prefix: self.key(field),
        }
    }
    fn real(&self, field: &str, v: f64, r: Interval) -> Result<(), ConfigError> {
        self.real_bounded(field, v, r, &[])
    }
    /// Checks `v` against a range set by other values: the error also names `bounds`.
    fn real_bounded(
        &self,
        field: &str,
        v: f64,
        r: Interval,
        bounds: &[&str],
    ) -> Result<(), ConfigError> {
        r.check(&self.prefix, field, v)
            .map_err(|rejected| self.out_of_range(rejected, bounds))
    }
    fn int(&self, field: &str, v: u64, lo: u64, hi: u64) -> Result<(), ConfigError> {
        check_int(&self.prefix, field, v, lo, hi)
            .map_err(|rejected| self.out_of_range(rejected, &[]))
    }
    fn out_of_range(&self, rejected: OutOfRange, bounds: &[&str]) -> ConfigError {
        ConfigError::OutOfRange {
            key: rejected.key,
            value: rejected.value,
            range: rejected.range,
            bound_keys: bounds.iter().map(|b| self.key(b)).collect(),
        }
    }
    /// Checks a body's `start_xy_m` and `start_yaw_rad`.
    fn start_pose(&self, xy: [f64; 2], yaw_rad: f64) -> Result<(), ConfigError> {
        self.real("start_xy_m[0]", xy[0], Interval::closed(-1e4, 1e4))?;
        self.real("start_xy_m[1]", xy[1], Interval::closed(-1e4, 1e4))?;
        self.real("start_yaw_rad", yaw_rad, Interval::closed(-TAU, TAU))
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
