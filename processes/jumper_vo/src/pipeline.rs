//! The jumper VO pipeline (paper §2, steps 1–7) with keyframes, altimeter scale and a ballistic
//! fallback.
//!
//! Per frame ([`JumperVo::process_frame`]):
//!
//! 1. track the live features into the new frame (KLT, forward–backward check);
//! 2. estimate `cam_cur_from_cam_kf` against the **keyframe** (§2.1, longer baseline): 5-point
//!    (or 8-point) essential RANSAC and homography RANSAC, model selection, homography
//!    decomposition picked with the gravity direction predicted by the current attitude;
//! 3. attitude: `world_from_cam_kf · cam_kf_from_cam_cur` (rotation error grows per keyframe,
//!    not per frame); with `attitude_from_spin_fit`, the launch attitude turned by one constant
//!    angular rate fitted to the keyframe intervals ([`crate::spin`]: torque-free flight);
//! 4. translation direction in the world frame (eq. 5), scaled by the configured
//!    [`ScaleMethod`]; position = keyframe position + scale · direction (step 6);
//! 5. keyframe when the median rotation-compensated parallax or the surviving track count
//!    crosses its threshold; the new keyframe triangulates a world-frame cloud and tops up the
//!    features (step 1 again).
//!
//! Starvation (black, blurred or sky frames, landing impact, RANSAC failure) never diverges:
//! the pose is propagated with the ballistic model (fitted launch velocity and gravity, or the
//! last velocity for the eq. 4 baseline) and a constant angular rate, confidence drops to 0.1,
//! and the current frame becomes a fresh keyframe so tracking resumes at the next one. After
//! touchdown the position slides to rest along the touchdown velocity (the landing cage's
//! damping), the altitude averages the altimeter, and the tracker is re-initialized.
//!
//! Time counts from the launch: [`JumperVo::start_hop_at`] takes the launch instant and pose
//! at rest, so the predicted touchdown is at the launch's rest altitude even when the first
//! image comes a frame after the launch.

use crate::ballistic::BallisticFit;
use crate::cloud::fill_heights_above_ground;
use crate::config::{ConfigError, JumperVoConfig, SolverChoice};
use crate::flight_ba::HopWindow;
use crate::frames::body_from_camera;
use crate::output::{FrameInput, VoOutput, VoStatus};
use crate::spin::SpinFit;
use crate::tracks::{FeatureTracks, TrackError};
use hopnav_vision::camera::PinholeCamera;
use hopnav_vision::two_view::{EssentialSolver, MotionModel, TwoViewConfig, TwoViewEstimator};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector2, Vector3};

mod adjust;
mod cloud_tracks;
mod estimate;
mod keyframe_history;
mod landing;
mod motion;

pub use adjust::BaStats;
use keyframe_history::KeyframeHistory;

/// Error creating a [`JumperVo`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VoError {
    /// A configuration value is out of range.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The front end could not be built for this camera.
    #[error("front end: {0}")]
    Tracks(#[from] TrackError),
    /// The initial pose is not finite.
    #[error("initial_world_from_body is not finite")]
    BadInitialPose,
}

#[derive(Debug, Clone, Copy)]
struct Keyframe {
    world_from_cam: Isometry3<f64>,
    tau_s: f64,
    /// Camera altitude at the keyframe (altimeter + lever arm), for eq. 4.
    camera_altitude_m: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    WaitingFirstFrame,
    Flight,
    Landed,
}

