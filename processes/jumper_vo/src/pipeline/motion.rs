//! The hop's motion between vision fixes: the ballistic fit's descent and impact, the
//! propagated pose when vision has nothing to say, and the rates it propagates with.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{JumperVo, Keyframe, Phase};
use crate::config::ScaleMethod;
use crate::output::{FrameInput, VoOutput, VoStatus};

impl JumperVo {
    /// Fitted body height above the launch altitude at `tau`, when the fit is descending
    /// (past the apex, after the first second with enough altimeter samples).
    pub(super) fn descent_height_m(&self, tau: f64) -> Option<f64> {
        if tau <= 1.0 || self.fit.altitude_rows() < 10 {
            return None;
        }
        let v0 = self.fit.solve()?;
        if self.fit.velocity(&v0, tau).z >= 0.0 {
            return None;
        }
        Some(self.fit.predict(&v0, tau).z - self.fit.launch_position_m().z)
    }

    /// Impact time for a vision breakdown seen at `tau`: the fit's return to the launch
    /// altitude if it falls between the last good frame and this one, else the midpoint.
    pub(super) fn impact_tau_s(&self, tau: f64) -> f64 {
        let last = self.last_tau_s;
        match self.fit.touchdown_tau_s() {
            Some(td) if td >= last && td <= tau => td,
            _ => 0.5 * (last + tau),
        }
    }

    pub(super) fn propagated_position(&self, tau: f64) -> Vector3<f64> {
        match self.config.scale_method {
            ScaleMethod::Ballistic => self
                .fit
                .position_m(tau)
                .map(|p| p.coords)
                .unwrap_or(self.last_world_from_body.translation.vector),
            ScaleMethod::PaperEq4 => {
                let dt = tau - self.last_tau_s;
                self.last_world_from_body.translation.vector + self.velocity_mps * dt
                    - Vector3::z() * (0.5 * self.config.gravity_mps2 * dt * dt)
            }
        }
    }

    pub(super) fn update_rates(&mut self, new: &Isometry3<f64>, tau: f64, rotation_valid: bool) {
        let dt = tau - self.last_tau_s;
        if dt > 0.0 {
            let v = (new.translation.vector - self.last_world_from_body.translation.vector) / dt
                - Vector3::z() * (0.5 * self.config.gravity_mps2 * dt);
            if v.iter().all(|x| x.is_finite()) {
                // Clamped: a singular eq. (4) step must not feed back into the propagation.
                let max = self.config.max_speed_mps;
                self.velocity_mps = if v.norm() > max {
                    v * (max / v.norm())
                } else {
                    v
                };
            }
            if rotation_valid {
                let w = (new.rotation * self.last_world_from_body.rotation.inverse()).scaled_axis()
                    / dt;
                if w.iter().all(|x| x.is_finite()) {
                    self.angular_velocity_radps = w;
                }
            }
        }
        self.last_world_from_body = *new;
        self.last_tau_s = tau;
    }

    pub(super) fn propagate(
        &mut self,
        input: &FrameInput<'_>,
        tau: f64,
        tracked: usize,
        altitude: Option<f64>,
    ) -> VoOutput {
        let dt = tau - self.last_tau_s;
        let rotation = if self.config.attitude_from_spin_fit {
            self.spin.attitude_at(tau)
        } else {
            UnitQuaternion::from_scaled_axis(self.angular_velocity_radps * dt)
                * self.last_world_from_body.rotation
        };
        let position = self.propagated_position(tau);
        let pose = Isometry3::from_parts(Translation3::from(position), rotation);
        self.last_vision_body_rotation = Some(rotation);
        // Restart tracking from this frame.
        self.tracks.retain(&[]);
        let features = self.tracks.set_keyframe().unwrap_or(0);
        let pose = self.adjust_at_keyframe(tau).unwrap_or(pose);
        let world_from_cam = pose * self.body_from_camera;
        let lever = self.lever_world(&rotation);
        self.keyframe = Keyframe {
            world_from_cam,
            tau_s: tau,
            camera_altitude_m: altitude
                .map(|z| z + lever.z)
                .or(Some(world_from_cam.translation.z)),
        };
        self.record_keyframe();
        let w = self.angular_velocity_radps;
        self.update_rates(&pose, tau, false);
        self.angular_velocity_radps = w;
        let mut out = self.output(input, VoStatus::Propagating);
        out.confidence = 0.1;
        out.is_keyframe = true;
        out.tracked_features = tracked.max(features);
        out
    }

    /// σ of the position `tau` after the launch, relative to the launch point: the launch
    /// velocity's covariance carried over `tau`, and after a landing the slide's scatter on
    /// top of the touchdown's. NaN while the velocity is unobservable.
    pub(super) fn position_sigma_m(&self, tau: f64) -> f64 {
        let flight_sigma = |tau: f64| {
            self.fit
                .velocity_covariance()
                .map_or(f64::NAN, |c| tau.max(0.0) * c.trace().max(0.0).sqrt())
        };
        match (self.phase, self.touchdown) {
            (Phase::Landed, Some(touchdown)) => {
                let slide = self.config.landing_slide_sigma_m;
                (flight_sigma(touchdown.tau_s).powi(2) + 2.0 * slide * slide).sqrt()
            }
            (Phase::WaitingFirstFrame, _) => 0.0,
            _ => flight_sigma(tau),
        }
    }
}
