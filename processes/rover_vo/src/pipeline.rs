//! The rover stereo VO pipeline, one call per stereo frame ([`RoverVo::process_frame`]).
//!
//! Per frame: build the left pyramid; KLT-track the map features from the previous left image
//! (initial guesses from the IMU-predicted pose); stereo-match the tracked features in the
//! current pair; RANSAC (2-point with IMU roll/pitch, else 3-point) + Gauss–Newton on the
//! reprojection error of the **world-frame** map points (frame-to-map, so errors do not
//! accumulate between keyframes). At a keyframe (too few tracks, or enough motion since the
//! last one) new corners are detected, stereo-triangulated from the current pose and added to
//! the map, and a world-frame cloud with heights above the local ground is produced.
//!
//! When a frame cannot be trusted (textureless view, stereo pair that disagrees, too few
//! inliers), the pose is propagated: attitude from the IMU (relative to the last good frame),
//! position held, confidence < 0.5; the map is rebuilt from the held pose as soon as the
//! stereo pair gives enough points again.
//!
//! Buffers are allocated in [`RoverVo::new`]; `process_frame` does not allocate.

use crate::config::RoverVoConfig;
use crate::ground::{GroundModel, LocalGround};
use crate::motion::{Correspondence, Intrinsics, MotionEstimate, MotionEstimator, Tilt};
use crate::stereo::{StereoMatcher, StereoParams};
use hopnav_vision::corners::{Corner, CornerConfig, CornerDetector, CornerError};
use hopnav_vision::image::ImageView;
use hopnav_vision::klt::{KltConfig, KltError, KltTracker, TrackStatus};
use hopnav_vision::pyramid::{Pyramid, PyramidConfig, PyramidError};
use nalgebra::{Isometry3, Point2, Point3, UnitQuaternion, Vector3};

mod tracks;

/// Error creating the pipeline.
#[derive(Debug, thiserror::Error)]
pub enum VoError {
    /// The configuration is invalid.
    #[error(transparent)]
    Config(#[from] crate::config::ConfigError),
    /// The stereo geometry is invalid.
    #[error(transparent)]
    Stereo(#[from] crate::stereo::StereoError),
    /// The pyramid could not be created (image too small).
    #[error(transparent)]
    Pyramid(#[from] PyramidError),
    /// The tracker could not be created.
    #[error(transparent)]
    Klt(#[from] KltError),
    /// The corner detector could not be created.
    #[error(transparent)]
    Corners(#[from] CornerError),
}

/// Stereo rig geometry (from the image header).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoRig {
    /// View width, pixels.
    pub width_px: u32,
    /// View height, pixels.
    pub height_px: u32,
    /// Intrinsics of both (rectified) views.
    pub intrinsics: Intrinsics,
    /// Baseline, metres; the right camera is along the left camera's +x.
    pub baseline_m: f64,
    /// Left camera on the rover body.
    pub body_from_camera: Isometry3<f64>,
}

/// One stereo frame.
#[derive(Debug, Clone, Copy)]
pub struct StereoFrame<'a> {
    /// Left view.
    pub left: ImageView<'a>,
    /// Right view.
    pub right: ImageView<'a>,
    /// IMU `world_from_body` attitude, if a sample arrived.
    pub imu_attitude: Option<UnitQuaternion<f64>>,
}

/// What the pose of a frame is based on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VoStatus {
    /// Vision estimate from tracked map points.
    Tracking,
    /// Map (re)built at this frame from the stereo pair; pose kept.
    Initialized,
    /// No trustworthy vision: attitude from the IMU, position held.
    Propagated,
}

/// Why a frame's vision estimate was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejection {
    /// The left image could not be processed.
    BadImage,
    /// No map yet (start, or after a loss).
    NoMap,
    /// Too few tracked features.
    TooFewTracks,
    /// RANSAC failed.
    Motion(crate::motion::MotionError),
    /// Too few inliers.
    FewInliers,
    /// Too small an inlier share of the tracks.
    LowInlierRatio,
    /// The estimated step is implausibly large.
    ImplausibleStep,
}

/// Result of one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoOutput {
    /// Why the vision estimate was not used (`None`: it was).
    pub rejection: Option<Rejection>,
    /// Estimated pose.
    pub world_from_body: Isometry3<f64>,
    /// 0–1; below 0.5 the pose is propagated.
    pub confidence: f64,
    /// What the pose is based on.
    pub status: VoStatus,
    /// Features tracked into this frame.
    pub tracked_features: usize,
    /// RANSAC inliers.
    pub inliers: usize,
    /// Whether this frame is a keyframe (a cloud is available in [`RoverVo::cloud`]).
    pub is_keyframe: bool,
}

