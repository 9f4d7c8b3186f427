//! The pipeline's side of the local bundle adjustment ([`crate::flight_ba`]): each flight
//! keyframe's tracks go into the hop's window, the adjustment runs, and an accepted result
//! becomes the flight's launch velocity, spin and launch attitude for the fits.

use super::JumperVo;
use crate::flight_ba::{self, BaOutcome, BaSettings, FlightModel, FlightParams, FlightPrior};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// Ground points an adjustment needs.
const MIN_POINTS: usize = 30;
/// Levenberg–Marquardt iterations per keyframe.
const MAX_ITERATIONS: usize = 10;
/// Rays of a point must meet at this angle at least (degrees) to give it a depth.
const MIN_RAY_ANGLE_DEG: f64 = 0.5;
/// An adjustment that leaves the median sighting further off than this (σs) is not taken.
const MAX_MEDIAN_ERROR_SIGMAS: f64 = 3.0;

/// What the bundle adjustment did over the VO's life.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BaStats {
    /// Adjustments tried (flight keyframes with the adjustment on).
    pub tried: u64,
    /// Adjustments whose result the fits took.
    pub accepted: u64,
    /// The last accepted result.
    pub last: Option<BaOutcome>,
}

impl JumperVo {
    /// What the bundle adjustment did so far.
    pub fn ba_stats(&self) -> BaStats {
        self.ba_stats
    }

    /// The flight model of the current hop.
    fn flight_model(&self) -> FlightModel {
        FlightModel {
            launch_position_m: self.fit.launch_position_m().coords,
            launch_rotation: self.launch_world_from_body.rotation,
            gravity_mps2: self.config.gravity_mps2,
            body_from_camera: self.body_from_camera,
        }
    }

    /// Records the tracks of the keyframe just set at `tau` and, with the adjustment on, runs
    /// it. Returns the refined body pose at `tau` when the fits took a result.
    pub(super) fn adjust_at_keyframe(&mut self, tau: f64) -> Option<Isometry3<f64>> {
        // A keyframe that sees nothing (sky, a black frame) would only push seeing ones out
        // of the window, and an adjustment without new sightings has nothing to add.
        if self.tracks.track_id().is_empty() {
            return None;
        }
        let camera = self.camera;
        let tracks = self
            .tracks
            .track_id()
            .iter()
            .zip(self.tracks.current_px())
            .map(|(&id, px)| (id, camera.pixel_f32_to_normalized(*px)));
        self.ba_window.add_keyframe(tau, tracks);
        if !self.config.bundle_adjustment || self.ba_window.keyframes() < 3 {
            return None;
        }
        self.ba_stats.tried += 1;
        let model = self.flight_model();
        let start = FlightParams {
            velocity_mps: self.fit.solve().unwrap_or(self.commanded_velocity_mps),
            rate_radps: self.spin.rate_radps(),
            attitude_correction_rad: self.ba_attitude_correction_rad,
        };
        let outcome = flight_ba::adjust(
            &model,
            &self.flight_prior(),
            &self.ba_settings(),
            &start,
            self.ba_window.sightings(),
            self.ba_window.altitudes(),
        )
        .ok()
        .filter(|o| o.median_error_sigmas_after <= MAX_MEDIAN_ERROR_SIGMAS)?;
        let params = outcome.params;
        self.ba_stats.accepted += 1;
        self.ba_stats.last = Some(outcome);
        self.ba_attitude_correction_rad = params.attitude_correction_rad;
        self.fit
            .set_refined(&params.velocity_mps, outcome.velocity_covariance);
        let launch = UnitQuaternion::from_scaled_axis(params.attitude_correction_rad)
            * model.launch_rotation;
        self.spin.set_refined(&params.rate_radps, &launch);
        Some(model.world_from_body(&params, tau))
    }

    /// The adjustment's priors: the commanded launch and spin (the spin only while the spin
    /// fit has not doubted it) and the resting attitude.
    fn flight_prior(&self) -> FlightPrior {
        let commanded = self.config.launch_speed_mps > 0.0;
        FlightPrior {
            mean: FlightParams {
                velocity_mps: self.commanded_velocity_mps,
                rate_radps: self.spin.prior_radps(),
                attitude_correction_rad: Vector3::zeros(),
            },
            velocity_sigma_mps: if commanded {
                self.config.launch_velocity_sigma_mps
            } else {
                0.0
            },
            rate_sigma_radps: if self.spin.prior_doubted() {
                0.0
            } else {
                self.config.launch_angular_velocity_sigma_radps
            },
            attitude_sigma_rad: self.config.ba_launch_attitude_sigma_rad,
        }
    }

    fn ba_settings(&self) -> BaSettings {
        BaSettings {
            sighting_sigma: self.config.pixel_sigma_px / self.camera.mean_focal_px(),
            robust_scale_sigmas: self.config.ba_robust_scale_sigmas,
            altimeter_sigma_m: self.config.altimeter_sigma_m,
            max_iterations: MAX_ITERATIONS,
            min_points: MIN_POINTS,
            min_ray_angle_rad: MIN_RAY_ANGLE_DEG.to_radians(),
        }
    }
}
