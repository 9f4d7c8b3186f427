//! The dataset folder (`--export-dataset DIR`): PGM streams, sensor CSVs, TUM trajectories.

use std::path::PathBuf;

use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CloudHeader, FeaturePoint, ImageHeader, ImuSample, PoseEstimate,
};
use serde_json::json;

use crate::RecorderError;
use crate::writers::{
    ImageStream, TextFile, io_error, write_altimeter, write_cloud, write_estimate, write_imu,
    write_truth,
};

/// The files of one dataset, opened once, appended to every frame.
pub struct Dataset {
    dir: PathBuf,
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

impl Dataset {
    /// A dataset in `dir` (created if missing).
    pub fn create(dir: PathBuf) -> Result<Self, RecorderError> {
        std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
        Ok(Self {
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

    /// Appends both robots' ground truth.
    pub fn body_states(&mut self, states: &BodyStates) -> Result<(), RecorderError> {
        let t_s = states.stamp.sim_time_ns as f64 * 1e-9;
        write_truth(&mut self.truth_jumper, t_s, &states.jumper)?;
        write_truth(&mut self.truth_rover, t_s, &states.rover)
    }

    /// Appends an altimeter sample.
    pub fn altimeter(&mut self, sample: &AltimeterSample) -> Result<(), RecorderError> {
        write_altimeter(&mut self.altimeter_csv, sample)
    }

    /// Appends an IMU sample.
    pub fn imu(&mut self, sample: &ImuSample) -> Result<(), RecorderError> {
        write_imu(&mut self.imu_csv, sample)
    }

    /// Appends a jumper VO estimate.
    pub fn jumper_pose(&mut self, pose: &PoseEstimate) -> Result<(), RecorderError> {
        write_estimate(&mut self.estimate_jumper, pose)
    }

    /// Appends a rover VO estimate.
    pub fn rover_pose(&mut self, pose: &PoseEstimate) -> Result<(), RecorderError> {
        write_estimate(&mut self.estimate_rover, pose)
    }

    /// Appends a feature cloud.
    pub fn cloud(
        &mut self,
        header: &CloudHeader,
        points: &[FeaturePoint],
    ) -> Result<(), RecorderError> {
        write_cloud(&mut self.clouds_csv, header, points)
    }

    /// Writes a jumper image.
    pub fn jumper_image(
        &mut self,
        header: &ImageHeader,
        pixels: &[u8],
    ) -> Result<(), RecorderError> {
        self.jumper_stream.write(header, pixels, 0)?;
        self.note_camera("jumper", header);
        Ok(())
    }

    /// Writes both views of a rover stereo pair.
    pub fn rover_pair(&mut self, header: &ImageHeader, pixels: &[u8]) -> Result<(), RecorderError> {
        self.rover_left.write(header, pixels, 0)?;
        if header.view_count > 1 {
            self.rover_right.write(header, pixels, 1)?;
        }
        self.note_camera("rover_stereo", header);
        Ok(())
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

    /// Flushes every file.
    pub fn flush_all(&mut self) -> Result<(), RecorderError> {
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

    /// Flushes every file and writes `cameras.json`.
    pub fn finish(&mut self) -> Result<(), RecorderError> {
        self.flush_all()?;
        let path = self.dir.join("cameras.json");
        let text = serde_json::to_string_pretty(&self.cameras).unwrap_or_default();
        std::fs::write(&path, text).map_err(io_error(&path))
    }

    /// One line on what was written.
    pub fn describe(&self) -> String {
        format!(
            "dataset {}: {} jumper images, {} rover stereo pairs",
            self.dir.display(),
            self.jumper_stream.written,
            self.rover_left.written
        )
    }
}