/// A world-frame cloud point of a keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudPoint {
    /// World position, metres.
    pub position_m: Point3<f64>,
    /// Height above the local ground, metres (`NaN` if unknown).
    pub height_above_ground_m: f64,
    /// Depth σ when triangulated, metres.
    pub depth_sigma_m: f64,
    /// Track id.
    pub track_id: u32,
}

/// The pose expected for a frame before vision, from the IMU and the last motion.
struct Prediction {
    /// Predicted `world_from_body` (the tracker's initial guess).
    predicted: Isometry3<f64>,
    /// What the pose becomes without vision: predicted attitude, position held.
    held: Isometry3<f64>,
    /// IMU roll and pitch for the motion estimate, if used.
    tilt: Option<Tilt>,
}

/// The stereo VO.
pub struct RoverVo {
    config: RoverVoConfig,
    rig: StereoRig,
    stereo: StereoMatcher,
    pyr_prev: Pyramid,
    pyr_cur: Pyramid,
    klt: KltTracker,
    detector: CornerDetector,
    motion: MotionEstimator,
    ground: LocalGround,
    // Map: parallel arrays, one entry per track.
    track_px: Vec<Point2<f32>>,
    track_world: Vec<Point3<f64>>,
    track_sigma_m: Vec<f64>,
    track_id: Vec<u32>,
    // Scratch.
    next_px: Vec<Point2<f32>>,
    status: Vec<TrackStatus>,
    corrs: Vec<Correspondence>,
    corners: Vec<Corner>,
    cloud: Vec<CloudPoint>,
    cloud_points: Vec<Point3<f64>>,
    heights: Vec<f64>,
    // State.
    world_from_body: Isometry3<f64>,
    last_motion: Isometry3<f64>,
    keyframe_pose: Isometry3<f64>,
    imu_prev: Option<UnitQuaternion<f64>>,
    next_id: u32,
    have_prev: bool,
}

impl RoverVo {
    /// A pipeline starting at `world_from_body`.
    pub fn new(
        config: RoverVoConfig,
        rig: StereoRig,
        world_from_body: Isometry3<f64>,
    ) -> Result<Self, VoError> {
        config.validate()?;
        let (w, h) = (rig.width_px as usize, rig.height_px as usize);
        let k = rig.intrinsics;
        let stereo = StereoMatcher::new(
            rig.width_px,
            rig.height_px,
            StereoParams {
                fx_px: k.fx_px,
                fy_px: k.fy_px,
                cx_px: k.cx_px,
                cy_px: k.cy_px,
                baseline_m: rig.baseline_m,
                min_disparity_px: config.min_disparity_px,
                max_disparity_px: config.max_disparity_px,
                patch_radius_px: config.stereo_patch_radius_px,
                min_zncc: config.min_zncc,
                left_right_max_px: config.left_right_max_px,
                disparity_sigma_px: config.disparity_sigma_px,
                max_depth_m: config.max_depth_m,
                min_patch_std: 2.0,
                max_half_disagreement_px: config.stereo_max_half_disagreement_px,
            },
        )?;
        let pyr = PyramidConfig {
            levels: 3,
            border_px: 12,
        };
        let klt = KltConfig {
            window_radius_px: 5,
            ..KltConfig::default()
        };
        let corners = CornerConfig {
            max_features: config.max_features,
            grid_cols: 8,
            grid_rows: 6,
            min_distance_px: 7.0,
            border_px: 10,
            fill_leftover_budget: true,
            ..CornerConfig::default()
        };
        let n = config.max_features;
        Ok(Self {
            stereo,
            pyr_prev: Pyramid::new(w, h, pyr)?,
            pyr_cur: Pyramid::new(w, h, pyr)?,
            klt: KltTracker::new(klt, n)?,
            detector: CornerDetector::new(w, h, corners)?,
            motion: MotionEstimator::new(config.reprojection_threshold_px, n),
            ground: LocalGround::new(n),
            track_px: Vec::with_capacity(n),
            track_world: Vec::with_capacity(n),
            track_sigma_m: Vec::with_capacity(n),
            track_id: Vec::with_capacity(n),
            next_px: Vec::with_capacity(n),
            status: Vec::with_capacity(n),
            corrs: Vec::with_capacity(n),
            corners: Vec::with_capacity(n),
            cloud: Vec::with_capacity(n),
            cloud_points: Vec::with_capacity(n),
            heights: Vec::with_capacity(n),
            world_from_body,
            last_motion: Isometry3::identity(),
            keyframe_pose: world_from_body,
            imu_prev: None,
            next_id: 0,
            have_prev: false,
            config,
            rig,
        })
    }