/// Jumper monocular VO with altimeter scale. Allocates in `new`; per frame only keyframes
/// allocate (the cloud).
#[derive(Debug, Clone)]
pub struct JumperVo {
    config: JumperVoConfig,
    camera: PinholeCamera,
    body_from_camera: Isometry3<f64>,
    tracks: FeatureTracks,
    estimator: TwoViewEstimator,
    x1: Vec<Vector2<f64>>,
    x2: Vec<Vector2<f64>>,
    keep: Vec<bool>,
    parallax: Vec<f64>,
    phase: Phase,
    launch_t_s: f64,
    launch_world_from_body: Isometry3<f64>,
    fit: BallisticFit,
    /// The flight's attitude model (used when `attitude_from_spin_fit`).
    spin: SpinFit,
    keyframe: Keyframe,
    /// The hop's recent keyframes, where cloud tracks were born.
    history: KeyframeHistory,
    last_world_from_body: Isometry3<f64>,
    /// The last accepted vision attitude (body), on the current keyframe's base: the angular
    /// rate check compares vision with vision, never with the spin fit's output.
    last_vision_body_rotation: Option<UnitQuaternion<f64>>,
    last_tau_s: f64,
    /// World-frame angular velocity (rotation vector per second).
    angular_velocity_radps: Vector3<f64>,
    /// World-frame body velocity (eq. 4 propagation).
    velocity_mps: Vector3<f64>,
    frame_dt_s: f64,
    /// After touchdown: weighted sum and weight of the body altitude (the fit at impact as a
    /// prior, then every altimeter sample): the held altitude is their mean.
    landed_altitude_sum_m: f64,
    landed_altitude_weight: f64,
    /// Launch instant of the hop, when known before its first image ([`Self::start_hop_at`]).
    pending_launch_t_s: Option<f64>,
    /// Commanded launch velocity, world frame (zero without a commanded speed).
    commanded_velocity_mps: Vector3<f64>,
    /// Touchdown, once landed.
    touchdown: Option<Touchdown>,
    /// Consecutive well-tracked frames with a still image while the fit still climbs: a hop
    /// that never left the ground (the jumper wedged against a rock, or on its side).
    still_climbing_frames: u32,
    /// Log-likelihood ratio, over the altimeter samples since launch, of "the commanded hop
    /// flies" against "the body stayed at its launch altitude".
    launch_llr: f64,
    /// The hop's keyframe sightings and altimeter samples for the bundle adjustment.
    ba_window: HopWindow,
    /// The last accepted correction of the resting attitude (the next adjustment's start).
    ba_attitude_correction_rad: Vector3<f64>,
    ba_stats: BaStats,
}

/// Where and how fast the jumper came down; the landed position slides from there.
#[derive(Debug, Clone, Copy)]
struct Touchdown {
    tau_s: f64,
    position_m: Vector3<f64>,
    /// Horizontal velocity at the impact, world frame.
    horizontal_velocity_mps: Vector3<f64>,
}

impl JumperVo {
    /// Validates `config` and allocates the front end for `camera`, mounted as the config's
    /// `mount_pitch_down_rad` and `camera_offset_body_m` say.
    pub fn new(
        config: JumperVoConfig,
        camera: PinholeCamera,
        initial_world_from_body: Isometry3<f64>,
    ) -> Result<Self, VoError> {
        let [ox, oy, oz] = config.camera_offset_body_m;
        let mount = body_from_camera(config.mount_pitch_down_rad, &Vector3::new(ox, oy, oz));
        Self::with_mount(config, camera, mount, initial_world_from_body)
    }

