//! `hopnav topic bw`: bytes per second of a topic, over a sliding window and over a whole
//! watch.

use std::collections::VecDeque;

/// Bandwidth of a run of arrivals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandwidthStats {
    /// Samples counted.
    pub samples: usize,
    /// Bytes per second: the bytes of every sample after the first over the time from the
    /// first arrival to the last (as a rate counts periods, not samples).
    pub bytes_per_s: f64,
    /// Mean sample size, bytes.
    pub mean_sample_bytes: f64,
    /// Smallest sample, bytes.
    pub min_sample_bytes: usize,
    /// Largest sample, bytes.
    pub max_sample_bytes: usize,
}

/// Running sums of a set of arrivals, from which [`BandwidthStats`] follow.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Sums {
    samples: usize,
    bytes: u128,
    first_ns: u64,
    first_bytes: usize,
    last_ns: u64,
    min_bytes: usize,
    max_bytes: usize,
}

impl Sums {
    fn stats(&self) -> Option<BandwidthStats> {
        let span_ns = self.last_ns.checked_sub(self.first_ns)?;
        if self.samples < 2 || span_ns == 0 {
            return None;
        }
        let after_first = self.bytes.saturating_sub(self.first_bytes as u128);
        Some(BandwidthStats {
            samples: self.samples,
            bytes_per_s: after_first as f64 / (span_ns as f64 * 1e-9),
            mean_sample_bytes: self.bytes as f64 / self.samples as f64,
            min_sample_bytes: self.min_bytes,
            max_sample_bytes: self.max_bytes,
        })
    }
}

/// The arrivals of the last `window_ns` with their sizes, for the line printed every second.
#[derive(Debug, Clone)]
pub struct ByteWindow {
    window_ns: u64,
    arrivals: VecDeque<(u64, usize)>,
}

impl ByteWindow {
    /// An empty window `window_ns` long.
    pub fn new(window_ns: u64) -> Self {
        Self {
            window_ns,
            arrivals: VecDeque::new(),
        }
    }

    /// Adds a sample of `bytes` arrived at `now_ns` and forgets those older than the window.
    pub fn push(&mut self, now_ns: u64, bytes: usize) {
        self.arrivals.push_back((now_ns, bytes));
        self.forget_before(now_ns);
    }

    /// The bandwidth of the samples within the window ending at `now_ns`; `None` below two
    /// samples or when they span no time.
    pub fn stats(&mut self, now_ns: u64) -> Option<BandwidthStats> {
        self.forget_before(now_ns);
        let mut sums = ByteTotals::default();
        for &(arrival_ns, bytes) in &self.arrivals {
            sums.push(arrival_ns, bytes);
        }
        sums.stats()
    }

    fn forget_before(&mut self, now_ns: u64) {
        let oldest_kept_ns = now_ns.saturating_sub(self.window_ns);
        while self
            .arrivals
            .front()
            .is_some_and(|&(arrival_ns, _)| arrival_ns < oldest_kept_ns)
        {
            self.arrivals.pop_front();
        }
    }
}

/// Byte counts over a whole watch, in constant memory: the summary printed at the end.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ByteTotals(Sums);

impl ByteTotals {
    /// Adds a sample of `bytes` arrived at `now_ns` (not before the last one).
    pub fn push(&mut self, now_ns: u64, bytes: usize) {
        let sums = &mut self.0;
        if sums.samples == 0 {
            sums.first_ns = now_ns;
            sums.first_bytes = bytes;
            sums.min_bytes = bytes;
        }
        sums.min_bytes = sums.min_bytes.min(bytes);
        sums.max_bytes = sums.max_bytes.max(bytes);
        sums.bytes += bytes as u128;
        sums.last_ns = now_ns;
        sums.samples += 1;
    }

    /// Samples so far.
    pub fn samples(&self) -> usize {
        self.0.samples
    }

    /// Bytes so far.
    pub fn bytes(&self) -> u128 {
        self.0.bytes
    }

    /// The whole watch's bandwidth; `None` below two samples.
    pub fn stats(&self) -> Option<BandwidthStats> {
        self.0.stats()
    }
}

/// `bytes` in the largest binary unit that keeps it at least 1 (B, KiB, MiB, GiB).
pub fn human_bytes(bytes: f64) -> String {
    const UNITS: [&str; 4] = ["B", "KiB", "MiB", "GiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} {}", UNITS[unit])
    } else {
        format!("{value:.2} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u64 = 1_000_000;

    #[test]
    fn ten_samples_of_a_kib_a_tenth_of_a_second_apart_make_ten_kib_per_second() {
        let mut totals = ByteTotals::default();
        for i in 0..10 {
            totals.push(i * 100 * MS, 1024);
        }
        let stats = totals.stats().expect("stats");
        assert!((stats.bytes_per_s - 10_240.0).abs() < 1e-6, "{stats:?}");
        assert_eq!(
            (stats.min_sample_bytes, stats.max_sample_bytes),
            (1024, 1024)
        );
        assert_eq!(totals.bytes(), 10_240);
    }

    #[test]
    fn the_window_forgets_old_samples_and_keeps_the_size_range_of_the_rest() {
        let mut window = ByteWindow::new(1000 * MS);
        window.push(0, 1_000_000);
        for i in 1..=20 {
            window.push(3000 * MS + i * 50 * MS, if i % 2 == 0 { 100 } else { 300 });
        }
        let stats = window.stats(4000 * MS).expect("stats");
        assert_eq!(
            stats.max_sample_bytes, 300,
            "the old big sample is forgotten"
        );
        assert_eq!(stats.min_sample_bytes, 100);
        assert!((stats.mean_sample_bytes - 200.0).abs() < 1e-9);
        assert!(window.stats(60_000 * MS).is_none(), "all forgotten");
    }

    #[test]
    fn fewer_than_two_samples_or_no_time_give_no_bandwidth() {
        let mut totals = ByteTotals::default();
        assert!(totals.stats().is_none());
        totals.push(5, 10);
        assert!(totals.stats().is_none());
        totals.push(5, 10);
        assert!(totals.stats().is_none(), "two samples at one instant");
    }

    #[test]
    fn sizes_read_in_binary_units() {
        assert_eq!(human_bytes(512.0), "512 B");
        assert_eq!(human_bytes(1536.0), "1.50 KiB");
        assert_eq!(human_bytes(3.0 * 1024.0 * 1024.0), "3.00 MiB");
    }
}
