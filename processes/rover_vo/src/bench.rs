//! Own-harness benchmark of [`crate::pipeline::RoverVo::process_frame`] on a rendered traverse:
//! cost per stereo frame (320×240, target ≤ 10 ms), p50/p99/max, split into keyframes and
//! tracking frames. Rendering is done once, before timing. Wall time and the thread's CPU time
//! are both reported: on a shared, loaded machine the wall-time tail measures preemption.
//!
//! ```no_run
//! use hopnav_rover_vo::bench::{BenchOptions, run};
//! println!("{}", run(&BenchOptions::default()).unwrap());
//! ```

use crate::config::RoverVoConfig;
use crate::run::{RunError, quantile, run_traverse};
use crate::simulate::{TraverseConfig, simulate_traverse};

/// What to benchmark.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// The traverse (default: the first 400 frames of the evaluation traverse).
    pub traverse: TraverseConfig,
    /// VO settings.
    pub vo: RoverVoConfig,
    /// Passes over the traverse.
    pub repeats: usize,
}

impl Default for BenchOptions {
    fn default() -> Self {
        Self {
            traverse: TraverseConfig {
                max_frames: Some(400),
                ..TraverseConfig::default()
            },
            vo: RoverVoConfig::default(),
            repeats: 3,
        }
    }
}

/// Per-frame timing statistics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenchReport {
    /// Frames timed.
    pub frames: usize,
    /// Median, milliseconds.
    pub p50_ms: f64,
    /// 99th percentile, milliseconds.
    pub p99_ms: f64,
    /// Maximum, milliseconds.
    pub max_ms: f64,
    /// Median of keyframes only, milliseconds.
    pub keyframe_p50_ms: f64,
    /// Median of non-keyframes only, milliseconds.
    pub tracking_p50_ms: f64,
    /// Mean tracked features per frame.
    pub mean_features: f64,
    /// Thread CPU time per frame, median, milliseconds.
    pub cpu_p50_ms: f64,
    /// Thread CPU time per frame, 99th percentile, milliseconds.
    pub cpu_p99_ms: f64,
    /// Thread CPU time per frame, maximum, milliseconds.
    pub cpu_max_ms: f64,
}

/// CPU time consumed by the calling thread, seconds (NaN if unavailable).
pub(crate) fn thread_cpu_time_s() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call, and
    // CLOCK_THREAD_CPUTIME_ID is a clock id every Linux supports.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc == 0 {
        ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
    } else {
        f64::NAN
    }
}

impl std::fmt::Display for BenchReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "rover VO process_frame over {} stereo frames: wall p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms \
             (keyframes p50 {:.2} ms, tracking p50 {:.2} ms, {:.0} features/frame); \
             thread CPU p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
            self.frames,
            self.p50_ms,
            self.p99_ms,
            self.max_ms,
            self.keyframe_p50_ms,
            self.tracking_p50_ms,
            self.mean_features,
            self.cpu_p50_ms,
            self.cpu_p99_ms,
            self.cpu_max_ms
        )
    }
}

/// Renders the traverse once, runs the VO `repeats` times over it and reports frame times.
pub fn run(options: &BenchOptions) -> Result<BenchReport, RunError> {
    let sim = simulate_traverse(&options.traverse)?;
    let mut all = Vec::new();
    let mut keyframes = Vec::new();
    let mut tracking = Vec::new();
    let mut cpu = Vec::new();
    let mut features = 0usize;
    for _ in 0..options.repeats.max(1) {
        let run = run_traverse(&sim, &options.vo)?;
        cpu.extend(run.frame_cpu_us.iter().map(|us| us / 1e3));
        for (out, &us) in run.outputs.iter().zip(&run.frame_time_us) {
            let ms = us / 1e3;
            all.push(ms);
            features += out.tracked_features;
            if out.is_keyframe {
                keyframes.push(ms);
            } else {
                tracking.push(ms);
            }
        }
    }
    for v in [&mut all, &mut keyframes, &mut tracking, &mut cpu] {
        v.sort_by(f64::total_cmp);
    }
    Ok(BenchReport {
        frames: all.len(),
        p50_ms: quantile(&all, 0.5),
        p99_ms: quantile(&all, 0.99),
        max_ms: all.last().copied().unwrap_or(f64::NAN),
        keyframe_p50_ms: quantile(&keyframes, 0.5),
        tracking_p50_ms: quantile(&tracking, 0.5),
        mean_features: features as f64 / all.len().max(1) as f64,
        cpu_p50_ms: quantile(&cpu, 0.5),
        cpu_p99_ms: quantile(&cpu, 0.99),
        cpu_max_ms: cpu.last().copied().unwrap_or(f64::NAN),
    })
}
