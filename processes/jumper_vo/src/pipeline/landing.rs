//! The ends of a hop: whether the launch happened at all, the touchdown, the slide to rest and
//! the frames on the ground.

use super::{JumperVo, Keyframe, Phase, STILL_FLOW_PX, Touchdown};
use crate::config::ScaleMethod;
use crate::output::{FrameInput, VoOutput, VoStatus};
use nalgebra::{Isometry3, Translation3, Vector3};

impl JumperVo {
    /// Adds an altimeter sample to [`Self::launch_llr`], while the commanded arc climbs.
    pub(super) fn weigh_launch(&mut self, tau: f64, altitude_m: f64) {
        let v = self.commanded_velocity_mps;
        let climbed_m = v.z * tau - 0.5 * self.config.gravity_mps2 * tau * tau;
        if v.z <= 0.0 || climbed_m <= 0.0 || tau * self.config.gravity_mps2 > v.z {
            return;
        }
        let z0 = self.fit.launch_position_m().z;
        let sigma = self.config.altimeter_sigma_m.max(1e-3);
        let stayed = altitude_m - z0;
        let flew = altitude_m - z0 - climbed_m;
        self.launch_llr += (stayed * stayed - flew * flew) / (2.0 * sigma * sigma);
    }

    /// True once the altimeter says the body stayed at its launch altitude (odds of
    /// e^[`FAILED_LAUNCH_LLR`] against the commanded climb), or the image has stayed still for
    /// [`FAILED_LAUNCH_STILL_FRAMES`] well-tracked frames while the fit still climbs. A real
    /// flight is never still (at 4 m/s and 10 m up the ground moves ~15 px per frame), and a
    /// still image on the way down is a landing. Near the ground a wedged body's small rocking
    /// moves the image more than that, hence the altimeter.
    pub(super) fn launch_failed(&mut self, tau: f64, tracked: usize) -> bool {
        let still = tracked >= self.config.min_tracked_features
            && self.tracks.median_flow_norm_px() < STILL_FLOW_PX;
        let climbing = self
            .fit
            .solve()
            .is_some_and(|v0| self.fit.velocity(&v0, tau).z > 0.0);
        if still && climbing {
            self.still_climbing_frames += 1;
        } else {
            self.still_climbing_frames = 0;
        }
        self.still_climbing_frames >= FAILED_LAUNCH_STILL_FRAMES
            || self.launch_llr < -FAILED_LAUNCH_LLR
    }

    pub(super) fn land(
        &mut self,
        input: &FrameInput<'_>,
        touchdown_tau: f64,
        tau: f64,
    ) -> VoOutput {
        let position = match self.config.scale_method {
            ScaleMethod::Ballistic => self
                .fit
                .position_m(touchdown_tau)
                .map(|p| p.coords)
                .unwrap_or(self.last_world_from_body.translation.vector),
            ScaleMethod::PaperEq4 => self.propagated_position(touchdown_tau.max(self.last_tau_s)),
        };
        let horizontal_velocity_mps = match self.config.scale_method {
            ScaleMethod::Ballistic => self
                .fit
                .solve()
                .map(|v0| self.fit.velocity(&v0, touchdown_tau))
                .unwrap_or(self.velocity_mps),
            ScaleMethod::PaperEq4 => self.velocity_mps,
        };
        self.land_at(input, position, horizontal_velocity_mps, touchdown_tau, tau)
    }

    /// Lands at `position` with `horizontal_velocity_mps` at `touchdown_tau`, now `tau`.
    pub(super) fn land_at(
        &mut self,
        input: &FrameInput<'_>,
        position: Vector3<f64>,
        horizontal_velocity_mps: Vector3<f64>,
        touchdown_tau: f64,
        tau: f64,
    ) -> VoOutput {
        self.phase = Phase::Landed;
        let mut horizontal_velocity_mps =
            Vector3::new(horizontal_velocity_mps.x, horizontal_velocity_mps.y, 0.0);
        let max = self.config.max_speed_mps;
        if !horizontal_velocity_mps.iter().all(|v| v.is_finite()) {
            horizontal_velocity_mps = Vector3::zeros();
        } else if horizontal_velocity_mps.norm() > max {
            horizontal_velocity_mps *= max / horizontal_velocity_mps.norm();
        }
        let touchdown = Touchdown {
            tau_s: touchdown_tau,
            position_m: position,
            horizontal_velocity_mps,
        };
        self.touchdown = Some(touchdown);
        let position = self.slid_position_m(&touchdown, tau);
        let pose = Isometry3::from_parts(
            Translation3::from(position),
            self.last_world_from_body.rotation,
        );
        self.tracks.reset();
        let _ = self.tracks.track(&input.image);
        let features = self.tracks.set_keyframe().unwrap_or(0);
        self.keyframe = Keyframe {
            world_from_cam: pose * self.body_from_camera,
            tau_s: tau,
            camera_altitude_m: None,
        };
        self.last_world_from_body = pose;
        self.last_tau_s = tau;
        self.landed_altitude_weight = LANDING_PRIOR_WEIGHT;
        self.landed_altitude_sum_m = LANDING_PRIOR_WEIGHT * position.z;
        self.velocity_mps = Vector3::zeros();
        self.angular_velocity_radps = Vector3::zeros();
        let mut out = self.output(input, VoStatus::Landed);
        out.confidence = 0.3;
        out.is_keyframe = true;
        out.tracked_features = features;
        out
    }

