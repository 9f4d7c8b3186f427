//! The `rover_vo` process: runs [`RoverVo`] on the rover's stereo stream and publishes the pose
//! every frame (`ROVER_POSE`) and a world-frame cloud at keyframes (`ROVER_CLOUD`).
//!
//! **Start pose** (never ground truth): attitude from the first IMU sample; (x, y) from
//! `rover_vo.start_xy_m`, else `physics.rover.start_xy_m`, else the scenario's start point
//! (`world.scenario.start_m`, rover 1.5 m to its right, as physics places it), else the physics
//! default; z = `rover_vo.start_ground_z_m` + the body height above the ground plane the first
//! stereo pair measures. Intrinsics, baseline and the left camera mount come from the header.
//!
//! Headers are checked beyond the transport's checks (two Mono8 views of the rig's size,
//! finite intrinsics, positive baseline); a bad sample is counted and skipped. The pipeline is
//! allocated once, at the first valid stereo header (the geometry is only known then), and
//! again only if the geometry changes.

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_ipc::messages::{
    CloudHeader, FeaturePoint, FrameTick, ImageHeader, ImuSample, PixelFormat, Pose3, PoseEstimate,
    PoseQuality, Robot, SampleStamp,
};
use hopnav_ipc::node_error::NodeError;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, SlicePublisher, SliceSubscriber, Subscriber, ValidSlice};
use hopnav_vision::image::ImageView;
use nalgebra::{Isometry3, Quaternion, UnitQuaternion};

use hopnav_rover_vo::config::RoverVoConfig;
use hopnav_rover_vo::motion::{Intrinsics, Tilt};
use hopnav_rover_vo::pipeline::{RoverVo, StereoFrame, StereoRig, VoOutput, VoStatus, start_pose};

/// Why the rover VO process failed: only the plumbing every node shares.
pub type RoverVoProcessError = NodeError;

/// Physics' default rover start, used when neither the config nor a scenario gives one.
const PHYSICS_DEFAULT_START_XY_M: [f64; 2] = [-12.0, -1.5];
/// Physics places the rover this far to the right (−y) of a scenario's start point.
const SCENARIO_START_OFFSET_M: f64 = 1.5;

/// Parses and validates `[rover_vo]`; errors name `rover_vo.<key>` and the allowed range.
/// `start_xy_m` is resolved (see the module docs), so the result always has one.
pub fn rover_vo_section(config: &HopnavConfig) -> Result<RoverVoConfig, ConfigError> {
    let mut section: RoverVoConfig = parse_section(config, "rover_vo")?;
    if section.start_xy_m.is_none() {
        section.start_xy_m = Some(resolve_start_xy(config)?);
    }
    section.validate()?;
    Ok(section)
}

fn resolve_start_xy(config: &HopnavConfig) -> Result<[f64; 2], ConfigError> {
    let explicit = config
        .sections
        .get("physics")
        .and_then(|physics| physics.get("rover"))
        .and_then(|rover| rover.get("start_xy_m"));
    if let Some(value) = explicit {
        let xy = value.as_array().and_then(|a| {
            let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
            match a.as_slice() {
                [x, y] => Some([num(x)?, num(y)?]),
                _ => None,
            }
        });
        return xy.ok_or_else(|| ConfigError::Schema {
            key: "physics.rover.start_xy_m".into(),
            message: "expected two numbers".into(),
        });
    }
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    Ok(match world.scenario.start_m {
        Some([x, y]) => [x, y - SCENARIO_START_OFFSET_M],
        None => PHYSICS_DEFAULT_START_XY_M,
    })
}

/// Runs the rover VO once per frame.
pub struct RoverVoProcess {
    config: RoverVoConfig,
    vo: Option<RoverVo>,
    started: bool,
    stereo: SliceSubscriber<ImageHeader>,
    imu: Subscriber<ImuSample>,
    poses: Publisher<PoseEstimate>,
    clouds: SlicePublisher<CloudHeader>,
    last_imu: Option<UnitQuaternion<f64>>,
    keyframes: u64,
    bad_headers: u64,
    /// A restarted incarnation: the supervisor's relay of the last pose published before the
    /// restart, read once at the first step.
    resume: Option<Subscriber<PoseEstimate>>,
    /// The pose to continue from, until the pipeline exists.
    resume_pose: Option<Isometry3<f64>>,
    /// The frame that pose was measured on: the restarted pipeline anchors on that frame's
    /// images (from the stereo topic's history) before it tracks the newest, so the motion
    /// between the last published pose and the first new one is measured, not lost.
    resume_frame_index: Option<u64>,
}

