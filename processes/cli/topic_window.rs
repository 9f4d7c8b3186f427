//! What the watching tools (`topic hz`, `topic bw`, `top`) share: their window and duration
//! options, and how a watch's end becomes the exit code.

use std::ops::ControlFlow;
use std::process::ExitCode;

use std::time::Duration;

use clap::Args;
use hopnav_ipc::live::{self, WatchEnd, Watcher};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::transport::RejectCounts;

use crate::topic_cmd::{RunChoice, watch_failed};

#[derive(Debug, Args)]
pub struct WindowArgs {
    /// Seconds of arrivals the windowed figures cover (a rate, a bandwidth, or `top`'s frame
    /// time percentiles), printed every second.
    #[arg(long, default_value_t = 10.0, value_parser = positive_seconds)]
    pub window_s: f64,
    /// Stop after this many seconds (default: until Ctrl-C or the launch ends).
    #[arg(long, value_parser = positive_seconds)]
    pub duration_s: Option<f64>,
    #[command(flatten)]
    pub run: RunChoice,
}

impl WindowArgs {
    /// The window, nanoseconds.
    pub fn window_ns(&self) -> u64 {
        seconds_to_ns(self.window_s)
    }

    /// When a watch started at `started_ns` stops (`None`: when stopped or the launch ends).
    pub fn stop_ns(&self, started_ns: u64) -> Option<u64> {
        self.duration_s
            .map(|duration_s| started_ns + seconds_to_ns(duration_s))
    }
}

/// A finished watch of one topic.
pub struct Watched<W> {
    pub namespace: Namespace,
    /// The topic's full name.
    pub name: String,
    /// What watched it, with all it gathered.
    pub watcher: W,
    pub end: WatchEnd,
    pub rejected: RejectCounts,
    pub elapsed_s: f64,
}

/// Watches `topic` of the launch `window` names, ticking every second, with the watcher
/// `make` builds from the launch and the start time; the exit code after saying why when it
/// cannot.
pub fn watch_topic<W: Watcher>(
    window: &WindowArgs,
    topic: &str,
    make: impl FnOnce(&Namespace, u64) -> W,
) -> Result<Watched<W>, ExitCode> {
    let (namespace, known) = window.run.topic(topic)?;
    let name = known.spec.name.to_string();
    let started_ns = hopnav_ipc::stamp::monotonic_now_ns();
    let mut watcher = make(&namespace, started_ns);
    eprintln!("subscribed to {name} in launch {}", namespace.run_id());
    let (end, rejected) = live::watch(&namespace, &known, Duration::from_secs(1), &mut watcher)
        .map_err(|error| watch_failed(&namespace, topic, error))?;
    Ok(Watched {
        namespace,
        name,
        watcher,
        end,
        rejected,
        elapsed_s: hopnav_ipc::stamp::elapsed_since_ns(started_ns) as f64 * 1e-9,
    })
}

/// Goes on until `stop_ns`, if there is one.
pub fn continue_until(stop_ns: Option<u64>, now_ns: u64) -> ControlFlow<()> {
    if stop_ns.is_some_and(|stop_ns| now_ns >= stop_ns) {
        ControlFlow::Break(())
    } else {
        ControlFlow::Continue(())
    }
}

/// The exit code of a watch that ended with `end` (saying so when the launch ended).
pub fn exit_code(namespace: &Namespace, end: WatchEnd) -> ExitCode {
    match end {
        WatchEnd::Stopped => ExitCode::SUCCESS,
        WatchEnd::LaunchEnded => {
            eprintln!("launch {} ended", namespace.run_id());
            ExitCode::SUCCESS
        }
        WatchEnd::Interrupted => ExitCode::from(crate::EXIT_INTERRUPTED),
    }
}

pub fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if seconds.is_finite() && seconds > 0.0 && seconds <= 1e6 => Ok(seconds),
        _ => Err(format!("{text:?} is not a number of seconds in (0, 1e6]")),
    }
}

pub fn seconds_to_ns(seconds: f64) -> u64 {
    (seconds * 1e9) as u64
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
    fn a_watch_goes_on_until_its_stop() {
        assert!(continue_until(None, u64::MAX).is_continue());
        assert!(continue_until(Some(10), 9).is_continue());
        assert!(continue_until(Some(10), 10).is_break());
    }
}
