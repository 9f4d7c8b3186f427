//! The vision estimate of a frame against the keyframe: the two-view solution, its inlier
//! parallax, and the position it scales to.

use super::{Estimate, JumperVo};
use crate::config::ScaleMethod;
use crate::scale;
use hopnav_vision::two_view::{MotionModel, TwoViewEstimate};
use nalgebra::{Isometry3, Point2, Translation3, Unit, UnitQuaternion, Vector3};

/// A position measured along the vision direction from the keyframe.
#[derive(Debug, Clone, Copy)]
struct ScaledPosition {
    /// Body position, world frame, metres.
    position_m: Vector3<f64>,
    /// Distance along the direction, metres.
    scale_m: f64,
    /// Keyframe camera centre it was measured from, world frame, metres.
    keyframe_center_m: Vector3<f64>,
}

/// Where the cameras were at the keyframe and now: the lever arms (body origin to camera,
/// world frame) and the keyframe camera centre.
#[derive(Debug, Clone, Copy)]
struct Levers {
    keyframe_m: Vector3<f64>,
    current_m: Vector3<f64>,
    keyframe_center_m: Vector3<f64>,
}

impl JumperVo {
    /// Vision estimate against the keyframe; `None` on starvation or geometric failure.
    pub(super) fn estimate(
        &mut self,
        tau: f64,
        tracked: usize,
        altitude: Option<f64>,
    ) -> Option<Estimate> {
        let est = self.two_view(tracked)?;
        let rel = est.cam2_from_cam1;
        let median_parallax_rad = self.inlier_parallax_rad(&rel);
        self.mark_inliers();
        let vision_cam_rotation = self.keyframe.world_from_cam.rotation * rel.rotation.inverse();
        let vision_body_rotation = vision_cam_rotation * self.body_from_camera.rotation.inverse();
        if !self.rate_is_plausible(tau, &vision_body_rotation) {
            return None;
        }
        // The world-frame rotation since the keyframe, as vision measured it.
        let rotation_since_keyframe =
            vision_cam_rotation * self.keyframe.world_from_cam.rotation.inverse();
        let body_rotation = if self.config.attitude_from_spin_fit {
            self.spin.attitude_at(tau)
        } else {
            vision_body_rotation
        };
        let levers = Levers {
            keyframe_m: self.lever_world(
                &(self.keyframe.world_from_cam.rotation * self.body_from_camera.rotation.inverse()),
            ),
            current_m: self.lever_world(&body_rotation),
            keyframe_center_m: self.keyframe.world_from_cam.translation.vector,
        };
        let usable_translation = est.model != MotionModel::PureRotation
            && median_parallax_rad >= self.config.keyframe_min_parallax_deg.to_radians();
        let scaled = if usable_translation {
            self.scaled_position(tau, altitude, &rel, &levers)
        } else {
            None
        };
        let position = scaled
            .map(|s| s.position_m)
            .unwrap_or_else(|| self.propagated_position(tau));
        Some(Estimate {
            world_from_body: Isometry3::from_parts(Translation3::from(position), body_rotation),
            model: est.model,
            inliers: self.estimator.inliers().len(),
            tracked,
            median_parallax_rad,
            scale_m: scaled.map(|s| s.scale_m),
            keyframe_center_m: scaled.map_or(levers.keyframe_center_m, |s| s.keyframe_center_m),
            rotation_since_keyframe,
            vision_body_rotation,
        })
    }

    /// The two-view solution of the tracks between the keyframe and this frame, if there are
    /// enough tracks and inliers.
    fn two_view(&mut self, tracked: usize) -> Option<TwoViewEstimate> {
        if tracked < self.config.min_tracked_features {
            return None;
        }
        self.x1.clear();
        self.x2.clear();
        let cam = self.camera;
        let to_norm = |p: &Point2<f32>| cam.pixel_f32_to_normalized(*p);
        self.x1
            .extend(self.tracks.keyframe_px().iter().map(to_norm));
        self.x2.extend(self.tracks.current_px().iter().map(to_norm));
        let down_cam_kf =
            Unit::new_normalize(self.keyframe.world_from_cam.rotation.inverse() * -Vector3::z());
        let est = self
            .estimator
            .estimate(&self.x1, &self.x2, Some(&down_cam_kf));
        let est = est.ok()?;
        let inliers = self.estimator.inliers();
        if inliers.len() < self.config.min_tracked_features
            || (inliers.len() as f64) < self.config.min_inlier_ratio * tracked as f64
        {
            return None;
        }
        Some(est)
    }

