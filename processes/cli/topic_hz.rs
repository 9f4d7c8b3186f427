//! `hopnav topic hz TOPIC`: the receive rate of one topic of a running launch, every second.

use std::ops::ControlFlow;
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use hopnav_ipc::live::{self, ArrivalWindow, RateStats, RateTotals, TapSample, WatchEnd, Watcher};

use crate::topic_cmd::{RunChoice, watch_failed};

#[derive(Debug, Args)]
pub struct HzArgs {
    /// Topic name, e.g. hopnav/camera/jumper (the hopnav/ prefix may be left out).
    topic: String,
    /// Seconds of arrivals the printed rate covers.
    #[arg(long, default_value_t = 10.0, value_parser = positive_seconds)]
    window_s: f64,
    /// Stop after this many seconds (default: until Ctrl-C or the launch ends).
    #[arg(long, value_parser = positive_seconds)]
    duration_s: Option<f64>,
    #[command(flatten)]
    run: RunChoice,
}

fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if seconds.is_finite() && seconds > 0.0 && seconds <= 1e6 => Ok(seconds),
        _ => Err(format!("{text:?} is not a number of seconds in (0, 1e6]")),
    }
}

pub fn run(args: &HzArgs) -> ExitCode {
    let (namespace, topic) = match args.run.topic(&args.topic) {
        Ok(found) => found,
        Err(code) => return code,
    };
    let name = topic.spec.name.to_string();
    let started_ns = hopnav_ipc::stamp::monotonic_now_ns();
    let mut meter = RateMeter {
        window: ArrivalWindow::new(seconds_to_ns(args.window_s)),
        window_s: args.window_s,
        received: RateTotals::default(),
        published: RateTotals::default(),
        stop_ns: args
            .duration_s
            .map(|duration_s| started_ns + seconds_to_ns(duration_s)),
    };
    eprintln!("subscribed to {name} in launch {}", namespace.run_id());
    let watched = live::watch(&namespace, &topic, Duration::from_secs(1), &mut meter);
    let (end, rejected) = match watched {
        Ok(result) => result,
        Err(error) => return watch_failed(&namespace, &args.topic, error),
    };
    let elapsed_s = hopnav_ipc::stamp::elapsed_since_ns(started_ns) as f64 * 1e-9;
    println!(
        "{name}: {} samples in {elapsed_s:.1} s; {}; by publish stamps: {}; rejected {}",
        meter.received.samples(),
        total_text(meter.received.stats()),
        total_text(meter.published.stats()),
        rejected.total()
    );
    match end {
        WatchEnd::Stopped => ExitCode::SUCCESS,
        WatchEnd::LaunchEnded => {
            eprintln!("launch {} ended", namespace.run_id());
            ExitCode::SUCCESS
        }
        WatchEnd::Interrupted => ExitCode::from(crate::EXIT_INTERRUPTED),
    }
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
        if self.stop_ns.is_some_and(|stop_ns| now_ns >= stop_ns) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

fn seconds_to_ns(seconds: f64) -> u64 {
    (seconds * 1e9) as u64
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
    fn seconds_must_be_positive() {
        assert_eq!(positive_seconds("2.5"), Ok(2.5));
        assert!(positive_seconds("0").is_err());
        assert!(positive_seconds("-1").is_err());
        assert!(positive_seconds("nan").is_err());
    }

    #[test]
    fn the_line_says_when_there_is_no_rate() {
        assert!(window_line(None, 10.0).contains("fewer than 2 samples"));
        let stats = live::rate_stats(&[0, 100_000_000, 200_000_000]);
        let line = window_line(stats, 10.0);
        assert!(line.starts_with("average rate: 10.000 Hz"), "{line}");
    }
}
