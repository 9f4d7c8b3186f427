//! `hopnav topic bw TOPIC`: the bandwidth of one topic of a running launch, every second.
//!
//! The bytes are what each sample occupies in shared memory. Zero-copy moves none of them;
//! the figure says what a bridge or a recorder of this topic must carry.

use std::ops::ControlFlow;
use std::process::ExitCode;

use clap::Args;
use hopnav_ipc::live::{BandwidthStats, ByteTotals, ByteWindow, TapSample, Watcher, human_bytes};

use crate::topic_window::{WindowArgs, continue_until, exit_code, watch_topic};

#[derive(Debug, Args)]
pub struct BwArgs {
    /// Topic name, e.g. hopnav/camera/jumper (the hopnav/ prefix may be left out).
    topic: String,
    #[command(flatten)]
    window: WindowArgs,
}

pub fn run(args: &BwArgs) -> ExitCode {
    let watched = match watch_topic(&args.window, &args.topic, |_, started_ns| ByteMeter {
        window: ByteWindow::new(args.window.window_ns()),
        window_s: args.window.window_s,
        totals: ByteTotals::default(),
        stop_ns: args.window.stop_ns(started_ns),
    }) {
        Ok(watched) => watched,
        Err(code) => return code,
    };
    let (meter, elapsed_s) = (&watched.watcher, watched.elapsed_s);
    println!(
        "{}: {} samples, {} in {elapsed_s:.1} s; {}; rejected {}",
        watched.name,
        meter.totals.samples(),
        human_bytes(meter.totals.bytes() as f64),
        match meter.totals.stats() {
            Some(stats) => stats_text(&stats),
            None => "no bandwidth (fewer than 2 samples)".to_owned(),
        },
        watched.rejected.total()
    );
    exit_code(&watched.namespace, watched.end)
}

/// The sizes of one watch's samples: the window printed every second and the totals.
struct ByteMeter {
    window: ByteWindow,
    window_s: f64,
    totals: ByteTotals,
    stop_ns: Option<u64>,
}

impl Watcher for ByteMeter {
    fn on_sample(&mut self, sample: &dyn TapSample, arrival_ns: u64) {
        let bytes = sample.payload_bytes();
        self.window.push(arrival_ns, bytes);
        self.totals.push(arrival_ns, bytes);
    }

    fn on_tick(&mut self, now_ns: u64) -> ControlFlow<()> {
        println!("{}", window_line(self.window.stats(now_ns), self.window_s));
        continue_until(self.stop_ns, now_ns)
    }
}

/// Bandwidth, mean and range of sample sizes.
fn stats_text(stats: &BandwidthStats) -> String {
    format!(
        "{}/s, mean {} min {} max {} per sample",
        human_bytes(stats.bytes_per_s),
        human_bytes(stats.mean_sample_bytes),
        human_bytes(stats.min_sample_bytes as f64),
        human_bytes(stats.max_sample_bytes as f64)
    )
}

/// The line printed every second, like `ros2 topic bw`.
fn window_line(stats: Option<BandwidthStats>, window_s: f64) -> String {
    match stats {
        Some(stats) => format!(
            "average: {}  window: {} samples in {window_s} s",
            stats_text(&stats),
            stats.samples
        ),
        None => format!("no bandwidth yet: fewer than 2 samples in the last {window_s} s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topic_window::seconds_to_ns;

    #[test]
    fn the_line_reads_bytes_per_second_and_sample_sizes() {
        assert!(window_line(None, 10.0).contains("fewer than 2 samples"));
        let mut window = ByteWindow::new(seconds_to_ns(10.0));
        for i in 0..11 {
            window.push(i * 100_000_000, 2 * 1024 * 1024);
        }
        let line = window_line(window.stats(1_000_000_000), 10.0);
        assert!(
            line.starts_with("average: 20.00 MiB/s, mean 2.00 MiB"),
            "{line}"
        );
        assert!(line.ends_with("11 samples in 10 s"), "{line}");
    }
}
