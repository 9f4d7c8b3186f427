//! `hopnav topic hz TOPIC`: the receive rate of one topic of a running launch, every second.

use std::ops::ControlFlow;
use std::process::ExitCode;

use clap::Args;
use hopnav_ipc::live::{ArrivalWindow, RateStats, RateTotals, TapSample, Watcher};

use crate::topic_window::{WindowArgs, continue_until, exit_code, watch_topic};

#[derive(Debug, Args)]
pub struct HzArgs {
    /// Topic name, e.g. hopnav/camera/jumper (the hopnav/ prefix may be left out).
    topic: String,
    #[command(flatten)]
    window: WindowArgs,
}

pub fn run(args: &HzArgs) -> ExitCode {
    let watched = match watch_topic(&args.window, &args.topic, |_, started_ns| RateMeter {
        window: ArrivalWindow::new(args.window.window_ns()),
        window_s: args.window.window_s,
        received: RateTotals::default(),
        published: RateTotals::default(),
        stop_ns: args.window.stop_ns(started_ns),
    }) {
        Ok(watched) => watched,
        Err(code) => return code,
    };
    let (meter, elapsed_s) = (&watched.watcher, watched.elapsed_s);
    println!(
        "{}: {} samples in {elapsed_s:.1} s; {}; by publish stamps: {}; rejected {}",
        watched.name,
        meter.received.samples(),
        total_text(meter.received.stats()),
        total_text(meter.published.stats()),
        watched.rejected.total()
    );
    exit_code(&watched.namespace, watched.end)
}

/// The arrivals of one watch: the window printed every second and the totals at the end.
struct RateMeter {
    window: ArrivalWindow,
    window_s: f64,
    received: RateTotals,
    /// The publisher's own stamps: its rate without this tool's wake-up jitter.
    published: RateTotals,
    stop_ns: Option<u64>,
}

impl Watcher for RateMeter {
    fn on_sample(&mut self, sample: &dyn TapSample, arrival_ns: u64) {
        self.window.push(arrival_ns);
        self.received.push(arrival_ns);
        self.published.push(sample.stamp().publish_stamp_ns);
    }

    fn on_tick(&mut self, now_ns: u64) -> ControlFlow<()> {
        println!("{}", window_line(self.window.stats(now_ns), self.window_s));
        continue_until(self.stop_ns, now_ns)
    }
}

/// The line printed every second, like `ros2 topic hz`.
fn window_line(stats: Option<RateStats>, window_s: f64) -> String {
    match stats {
        Some(stats) => format!(
            "average rate: {:.3} Hz  min: {:.4} s  max: {:.4} s  std dev: {:.5} s  window: {} samples in {window_s} s",
            stats.mean_rate_hz,
            stats.min_period_s,
            stats.max_period_s,
            stats.std_dev_period_s,
            stats.samples
        ),
        None => format!("no rate yet: fewer than 2 samples in the last {window_s} s"),
    }
}

/// The whole watch's mean rate and period range.
fn total_text(stats: Option<RateStats>) -> String {
    match stats {
        Some(stats) => format!(
            "mean rate {:.4} Hz, period min {:.4} s max {:.4} s",
            stats.mean_rate_hz, stats.min_period_s, stats.max_period_s
        ),
        None => "no rate (fewer than 2 samples)".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_says_when_there_is_no_rate() {
        assert!(window_line(None, 10.0).contains("fewer than 2 samples"));
        let stats = hopnav_ipc::live::rate_stats(&[0, 100_000_000, 200_000_000]);
        let line = window_line(stats, 10.0);
        assert!(line.starts_with("average rate: 10.000 Hz"), "{line}");
    }
}
