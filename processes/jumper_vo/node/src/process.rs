//! The `jumper_vo` process: runs the pipeline on the jumper's camera stream and publishes the
//! pose every frame and a world-frame feature cloud at keyframes.
//!
//! It starts a hop when physics announces a launch (`HopLaunch`: the commanded attitude and
//! velocity, and for the first hop the mission's start point); it never reads ground truth.
//! Intrinsics and the camera mount come from the image header.

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_ipc::messages::{
    AltimeterSample, CloudHeader, FeaturePoint, FrameTick, HopLaunch, ImageHeader, Pose3,
    PoseEstimate, PoseQuality, Robot,
};
use hopnav_ipc::node_error::NodeError;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SlicePublisher, SliceSubscriber, Subscriber};
use hopnav_vision::camera::PinholeCamera;
use hopnav_vision::image::ImageView;
use nalgebra::{Isometry3, Translation3, Vector3};

use hopnav_jumper_vo::config::JumperVoConfig;
use hopnav_jumper_vo::output::{FrameInput, VoStatus};
use hopnav_jumper_vo::pipeline::JumperVo;

/// Why the jumper VO process failed: only the plumbing every node shares.
pub type JumperVoProcessError = NodeError;

/// Parses and validates `[jumper_vo]`; errors name `jumper_vo.<key>`.
pub fn jumper_vo_section(config: &HopnavConfig) -> Result<JumperVoConfig, ConfigError> {
    let section: JumperVoConfig = parse_section(config, "jumper_vo")?;
    section.validate().map_err(|error| ConfigError::Schema {
        key: "jumper_vo".into(),
        message: error.to_string(),
    })?;
    Ok(section)
}

/// Runs the jumper VO once per frame.
pub struct JumperVoProcess {
    config: JumperVoConfig,
    vo: Option<JumperVo>,
    pending_launch: Option<HopLaunch>,
    last_hop_index: u32,
    images: SliceSubscriber<ImageHeader>,
    altimeter: Subscriber<AltimeterSample>,
    launches: Subscriber<HopLaunch>,
    poses: hopnav_ipc::transport::Publisher<PoseEstimate>,
    clouds: SlicePublisher<CloudHeader>,
    keyframes: u64,
    /// A restarted incarnation: the supervisor's relays of the last pose published and the
    /// last hop launch before the restart, read once at the first step.
    resume: Option<(Subscriber<PoseEstimate>, Subscriber<HopLaunch>)>,
    /// Where the jumper rested when this incarnation started, for the next hop's start.
    resume_position: Option<Vector3<f64>>,
}

impl JumperVoProcess {
    /// Starts the pipeline (or a new hop) from a launch; the pipeline carries the commanded
    /// launch from the launch instant to the first image after it.
    fn start_hop(&mut self, launch: &HopLaunch, header: &ImageHeader) {
        let attitude = launch.world_from_body.to_isometry().rotation;
        let launch_position = match (&self.vo, launch.position_known) {
            (_, 1) => Vector3::from(launch.world_from_body.position_m),
            // Later hops start where the VO believes the jumper landed.
            (Some(vo), _) => vo.last_world_from_body().translation.vector,
            // Restarted while resting: the hop starts where the last pose put the jumper.
            (None, _) => match self.resume_position.take() {
                Some(position) => position,
                None => return, // no known position: wait for one
            },
        };
        let velocity = Vector3::from(launch.velocity_mps);
        let mut config = self.config.clone();
        config.launch_speed_mps = velocity.norm();
        config.launch_elevation_rad = (velocity.z / velocity.norm().max(1e-9)).asin();
        let launch_pose = Isometry3::from_parts(Translation3::from(launch_position), attitude);
        let intrinsics = &header.intrinsics;
        let Ok(camera) = PinholeCamera::new(
            header.width_px,
            header.height_px,
            intrinsics.fx_px,
            intrinsics.fy_px,
            intrinsics.cx_px,
            intrinsics.cy_px,
        ) else {
            return;
        };
        let mount = header.body_from_camera.to_isometry();
        if let Ok(mut vo) = JumperVo::with_mount(config, camera, mount, launch_pose) {
            // The first image comes up to a second after the launch (later is a stale launch:
            // the pipeline clamps it).
            vo.start_hop_at(launch_pose, launch.launch_time_ns as f64 * 1e-9);
            self.vo = Some(vo);
            self.last_hop_index = launch.hop_index;
        }
    }
}

