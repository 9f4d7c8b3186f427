//! The supervisor's view of one process: its child, restart state and statistics.

use std::time::Instant;

use hopnav_config::ProcessConfig;
use hopnav_ipc::latency::LatencySummary;

use crate::child::ChildProcess;
use crate::report::{ExitRecord, ProcessReport};
use crate::restart::RestartTracker;

/// Where a process is in its life.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// Spawned, waiting for its ready heartbeat.
    Starting {
        /// When it was spawned.
        since: Instant,
    },
    /// Ready and stepping frames.
    Running,
    /// Exited; restarts at the given time.
    WaitingToRestart {
        /// Restart time (after backoff).
        at: Instant,
    },
    /// Exited and stays stopped.
    Stopped,
}

/// One row of the process table.
#[derive(Debug)]
pub struct Slot {
    /// Process name.
    pub name: String,
    /// Its configuration.
    pub config: ProcessConfig,
    /// Restart policy state.
    pub restarts: RestartTracker,
    /// The running child, if any.
    pub child: Option<ChildProcess>,
    /// Starts before the current one.
    pub incarnation: u32,
    /// Life phase.
    pub phase: Phase,
    /// Last heartbeat from the current incarnation.
    pub last_heartbeat: Instant,
    /// Processing time of every completed frame, ns.
    pub cycle_times_ns: Vec<u64>,
    /// Processing time of the last completed frame, ns.
    pub last_cycle_ns: u64,
    /// Completed frames over budget.
    pub budget_misses: u64,
    /// Hangs the watchdog detected.
    pub hangs_detected: u32,
    /// Last reported rejected-sample count, per incarnation summed.
    pub rejected_samples: u64,
    rejected_before_incarnation: u64,
    /// Unplanned exits.
    pub exits: Vec<ExitRecord>,
    /// Set when the watchdog killed it: why it counted as hung (names the exit).
    pub killed_for_hang: Option<String>,
    /// The prepared standby promoted on the next restart, if any.
    pub standby: Option<ChildProcess>,
    /// A standby died on its own: restarts of this slot are cold from then on.
    pub standby_failed: bool,
    /// CPU time of the current child when the watchdog first saw its silence pass one frame
    /// period, and when it saw it.
    pub silence_cpu_time_ns: Option<(u64, Instant)>,
    /// Start-up time the current incarnation reported in its ready heartbeat, s.
    pub last_startup_s: Option<f64>,
}

impl Slot {
    /// A slot that has not been started yet.
    pub fn new(
        name: String,
        config: ProcessConfig,
        restarts: RestartTracker,
        frames: usize,
    ) -> Self {
        Self {
            name,
            config,
            restarts,
            child: None,
            incarnation: 0,
            phase: Phase::Stopped,
            last_heartbeat: Instant::now(),
            cycle_times_ns: Vec::with_capacity(frames.min(1 << 22)),
            last_cycle_ns: 0,
            budget_misses: 0,
            hangs_detected: 0,
            rejected_samples: 0,
            rejected_before_incarnation: 0,
            exits: Vec::new(),
            killed_for_hang: None,
            standby: None,
            standby_failed: false,
            silence_cpu_time_ns: None,
            last_startup_s: None,
        }
    }

    /// Records a completed frame's processing time.
    pub fn record_cycle(&mut self, processing_time_ns: u64) {
        self.last_cycle_ns = processing_time_ns;
        self.cycle_times_ns.push(processing_time_ns);
        if processing_time_ns as f64 > self.config.budget_ms * 1e6 {
            self.budget_misses += 1;
        }
    }

    /// Updates the rejected count from the current incarnation's heartbeat.
    pub fn record_rejected(&mut self, rejected_by_incarnation: u64) {
        self.rejected_samples = self.rejected_before_incarnation + rejected_by_incarnation;
    }

    /// Called when a new incarnation starts.
    pub fn begin_incarnation(&mut self) {
        self.rejected_before_incarnation = self.rejected_samples;
    }

    /// The report row.
    pub fn report(&self) -> ProcessReport {
        let mut cycles = self.cycle_times_ns.clone();
        ProcessReport {
            name: self.name.clone(),
            stage: self.config.stage,
            budget_ms: self.config.budget_ms,
            cycle_time: LatencySummary::from_ns(&mut cycles),
            budget_misses: self.budget_misses,
            frames_completed: self.cycle_times_ns.len() as u64,
            restarts: self.restarts.total_restarts(),
            exits: self.exits.clone(),
            hangs_detected: self.hangs_detected,
            rejected_samples: self.rejected_samples,
        }
    }
}
