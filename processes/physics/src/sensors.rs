//! Sensor models: the jumper's barometric altimeter and the rover's IMU.
//!
//! # Altimeter
//! Exponential atmosphere `p = p0 · exp(−h / H)` with `h = z − z_datum`. Noise is defined in
//! altitude (Table 1: Gaussian, σ = 1 m): `h_meas = h + N(0, σ²)`, then
//! `p_meas = p0 · exp(−h_meas / H)`, optionally quantised to `pressure_resolution_pa`
//! (the reported altitude is then recomputed from the quantised pressure).
//!
//! # IMU
//! The rover's kinematics give, per substep, the world acceleration `a` and angular velocity
//! `ω`. [`ImuAccumulator`] averages the body-frame specific force `Rᵀ·(a − g)` (with
//! `g = (0, 0, −g)`, so a rover at rest reads `+g` along body z) and the body-frame rate `Rᵀ·ω`
//! over the frame's substeps. [`Imu::sample`] adds constant biases (drawn once from the seed)
//! and white noise, and reports an attitude corrupted by a yaw drift (deterministic rate plus
//! random walk, applied about world z) and small roll/pitch white noise.

use crate::config::{AltimeterConfig, ImuConfig};
use crate::frame::{AltimeterSample, ImuSample};
use crate::math::{DQuat, DVec3, quat_from_yaw_pitch_roll, quat_to_xyzw, vec_to_array};
use crate::noise::NoiseRng;

/// Noise stream of the altimeter.
const ALTIMETER_STREAM: u64 = 0xA171;
/// Noise stream of the IMU.
const IMU_STREAM: u64 = 0x1300;

/// The jumper's barometric altimeter.
#[derive(Debug, Clone)]
pub struct Altimeter {
    cfg: AltimeterConfig,
    rng: NoiseRng,
}

impl Altimeter {
    /// An altimeter whose noise derives from `seed`.
    pub fn new(cfg: &AltimeterConfig, seed: u64) -> Self {
        Self {
            cfg: cfg.clone(),
            rng: NoiseRng::new(seed, ALTIMETER_STREAM),
        }
    }

    /// Pressure at altitude `h_m` above the datum, pascals.
    pub fn pressure_at_pa(&self, h_m: f64) -> f64 {
        self.cfg.surface_pressure_pa * (-h_m / self.cfg.scale_height_m).exp()
    }

    /// Altitude above the datum for pressure `p_pa`, metres.
    pub fn altitude_at_m(&self, p_pa: f64) -> f64 {
        -self.cfg.scale_height_m * (p_pa / self.cfg.surface_pressure_pa).ln()
    }

    /// The state of its noise generator.
    pub fn noise(&self) -> &NoiseRng {
        &self.rng
    }

    /// Continues the noise sequence of `rng` (from a previous incarnation's [`noise`]).
    ///
    /// [`noise`]: Self::noise
    pub fn restore_noise(&mut self, rng: NoiseRng) {
        self.rng = rng;
    }

    /// One sample for a body centre at world height `z_m`.
    pub fn sample(&mut self, z_m: f64) -> AltimeterSample {
        let true_altitude_m = z_m - self.cfg.datum_z_m;
        let noisy = true_altitude_m + self.rng.normal(self.cfg.sigma_m);
        let mut pressure_pa = self.pressure_at_pa(noisy);
        let mut altitude_m = noisy;
        let q = self.cfg.pressure_resolution_pa;
        if q > 0.0 {
            pressure_pa = (pressure_pa / q).round() * q;
            if pressure_pa > 0.0 {
                altitude_m = self.altitude_at_m(pressure_pa);
            }
        }
        AltimeterSample {
            pressure_pa,
            altitude_m,
            true_altitude_m,
        }
    }
}

/// Frame average of the body-frame specific force and angular rate.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ImuAccumulator {
    specific_force_sum: DVec3,
    rate_sum: DVec3,
    count: u32,
}

