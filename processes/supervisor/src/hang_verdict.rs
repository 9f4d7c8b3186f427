//! The watchdog's verdict on a running process that has stopped heartbeating.
//!
//! Three reasons, the most telling first: it is stopped (SIGSTOP) past the stall limit; it has
//! been silent past the hard limit whatever it does (a runaway step); or it has been asleep
//! past the stall limit without using CPU since its silence began. The last needs the CPU
//! counter to have stood still over a span the watchdog actually watched: a supervisor that
//! itself ran late on a loaded machine first sees a long silence and takes its baseline then,
//! and the children, late as it was, must get the time to run and heartbeat.

use crate::progress::ProgressSample;
use std::time::Duration;

/// The watchdog's limits, from `[watchdog]` and the frame period.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SilenceLimits {
    pub period: Duration,
    /// `watchdog.stall_timeout_frames` periods.
    pub stall: Duration,
    /// `watchdog.heartbeat_timeout_frames` periods.
    pub hard_frames: u32,
}

impl SilenceLimits {
    fn hard(&self) -> Duration {
        self.period * self.hard_frames
    }

    /// How long an unchanged CPU counter must have been watched to count as asleep: the part
    /// of the stall limit after the first period of silence, when the baseline is taken.
    fn asleep_span(&self) -> Duration {
        self.stall.saturating_sub(self.period)
    }
}

/// What the watchdog knows of one silent process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Silence {
    /// Since its last heartbeat.
    pub silent_for: Duration,
    /// Since the watchdog took `baseline_cpu_time_ns`.
    pub watched_for: Duration,
    /// Its CPU time when the watchdog first saw it silent for more than a period.
    pub baseline_cpu_time_ns: u64,
}

/// Why the process counts as hung, or `None` while it may still be only slow.
pub(crate) fn hang_verdict(
    limits: &SilenceLimits,
    silence: &Silence,
    progress: Option<ProgressSample>,
) -> Option<String> {
    let frames = silence.silent_for.as_secs_f64() / limits.period.as_secs_f64();
    let past_stall = silence.silent_for > limits.stall;
    match progress {
        Some(sample) if past_stall && sample.stopped => Some(format!(
            "stopped, no heartbeat for {frames:.1} frame periods"
        )),
        _ if silence.silent_for > limits.hard() => Some(format!(
            "no heartbeat for {frames:.1} frame periods, watchdog.heartbeat_timeout_frames = {}",
            limits.hard_frames
        )),
        Some(sample)
            if past_stall
                && silence.watched_for >= limits.asleep_span()
                && !sample.busy
                && sample.cpu_time_ns == silence.baseline_cpu_time_ns =>
        {
            Some(format!(
                "asleep without using CPU, no heartbeat for {frames:.1} frame periods"
            ))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: SilenceLimits = SilenceLimits {
        period: Duration::from_millis(100),
        stall: Duration::from_millis(150),
        hard_frames: 20,
    };

    fn ms(v: u64) -> Duration {
        Duration::from_millis(v)
    }

    /// A progress sample of a process in state `stopped`/`busy` that has used `cpu_time_ns`.
    fn sample(stopped: bool, busy: bool, cpu_time_ns: u64) -> Option<ProgressSample> {
        Some(ProgressSample {
            stopped,
            busy,
            cpu_time_ns,
        })
    }

    fn asleep(cpu_time_ns: u64) -> Option<ProgressSample> {
        sample(false, false, cpu_time_ns)
    }

    fn silence(silent_ms: u64, watched_ms: u64) -> Silence {
        Silence {
            silent_for: ms(silent_ms),
            watched_for: ms(watched_ms),
            baseline_cpu_time_ns: 7,
        }
    }

    #[test]
    fn an_idle_process_watched_past_the_stall_limit_is_hung() {
        let why = hang_verdict(&LIMITS, &silence(160, 55), asleep(7)).expect("hung");
        assert!(why.starts_with("asleep without using CPU"), "{why}");
    }

    #[test]
    fn a_late_supervisor_first_looks_before_it_judges_sleep() {
        // It woke 300 ms after the last heartbeat and took the baseline just now.
        assert_eq!(hang_verdict(&LIMITS, &silence(300, 0), asleep(7)), None);
        assert_eq!(hang_verdict(&LIMITS, &silence(340, 40), asleep(7)), None);
        assert!(hang_verdict(&LIMITS, &silence(360, 60), asleep(7)).is_some());
    }

    #[test]
    fn a_process_that_used_cpu_or_is_runnable_is_not_asleep() {
        assert_eq!(hang_verdict(&LIMITS, &silence(180, 80), asleep(8)), None);
        let runnable = sample(false, true, 7);
        assert_eq!(hang_verdict(&LIMITS, &silence(180, 80), runnable), None);
    }

    #[test]
    fn stopped_past_the_stall_limit_and_silent_past_the_hard_one_are_hung_at_once() {
        let stopped = sample(true, false, 7);
        let why = hang_verdict(&LIMITS, &silence(160, 0), stopped).expect("hung");
        assert!(why.starts_with("stopped"), "{why}");
        let busy = sample(false, true, 900);
        let why = hang_verdict(&LIMITS, &silence(2100, 0), busy).expect("hung");
        assert!(why.contains("heartbeat_timeout_frames = 20"), "{why}");
        assert!(hang_verdict(&LIMITS, &silence(2100, 0), None).is_some());
        assert_eq!(hang_verdict(&LIMITS, &silence(120, 20), None), None);
    }
}
