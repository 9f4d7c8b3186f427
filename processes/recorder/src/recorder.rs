//! The recorder's lifecycle: open files in `new`, append each frame in `step`, flush in `stop`.

use std::path::PathBuf;

use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CloudHeader, FrameTick, ImageHeader, ImuSample, PoseEstimate,
};
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SliceSubscriber, Subscriber};
use serde_json::json;

use crate::RecorderError;
use crate::writers::{
    ImageStream, TextFile, write_altimeter, write_cloud, write_estimate, write_imu, write_truth,
};

/// Writes every frame's sensor data and ground truth to a dataset folder.
pub struct Recorder {
    dir: PathBuf,
    body_states: Subscriber<BodyStates>,
    altimeter: Subscriber<AltimeterSample>,
    imu: Subscriber<ImuSample>,
    jumper_poses: Subscriber<PoseEstimate>,
    rover_poses: Subscriber<PoseEstimate>,
    jumper_images: SliceSubscriber<ImageHeader>,
    rover_stereo: SliceSubscriber<ImageHeader>,
    jumper_clouds: SliceSubscriber<CloudHeader>,
    rover_clouds: SliceSubscriber<CloudHeader>,
    jumper_stream: ImageStream,
    rover_left: ImageStream,
    rover_right: ImageStream,
    truth_jumper: TextFile,
    truth_rover: TextFile,
    estimate_jumper: TextFile,
    estimate_rover: TextFile,
    altimeter_csv: TextFile,
    imu_csv: TextFile,
    clouds_csv: TextFile,
    cameras: serde_json::Map<String, serde_json::Value>,
}

impl Recorder {
    /// A recorder writing into `dir` (created if missing).
    pub fn open(context: &ProcessContext, dir: PathBuf) -> Result<Self, RecorderError> {
        std::fs::create_dir_all(&dir).map_err(|source| RecorderError::Io {
            path: dir.display().to_string(),
            source,
        })?;
        let node = &context.node;
        Ok(Self {
            body_states: Subscriber::open(node, &topics::BODY_STATES)?,
            altimeter: Subscriber::open(node, &topics::ALTIMETER)?,
            imu: Subscriber::open(node, &topics::IMU)?,
            jumper_poses: Subscriber::open(node, &topics::JUMPER_POSE)?,
            rover_poses: Subscriber::open(node, &topics::ROVER_POSE)?,
            jumper_images: SliceSubscriber::open(node, &topics::JUMPER_IMAGE)?,
            rover_stereo: SliceSubscriber::open(node, &topics::ROVER_STEREO)?,
            jumper_clouds: SliceSubscriber::open(node, &topics::JUMPER_CLOUD)?,
            rover_clouds: SliceSubscriber::open(node, &topics::ROVER_CLOUD)?,
            jumper_stream: ImageStream::create(dir.join("jumper_cam"))?,
            rover_left: ImageStream::create(dir.join("rover_left"))?,
            rover_right: ImageStream::create(dir.join("rover_right"))?,
            truth_jumper: TextFile::create(
                dir.join("groundtruth_jumper.tum"),
                "# t tx ty tz qx qy qz qw",
            )?,
            truth_rover: TextFile::create(
                dir.join("groundtruth_rover.tum"),
                "# t tx ty tz qx qy qz qw",
            )?,
            estimate_jumper: TextFile::create(
                dir.join("estimate_jumper_vo.tum"),
                "# jumper_vo estimate: t tx ty tz qx qy qz qw",
            )?,
            estimate_rover: TextFile::create(
                dir.join("estimate_rover_vo.tum"),
                "# rover_vo estimate: t tx ty tz qx qy qz qw",
            )?,
            altimeter_csv: TextFile::create(
                dir.join("altimeter.csv"),
                "frame,t_s,pressure_pa,altitude_m,altitude_sigma_m",
            )?,
            imu_csv: TextFile::create(
                dir.join("imu.csv"),
                "frame,t_s,qx,qy,qz,qw,gyro_x_radps,gyro_y_radps,gyro_z_radps,accel_x_mps2,accel_y_mps2,accel_z_mps2",
            )?,
            clouds_csv: TextFile::create(
                dir.join("clouds.csv"),
                "robot,keyframe,t_s,camera_x_m,camera_y_m,camera_z_m,x_m,y_m,z_m,height_above_ground_m,depth_sigma_m,track_id",
            )?,
            cameras: serde_json::Map::new(),
            dir,
        })
    }

