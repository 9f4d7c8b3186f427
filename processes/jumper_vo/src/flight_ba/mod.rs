//! Local bundle adjustment of one hop: the keyframes' poses and the ground points they saw,
//! refined jointly with robust reprojection costs, the altimeter and the flight model.
//!
//! A hop flies without drag or torque, so its keyframe poses are not free: they are the flight
//! model's at each keyframe instant, and the model has nine parameters `θ`:
//!
//! - `v0`, the launch velocity: `p(τ) = p0 + v0 τ − ½ g τ² ẑ` (the launch position `p0` and
//!   `g` known);
//! - `ω`, the world-frame angular rate, and `δ`, a correction of the resting attitude `R0`:
//!   `R(τ) = exp(ω τ) · exp(δ) · R0` (torque-free spin of a body with a near-spherical inertia).
//!
//! Costs: each sighting of a track in a keyframe (Cauchy-robust, σ = the pixel noise), each
//! altimeter sample since the launch, and priors on `v0` (the commanded launch), `ω` (the
//! commanded spin, unless the spin fit has doubted it) and `δ` (the resting attitude). The
//! ground points `X_j` are eliminated by the Schur complement: one Levenberg–Marquardt
//! iteration costs one pass over the sightings and a 9×9 solve, a few milliseconds for a
//! whole hop (`hopnav bench vo`).
//!
//! Tying the poses to the model, rather than giving each keyframe six free parameters with
//! the model as a soft prior, is the stronger form of the same prior: it holds for the
//! simulated hops and the physics' free flight alike, and it leaves the solver nine shared
//! parameters however many keyframes the window holds.

mod solve;
mod window;

pub use solve::adjust;
pub use window::{AltitudeSample, HopWindow, Sighting};

use nalgebra::{Isometry3, Matrix3, SVector, Translation3, UnitQuaternion, Vector3};

/// What the flight model holds fixed: where and how the hop started, gravity and the mount.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightModel {
    /// Body position at the launch instant, world frame, metres.
    pub launch_position_m: Vector3<f64>,
    /// Body attitude at rest before the launch (world from body).
    pub launch_rotation: UnitQuaternion<f64>,
    /// Gravity, m/s² (acting along −z).
    pub gravity_mps2: f64,
    /// Camera pose in the body frame.
    pub body_from_camera: Isometry3<f64>,
}

/// The nine parameters the adjustment refines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightParams {
    /// Launch velocity, world frame, m/s.
    pub velocity_mps: Vector3<f64>,
    /// Angular rate, world frame, rad/s.
    pub rate_radps: Vector3<f64>,
    /// Rotation applied to the resting attitude before the spin (world frame), radians.
    pub attitude_correction_rad: Vector3<f64>,
}

/// Parameter vector layout: `[v0 (3), ω (3), δ (3)]`.
pub(crate) type ParamVector = SVector<f64, 9>;

impl FlightParams {
    pub(crate) fn to_vector(self) -> ParamVector {
        let mut v = ParamVector::zeros();
        v.fixed_rows_mut::<3>(0).copy_from(&self.velocity_mps);
        v.fixed_rows_mut::<3>(3).copy_from(&self.rate_radps);
        v.fixed_rows_mut::<3>(6)
            .copy_from(&self.attitude_correction_rad);
        v
    }

    pub(crate) fn from_vector(v: &ParamVector) -> Self {
        Self {
            velocity_mps: v.fixed_rows::<3>(0).into_owned(),
            rate_radps: v.fixed_rows::<3>(3).into_owned(),
            attitude_correction_rad: v.fixed_rows::<3>(6).into_owned(),
        }
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.to_vector().iter().all(|v| v.is_finite())
    }
}

impl FlightModel {
    /// Body position `tau_s` after the launch under `params`.
    pub fn position_m(&self, params: &FlightParams, tau_s: f64) -> Vector3<f64> {
        self.launch_position_m + params.velocity_mps * tau_s
            - Vector3::z() * (0.5 * self.gravity_mps2 * tau_s * tau_s)
    }

    /// Body attitude `tau_s` after the launch under `params`.
    pub fn attitude(&self, params: &FlightParams, tau_s: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_scaled_axis(params.rate_radps * tau_s)
            * UnitQuaternion::from_scaled_axis(params.attitude_correction_rad)
            * self.launch_rotation
    }

    /// `world_from_body` `tau_s` after the launch under `params`.
    pub fn world_from_body(&self, params: &FlightParams, tau_s: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.position_m(params, tau_s)),
            self.attitude(params, tau_s),
        )
    }

    /// `camera_from_world` `tau_s` after the launch under `params`.
    pub(crate) fn camera_from_world(&self, params: &FlightParams, tau_s: f64) -> Isometry3<f64> {
        (self.world_from_body(params, tau_s) * self.body_from_camera).inverse()
    }
}

/// What the adjustment believes before it looks: the parameters' prior means and spreads.
/// A σ ≤ 0 or not finite leaves that parameter without a prior.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightPrior {
    /// Prior means.
    pub mean: FlightParams,
    /// σ of each launch-velocity component, m/s.
    pub velocity_sigma_mps: f64,
    /// σ of each angular-rate component, rad/s.
    pub rate_sigma_radps: f64,
    /// σ of each component of the resting attitude's correction, radians.
    pub attitude_sigma_rad: f64,
}

/// How the adjustment weighs and stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaSettings {
    /// σ of a sighting in normalized image coordinates (pixel σ / focal length).
    pub sighting_sigma: f64,
    /// Cauchy scale, in sighting σs: residuals beyond it count less and less.
    pub robust_scale_sigmas: f64,
    /// σ of an altimeter sample, metres.
    pub altimeter_sigma_m: f64,
    /// Levenberg–Marquardt iterations at most.
    pub max_iterations: usize,
    /// Ground points needed for an adjustment.
    pub min_points: usize,
    /// A point whose sightings' rays meet at less than this angle is left out (no depth).
    pub min_ray_angle_rad: f64,
}

/// The adjustment's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaOutcome {
    /// The refined parameters.
    pub params: FlightParams,
    /// Ground points adjusted.
    pub points: usize,
    /// Sightings of those points.
    pub sightings: usize,
    /// Iterations run.
    pub iterations: usize,
    /// Total robust cost at the start and at the end (σ-weighted squares).
    pub cost_before: f64,
    /// See `cost_before`.
    pub cost_after: f64,
    /// Median reprojection error of the sightings at the start and the end, in σs.
    pub median_error_sigmas_before: f64,
    /// See `median_error_sigmas_before`.
    pub median_error_sigmas_after: f64,
    /// Covariance of the launch velocity, (m/s)², scaled by the residuals' variance factor
    /// when they are wider than the pixel σ; `None` when singular.
    pub velocity_covariance: Option<Matrix3<f64>>,
}

/// Why no adjustment was made.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum BaError {
    /// Too few tracks were seen from two keyframes with enough parallax.
    #[error("{found} ground points seen from two keyframes with parallax, {needed} needed")]
    TooFewPoints {
        /// Points usable.
        found: usize,
        /// Points needed.
        needed: usize,
    },
    /// The start or a setting is not finite or not positive.
    #[error("bundle adjustment input not finite or not positive: {0}")]
    BadInput(&'static str),
    /// The normal equations could not be solved.
    #[error("bundle adjustment normal equations singular")]
    Singular,
}

#[cfg(test)]
mod tests;
