//! Restart decisions: policy, exponential backoff and restart intensity (dora/Erlang style).

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use hopnav_config::{RestartConfig, RestartPolicy};

/// How a process ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ExitKind {
    /// Exit code 0.
    Clean,
    /// Non-zero exit code.
    Failed(i32),
    /// Killed by a signal (crash, kill -9, or our watchdog).
    Signaled(i32),
}

impl ExitKind {
    /// True unless the process exited with code 0.
    pub fn is_failure(&self) -> bool {
        !matches!(self, ExitKind::Clean)
    }
}

impl std::fmt::Display for ExitKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExitKind::Clean => write!(f, "exited cleanly"),
            ExitKind::Failed(code) => write!(f, "exited with code {code}"),
            ExitKind::Signaled(signal) => write!(f, "killed by signal {signal}"),
        }
    }
}

/// What to do after an exit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RestartDecision {
    /// Start again after the backoff delay.
    RestartAfter(Duration),
    /// Leave it stopped (policy says so).
    LeaveStopped,
    /// Too many restarts within the window: stop the whole launch.
    IntensityExceeded {
        /// Restarts counted in the window, including this one.
        restarts_in_window: usize,
        /// The window.
        window: Duration,
    },
}

/// Restart bookkeeping of one process.
#[derive(Debug, Clone)]
pub struct RestartTracker {
    policy: RestartPolicy,
    max_restarts: usize,
    window: Duration,
    backoff_initial: Duration,
    backoff_max: Duration,
    recent_restarts: VecDeque<Instant>,
    total_restarts: u32,
}

impl RestartTracker {
    /// A tracker for `policy` with the launch's intensity limits.
    pub fn new(policy: RestartPolicy, config: &RestartConfig) -> Self {
        Self {
            policy,
            max_restarts: config.max_restarts as usize,
            window: Duration::from_secs_f64(config.window_s),
            backoff_initial: Duration::from_millis(config.backoff_initial_ms),
            backoff_max: Duration::from_millis(config.backoff_max_ms),
            recent_restarts: VecDeque::new(),
            total_restarts: 0,
        }
    }

    /// Restarts so far.
    pub fn total_restarts(&self) -> u32 {
        self.total_restarts
    }

    /// Decides what follows `exit` at `now`, and records the restart if there is one.
    pub fn on_exit(&mut self, exit: &ExitKind, now: Instant) -> RestartDecision {
        let wanted = match self.policy {
            RestartPolicy::Never => false,
            RestartPolicy::OnFailure => exit.is_failure(),
            RestartPolicy::Always => true,
        };
        if !wanted {
            return RestartDecision::LeaveStopped;
        }
        while let Some(oldest) = self.recent_restarts.front() {
            if now.duration_since(*oldest) > self.window {
                self.recent_restarts.pop_front();
            } else {
                break;
            }
        }
        if self.recent_restarts.len() >= self.max_restarts {
            return RestartDecision::IntensityExceeded {
                restarts_in_window: self.recent_restarts.len() + 1,
                window: self.window,
            };
        }
        // An isolated crash restarts at once (a restart must land within a frame or two); each
        // further restart still inside the window doubles the delay from backoff_initial, so a
        // crash loop slows down.
        let backoff = match self.recent_restarts.len() {
            0 => Duration::ZERO,
            earlier => self
                .backoff_initial
                .saturating_mul(1 << (earlier - 1).min(20) as u32)
                .min(self.backoff_max),
        };
        self.recent_restarts.push_back(now);
        self.total_restarts += 1;
        RestartDecision::RestartAfter(backoff)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(max_restarts: u32) -> RestartConfig {
        RestartConfig {
            max_restarts,
            window_s: 10.0,
            backoff_initial_ms: 100,
            backoff_max_ms: 350,
            warm_standby: true,
        }
    }

    #[test]
    fn policies_decide_by_exit_kind() {
        let now = Instant::now();
        let mut never = RestartTracker::new(RestartPolicy::Never, &config(5));
        assert_eq!(
            never.on_exit(&ExitKind::Signaled(9), now),
            RestartDecision::LeaveStopped
        );
        let mut on_failure = RestartTracker::new(RestartPolicy::OnFailure, &config(5));
        assert_eq!(
            on_failure.on_exit(&ExitKind::Clean, now),
            RestartDecision::LeaveStopped
        );
        assert!(matches!(
            on_failure.on_exit(&ExitKind::Failed(1), now),
            RestartDecision::RestartAfter(_)
        ));
        let mut always = RestartTracker::new(RestartPolicy::Always, &config(5));
        assert!(matches!(
            always.on_exit(&ExitKind::Clean, now),
            RestartDecision::RestartAfter(_)
        ));
    }

    #[test]
    fn backoff_doubles_up_to_the_cap() {
        let now = Instant::now();
        let mut tracker = RestartTracker::new(RestartPolicy::OnFailure, &config(10));
        let delays: Vec<_> = (0..4)
            .map(|_| match tracker.on_exit(&ExitKind::Signaled(9), now) {
                RestartDecision::RestartAfter(delay) => delay.as_millis(),
                other => panic!("unexpected {other:?}"),
            })
            .collect();
        assert_eq!(delays, vec![0, 100, 200, 350]);
        assert_eq!(tracker.total_restarts(), 4);
    }

    #[test]
    fn intensity_counts_only_restarts_inside_the_window() {
        let start = Instant::now();
        let mut tracker = RestartTracker::new(RestartPolicy::OnFailure, &config(2));
        assert!(matches!(
            tracker.on_exit(&ExitKind::Failed(1), start),
            RestartDecision::RestartAfter(_)
        ));
        assert!(matches!(
            tracker.on_exit(&ExitKind::Failed(1), start),
            RestartDecision::RestartAfter(_)
        ));
        assert!(matches!(
            tracker.on_exit(&ExitKind::Failed(1), start + Duration::from_secs(1)),
            RestartDecision::IntensityExceeded {
                restarts_in_window: 3,
                ..
            }
        ));
        let later = start + Duration::from_secs(11);
        assert!(matches!(
            tracker.on_exit(&ExitKind::Failed(1), later),
            RestartDecision::RestartAfter(delay) if delay.is_zero()
        ));
    }
}