/// The stereo rig a header describes, or `None` if the header is unusable.
pub fn rig_from_header(header: &ImageHeader, slice_len: usize) -> Option<StereoRig> {
    let k = &header.intrinsics;
    let finite = [k.fx_px, k.fy_px, k.cx_px, k.cy_px, header.baseline_m]
        .iter()
        .all(|v| v.is_finite());
    let mount = header.body_from_camera;
    let mount_finite = mount
        .position_m
        .iter()
        .chain(&mount.orientation_xyzw)
        .all(|v| v.is_finite());
    let ok = finite
        && mount_finite
        && header.view_count == 2
        && header.format == PixelFormat::Mono8.code()
        && header.width_px >= 32
        && header.height_px >= 32
        && header.stride_bytes >= header.width_px
        && header.expected_len_bytes() <= slice_len
        && k.fx_px > 0.0
        && k.fy_px > 0.0
        && header.baseline_m > 0.0
        && header.baseline_m < 10.0;
    ok.then(|| StereoRig {
        width_px: header.width_px,
        height_px: header.height_px,
        intrinsics: Intrinsics {
            fx_px: k.fx_px,
            fy_px: k.fy_px,
            cx_px: k.cx_px,
            cy_px: k.cy_px,
        },
        baseline_m: header.baseline_m,
        body_from_camera: mount.to_isometry(),
    })
}

fn imu_attitude(sample: &ImuSample) -> Option<UnitQuaternion<f64>> {
    let [x, y, z, w] = sample.attitude_xyzw;
    let q = Quaternion::new(w, x, y, z);
    let norm = q.norm();
    (q.coords.iter().all(|v| v.is_finite()) && (norm - 1.0).abs() < 0.1)
        .then(|| UnitQuaternion::from_quaternion(q))
}

impl RoverVoProcess {
    /// A restart's first images: feeds the frame of the last published pose to a pipeline
    /// placed at that pose (nothing published: that pose is out already), then returns the
    /// newest frame to track from it. Without the anchor frame in the history, the newest
    /// frame starts the pipeline at the resumed pose and the motion in between is lost; with
    /// no frame at all, it waits for the next step.
    fn anchor_on_resumed_frame(
        &mut self,
        frame_index: u64,
    ) -> Result<Option<ValidSlice<ImageHeader>>, RoverVoProcessError> {
        while let Some(image) = self.stereo.receive()? {
            let image_frame = image.header().stamp.frame_index;
            if image_frame < frame_index {
                continue;
            }
            if image_frame == frame_index {
                self.process_image(image, false)?;
                eprintln!("rover_vo: resumed on frame {frame_index}, the last pose published");
                return Ok(self.stereo.receive_latest()?);
            }
            eprintln!(
                "rover_vo: restarted without frame {frame_index} (history starts at \
                 {image_frame}): the motion since the last published pose is lost"
            );
            // Hold at most two samples (the subscriber's limit): the newest so far and the next.
            let mut newest = image;
            while let Some(next) = self.stereo.receive()? {
                newest = next;
            }
            return Ok(Some(newest));
        }
        // Nothing yet: the camera delivers its history at its next send.
        self.resume_frame_index = Some(frame_index);
        Ok(None)
    }

    /// Runs the pipeline on one stereo pair; publishes its pose (and a cloud at keyframes)
    /// only if `publish`.
    fn process_image(
        &mut self,
        image: ValidSlice<ImageHeader>,
        publish: bool,
    ) -> Result<(), RoverVoProcessError> {
        let header = *image.header();
        let Some((rig, left, right)) = stereo_views(&header, image.elements()) else {
            self.bad_headers += 1;
            return Ok(());
        };
        if !self.ensure_pipeline(rig) {
            self.bad_headers += 1;
            return Ok(());
        }
        let frame = StereoFrame {
            left,
            right,
            imu_attitude: self.last_imu,
        };
        if !self.start_if_needed(&frame, &rig) {
            return Ok(()); // the start attitude comes from the IMU: wait for it
        }
        let Some(vo) = self.vo.as_mut() else {
            return Ok(());
        };
        let output = vo.process_frame(&frame);
        drop(image);
        if !publish {
            return Ok(());
        }
        self.publish(&output, &header.stamp, &rig)
    }

