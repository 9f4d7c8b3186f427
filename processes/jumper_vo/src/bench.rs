//! Own-harness benchmark of [`crate::pipeline::JumperVo::process_frame`] on a rendered hop:
//! per-frame cost p50/p99/max at 320² with up to `max_features` features (target p99 ≤ 10 ms
//! with the local bundle adjustment).
//! Run with `hopnav bench vo`.

use crate::config::JumperVoConfig;
use crate::pipeline::VoError;
use crate::run::run_hop;
use crate::simulate::SimulatedHop;

/// Per-frame timing statistics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameCost {
    /// Frames timed.
    pub frames: usize,
    /// Median, microseconds.
    pub p50_us: f64,
    /// 99th percentile, microseconds.
    pub p99_us: f64,
    /// Maximum, microseconds.
    pub max_us: f64,
    /// Mean tracked features per frame.
    pub mean_features: f64,
    /// Median thread CPU time, microseconds (NaN without a thread CPU clock).
    pub cpu_p50_us: f64,
    /// 99th percentile of the thread CPU time, microseconds.
    pub cpu_p99_us: f64,
}

impl std::fmt::Display for FrameCost {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "process_frame over {} frames: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms ({:.0} features/frame); \
             thread CPU time p50 {:.2} ms, p99 {:.2} ms (wall minus time other processes took)",
            self.frames,
            self.p50_us / 1e3,
            self.p99_us / 1e3,
            self.max_us / 1e3,
            self.mean_features,
            self.cpu_p50_us / 1e3,
            self.cpu_p99_us / 1e3,
        )
    }
}

/// Runs the pipeline `repeats` times over `hop` and summarizes the frame times.
pub fn bench_hop(
    hop: &SimulatedHop,
    config: &JumperVoConfig,
    repeats: usize,
) -> Result<FrameCost, VoError> {
    let mut times = Vec::new();
    let mut cpu_times = Vec::new();
    let mut features = 0usize;
    for _ in 0..repeats.max(1) {
        let run = run_hop(hop, config)?;
        times.extend_from_slice(&run.frame_time_us);
        cpu_times.extend_from_slice(&run.frame_cpu_us);
        features += run
            .outputs
            .iter()
            .map(|o| o.tracked_features)
            .sum::<usize>();
    }
    times.sort_by(f64::total_cmp);
    cpu_times.sort_by(f64::total_cmp);
    Ok(FrameCost {
        frames: times.len(),
        p50_us: quantile(&times, 0.5),
        p99_us: quantile(&times, 0.99),
        max_us: times.last().copied().unwrap_or(f64::NAN),
        mean_features: features as f64 / times.len().max(1) as f64,
        cpu_p50_us: quantile(&cpu_times, 0.5),
        cpu_p99_us: quantile(&cpu_times, 0.99),
    })
}

/// Quantile `p` of sorted `values` (nearest rank); NaN when empty.
fn quantile(values: &[f64], p: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let i = ((values.len() - 1) as f64 * p).round() as usize;
    values[i.min(values.len() - 1)]
}
