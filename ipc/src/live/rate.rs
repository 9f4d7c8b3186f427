//! Receive-rate statistics (`hopnav topic hz`), plain functions of arrival times.

use std::collections::VecDeque;

/// Rate and period spread of a run of arrivals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateStats {
    /// Arrivals counted.
    pub samples: usize,
    /// Mean rate: periods per second between the first and the last arrival.
    pub mean_rate_hz: f64,
    /// Shortest period between two arrivals.
    pub min_period_s: f64,
    /// Longest period between two arrivals.
    pub max_period_s: f64,
    /// Standard deviation of the periods.
    pub std_dev_period_s: f64,
}

/// Statistics of `arrivals_ns` (ascending nanosecond times); `None` below two arrivals, or
/// when they span no time.
pub fn rate_stats(arrivals_ns: &[u64]) -> Option<RateStats> {
    let (first_ns, last_ns) = (*arrivals_ns.first()?, *arrivals_ns.last()?);
    let span_s = last_ns.checked_sub(first_ns)? as f64 * 1e-9;
    if arrivals_ns.len() < 2 || span_s <= 0.0 {
        return None;
    }
    let periods_s: Vec<f64> = arrivals_ns
        .windows(2)
        .map(|pair| pair[1].saturating_sub(pair[0]) as f64 * 1e-9)
        .collect();
    let mean_period_s = span_s / periods_s.len() as f64;
    let variance_s2 = periods_s
        .iter()
        .map(|period_s| (period_s - mean_period_s).powi(2))
        .sum::<f64>()
        / periods_s.len() as f64;
    Some(RateStats {
        samples: arrivals_ns.len(),
        mean_rate_hz: 1.0 / mean_period_s,
        min_period_s: periods_s.iter().copied().fold(f64::INFINITY, f64::min),
        max_period_s: periods_s.iter().copied().fold(0.0, f64::max),
        std_dev_period_s: variance_s2.sqrt(),
    })
}

/// The arrivals of the last `window_ns`, for the rate printed every second.
#[derive(Debug, Clone)]
pub struct ArrivalWindow {
    window_ns: u64,
    arrivals_ns: VecDeque<u64>,
}

impl ArrivalWindow {
    /// An empty window `window_ns` long.
    pub fn new(window_ns: u64) -> Self {
        Self {
            window_ns,
            arrivals_ns: VecDeque::new(),
        }
    }

    /// Adds an arrival at `now_ns` and forgets those older than the window.
    pub fn push(&mut self, now_ns: u64) {
        self.arrivals_ns.push_back(now_ns);
        self.forget_before(now_ns);
    }

    /// The statistics of the arrivals within the window ending at `now_ns`.
    pub fn stats(&mut self, now_ns: u64) -> Option<RateStats> {
        self.forget_before(now_ns);
        rate_stats(self.arrivals_ns.make_contiguous())
    }

    fn forget_before(&mut self, now_ns: u64) {
        let oldest_kept_ns = now_ns.saturating_sub(self.window_ns);
        while self
            .arrivals_ns
            .front()
            .is_some_and(|&arrival_ns| arrival_ns < oldest_kept_ns)
        {
            self.arrivals_ns.pop_front();
        }
    }
}

/// Counts over a whole watch, in constant memory: the summary printed at the end.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RateTotals {
    samples: usize,
    first_ns: u64,
    last_ns: u64,
    min_period_ns: u64,
    max_period_ns: u64,
}

impl RateTotals {
    /// Adds an arrival at `now_ns` (not before the last one).
    pub fn push(&mut self, now_ns: u64) {
        if self.samples == 0 {
            self.first_ns = now_ns;
            self.min_period_ns = u64::MAX;
        } else {
            let period_ns = now_ns.saturating_sub(self.last_ns);
            self.min_period_ns = self.min_period_ns.min(period_ns);
            self.max_period_ns = self.max_period_ns.max(period_ns);
        }
        self.last_ns = now_ns;
        self.samples += 1;
    }

    /// Arrivals so far.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Mean rate, min and max period over every arrival (no standard deviation: it would
    /// need every period kept); `None` below two arrivals.
    pub fn stats(&self) -> Option<RateStats> {
        let span_ns = self.last_ns.saturating_sub(self.first_ns);
        if self.samples < 2 || span_ns == 0 {
            return None;
        }
        Some(RateStats {
            samples: self.samples,
            mean_rate_hz: (self.samples - 1) as f64 / (span_ns as f64 * 1e-9),
            min_period_s: self.min_period_ns as f64 * 1e-9,
            max_period_s: self.max_period_ns as f64 * 1e-9,
            std_dev_period_s: f64::NAN,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u64 = 1_000_000;

    #[test]
    fn a_steady_stream_has_its_rate_and_no_spread() {
        let arrivals: Vec<u64> = (0..11).map(|i| 5 * MS + i * 100 * MS).collect();
        let stats = rate_stats(&arrivals).unwrap();
        assert_eq!(stats.samples, 11);
        assert!((stats.mean_rate_hz - 10.0).abs() < 1e-9);
        assert!((stats.min_period_s - 0.1).abs() < 1e-12);
        assert!((stats.max_period_s - 0.1).abs() < 1e-12);
        assert!(stats.std_dev_period_s < 1e-12);
    }

    #[test]
    fn jitter_shows_in_min_max_and_spread_not_in_the_mean() {
        // Periods 90, 110, 90, 110 ms: mean 100 ms.
        let arrivals = [0, 90 * MS, 200 * MS, 290 * MS, 400 * MS];
        let stats = rate_stats(&arrivals).unwrap();
        assert!((stats.mean_rate_hz - 10.0).abs() < 1e-9);
        assert!((stats.min_period_s - 0.09).abs() < 1e-12);
        assert!((stats.max_period_s - 0.11).abs() < 1e-12);
        assert!((stats.std_dev_period_s - 0.01).abs() < 1e-12);
    }

    #[test]
    fn fewer_than_two_arrivals_give_no_rate() {
        assert_eq!(rate_stats(&[]), None);
        assert_eq!(rate_stats(&[7]), None);
        assert_eq!(rate_stats(&[7, 7]), None);
    }

    #[test]
    fn the_window_forgets_old_arrivals() {
        let mut window = ArrivalWindow::new(1000 * MS);
        // 20 Hz for a second, then 10 Hz for two seconds.
        for i in 0..20 {
            window.push(i * 50 * MS);
        }
        for i in 0..20 {
            window.push(1000 * MS + i * 100 * MS);
        }
        let stats = window.stats(2900 * MS).unwrap();
        assert!((stats.mean_rate_hz - 10.0).abs() < 1e-9, "{stats:?}");
        assert_eq!(stats.samples, 11);
        // Nothing arrives for longer than the window: no rate.
        assert_eq!(window.stats(5000 * MS), None);
    }

    #[test]
    fn totals_match_the_full_statistics() {
        let arrivals = [0, 90 * MS, 200 * MS, 290 * MS, 400 * MS];
        let mut totals = RateTotals::default();
        assert_eq!(totals.stats(), None);
        for arrival in arrivals {
            totals.push(arrival);
        }
        let full = rate_stats(&arrivals).unwrap();
        let total = totals.stats().unwrap();
        assert_eq!(totals.samples(), 5);
        assert!((total.mean_rate_hz - full.mean_rate_hz).abs() < 1e-9);
        assert!((total.min_period_s - full.min_period_s).abs() < 1e-12);
        assert!((total.max_period_s - full.max_period_s).abs() < 1e-12);
    }
}