    /// A pipeline for `rig`: the current one, or a new one (after a geometry change, carrying
    /// the pose over; after a restart, at the resumed pose). `false` if it cannot be built.
    fn ensure_pipeline(&mut self, rig: StereoRig) -> bool {
        if self.vo.as_ref().is_some_and(|vo| *vo.rig() == rig) {
            return true;
        }
        let carried = self
            .vo
            .as_ref()
            .map(RoverVo::world_from_body)
            .or(self.resume_pose.take());
        let Ok(vo) = RoverVo::new(
            self.config.clone(),
            rig,
            carried.unwrap_or_else(Isometry3::identity),
        ) else {
            return false;
        };
        self.vo = Some(vo);
        self.started = carried.is_some();
        true
    }

    /// Places a pipeline that has no pose yet at the start pose (see the module docs);
    /// `false` while there is no IMU attitude to start from.
    fn start_if_needed(&mut self, frame: &StereoFrame<'_>, rig: &StereoRig) -> bool {
        if self.started {
            return true;
        }
        let (Some(vo), Some(attitude)) = (self.vo.as_mut(), self.last_imu) else {
            return false;
        };
        let height_m = vo
            .body_height_above_ground_m(frame, Tilt::from_attitude(&attitude))
            .unwrap_or(rig.body_from_camera.translation.z * 0.4);
        let start_xy = self.config.start_xy_m.unwrap_or(PHYSICS_DEFAULT_START_XY_M);
        vo.reset(start_pose(
            attitude,
            start_xy,
            self.config.start_ground_z_m,
            height_m,
        ));
        self.started = true;
        true
    }

    /// Publishes the pose of `output` and, at a keyframe, the pipeline's cloud.
    fn publish(
        &mut self,
        output: &VoOutput,
        stamp: &SampleStamp,
        rig: &StereoRig,
    ) -> Result<(), RoverVoProcessError> {
        self.poses.send(
            PoseEstimate::from_vo(
                Robot::Rover,
                stamp,
                Pose3::from_isometry(&output.world_from_body),
                output.confidence,
                1.0,
                output.tracked_features,
                output.is_keyframe,
            )
            .with_quality(rover_pose_quality(output)),
        )?;
        let Some(vo) = self.vo.as_ref() else {
            return Ok(());
        };
        if output.is_keyframe && self.config.publish_cloud {
            let cloud = vo.cloud();
            self.keyframes += 1;
            self.clouds.send_keyframe_cloud(
                Robot::Rover,
                stamp,
                Pose3::from_isometry(&(output.world_from_body * rig.body_from_camera)),
                self.keyframes,
                cloud.len(),
                |index| {
                    let point = &cloud[index];
                    FeaturePoint::from_estimate(
                        point.position_m.into(),
                        Some(point.height_above_ground_m),
                        point.track_id,
                        point.depth_sigma_m,
                    )
                },
            )?;
        }
        Ok(())
    }
}

/// The rig a stereo header describes and its two views, or `None` if either is unusable.
fn stereo_views<'a>(
    header: &ImageHeader,
    pixels: &'a [u8],
) -> Option<(StereoRig, ImageView<'a>, ImageView<'a>)> {
    let rig = rig_from_header(header, pixels.len())?;
    let view_len = header.view_len_bytes();
    let (w, h, stride) = (
        header.width_px as usize,
        header.height_px as usize,
        header.stride_bytes as usize,
    );
    let left = ImageView::new(&pixels[..view_len], w, h, stride).ok()?;
    let right = ImageView::new(&pixels[view_len..2 * view_len], w, h, stride).ok()?;
    Some((rig, left, right))
}

impl Process for RoverVoProcess {
    type Error = RoverVoProcessError;