    /// The rig this pipeline was built for.
    pub fn rig(&self) -> &StereoRig {
        &self.rig
    }

    /// The current pose estimate.
    pub fn world_from_body(&self) -> Isometry3<f64> {
        self.world_from_body
    }

    /// Moves the estimate to `world_from_body` and drops the map (e.g. a known start pose).
    pub fn reset(&mut self, world_from_body: Isometry3<f64>) {
        self.world_from_body = world_from_body;
        self.keyframe_pose = world_from_body;
        self.last_motion = Isometry3::identity();
        self.clear_tracks();
        self.have_prev = false;
    }

    /// The cloud of the last keyframe.
    pub fn cloud(&self) -> &[CloudPoint] {
        &self.cloud
    }

    /// Height of the body origin above the ground plane seen by this stereo pair, metres,
    /// with the body leveled by `tilt` (`None` if too few ground points).
    pub fn body_height_above_ground_m(
        &mut self,
        frame: &StereoFrame<'_>,
        tilt: Tilt,
    ) -> Option<f64> {
        self.pyr_cur.build(&frame.left).ok()?;
        let level = self.pyr_cur.level(0)?;
        self.detector.detect(level, &[], &mut self.corners).ok()?;
        self.cloud_points.clear();
        for c in &self.corners {
            if let Ok(p) =
                self.stereo
                    .match_point(&frame.left, &frame.right, c.position_px.x, c.position_px.y)
            {
                let body = self.rig.body_from_camera * p.point_camera_m;
                self.cloud_points.push(tilt.leveling * body);
            }
        }
        if self.cloud_points.len() < 20 {
            return None;
        }
        let plane = GroundModel::fit(
            &self.cloud_points,
            self.config.ground_keep_fraction,
            &mut self.heights,
        )?;
        Some(-plane.height_at(0.0, 0.0))
    }

    fn clear_tracks(&mut self) {
        self.truncate_tracks(0);
    }

    /// Processes one stereo frame.
    pub fn process_frame(&mut self, frame: &StereoFrame<'_>) -> VoOutput {
        let prediction = self.predict(frame.imu_attitude);
        if self.pyr_cur.build(&frame.left).is_err() {
            let mut out = self.propagate(prediction.held, 0);
            out.rejection = Some(Rejection::BadImage);
            return out;
        }
        let tracked = self.track(&prediction.predicted);
        self.stereo_tracks(frame, &prediction.predicted);
        let mut output = match self.vision_estimate(prediction.tilt, tracked) {
            Ok(m) => self.accept(m, tracked),
            Err(rejection) => self.lose(prediction.held, tracked, rejection),
        };
        self.keyframe_if_needed(frame, &mut output);
        std::mem::swap(&mut self.pyr_prev, &mut self.pyr_cur);
        self.have_prev = true;
        output.world_from_body = self.world_from_body;
        output
    }

    /// Prediction: IMU relative rotation (or last motion), constant velocity translation.
    fn predict(&mut self, imu_attitude: Option<UnitQuaternion<f64>>) -> Prediction {
        let imu = imu_attitude.filter(|q| q.coords.iter().all(|v| v.is_finite()));
        let delta_rotation = match (self.imu_prev, imu) {
            (Some(prev), Some(now)) => prev.inverse() * now,
            _ => self.last_motion.rotation,
        };
        if imu.is_some() {
            self.imu_prev = imu;
        }
        let mut predicted = self.world_from_body;
        predicted.rotation = self.world_from_body.rotation * delta_rotation;
        predicted.translation.vector += self.last_motion.translation.vector;
        let tilt = if self.config.use_imu_tilt {
            let sigma = self.config.imu_tilt_sigma_rad;
            imu.map(|q| Tilt {
                prior_sigma_rad: (sigma > 0.0).then_some(sigma),
                ..Tilt::from_attitude(&q)
            })
        } else {
            None
        };
        let held = Isometry3::from_parts(self.world_from_body.translation, predicted.rotation);
        Prediction {
            predicted,
            held,
            tilt,
        }
    }