impl ImuAccumulator {
    /// Adds one substep: `world_from_body`, world acceleration, world angular velocity.
    pub fn add(
        &mut self,
        world_from_body: DQuat,
        accel_world: DVec3,
        angvel_world: DVec3,
        g_mps2: f64,
    ) {
        let body_from_world = world_from_body.conjugate();
        let gravity = DVec3::new(0.0, 0.0, -g_mps2);
        self.specific_force_sum += body_from_world * (accel_world - gravity);
        self.rate_sum += body_from_world * angvel_world;
        self.count += 1;
    }

    /// Mean (specific force, angular rate) in the body frame, and resets.
    pub fn take_mean(&mut self) -> (DVec3, DVec3) {
        let n = f64::from(self.count.max(1));
        let out = (self.specific_force_sum / n, self.rate_sum / n);
        *self = Self::default();
        out
    }
}

/// The rover's IMU noise model.
#[derive(Debug, Clone)]
pub struct Imu {
    cfg: ImuConfig,
    rng: NoiseRng,
    gyro_bias: DVec3,
    accel_bias: DVec3,
    yaw_error_rad: f64,
}

impl Imu {
    /// An IMU whose biases and noise derive from `seed`.
    pub fn new(cfg: &ImuConfig, seed: u64) -> Self {
        let mut rng = NoiseRng::new(seed, IMU_STREAM);
        let mut draw =
            |sigma: f64| DVec3::new(rng.normal(sigma), rng.normal(sigma), rng.normal(sigma));
        let gyro_bias = draw(cfg.gyro_bias_sigma_radps);
        let accel_bias = draw(cfg.accel_bias_sigma_mps2);
        Self {
            cfg: cfg.clone(),
            rng,
            gyro_bias,
            accel_bias,
            yaw_error_rad: 0.0,
        }
    }

    /// Current yaw error of the reported attitude, radians.
    pub fn yaw_error_rad(&self) -> f64 {
        self.yaw_error_rad
    }

    /// The state of its noise generator.
    pub fn noise(&self) -> &NoiseRng {
        &self.rng
    }

    /// Continues where a previous incarnation left off: its noise generator and its yaw error
    /// (the biases derive from the seed and are the same).
    pub fn restore(&mut self, rng: NoiseRng, yaw_error_rad: f64) {
        self.rng = rng;
        self.yaw_error_rad = yaw_error_rad;
    }

    /// One sample from the frame means and the true attitude; `frame_s` drives the yaw drift.
    pub fn sample(
        &mut self,
        specific_force_body: DVec3,
        rate_body: DVec3,
        world_from_body: DQuat,
        frame_s: f64,
    ) -> ImuSample {
        let c = &self.cfg;
        self.yaw_error_rad += c.yaw_drift_radps * frame_s
            + self
                .rng
                .normal(c.yaw_random_walk_rad_per_sqrt_s * frame_s.max(0.0).sqrt());
        let roll_n = self.rng.normal(c.attitude_noise_rad);
        let pitch_n = self.rng.normal(c.attitude_noise_rad);
        let attitude = DQuat::from_rotation_z(self.yaw_error_rad)
            * world_from_body
            * quat_from_yaw_pitch_roll(0.0, pitch_n, roll_n);
        let gyro_noise = c.gyro_noise_radps;
        let accel_noise = c.accel_noise_mps2;
        let mut white = |sigma: f64| {
            DVec3::new(
                self.rng.normal(sigma),
                self.rng.normal(sigma),
                self.rng.normal(sigma),
            )
        };
        let rate = rate_body + self.gyro_bias + white(gyro_noise);
        let force = specific_force_body + self.accel_bias + white(accel_noise);
        ImuSample {
            orientation_xyzw: quat_to_xyzw(attitude.normalize()),
            angular_velocity_body_radps: vec_to_array(rate),
            specific_force_body_mps2: vec_to_array(force),
        }
    }
}
