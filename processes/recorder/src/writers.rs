//! Buffered files of one dataset, opened once, appended to every frame.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use hopnav_ipc::messages::{
    AltimeterSample, BodyState, CloudHeader, FeaturePoint, ImageHeader, ImuSample, PoseEstimate,
    Robot,
};

use crate::formats::pgm::write_pgm;
use crate::formats::tum::{TumPose, write_tum_line};
use crate::{RecorderError, RecordingError};

/// Turns an OS error on `path` into the recorder's [`RecordingError::Io`].
pub(crate) fn io_error(path: &Path) -> impl Fn(std::io::Error) -> RecorderError + '_ {
    move |source| {
        RecorderError::Own(RecordingError::Io {
            path: path.display().to_string(),
            source,
        })
    }
}

/// A CSV (or TUM) file with a header line.
pub struct TextFile {
    path: PathBuf,
    out: BufWriter<File>,
}

impl TextFile {
    /// Creates `path` and writes `header`.
    pub fn create(path: PathBuf, header: &str) -> Result<Self, RecorderError> {
        let file = File::create(&path).map_err(io_error(&path))?;
        let mut out = BufWriter::new(file);
        writeln!(out, "{header}").map_err(io_error(&path))?;
        Ok(Self { path, out })
    }

    /// Runs `write` on the file, naming the file in any error.
    pub fn append(
        &mut self,
        write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
    ) -> Result<(), RecorderError> {
        write(&mut self.out).map_err(io_error(&self.path))
    }

    /// Flushes to disk.
    pub fn flush(&mut self) -> Result<(), RecorderError> {
        self.out.flush().map_err(io_error(&self.path))
    }
}

/// One camera stream: a folder of PGMs and its index.
pub struct ImageStream {
    dir: PathBuf,
    index: TextFile,
    /// Images written.
    pub written: u64,
}

impl ImageStream {
    /// Creates `dir` and its `index.csv`.
    pub fn create(dir: PathBuf) -> Result<Self, RecorderError> {
        std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
        let index = TextFile::create(dir.join("index.csv"), "frame,t_s,file")?;
        Ok(Self {
            dir,
            index,
            written: 0,
        })
    }

    /// Writes view `view` of an image sample.
    pub fn write(
        &mut self,
        header: &ImageHeader,
        pixels: &[u8],
        view: usize,
    ) -> Result<(), RecorderError> {
        let frame = header.stamp.frame_index;
        let file_name = format!("{frame:06}.pgm");
        let path = self.dir.join(&file_name);
        let view_len = header.view_len_bytes();
        let view_pixels = pixels
            .get(view * view_len..(view + 1) * view_len)
            .unwrap_or(&[]);
        let file = File::create(&path).map_err(io_error(&path))?;
        let mut out = BufWriter::new(file);
        write_pgm(
            &mut out,
            header.width_px as usize,
            header.height_px as usize,
            header.stride_bytes as usize,
            view_pixels,
        )
        .and_then(|()| out.flush())
        .map_err(io_error(&path))?;
        let t_s = header.stamp.sim_time_ns as f64 * 1e-9;
        self.index
            .append(|out| writeln!(out, "{frame},{t_s:.3},{file_name}"))?;
        self.written += 1;
        Ok(())
    }

    /// Flushes the index.
    pub fn flush(&mut self) -> Result<(), RecorderError> {
        self.index.flush()
    }
}

/// Appends a body state as a TUM line.
pub fn write_truth(file: &mut TextFile, t_s: f64, body: &BodyState) -> Result<(), RecorderError> {
    let pose = TumPose {
        t_s,
        position_m: body.world_from_body.position_m,
        orientation_xyzw: body.world_from_body.orientation_xyzw,
    };
    file.append(|out| write_tum_line(out, &pose))
}

/// Appends a VO pose estimate as a TUM line stamped with its sim time.
pub fn write_estimate(file: &mut TextFile, pose: &PoseEstimate) -> Result<(), RecorderError> {
    let pose = TumPose {
        t_s: pose.stamp.sim_time_ns as f64 * 1e-9,
        position_m: pose.world_from_body.position_m,
        orientation_xyzw: pose.world_from_body.orientation_xyzw,
    };
    file.append(|out| write_tum_line(out, &pose))
}

/// Appends the points of one feature cloud, each with the camera position it was seen from.
pub fn write_cloud(
    file: &mut TextFile,
    header: &CloudHeader,
    points: &[FeaturePoint],
) -> Result<(), RecorderError> {
    let t_s = header.stamp.sim_time_ns as f64 * 1e-9;
    let [cx, cy, cz] = header.world_from_camera.position_m;
    let robot = match Robot::from_code(header.robot) {
        Some(Robot::Jumper) => "jumper",
        Some(Robot::Rover) => "rover",
        None => "unknown",
    };
    file.append(|out| {
        for point in points {
            let [x, y, z] = point.position_m;
            writeln!(
                out,
                "{robot},{},{t_s:.3},{cx:.3},{cy:.3},{cz:.3},{x:.3},{y:.3},{z:.3},{:.3},{:.4},{}",
                header.keyframe_index,
                point.height_above_ground_m,
                point.depth_sigma_m,
                point.track_id
            )?;
        }
        Ok(())
    })
}

/// Appends an altimeter sample.
pub fn write_altimeter(file: &mut TextFile, sample: &AltimeterSample) -> Result<(), RecorderError> {
    let t_s = sample.stamp.sim_time_ns as f64 * 1e-9;
    file.append(|out| {
        writeln!(
            out,
            "{},{t_s:.3},{:.4},{:.4},{:.3}",
            sample.stamp.frame_index,
            sample.pressure_pa,
            sample.altitude_m,
            sample.altitude_sigma_m
        )
    })
}

/// Appends an IMU sample.
pub fn write_imu(file: &mut TextFile, sample: &ImuSample) -> Result<(), RecorderError> {
    let t_s = sample.stamp.sim_time_ns as f64 * 1e-9;
    let [qx, qy, qz, qw] = sample.attitude_xyzw;
    let [wx, wy, wz] = sample.angular_rate_radps;
    let [ax, ay, az] = sample.specific_force_mps2;
    file.append(|out| {
        writeln!(
            out,
            "{},{t_s:.3},{qx:.9},{qy:.9},{qz:.9},{qw:.9},{wx:.6},{wy:.6},{wz:.6},{ax:.6},{ay:.6},{az:.6}",
            sample.stamp.frame_index
        )
    })
}