    fn note_camera(&mut self, name: &str, header: &ImageHeader) {
        if self.cameras.contains_key(name) {
            return;
        }
        let intrinsics = &header.intrinsics;
        self.cameras.insert(
            name.to_owned(),
            json!({
                "width_px": header.width_px,
                "height_px": header.height_px,
                "fx_px": intrinsics.fx_px,
                "fy_px": intrinsics.fy_px,
                "cx_px": intrinsics.cx_px,
                "cy_px": intrinsics.cy_px,
                "baseline_m": header.baseline_m,
                "model": "pinhole, no distortion; camera frame x right, y down, z forward",
            }),
        );
    }

    fn flush_all(&mut self) -> Result<(), RecorderError> {
        self.jumper_stream.flush()?;
        self.rover_left.flush()?;
        self.rover_right.flush()?;
        self.truth_jumper.flush()?;
        self.truth_rover.flush()?;
        self.estimate_jumper.flush()?;
        self.estimate_rover.flush()?;
        self.altimeter_csv.flush()?;
        self.clouds_csv.flush()?;
        self.imu_csv.flush()
    }

    fn write_cameras(&self) -> Result<(), RecorderError> {
        let path = self.dir.join("cameras.json");
        let text = serde_json::to_string_pretty(&self.cameras).unwrap_or_default();
        std::fs::write(&path, text).map_err(|source| RecorderError::Io {
            path: path.display().to_string(),
            source,
        })
    }
}

impl Process for Recorder {
    type Error = RecorderError;

    fn new(context: &ProcessContext) -> Result<Self, RecorderError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        if config.recorder.dir.trim().is_empty() {
            return Err(RecorderError::NoDirectory);
        }
        Self::open(context, PathBuf::from(&config.recorder.dir))
    }

    fn step(&mut self, _context: &ProcessContext, _tick: &FrameTick) -> Result<(), RecorderError> {
        while let Some(states) = self.body_states.receive()? {
            let t_s = states.stamp.sim_time_ns as f64 * 1e-9;
            write_truth(&mut self.truth_jumper, t_s, &states.jumper)?;
            write_truth(&mut self.truth_rover, t_s, &states.rover)?;
        }
        while let Some(sample) = self.altimeter.receive()? {
            write_altimeter(&mut self.altimeter_csv, &sample)?;
        }
        while let Some(sample) = self.imu.receive()? {
            write_imu(&mut self.imu_csv, &sample)?;
        }
        while let Some(pose) = self.jumper_poses.receive()? {
            write_estimate(&mut self.estimate_jumper, &pose)?;
        }
        while let Some(pose) = self.rover_poses.receive()? {
            write_estimate(&mut self.estimate_rover, &pose)?;
        }
        while let Some(cloud) = self.jumper_clouds.receive()? {
            write_cloud(&mut self.clouds_csv, cloud.header(), cloud.elements())?;
        }
        while let Some(cloud) = self.rover_clouds.receive()? {
            write_cloud(&mut self.clouds_csv, cloud.header(), cloud.elements())?;
        }
        while let Some(image) = self.jumper_images.receive()? {
            let header = *image.header();
            self.jumper_stream.write(&header, image.elements(), 0)?;
            self.note_camera("jumper", &header);
        }
        while let Some(pair) = self.rover_stereo.receive()? {
            let header = *pair.header();
            self.rover_left.write(&header, pair.elements(), 0)?;
            if header.view_count > 1 {
                self.rover_right.write(&header, pair.elements(), 1)?;
            }
            self.note_camera("rover_stereo", &header);
        }
        // Flush every frame: a killed recorder loses at most the frame in progress.
        self.flush_all()
    }

    fn rejected_samples(&self) -> u64 {
        self.body_states.rejected().total()
            + self.altimeter.rejected().total()
            + self.imu.rejected().total()
            + self.jumper_poses.rejected().total()
            + self.rover_poses.rejected().total()
            + self.jumper_images.rejected().total()
            + self.rover_stereo.rejected().total()
            + self.jumper_clouds.rejected().total()
            + self.rover_clouds.rejected().total()
    }

    fn stop(&mut self, context: &ProcessContext) {
        if let Err(error) = self.flush_all().and_then(|()| self.write_cameras()) {
            eprintln!("[{}] {error}", context.identity.name);
        }
        eprintln!(
            "[{}] dataset {}: {} jumper images, {} rover stereo pairs",
            context.identity.name,
            self.dir.display(),
            self.jumper_stream.written,
            self.rover_left.written
        );
    }
}
