//! The jumper's altimeter and the rover's IMU.

use hopnav_config::range::Interval;
use serde::{Deserialize, Serialize};

use super::Keys;
use crate::error::ConfigError;

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
        k.real("sigma_m", self.sigma_m, Interval::closed(0.0, 100.0))?;
        k.real(
            "surface_pressure_pa",
            self.surface_pressure_pa,
            Interval::left_open(0.0, 1e6),
        )?;
        k.real(
            "scale_height_m",
            self.scale_height_m,
            Interval::closed(100.0, 1e6),
        )?;
        k.real("datum_z_m", self.datum_z_m, Interval::closed(-1e4, 1e4))?;
        k.real(
            "pressure_resolution_pa",
            self.pressure_resolution_pa,
            Interval::closed(0.0, 100.0),
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
            Interval::closed(0.0, 1.0),
        )?;
        k.real(
            "gyro_bias_sigma_radps",
            self.gyro_bias_sigma_radps,
            Interval::closed(0.0, 1.0),
        )?;
        k.real(
            "accel_noise_mps2",
            self.accel_noise_mps2,
            Interval::closed(0.0, 10.0),
        )?;
        k.real(
            "accel_bias_sigma_mps2",
            self.accel_bias_sigma_mps2,
            Interval::closed(0.0, 10.0),
        )?;
        k.real(
            "attitude_noise_rad",
            self.attitude_noise_rad,
            Interval::closed(0.0, 1.0),
        )?;
        k.real(
            "yaw_drift_radps",
            self.yaw_drift_radps,
            Interval::closed(-1.0, 1.0),
        )?;
        k.real(
            "yaw_random_walk_rad_per_sqrt_s",
            self.yaw_random_walk_rad_per_sqrt_s,
            Interval::closed(0.0, 1.0),
        )
    }
}