    /// Like [`Self::new`] with an explicit `body_from_camera` (e.g. from the image header).
    pub fn with_mount(
        config: JumperVoConfig,
        camera: PinholeCamera,
        body_from_camera: Isometry3<f64>,
        initial_world_from_body: Isometry3<f64>,
    ) -> Result<Self, VoError> {
        config.validate()?;
        if !body_from_camera
            .to_homogeneous()
            .iter()
            .all(|v| v.is_finite())
        {
            return Err(VoError::BadInitialPose);
        }
        if !initial_world_from_body
            .to_homogeneous()
            .iter()
            .all(|v| v.is_finite())
        {
            return Err(VoError::BadInitialPose);
        }
        let tracks = FeatureTracks::new(
            camera.width_px as usize,
            camera.height_px as usize,
            config.max_features,
        )?;
        let mut tv = TwoViewConfig::for_camera(&camera);
        tv.sigma_px = config.pixel_sigma_px;
        tv.min_inliers = config.min_tracked_features;
        // Frames that need more essential hypotheses than this have under ~45 % inliers (5-point,
        // p = 0.999): near the landing and after starvation. They set the p99 frame time
        // (500 hypotheses ≈ 8 ms) and the homography wins on the planar ground anyway.
        tv.max_iterations = ESSENTIAL_MAX_HYPOTHESES;
        tv.solver = match config.essential_solver {
            SolverChoice::FivePoint => EssentialSolver::FivePoint,
            SolverChoice::EightPoint => EssentialSolver::EightPoint,
        };
        let n = config.max_features;
        let mut vo = Self {
            estimator: TwoViewEstimator::new(tv, n),
            x1: Vec::with_capacity(n),
            x2: Vec::with_capacity(n),
            keep: Vec::with_capacity(n),
            parallax: Vec::with_capacity(n),
            tracks,
            camera,
            body_from_camera,
            phase: Phase::WaitingFirstFrame,
            launch_t_s: 0.0,
            launch_world_from_body: initial_world_from_body,
            fit: BallisticFit::new(
                initial_world_from_body.translation.vector.into(),
                config.gravity_mps2,
            ),
            spin: SpinFit::new(UnitQuaternion::identity(), Vector3::zeros(), 0.0),
            last_vision_body_rotation: None,
            keyframe: Keyframe {
                world_from_cam: initial_world_from_body * body_from_camera,
                tau_s: 0.0,
                camera_altitude_m: None,
            },
            history: KeyframeHistory::default(),
            last_world_from_body: initial_world_from_body,
            last_tau_s: 0.0,
            angular_velocity_radps: Vector3::zeros(),
            velocity_mps: Vector3::zeros(),
            frame_dt_s: 0.1,
            landed_altitude_sum_m: 0.0,
            landed_altitude_weight: 0.0,
            pending_launch_t_s: None,
            commanded_velocity_mps: Vector3::zeros(),
            touchdown: None,
            still_climbing_frames: 0,
            launch_llr: 0.0,
            ba_window: HopWindow::new(config.ba_window_keyframes),
            ba_attitude_correction_rad: Vector3::zeros(),
            ba_stats: BaStats::default(),
            config,
        };
        vo.start_hop(initial_world_from_body);
        Ok(vo)
    }

    /// Starts a new hop from `world_from_body` (e.g. after a landing): the next frame is the
    /// launch instant. Non-finite poses are ignored.
    pub fn start_hop(&mut self, world_from_body: Isometry3<f64>) {
        if !world_from_body
            .to_homogeneous()
            .iter()
            .all(|v| v.is_finite())
        {
            return;
        }
        self.phase = Phase::WaitingFirstFrame;
        self.pending_launch_t_s = None;
        self.touchdown = None;
        self.still_climbing_frames = 0;
        self.launch_llr = 0.0;
        self.ba_window.clear();
        self.ba_attitude_correction_rad = Vector3::zeros();
        self.commanded_velocity_mps = Vector3::zeros();
        self.launch_world_from_body = world_from_body;
        self.last_world_from_body = world_from_body;
        self.last_vision_body_rotation = None;
        self.fit = BallisticFit::new(
            world_from_body.translation.vector.into(),
            self.config.gravity_mps2,
        );
        self.velocity_mps = Vector3::zeros();
        if self.config.launch_speed_mps > 0.0 {
            let heading = world_from_body.rotation * Vector3::x();
            let yaw = heading.y.atan2(heading.x);
            let (se, ce) = self.config.launch_elevation_rad.sin_cos();
            let v = self.config.launch_speed_mps * Vector3::new(ce * yaw.cos(), ce * yaw.sin(), se);
            self.fit
                .add_velocity_prior(&v, self.config.launch_velocity_sigma_mps);
            self.velocity_mps = v;
            self.commanded_velocity_mps = v;
        }
        let [wx, wy, wz] = self.config.launch_angular_velocity_body_radps;
        self.angular_velocity_radps = world_from_body.rotation * Vector3::new(wx, wy, wz);
        self.spin = SpinFit::new(
            world_from_body.rotation,
            self.angular_velocity_radps,
            self.config.launch_angular_velocity_sigma_radps,
        );
        self.tracks.reset();
    }

