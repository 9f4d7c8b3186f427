//! A keyframe's cloud from its tracks: each triangulated over its whole age, from the keyframe
//! its corner was born in (see [`JumperVoConfig::cloud_track_keyframes`]), where that checks
//! out, else over the last keyframe interval.
//!
//! [`JumperVoConfig::cloud_track_keyframes`]: crate::config::JumperVoConfig

use super::JumperVo;
use super::keyframe_history::KeyframeRecord;
use crate::cloud::{
    MAX_REPROJECTION_ERROR_PX, TwoViews, WorldPoint, reprojects_within, triangulate_views,
};
use crate::config::ScaleMethod;
use nalgebra::{Isometry3, Translation3};

impl JumperVo {
    /// The RANSAC inliers of the current pair triangulated to `world_from_cam` (this
    /// keyframe): from their birth keyframe when the point reprojects into the birth view, the
    /// last keyframe `world_from_cam1` and this one, else between the last keyframe and this.
    pub(super) fn triangulate_keyframe_cloud(
        &self,
        world_from_cam1: &Isometry3<f64>,
        world_from_cam: &Isometry3<f64>,
    ) -> Vec<WorldPoint> {
        let now_from_world = world_from_cam.inverse();
        let focal_px = self.camera.mean_focal_px();
        let inliers = self.estimator.inliers();
        let mut points = Vec::with_capacity(inliers.len());
        for &i in inliers {
            let (Some(x_first), Some(x_now)) = (self.x1.get(i), self.x2.get(i)) else {
                continue;
            };
            let pair = TwoViews {
                world_from_first: *world_from_cam1,
                x_first: *x_first,
                x_now: *x_now,
                intervals: 1,
            };
            let point = self
                .birth_views(i)
                .and_then(|views| triangulate_views(&now_from_world, &views, focal_px))
                .filter(|point| {
                    reprojects_within(
                        world_from_cam1,
                        point,
                        x_first,
                        focal_px,
                        MAX_REPROJECTION_ERROR_PX,
                    )
                })
                .or_else(|| triangulate_views(&now_from_world, &pair, focal_px));
            points.extend(point);
        }
        points
    }

    /// Remembers the keyframe just set, under the tracker's serial.
    pub(super) fn record_keyframe(&mut self) {
        self.history.record(KeyframeRecord {
            serial: self.tracks.keyframe_serial(),
            launch_t_s: self.launch_t_s,
            tau_s: self.keyframe.tau_s,
            world_from_cam: self.keyframe.world_from_cam,
        });
    }

    /// Track `i` seen from the keyframe it was born in and now, when that keyframe is older
    /// than the current one and within `cloud_track_keyframes`. The birth camera's position
    /// is the fit's at that instant (plus the lever arm), as the current keyframe's is.
    fn birth_views(&self, i: usize) -> Option<TwoViews> {
        let serial = *self.tracks.birth_serial().get(i)?;
        let age = self.tracks.keyframe_serial().wrapping_sub(serial);
        if age == 0 || age > self.config.cloud_track_keyframes.saturating_sub(1) {
            return None;
        }
        let record = self.history.get(serial, self.launch_t_s)?;
        // The birth keyframe's attitude as the flight's latest fit has it.
        let rotation = if self.config.attitude_from_spin_fit {
            self.spin.attitude_at(record.tau_s) * self.body_from_camera.rotation
        } else {
            record.rotation()
        };
        let centre_m = match self.config.scale_method {
            ScaleMethod::Ballistic => {
                let lever =
                    self.lever_world(&(rotation * self.body_from_camera.rotation.inverse()));
                self.fit.position_m(record.tau_s)?.coords + lever
            }
            ScaleMethod::PaperEq4 => record.world_from_cam.translation.vector,
        };
        let birth_px = self.tracks.birth_px().get(i)?;
        Some(TwoViews {
            world_from_first: Isometry3::from_parts(Translation3::from(centre_m), rotation),
            x_first: self.camera.pixel_f32_to_normalized(*birth_px),
            x_now: *self.x2.get(i)?,
            intervals: age + 1,
        })
    }
}
