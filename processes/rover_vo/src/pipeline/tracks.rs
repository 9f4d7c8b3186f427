//! The pipeline's map of tracked features: KLT tracking, stereo correspondences, inlier
//! pruning, new keyframe points, and the keyframe cloud built from them.

use super::{CloudPoint, RoverVo, StereoFrame};
use crate::motion::Correspondence;
use hopnav_vision::klt::TrackStatus;
use nalgebra::{Isometry3, Point2};

impl RoverVo {
    /// KLT from the previous left image; drops lost tracks. Returns the tracked count.
    pub(super) fn track(&mut self, predicted: &Isometry3<f64>) -> usize {
        if !self.have_prev || self.track_px.is_empty() {
            self.clear_tracks();
            return 0;
        }
        let camera_from_world = (predicted * self.rig.body_from_camera).inverse();
        self.next_px.clear();
        for (px, x) in self.track_px.iter().zip(&self.track_world) {
            let guess = self
                .rig
                .intrinsics
                .project(&(camera_from_world * x))
                .map_or(*px, |p| Point2::new(p.x as f32, p.y as f32));
            self.next_px.push(guess);
        }
        self.status.clear();
        self.status
            .resize(self.track_px.len(), TrackStatus::InvalidInput);
        if self
            .klt
            .track(
                &self.pyr_prev,
                &self.pyr_cur,
                &self.track_px,
                &mut self.next_px,
                &mut self.status,
                true,
            )
            .is_err()
        {
            self.clear_tracks();
            return 0;
        }
        let mut keep = 0;
        for i in 0..self.track_px.len() {
            if self.status[i] == TrackStatus::Tracked {
                self.move_track(i, keep, self.next_px[i]);
                keep += 1;
            }
        }
        self.truncate_tracks(keep);
        keep
    }

    /// Builds the correspondences of the tracks, with the current stereo points (searched
    /// around the disparity the predicted pose implies).
    pub(super) fn stereo_tracks(&mut self, frame: &StereoFrame<'_>, predicted: &Isometry3<f64>) {
        self.corrs.clear();
        let camera_from_world = (predicted * self.rig.body_from_camera).inverse();
        let fb = self.rig.intrinsics.fx_px * self.rig.baseline_m;
        for (px, x) in self.track_px.iter().zip(&self.track_world) {
            let z_m = (camera_from_world * x).z;
            let range = (z_m > 0.1).then(|| {
                let d = fb / z_m;
                let half = 3.0 + 0.3 * d;
                (d - half, d + half)
            });
            let point_camera_m = self
                .stereo
                .match_point_in_range(&frame.left, &frame.right, px.x, px.y, range)
                .ok()
                .map(|p| p.point_camera_m);
            self.corrs.push(Correspondence {
                point_world_m: *x,
                pixel: Point2::new(f64::from(px.x), f64::from(px.y)),
                point_camera_m,
            });
        }
    }

    /// Keeps only the tracks that were motion inliers.
    pub(super) fn keep_inliers(&mut self) {
        let mut keep = 0;
        for i in 0..self.track_px.len() {
            if self.motion.is_inlier(i) {
                self.move_track(i, keep, self.track_px[i]);
                self.corrs[keep] = self.corrs[i];
                keep += 1;
            }
        }
        self.truncate_tracks(keep);
        self.corrs.truncate(keep);
    }

    /// Moves track `from` to slot `to` (`to ≤ from`, compacting the map in place), at pixel
    /// `px`.
    fn move_track(&mut self, from: usize, to: usize, px: Point2<f32>) {
        self.track_px[to] = px;
        self.track_world[to] = self.track_world[from];
        self.track_sigma_m[to] = self.track_sigma_m[from];
        self.track_id[to] = self.track_id[from];
    }

    /// Keeps the first `len` tracks.
    pub(super) fn truncate_tracks(&mut self, len: usize) {
        self.track_px.truncate(len);
        self.track_world.truncate(len);
        self.track_sigma_m.truncate(len);
        self.track_id.truncate(len);
    }

    /// Detects corners away from the tracks, triangulates them from the current pose and adds
    /// them to the map. Returns how many were added.
    pub(super) fn add_keyframe_points(&mut self, frame: &StereoFrame<'_>) -> usize {
        let Some(level) = self.pyr_cur.level(0) else {
            return 0;
        };
        if self
            .detector
            .detect(level, &self.track_px, &mut self.corners)
            .is_err()
        {
            return 0;
        }
        let world_from_camera = self.world_from_body * self.rig.body_from_camera;
        let mut added = 0;
        for c in &self.corners {
            if self.track_px.len() >= self.config.max_features {
                break;
            }
            let Ok(p) = self.stereo.match_point(
                &frame.left,
                &frame.right,
                c.position_px.x,
                c.position_px.y,
            ) else {
                continue;
            };
            self.track_px.push(c.position_px);
            self.track_world.push(world_from_camera * p.point_camera_m);
            self.track_sigma_m.push(p.depth_sigma_m);
            self.track_id.push(self.next_id);
            self.next_id = self.next_id.wrapping_add(1);
            added += 1;
        }
        added
    }

    /// The keyframe cloud: every map point, with its height above the local ground.
    pub(super) fn build_cloud(&mut self) {
        self.cloud_points.clear();
        self.cloud_points.extend_from_slice(&self.track_world);
        self.ground.heights(
            &self.cloud_points,
            self.config.ground_radius_m,
            self.config.ground_keep_fraction,
            &mut self.heights,
        );
        self.cloud.clear();
        for i in 0..self.track_world.len() {
            self.cloud.push(CloudPoint {
                position_m: self.track_world[i],
                height_above_ground_m: self.heights.get(i).copied().unwrap_or(f64::NAN),
                depth_sigma_m: self.track_sigma_m[i],
                track_id: self.track_id[i],
            });
        }
    }
}