    /// The motion of this frame from the stereo-matched tracks, if there are enough of them and
    /// the estimate is plausible.
    fn vision_estimate(
        &mut self,
        tilt: Option<Tilt>,
        tracked: usize,
    ) -> Result<MotionEstimate, Rejection> {
        if self.track_px.is_empty() {
            return Err(Rejection::NoMap);
        }
        if self.corrs.len() < self.config.min_inliers {
            return Err(Rejection::TooFewTracks);
        }
        let m = self
            .motion
            .estimate(
                &self.corrs,
                &self.rig.body_from_camera,
                &self.rig.intrinsics,
                tilt,
            )
            .map_err(Rejection::Motion)?;
        let step_m =
            (m.world_from_body.translation.vector - self.world_from_body.translation.vector).norm();
        if m.inliers < self.config.min_inliers {
            Err(Rejection::FewInliers)
        } else if (m.inliers as f64) < self.config.min_inlier_ratio * tracked as f64 {
            Err(Rejection::LowInlierRatio)
        } else if step_m >= 2.0 {
            Err(Rejection::ImplausibleStep)
        } else {
            Ok(m)
        }
    }

    /// Takes the vision estimate `m` as the pose and keeps its inliers as the map.
    fn accept(&mut self, m: MotionEstimate, tracked: usize) -> VoOutput {
        self.last_motion = self.world_from_body.inverse() * m.world_from_body;
        self.world_from_body = m.world_from_body;
        self.keep_inliers();
        VoOutput {
            rejection: None,
            world_from_body: m.world_from_body,
            confidence: (0.5
                + 0.5 * (m.inliers as f64 / (4.0 * self.config.min_inliers as f64)).min(1.0))
            .min(1.0),
            status: VoStatus::Tracking,
            tracked_features: tracked,
            inliers: m.inliers,
            is_keyframe: false,
        }
    }

    /// Lost (or never had a map): drop the map, hold the position.
    fn lose(&mut self, held: Isometry3<f64>, tracked: usize, rejection: Rejection) -> VoOutput {
        let had_map = !self.track_px.is_empty();
        self.clear_tracks();
        self.world_from_body = held;
        self.last_motion = Isometry3::identity();
        let mut out = self.propagate(held, tracked);
        out.rejection = Some(rejection);
        out.status = if had_map {
            VoStatus::Propagated
        } else {
            out.status
        };
        out
    }

    /// Adds a keyframe when the map is thin or the rover has moved enough since the last one,
    /// (re)building the map when it was empty.
    fn keyframe_if_needed(&mut self, frame: &StereoFrame<'_>, output: &mut VoOutput) {
        let moved = self.keyframe_pose.inverse() * self.world_from_body;
        let need_keyframe = self.track_px.len() < self.config.keyframe_min_tracks
            || moved.translation.vector.norm() > self.config.keyframe_max_translation_m
            || moved.rotation.angle() > self.config.keyframe_max_rotation_rad;
        if !need_keyframe {
            return;
        }
        let was_empty = self.track_px.is_empty();
        let added = self.add_keyframe_points(frame);
        if was_empty && self.track_px.len() < self.config.min_inliers {
            // Not enough texture to (re)build the map: stay propagated.
            self.clear_tracks();
        } else if added > 0 || !was_empty {
            self.keyframe_pose = self.world_from_body;
            output.is_keyframe = true;
            if was_empty {
                output.status = VoStatus::Initialized;
                if self.next_id == added as u32 {
                    // First map, at the known start pose: trusted. After a loss the
                    // position is still the held one, so confidence stays low until the
                    // next frame is tracked.
                    output.confidence = output.confidence.max(0.5);
                }
            }
            self.build_cloud();
        }
    }

    fn propagate(&mut self, held: Isometry3<f64>, tracked: usize) -> VoOutput {
        self.world_from_body = held;
        VoOutput {
            rejection: None,
            world_from_body: held,
            confidence: 0.2,
            status: VoStatus::Propagated,
            tracked_features: tracked,
            inliers: 0,
            is_keyframe: false,
        }
    }
}

/// `world_from_body` at the start: attitude from the IMU, position from the known start
/// `(x, y)` and `z = ground_z_m + body_height_m`.
pub fn start_pose(
    imu_attitude: UnitQuaternion<f64>,
    start_xy_m: [f64; 2],
    ground_z_m: f64,
    body_height_m: f64,
) -> Isometry3<f64> {
    Isometry3::from_parts(
        Vector3::new(start_xy_m[0], start_xy_m[1], ground_z_m + body_height_m).into(),
        imu_attitude,
    )
}
