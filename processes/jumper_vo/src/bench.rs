//! Own-harness benchmark of [`crate::pipeline::JumperVo::process_frame`] on a rendered hop:
//! per-frame cost p50/p99/max at 320² with up to `max_features` features (target ≤ 5 ms).
//! Run with `hopnav bench vo`.

use crate::config::JumperVoConfig;
use crate::eval::run_hop;
use crate::pipeline::VoError;
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
}

impl std::fmt::Display for FrameCost {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "process_frame over {} frames: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms ({:.0} features/frame)",
            self.frames,
            self.p50_us / 1e3,
            self.p99_us / 1e3,
            self.max_us / 1e3,
            self.mean_features
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
    let mut features = 0usize;
    for _ in 0..repeats.max(1) {
        let run = run_hop(hop, config)?;
        times.extend_from_slice(&run.frame_time_us);
        features += run
            .outputs
            .iter()
            .map(|o| o.tracked_features)
            .sum::<usize>();
    }
    times.sort_by(f64::total_cmp);
    let q = |p: f64| -> f64 {
        if times.is_empty() {
            return f64::NAN;
        }
        let i = ((times.len() - 1) as f64 * p).round() as usize;
        times[i.min(times.len() - 1)]
    };
    Ok(FrameCost {
        frames: times.len(),
        p50_us: q(0.5),
        p99_us: q(0.99),
        max_us: times.last().copied().unwrap_or(f64::NAN),
        mean_features: features as f64 / times.len().max(1) as f64,
    })
}