    /// Median rotation-compensated parallax of the inliers under `rel`, radians.
    fn inlier_parallax_rad(&mut self, rel: &Isometry3<f64>) -> f64 {
        self.parallax.clear();
        for &i in self.estimator.inliers() {
            let b1 = rel.rotation * self.x1[i].push(1.0).normalize();
            let b2 = self.x2[i].push(1.0).normalize();
            self.parallax.push(b1.angle(&b2));
        }
        let mid = self.parallax.len() / 2;
        *self.parallax.select_nth_unstable_by(mid, f64::total_cmp).1
    }

    /// Flags the two-view inliers in `keep`, one flag per track.
    fn mark_inliers(&mut self) {
        self.keep.clear();
        self.keep.resize(self.x1.len(), false);
        for &i in self.estimator.inliers() {
            self.keep[i] = true;
        }
    }

    /// Whether the rotation since the last vision attitude is within the angular-rate limit.
    /// Torque-free flight keeps its angular rate: a jump is a wrong two-view solution (planar
    /// twofold ambiguity) or an impact, never motion to integrate.
    fn rate_is_plausible(&self, tau: f64, vision_body_rotation: &UnitQuaternion<f64>) -> bool {
        let dt_last_s = (tau - self.last_tau_s).max(1e-3);
        let last_rotation = self
            .last_vision_body_rotation
            .unwrap_or(self.last_world_from_body.rotation);
        let rate_radps = vision_body_rotation.angle_to(&last_rotation) / dt_last_s;
        !(rate_radps.is_nan() || rate_radps > self.config.max_angular_rate_radps)
    }

    /// The position along the two-view direction from the keyframe, scaled by the configured
    /// method (`None` without a direction or a scale).
    fn scaled_position(
        &mut self,
        tau: f64,
        altitude: Option<f64>,
        rel: &Isometry3<f64>,
        levers: &Levers,
    ) -> Option<ScaledPosition> {
        let dir_cam_kf = -(rel.rotation.inverse() * rel.translation.vector);
        let d = self.keyframe.world_from_cam.rotation * dir_cam_kf;
        let d = d.try_normalize(1e-9)?;
        match self.config.scale_method {
            ScaleMethod::Ballistic => self.ballistic_position(tau, &d, levers),
            ScaleMethod::PaperEq4 => Some(self.paper_eq4_position(tau, altitude, &d, levers)),
        }
    }

    /// Adds direction `d` to the ballistic fit and scales it by the fit.
    fn ballistic_position(
        &mut self,
        tau: f64,
        d: &Vector3<f64>,
        levers: &Levers,
    ) -> Option<ScaledPosition> {
        let offset = levers.current_m - levers.keyframe_m;
        self.fit.add_direction(
            self.keyframe.tau_s,
            tau,
            d,
            &offset,
            self.config.direction_sigma_rad,
        );
        let s = scale::ballistic(&self.fit, self.keyframe.tau_s, tau, d, &offset)?;
        // Re-anchor the keyframe on the current fit, then follow the ray.
        let anchor = self
            .fit
            .position_m(self.keyframe.tau_s)
            .map(|p| p.coords + levers.keyframe_m)
            .unwrap_or(levers.keyframe_center_m);
        Some(ScaledPosition {
            position_m: anchor + d * s - levers.current_m,
            scale_m: s,
            keyframe_center_m: anchor,
        })
    }

    /// Scales direction `d` by the paper's eq. 4 on the altimeter, else by the last speed.
    fn paper_eq4_position(
        &self,
        tau: f64,
        altitude: Option<f64>,
        d: &Vector3<f64>,
        levers: &Levers,
    ) -> ScaledPosition {
        let dt_kf = (tau - self.keyframe.tau_s).max(1e-3);
        let max_scale = self.config.max_speed_mps * dt_kf;
        let lambda = match (self.keyframe.camera_altitude_m, altitude) {
            (Some(za), Some(zb)) => {
                scale::paper_eq4(za, zb + levers.current_m.z, d, 0.05, max_scale)
            }
            _ => None,
        };
        let lambda = lambda.unwrap_or_else(|| {
            // Singular or missing: keep the last speed (ballistic).
            let v_mid = self.velocity_mps - Vector3::z() * (0.5 * self.config.gravity_mps2 * dt_kf);
            (v_mid * dt_kf).norm()
        });
        ScaledPosition {
            position_m: levers.keyframe_center_m + d * lambda - levers.current_m,
            scale_m: lambda,
            keyframe_center_m: levers.keyframe_center_m,
        }
    }
}
