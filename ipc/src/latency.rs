//! Percentile summaries of latency samples.

use serde::Serialize;

/// p50/p99/p99.9/max of a set of durations, in milliseconds.
#[derive(Debug, Default, Clone, Copy, PartialEq, Serialize)]
pub struct LatencySummary {
    /// Samples summarised.
    pub count: usize,
    /// Median, ms.
    pub p50_ms: f64,
    /// 99th percentile, ms.
    pub p99_ms: f64,
    /// 99.9th percentile, ms.
    pub p999_ms: f64,
    /// Largest sample, ms.
    pub max_ms: f64,
    /// Mean, ms.
    pub mean_ms: f64,
}

impl LatencySummary {
    /// Summarises nanosecond samples (sorted in place, nearest-rank percentiles).
    pub fn from_ns(samples_ns: &mut [u64]) -> Self {
        if samples_ns.is_empty() {
            return Self::default();
        }
        samples_ns.sort_unstable();
        let rank = |quantile: f64| {
            let index = (quantile * samples_ns.len() as f64).ceil() as usize;
            samples_ns[index.clamp(1, samples_ns.len()) - 1] as f64 / 1e6
        };
        let sum_ns: u128 = samples_ns.iter().map(|&ns| u128::from(ns)).sum();
        Self {
            count: samples_ns.len(),
            p50_ms: rank(0.5),
            p99_ms: rank(0.99),
            p999_ms: rank(0.999),
            max_ms: samples_ns[samples_ns.len() - 1] as f64 / 1e6,
            mean_ms: sum_ns as f64 / samples_ns.len() as f64 / 1e6,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles() {
        let mut samples: Vec<u64> = (1..=1000).rev().map(|ms| ms * 1_000_000).collect();
        let summary = LatencySummary::from_ns(&mut samples);
        assert_eq!(summary.count, 1000);
        assert_eq!(summary.p50_ms, 500.0);
        assert_eq!(summary.p99_ms, 990.0);
        assert_eq!(summary.p999_ms, 999.0);
        assert_eq!(summary.max_ms, 1000.0);
        assert_eq!(summary.mean_ms, 500.5);
    }

    #[test]
    fn empty_and_single_samples() {
        assert_eq!(LatencySummary::from_ns(&mut []).count, 0);
        let one = LatencySummary::from_ns(&mut [2_000_000]);
        assert_eq!((one.p50_ms, one.p999_ms, one.max_ms), (2.0, 2.0, 2.0));
    }
}