    fn new(context: &ProcessContext) -> Result<Self, RoverVoProcessError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        let section = rover_vo_section(&config)?;
        let node = &context.node;
        Ok(Self {
            clouds: SlicePublisher::open(node, &topics::ROVER_CLOUD, section.max_features)?,
            stereo: SliceSubscriber::open(node, &topics::ROVER_STEREO)?,
            imu: Subscriber::open(node, &topics::IMU)?,
            poses: Publisher::open(node, &topics::ROVER_POSE)?,
            config: section,
            vo: None,
            started: false,
            last_imu: None,
            keyframes: 0,
            bad_headers: 0,
            resume: if context.identity.incarnation > 0 {
                Some(Subscriber::open(node, &topics::RESUME_ROVER_POSE)?)
            } else {
                None
            },
            resume_pose: None,
            resume_frame_index: None,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        _tick: &FrameTick,
    ) -> Result<(), RoverVoProcessError> {
        if let Some(resume) = self.resume.take()
            && let Some(last) = resume.receive_latest()?
        {
            // Restarted: continue from the last pose published, not from the start point.
            self.resume_pose = Some(last.world_from_body.to_isometry());
            self.resume_frame_index = Some(last.stamp.frame_index);
        }
        // A restarted mapper gets the cloud history now, not at the next keyframe.
        self.clouds.update_connections()?;
        while let Some(sample) = self.imu.receive()? {
            if let Some(q) = imu_attitude(&sample) {
                self.last_imu = Some(q);
            } else {
                self.bad_headers += 1;
            }
        }
        let image = match self.resume_frame_index.take() {
            Some(frame_index) => self.anchor_on_resumed_frame(frame_index)?,
            None => self.stereo.receive_latest()?,
        };
        let Some(image) = image else {
            return Ok(()); // camera skipped this frame; the next one bridges the gap
        };
        self.process_image(image, true)
    }

    fn rejected_samples(&self) -> u64 {
        self.stereo.rejected().total() + self.imu.rejected().total() + self.bad_headers
    }
}

/// What the rover's pose rests on, as the pose message says it.
fn rover_pose_quality(output: &VoOutput) -> PoseQuality {
    match output.status {
        VoStatus::Tracking => PoseQuality::Measured,
        VoStatus::Initialized => PoseQuality::Initial,
        VoStatus::Propagated => PoseQuality::Coasting,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopnav_ipc::messages::CameraIntrinsics;

    #[test]
    fn section_resolves_the_start_and_names_bad_keys() {
        let config = hopnav_config::load(None).unwrap();
        let section = rover_vo_section(&config).unwrap();
        // The embedded default has a scenario, so the start is its point A, offset like physics.
        let world: hopnav_world::WorldConfig = parse_section(&config, "world").unwrap();
        let expected = match world.scenario.start_m {
            Some([x, y]) => [x, y - SCENARIO_START_OFFSET_M],
            None => PHYSICS_DEFAULT_START_XY_M,
        };
        assert_eq!(section.start_xy_m, Some(expected));
        let config = hopnav_config::load(Some("[physics.rover]\nstart_xy_m = [3.0, 4]\n")).unwrap();
        assert_eq!(
            rover_vo_section(&config).unwrap().start_xy_m,
            Some([3.0, 4.0])
        );
        let config = hopnav_config::load(Some("[world.scenario]\nstart_m = [5.0, 6.0]\n")).unwrap();
        assert_eq!(
            rover_vo_section(&config).unwrap().start_xy_m,
            Some([5.0, 4.5])
        );
        let config = hopnav_config::load(Some("[rover_vo]\nmin_zncc = 3.0\n")).unwrap();
        let err = rover_vo_section(&config).unwrap_err().to_string();
        assert!(
            err.contains("rover_vo.min_zncc") && err.contains("[0, 1]"),
            "{err}"
        );
        let config = hopnav_config::load(Some("[rover_vo]\nno_such_key = 1\n")).unwrap();
        assert!(rover_vo_section(&config).is_err());
    }

    #[test]
    fn bad_headers_are_rejected() {
        let good = ImageHeader {
            intrinsics: CameraIntrinsics {
                fx_px: 277.0,
                fy_px: 277.0,
                cx_px: 159.5,
                cy_px: 119.5,
            },
            baseline_m: 0.2,
            width_px: 320,
            height_px: 240,
            stride_bytes: 320,
            format: PixelFormat::Mono8.code(),
            view_count: 2,
            body_from_camera: Pose3::from_isometry(&Isometry3::identity()),
            ..ImageHeader::default()
        };
        let len = 2 * 320 * 240;
        assert!(rig_from_header(&good, len).is_some());
        assert!(rig_from_header(&good, len - 1).is_none());
        assert!(
            rig_from_header(
                &ImageHeader {
                    view_count: 1,
                    ..good
                },
                len
            )
            .is_none()
        );
        assert!(
            rig_from_header(
                &ImageHeader {
                    baseline_m: f64::NAN,
                    ..good
                },
                len
            )
            .is_none()
        );
        let mut nan_k = good;
        nan_k.intrinsics.fx_px = f64::INFINITY;
        assert!(rig_from_header(&nan_k, len).is_none());
        let imu = ImuSample {
            attitude_xyzw: [0.0, 0.0, 0.0, 1.0],
            ..ImuSample::default()
        };
        assert!(imu_attitude(&imu).is_some());
        let imu = ImuSample {
            attitude_xyzw: [f64::NAN, 0.0, 0.0, 1.0],
            ..ImuSample::default()
        };
        assert!(imu_attitude(&imu).is_none());
    }
}
