//! Runs the jumper VO over a simulated hop frame by frame and times each `process_frame`
//! call: the driver the benchmark ([`crate::bench`]) and the offline evaluation
//! (`hopnav_eval::jumper_vo`) share. It compares nothing with the truth.

use crate::config::JumperVoConfig;
use crate::output::{FrameInput, VoOutput};
use crate::pipeline::{JumperVo, VoError};
use crate::simulate::SimulatedHop;
use hopnav_vision::image::ImageView;
use nalgebra::Isometry3;
use std::time::Instant;

/// Outputs and per-frame timings of one run.
#[derive(Debug, Clone)]
pub struct HopRun {
    /// One output per frame.
    pub outputs: Vec<VoOutput>,
    /// Wall time of each `process_frame` call, microseconds.
    pub frame_time_us: Vec<f64>,
    /// CPU time of the calling thread in each `process_frame` call, microseconds (NaN where
    /// the clock is unavailable): unlike wall time, not inflated by other processes.
    pub frame_cpu_us: Vec<f64>,
}

/// CPU time consumed by the calling thread, seconds; `None` if the clock is unavailable.
pub fn thread_cpu_time_s() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call, and
    // CLOCK_THREAD_CPUTIME_ID is a clock id every supported (POSIX) target defines.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

impl HopRun {
    /// Estimated poses.
    pub fn poses(&self) -> Vec<Isometry3<f64>> {
        self.outputs.iter().map(|o| o.world_from_body).collect()
    }
}

/// Runs the pipeline over every frame of `hop`, starting from the true launch pose, with
/// `config`'s robot model replaced by the simulated robot's ([`SimulatedHop::robot_config`]).
pub fn run_hop(hop: &SimulatedHop, config: &JumperVoConfig) -> Result<HopRun, VoError> {
    let initial = hop
        .truth_world_from_body
        .first()
        .copied()
        .unwrap_or_else(Isometry3::identity);
    run_hop_from(hop, &hop.robot_config(config), initial)
}

/// Runs the pipeline over every frame of `hop` from `launch_world_from_body` with `config` as
/// given: what the VO believes about the launch (its pose, the commanded velocity and spin)
/// may differ from what was flown.
pub fn run_hop_from(
    hop: &SimulatedHop,
    config: &JumperVoConfig,
    launch_world_from_body: Isometry3<f64>,
) -> Result<HopRun, VoError> {
    let mut vo = JumperVo::new(config.clone(), hop.camera, launch_world_from_body)?;
    let mut run = HopRun {
        outputs: Vec::with_capacity(hop.images.len()),
        frame_time_us: Vec::with_capacity(hop.images.len()),
        frame_cpu_us: Vec::with_capacity(hop.images.len()),
    };
    for (k, image) in hop.images.iter().enumerate() {
        let Ok(view) = ImageView::packed(image, hop.width_px, hop.height_px) else {
            continue;
        };
        let input = FrameInput {
            frame_index: k as u64,
            t_s: hop.t_s.get(k).copied().unwrap_or(f64::NAN),
            image: view,
            altimeter_m: hop.altimeter_m.get(k).copied(),
        };
        let cpu_start = thread_cpu_time_s();
        let start = Instant::now();
        let out = vo.process_frame(input);
        run.frame_time_us.push(start.elapsed().as_secs_f64() * 1e6);
        let cpu_us = match (cpu_start, thread_cpu_time_s()) {
            (Some(a), Some(b)) => (b - a) * 1e6,
            _ => f64::NAN,
        };
        run.frame_cpu_us.push(cpu_us);
        run.outputs.push(out);
    }
    Ok(run)
}