impl JumperVoProcess {
    /// Reads what the supervisor kept of the previous incarnation: mid-flight, the flight
    /// continues from the last pose (a launch at that pose with the ballistic velocity of
    /// that instant); at rest, the next hop starts from it.
    fn resume(&mut self) -> Result<(), JumperVoProcessError> {
        let Some((poses, launches)) = self.resume.take() else {
            return Ok(());
        };
        let (pose, launch) = (poses.receive_latest()?, launches.receive_latest()?);
        if let Some(launch) = &launch {
            // That launch was handled before the restart; only a newer one starts a hop.
            self.last_hop_index = launch.hop_index;
        }
        let Some(pose) = pose else {
            return Ok(());
        };
        let position = Vector3::from(pose.world_from_body.position_m);
        let g = self.config.gravity_mps2;
        let in_flight = launch.filter(|launch| {
            let since_launch_s =
                (pose.stamp.sim_time_ns as f64 - launch.launch_time_ns as f64) * 1e-9;
            // Ballistic flight time over flat ground, less a frame for the landing.
            let flight_s = 2.0 * launch.velocity_mps[2] / g;
            since_launch_s >= 0.0 && since_launch_s < flight_s - 0.1
        });
        match in_flight {
            Some(launch) => {
                let since_launch_s =
                    (pose.stamp.sim_time_ns as f64 - launch.launch_time_ns as f64) * 1e-9;
                let mut velocity = launch.velocity_mps;
                velocity[2] -= g * since_launch_s;
                self.pending_launch = Some(HopLaunch {
                    world_from_body: pose.world_from_body,
                    velocity_mps: velocity,
                    launch_time_ns: pose.stamp.sim_time_ns,
                    position_known: 1,
                    ..launch
                });
            }
            None => self.resume_position = Some(position),
        }
        Ok(())
    }
}

impl Process for JumperVoProcess {
    type Error = JumperVoProcessError;

    fn new(context: &ProcessContext) -> Result<Self, JumperVoProcessError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        let section = jumper_vo_section(&config)?;
        let node = &context.node;
        Ok(Self {
            clouds: SlicePublisher::open(node, &topics::JUMPER_CLOUD, section.max_features * 2)?,
            config: section,
            vo: None,
            pending_launch: None,
            last_hop_index: 0,
            images: SliceSubscriber::open(node, &topics::JUMPER_IMAGE)?,
            altimeter: Subscriber::open(node, &topics::ALTIMETER)?,
            launches: Subscriber::open(node, &topics::HOP_LAUNCH)?,
            poses: hopnav_ipc::transport::Publisher::open(node, &topics::JUMPER_POSE)?,
            keyframes: 0,
            resume: if context.identity.incarnation > 0 {
                Some((
                    Subscriber::open(node, &topics::RESUME_JUMPER_POSE)?,
                    Subscriber::open(node, &topics::RESUME_HOP_LAUNCH)?,
                ))
            } else {
                None
            },
            resume_position: None,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        tick: &FrameTick,
    ) -> Result<(), JumperVoProcessError> {
        self.resume()?;
        // A restarted mapper gets the cloud history now, not at the next keyframe (a resting
        // jumper sends none for minutes).
        self.clouds.update_connections()?;
        if let Some(launch) = self.launches.receive_latest()?
            && launch.hop_index > self.last_hop_index
        {
            self.pending_launch = Some(launch);
        }
        let altitude_m = self
            .altimeter
            .receive_latest()?
            .map(|sample| sample.altitude_m);
        let Some(image) = self.images.receive_latest()? else {
            return Ok(()); // camera skipped this frame; the next one bridges the gap
        };
        let header = *image.header();
        if let Some(launch) = self.pending_launch.take() {
            self.start_hop(&launch, &header);
        }
        let Some(vo) = self.vo.as_mut() else {
            return Ok(()); // not launched yet: nothing to estimate
        };
        let Ok(view) = ImageView::new(
            image.elements(),
            header.width_px as usize,
            header.height_px as usize,
            header.stride_bytes as usize,
        ) else {
            return Ok(());
        };
        let output = vo.process_frame(FrameInput {
            frame_index: tick.stamp.frame_index,
            t_s: header.stamp.sim_time_ns as f64 * 1e-9,
            image: view,
            altimeter_m: altitude_m,
        });
        drop(image);
        let world_from_body = Pose3::from_isometry(&output.world_from_body);
        let stamp = header.stamp;
        self.poses.send(
            PoseEstimate::from_vo(
                Robot::Jumper,
                &stamp,
                world_from_body,
                output.confidence,
                output.scale.unwrap_or(0.0),
                output.tracked_features,
                output.is_keyframe,
            )
            .with_quality(pose_quality(output.status)),
        )?;
        if let Some(cloud) = &output.cloud {
            self.keyframes += 1;
            let cloud_camera = output
                .cloud_world_from_camera
                .map_or(world_from_body, |camera| Pose3::from_isometry(&camera));
            self.clouds.send_keyframe_cloud(
                Robot::Jumper,
                &stamp,
                cloud_camera,
                self.keyframes,
                cloud.len(),
                |index| {
                    let point = &cloud[index];
                    FeaturePoint::from_estimate(
                        point.position_m.into(),
                        point.height_above_ground_m,
                        index as u32,
                        point.depth_sigma_m,
                    )
                },
            )?;
        }
        Ok(())
    }

    fn rejected_samples(&self) -> u64 {
        self.images.rejected().total()
            + self.altimeter.rejected().total()
            + self.launches.rejected().total()
    }
}

/// What the jumper's pose rests on, as the pose message says it.
fn pose_quality(status: VoStatus) -> PoseQuality {
    match status {
        VoStatus::Tracking => PoseQuality::Measured,
        VoStatus::Propagating => PoseQuality::Coasting,
        VoStatus::Landed => PoseQuality::AtRest,
        VoStatus::Initializing => PoseQuality::Initial,
        VoStatus::Rejected => PoseQuality::Repeated,
    }
}