    /// Like [`Self::start_hop`] with the launch instant known: `launch_world_from_body` is the
    /// pose at rest, set to the launch attitude, at `launch_t_s`, and the first image may come
    /// later (up to a second): the commanded launch (velocity, spin and gravity) carries the
    /// pose to it. The fit then counts time from the real launch, so the touchdown is
    /// predicted at the launch's rest altitude rather than at the first image's.
    pub fn start_hop_at(&mut self, launch_world_from_body: Isometry3<f64>, launch_t_s: f64) {
        self.start_hop(launch_world_from_body);
        if launch_t_s.is_finite() && self.phase == Phase::WaitingFirstFrame {
            self.pending_launch_t_s = Some(launch_t_s);
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &JumperVoConfig {
        &self.config
    }

    /// The ballistic launch-velocity fit (diagnostics).
    pub fn ballistic_fit(&self) -> &BallisticFit {
        &self.fit
    }

    /// The last estimated `world_from_body` (where a new hop starts from).
    pub fn last_world_from_body(&self) -> Isometry3<f64> {
        self.last_world_from_body
    }

    /// `body_from_camera` of the mount.
    pub fn body_from_camera(&self) -> Isometry3<f64> {
        self.body_from_camera
    }

    fn lever_world(&self, rotation: &UnitQuaternion<f64>) -> Vector3<f64> {
        rotation * self.body_from_camera.translation.vector
    }

    fn output(&self, input: &FrameInput<'_>, status: VoStatus) -> VoOutput {
        VoOutput {
            frame_index: input.frame_index,
            t_s: input.t_s,
            world_from_body: self.last_world_from_body,
            confidence: 0.0,
            status,
            is_keyframe: false,
            tracked_features: 0,
            inliers: 0,
            scale: None,
            model: None,
            cloud: None,
            cloud_world_from_camera: None,
            position_sigma_m: f64::NAN,
        }
    }

    /// Runs steps 1–7 on one frame. Never panics; bad input gives a [`VoStatus::Rejected`] or
    /// [`VoStatus::Propagating`] output.
    pub fn process_frame(&mut self, input: FrameInput<'_>) -> VoOutput {
        let mut out = self.process_frame_estimate(input);
        out.position_sigma_m = self.position_sigma_m(out.t_s - self.launch_t_s);
        out
    }

    /// [`Self::process_frame`] without the position σ.
    fn process_frame_estimate(&mut self, input: FrameInput<'_>) -> VoOutput {
        if !input.t_s.is_finite() {
            return self.output(&input, VoStatus::Rejected);
        }
        if self.phase == Phase::WaitingFirstFrame {
            return self.first_frame(&input);
        }
        let tau = input.t_s - self.launch_t_s;
        let dt = tau - self.last_tau_s;
        if dt.is_nan() || dt <= 0.0 {
            return self.output(&input, VoStatus::Rejected);
        }
        self.frame_dt_s = dt;
        let altitude = input.altimeter_m.filter(|z| z.is_finite());
        if self.phase == Phase::Flight {
            if let Some(z) = altitude {
                self.fit.add_altitude(tau, z, self.config.altimeter_sigma_m);
                self.ba_window.add_altitude(tau, z);
                self.weigh_launch(tau, z);
            }
            if self
                .descent_height_m(tau)
                .is_some_and(|h| h <= -self.config.touchdown_max_drop_m)
            {
                return self.land(&input, tau, tau);
            }
        }
        let tracked = self.tracks.track(&input.image).unwrap_or(0);
        if self.phase == Phase::Landed {
            return self.landed_frame(&input, tau, tracked);
        }
        if self.launch_failed(tau, tracked) {
            // Without this the ballistic model flies the commanded hop on (metres of error).
            let launch_position_m = self.fit.launch_position_m().coords;
            return self.land_at(&input, launch_position_m, Vector3::zeros(), tau, tau);
        }
        match self.estimate(tau, tracked, altitude) {
            Some(est) => {
                // Analytic landings rest at the launch altitude: a still image there is the
                // ground.
                let still = self.tracks.median_flow_norm_px() < STILL_FLOW_PX;
                if let Some(td) = self.fit.touchdown_tau_s()
                    && still
                    && self.descent_height_m(tau).is_some_and(|h| h <= 0.0)
                {
                    return self.land(&input, td.min(tau), tau);
                }
                self.finish(est, &input, tau)
            }
            None => {
                // The impact ends tracking (tumble, dust, ground too close): while descending
                // near the ground, a vision breakdown is the touchdown, unless the fit still
                // flies above the launch's rest altitude and predicts the touchdown later (the
                // ground rushing into view breaks vision a frame or two before the impact).
                if let Some(h) = self.descent_height_m(tau)
                    && h <= self.config.touchdown_margin_m
                    && !(h > 0.0 && self.fit.touchdown_tau_s().is_some_and(|td| td > tau))
                {
                    let td = self.impact_tau_s(tau);
                    return self.land(&input, td, tau);
                }
                self.propagate(&input, tau, tracked, altitude)
            }
        }
    }

    fn first_frame(&mut self, input: &FrameInput<'_>) -> VoOutput {
        let launch_t_s = self.pending_launch_t_s.take().unwrap_or(input.t_s);
        let tau0 = (input.t_s - launch_t_s).clamp(0.0, 1.0);
        self.launch_t_s = input.t_s - tau0;
        self.last_tau_s = tau0;
        self.phase = Phase::Flight;
        // The commanded launch carries the pose from the launch instant to this image.
        let g = self.config.gravity_mps2;
        let position = self.launch_world_from_body.translation.vector
            + self.commanded_velocity_mps * tau0
            - Vector3::z() * (0.5 * g * tau0 * tau0);
        let rotation = UnitQuaternion::from_scaled_axis(self.angular_velocity_radps * tau0)
            * self.launch_world_from_body.rotation;
        let pose = Isometry3::from_parts(Translation3::from(position), rotation);
        self.last_world_from_body = pose;
        self.last_vision_body_rotation = Some(rotation);
        let altitude = input.altimeter_m.filter(|z| z.is_finite());
        if let Some(z) = altitude {
            self.fit
                .add_altitude(tau0, z, self.config.altimeter_sigma_m);
            self.ba_window.add_altitude(tau0, z);
        }
        self.tracks.reset();
        // A wrong-size image only leaves the tracker empty; the next frame retries.
        let _ = self.tracks.track(&input.image);
        let features = self.tracks.set_keyframe().unwrap_or(0);
        self.adjust_at_keyframe(tau0);
        let lever_z = self.lever_world(&rotation).z;
        self.keyframe = Keyframe {
            world_from_cam: pose * self.body_from_camera,
            tau_s: tau0,
            camera_altitude_m: altitude.map(|z| z + lever_z).or(Some(position.z + lever_z)),
        };
        self.record_keyframe();
        let mut out = self.output(input, VoStatus::Initializing);
        out.confidence = 1.0;
        out.is_keyframe = true;
        out.tracked_features = features;
        out
    }

    fn finish(&mut self, est: Estimate, input: &FrameInput<'_>, tau: f64) -> VoOutput {
        let mut pose = est.world_from_body;
        self.last_vision_body_rotation = Some(est.vision_body_rotation);
        let make_keyframe = est.median_parallax_rad
            >= self.config.keyframe_max_parallax_deg.to_radians()
            || est.inliers < self.config.keyframe_min_tracks
            || (est.inliers as f64)
                < self.config.keyframe_min_track_fraction * self.tracks.keyframe_count() as f64;
        if make_keyframe && self.config.attitude_from_spin_fit {
            // One row per keyframe interval: the frames in between measure the same interval
            // again, with the same keyframe's error.
            self.spin.add_increment(
                tau - self.keyframe.tau_s,
                &est.rotation_since_keyframe,
                self.config.keyframe_rotation_sigma_rad,
            );
            pose.rotation = self.spin.attitude_at(tau);
            self.keyframe.world_from_cam.rotation =
                self.spin.attitude_at(self.keyframe.tau_s) * self.body_from_camera.rotation;
            // The next keyframe's base is the fitted attitude.
            self.last_vision_body_rotation = Some(pose.rotation);
        }
        let mut world_from_cam = pose * self.body_from_camera;
        let mut cloud = None;
        let mut cloud_world_from_camera = None;
        if make_keyframe && self.config.publish_cloud && est.scale_m.is_some() {
            // The baseline is the measured one, vision direction times scale, from the keyframe
            // centre it was measured from. The stored keyframe pose predates the fit's
            // re-anchoring: its offset (6 % of the baseline on average over 8 simulated hops, up
            // to 100 % on the ascent) tilts the baseline and lifts the ground into rocks.
            let world_from_cam1 = Isometry3::from_parts(
                Translation3::from(est.keyframe_center_m),
                self.keyframe.world_from_cam.rotation,
            );
            let mut points = self.triangulate_keyframe_cloud(&world_from_cam1, &world_from_cam);
            fill_heights_above_ground(&mut points);
            cloud = Some(points);
            cloud_world_from_camera = Some(world_from_cam);
        }
        self.tracks.retain(&self.keep);
        let mut tracked_after = est.tracked;
        if make_keyframe {
            tracked_after = self.tracks.set_keyframe().unwrap_or(0);
            if let Some(refined) = self.adjust_at_keyframe(tau) {
                pose = refined;
                world_from_cam = pose * self.body_from_camera;
                self.last_vision_body_rotation = Some(pose.rotation);
            }
            let lever = self.lever_world(&pose.rotation);
            self.keyframe = Keyframe {
                world_from_cam,
                tau_s: tau,
                camera_altitude_m: input
                    .altimeter_m
                    .filter(|z| z.is_finite())
                    .map(|z| z + lever.z)
                    .or(Some(world_from_cam.translation.z)),
            };
            self.record_keyframe();
        }
        self.update_rates(&pose, tau, true);
        let inlier_ratio = est.inliers as f64 / est.tracked.max(1) as f64;
        VoOutput {
            frame_index: input.frame_index,
            t_s: input.t_s,
            world_from_body: pose,
            confidence: ((est.inliers as f64 / 150.0).min(1.0) * inlier_ratio).clamp(0.0, 1.0),
            status: VoStatus::Tracking,
            is_keyframe: make_keyframe,
            tracked_features: tracked_after.max(est.tracked),
            inliers: est.inliers,
            scale: est.scale_m,
            model: Some(est.model),
            cloud,
            cloud_world_from_camera,
            position_sigma_m: f64::NAN,
        }
    }
}

/// Essential RANSAC hypotheses at most per frame (the vision default is 500).
const ESSENTIAL_MAX_HYPOTHESES: usize = 200;

/// Median track displacement below which the image counts as still, pixels per frame.
const STILL_FLOW_PX: f32 = 0.3;

#[derive(Debug, Clone, Copy)]
struct Estimate {
    world_from_body: Isometry3<f64>,
    model: MotionModel,
    inliers: usize,
    tracked: usize,
    median_parallax_rad: f64,
    scale_m: Option<f64>,
    /// Keyframe camera centre the position was measured from along the vision direction,
    /// world frame, metres (the ballistic fit re-anchors it; the cloud must use the same one).
    keyframe_center_m: Vector3<f64>,
    /// World-frame rotation from the keyframe to this frame, as vision measured it.
    rotation_since_keyframe: UnitQuaternion<f64>,
    /// This frame's attitude (body) as vision measured it on the keyframe's base.
    vision_body_rotation: UnitQuaternion<f64>,
}