    /// Touchdown position plus the slide since (the landing cage's damping of the horizontal
    /// touchdown velocity, [`JumperVoConfig::landing_slide_decay_per_s`]).
    fn slid_position_m(&self, touchdown: &Touchdown, tau: f64) -> Vector3<f64> {
        let k = self.config.landing_slide_decay_per_s;
        let dt = (tau - touchdown.tau_s).max(0.0);
        if k <= 0.0 || !dt.is_finite() {
            return touchdown.position_m;
        }
        touchdown.position_m + touchdown.horizontal_velocity_mps * ((1.0 - (-k * dt).exp()) / k)
    }

    /// After touchdown: the position slides to rest (then is held), the altitude averages the
    /// altimeter, the rotation comes from vision when it works.
    pub(super) fn landed_frame(
        &mut self,
        input: &FrameInput<'_>,
        tau: f64,
        tracked: usize,
    ) -> VoOutput {
        let mut out = self.output(input, VoStatus::Landed);
        if let Some(touchdown) = self.touchdown {
            let p = self.slid_position_m(&touchdown, tau);
            out.world_from_body.translation.x = p.x;
            out.world_from_body.translation.y = p.y;
        }
        // On the ground the body altitude is constant: average the altimeter into it (the
        // fit's impact altitude is biased by any error of the fitted launch velocity).
        if let Some(z) = input.altimeter_m.filter(|z| z.is_finite()) {
            self.landed_altitude_sum_m += z;
            self.landed_altitude_weight += 1.0;
            out.world_from_body.translation.z =
                self.landed_altitude_sum_m / self.landed_altitude_weight;
        }
        out.tracked_features = tracked;
        if tracked >= self.config.min_tracked_features {
            self.x1.clear();
            self.x2.clear();
            let cam = self.camera;
            self.x1.extend(
                self.tracks
                    .keyframe_px()
                    .iter()
                    .map(|p| cam.pixel_f32_to_normalized(*p)),
            );
            self.x2.extend(
                self.tracks
                    .current_px()
                    .iter()
                    .map(|p| cam.pixel_f32_to_normalized(*p)),
            );
            let dt_s = (tau - self.last_tau_s).max(1e-3);
            if let Ok(est) = self.estimator.estimate(&self.x1, &self.x2, None) {
                let rotation = self.keyframe.world_from_cam.rotation
                    * est.cam2_from_cam1.rotation.inverse()
                    * self.body_from_camera.rotation.inverse();
                // Tumbling after the impact: vision rotations are not trusted; the body
                // holds its position and the estimate its low confidence.
                if rotation.angle_to(&self.last_world_from_body.rotation) / dt_s
                    <= self.config.max_angular_rate_radps
                {
                    out.world_from_body.rotation = rotation;
                    out.inliers = est.num_inliers;
                    out.model = Some(est.model);
                    out.confidence = 0.5;
                }
            }
        } else {
            self.tracks.retain(&[]);
            let _ = self.tracks.set_keyframe();
            let pose = self.last_world_from_body;
            self.keyframe.world_from_cam = pose * self.body_from_camera;
            out.is_keyframe = true;
        }
        self.last_world_from_body = out.world_from_body;
        self.last_tau_s = tau;
        out
    }
}

/// Weight of the fitted impact altitude against one altimeter sample after touchdown (the
/// fit's altitude σ is about half the altimeter's).
const LANDING_PRIOR_WEIGHT: f64 = 4.0;

/// Still frames while climbing after which a hop counts as never having left the ground.
const FAILED_LAUNCH_STILL_FRAMES: u32 = 3;

/// Log-odds against the commanded climb at which a hop counts as never having left the ground
/// (e^12: a real climb of a few metres reaches the opposite sign within a second).
const FAILED_LAUNCH_LLR: f64 = 12.0;
