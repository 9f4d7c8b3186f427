//! The vision estimate of a frame against the keyframe: the two-view solution, its inlier
//! parallax, and the position it scales to.

use super::{Estimate, JumperVo};
use crate::config::ScaleMethod;
use crate::scale;
use hopnav_vision::two_view::MotionModel;
use nalgebra::{Isometry3, Point2, Translation3, Unit, Vector3};

impl JumperVo {
    /// Vision estimate against the keyframe; `None` on starvation or geometric failure.
    pub(super) fn estimate(
        &mut self,
        tau: f64,
        tracked: usize,
        altitude: Option<f64>,
    ) -> Option<Estimate> {
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
        // Rotation-compensated parallax of the inliers.
        let rel = est.cam2_from_cam1;
        self.parallax.clear();
        for &i in inliers {
            let b1 = rel.rotation * self.x1[i].push(1.0).normalize();
            let b2 = self.x2[i].push(1.0).normalize();
            self.parallax.push(b1.angle(&b2));
        }
        let mid = self.parallax.len() / 2;
        let median_parallax_rad = *self.parallax.select_nth_unstable_by(mid, f64::total_cmp).1;
        self.keep.clear();
        self.keep.resize(self.x1.len(), false);
        for &i in inliers {
            self.keep[i] = true;
        }
        let vision_cam_rotation = self.keyframe.world_from_cam.rotation * rel.rotation.inverse();
        let vision_body_rotation = vision_cam_rotation * self.body_from_camera.rotation.inverse();
        let dt_last_s = (tau - self.last_tau_s).max(1e-3);
        let last_rotation = self
            .last_vision_body_rotation
            .unwrap_or(self.last_world_from_body.rotation);
        let rate_radps = vision_body_rotation.angle_to(&last_rotation) / dt_last_s;
        if rate_radps.is_nan() || rate_radps > self.config.max_angular_rate_radps {
            // Torque-free flight keeps its angular rate: a jump is a wrong two-view solution
            // (planar twofold ambiguity) or an impact, never motion to integrate.
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
        let lever_kf = self.lever_world(
            &(self.keyframe.world_from_cam.rotation * self.body_from_camera.rotation.inverse()),
        );
        let lever_cur = self.lever_world(&body_rotation);
        let center_kf = self.keyframe.world_from_cam.translation.vector;
        let mut position = None;
        let mut scale_m = None;
        let mut keyframe_center_m = center_kf;
        let usable_translation = est.model != MotionModel::PureRotation
            && median_parallax_rad >= self.config.keyframe_min_parallax_deg.to_radians();
        if usable_translation {
            let dir_cam_kf = -(rel.rotation.inverse() * rel.translation.vector);
            let d = self.keyframe.world_from_cam.rotation * dir_cam_kf;
            if let Some(d) = d.try_normalize(1e-9) {
                let offset = lever_cur - lever_kf;
                match self.config.scale_method {
                    ScaleMethod::Ballistic => {
                        self.fit.add_direction(
                            self.keyframe.tau_s,
                            tau,
                            &d,
                            &offset,
                            self.config.direction_sigma_rad,
                        );
                        if let Some(s) =
                            scale::ballistic(&self.fit, self.keyframe.tau_s, tau, &d, &offset)
                        {
                            // Re-anchor the keyframe on the current fit, then follow the ray.
                            let anchor = self
                                .fit
                                .position_m(self.keyframe.tau_s)
                                .map(|p| p.coords + lever_kf)
                                .unwrap_or(center_kf);
                            scale_m = Some(s);
                            keyframe_center_m = anchor;
                            position = Some(anchor + d * s - lever_cur);
                        }
                    }
                    ScaleMethod::PaperEq4 => {
                        let dt_kf = (tau - self.keyframe.tau_s).max(1e-3);
                        let max_scale = self.config.max_speed_mps * dt_kf;
                        let lambda = match (self.keyframe.camera_altitude_m, altitude) {
                            (Some(za), Some(zb)) => {
                                scale::paper_eq4(za, zb + lever_cur.z, &d, 0.05, max_scale)
                            }
                            _ => None,
                        };
                        let lambda = lambda.unwrap_or_else(|| {
                            // Singular or missing: keep the last speed (ballistic).
                            let v_mid = self.velocity_mps
                                - Vector3::z() * (0.5 * self.config.gravity_mps2 * dt_kf);
                            (v_mid * dt_kf).norm()
                        });
                        scale_m = Some(lambda);
                        position = Some(center_kf + d * lambda - lever_cur);
                    }
                }
            }
        }
        let position = position.unwrap_or_else(|| self.propagated_position(tau));
        Some(Estimate {
            world_from_body: Isometry3::from_parts(Translation3::from(position), body_rotation),
            model: est.model,
            inliers: inliers.len(),
            tracked,
            median_parallax_rad,
            scale_m,
            keyframe_center_m,
            rotation_since_keyframe,
            vision_body_rotation,
        })
    }
}
