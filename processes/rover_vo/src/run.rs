//! Runs the rover VO over a simulated traverse frame by frame, started as the process starts
//! it, and times each `process_frame` call: the driver the benchmark ([`crate::bench`]) and the
//! offline evaluation (`hopnav_eval::rover_vo`) share. It compares nothing with the truth.

use crate::config::RoverVoConfig;
use crate::motion::Tilt;
use crate::pipeline::{CloudPoint, RoverVo, StereoFrame, VoError, VoOutput, start_pose};
use crate::simulate::{SimError, SimulatedTraverse};
use hopnav_vision::image::ImageView;
use nalgebra::Isometry3;
use std::time::Instant;

/// Error of [`run_traverse`] (and of the benchmark, which also simulates the traverse).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The traverse could not be simulated.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The VO could not be created.
    #[error(transparent)]
    Vo(#[from] VoError),
    /// Too few frames to run.
    #[error("too few frames to evaluate")]
    TooFewFrames,
}

/// Outputs and timings of one run.
#[derive(Debug, Clone)]
pub struct TraverseRun {
    /// One output per frame.
    pub outputs: Vec<VoOutput>,
    /// Wall time of each `process_frame`, microseconds.
    pub frame_time_us: Vec<f64>,
    /// Thread CPU time of each `process_frame`, microseconds.
    pub frame_cpu_us: Vec<f64>,
    /// Keyframe clouds' points in total.
    pub cloud_points: usize,
    /// Every keyframe cloud point with the frame it was published at.
    pub clouds: Vec<(usize, CloudPoint)>,
}

/// Runs the VO over every frame of `sim`.
pub fn run_traverse(
    sim: &SimulatedTraverse,
    config: &RoverVoConfig,
) -> Result<TraverseRun, RunError> {
    let (Some(first_imu), Some(first_truth)) =
        (sim.imu_attitude.first(), sim.truth_world_from_body.first())
    else {
        return Err(RunError::TooFewFrames);
    };
    let (w, h) = (sim.rig.width_px as usize, sim.rig.height_px as usize);
    let start_xy = [first_truth.translation.x, first_truth.translation.y];
    let mut vo = RoverVo::new(config.clone(), sim.rig, Isometry3::identity())?;
    let mut run = TraverseRun {
        outputs: Vec::with_capacity(sim.left.len()),
        frame_time_us: Vec::with_capacity(sim.left.len()),
        frame_cpu_us: Vec::with_capacity(sim.left.len()),
        cloud_points: 0,
        clouds: Vec::new(),
    };
    let mut started = false;
    for k in 0..sim.left.len() {
        let (Ok(left), Ok(right)) = (
            ImageView::packed(&sim.left[k], w, h),
            ImageView::packed(&sim.right[k], w, h),
        ) else {
            continue;
        };
        let frame = StereoFrame {
            left,
            right,
            imu_attitude: sim.imu_attitude.get(k).copied(),
        };
        if !started {
            let height = vo
                .body_height_above_ground_m(&frame, Tilt::from_attitude(first_imu))
                .unwrap_or(0.4);
            vo.reset(start_pose(
                *first_imu,
                start_xy,
                sim.start_ground_z_m,
                height,
            ));
            started = true;
        }
        let cpu0 = crate::bench::thread_cpu_time_s();
        let t0 = Instant::now();
        let out = vo.process_frame(&frame);
        run.frame_time_us.push(t0.elapsed().as_secs_f64() * 1e6);
        run.frame_cpu_us
            .push((crate::bench::thread_cpu_time_s() - cpu0) * 1e6);
        if out.is_keyframe {
            run.cloud_points += vo.cloud().len();
            run.clouds.extend(vo.cloud().iter().map(|p| (k, *p)));
        }
        run.outputs.push(out);
    }
    Ok(run)
}

impl TraverseRun {
    /// Estimated poses.
    pub fn poses(&self) -> Vec<Isometry3<f64>> {
        self.outputs.iter().map(|o| o.world_from_body).collect()
    }
}

/// Quantile `q` of sorted `v`.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[(((sorted.len() - 1) as f64) * q).round() as usize]
}
