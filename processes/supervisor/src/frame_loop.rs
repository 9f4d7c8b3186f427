//! The supervisor's event loop: start the graph, tick frames, release stages, watch
//! heartbeats, reap and restart children, and shut down.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use hopnav_config::HopnavConfig;
use hopnav_ipc::IpcService;
use hopnav_ipc::messages::{
    BodyStates, ClockMode, FrameCommand, FrameTick, Heartbeat, ProcessState,
};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::process_loop::Promotion;
use hopnav_ipc::stamp::monotonic_now_ns;
use hopnav_ipc::transport::{Publisher, Subscriber};
use iceoryx2::prelude::{CallbackProgression, WaitSet};
use iceoryx2::waitset::WaitSetRunResult;

use crate::LaunchError;
use crate::child::{ChildProcess, ChildSpec};
use crate::fault_injector::{FaultAction, FaultInjector};
use crate::hang_verdict::{Silence, SilenceLimits, hang_verdict};
use crate::janitor::Janitor;
use crate::mission::MissionObserver;
use crate::progress::ProgressSample;
use crate::relay::SlotRelays;
use crate::report::ExitRecord;
use crate::restart::RestartDecision;
use crate::scheduler::{FrameOutcome, FrameScheduler, Release};
use crate::slot::{Phase, Slot};
use crate::status_line::StatusLine;

/// Longest the loop sleeps without an event: bounds how late it notices a dead child.
const HOUSEKEEPING: Duration = Duration::from_millis(20);

/// Why the frame loop ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoopEnd {
    /// Every requested frame completed.
    Completed,
    /// SIGINT or SIGTERM.
    Interrupted,
    /// Something made continuing impossible.
    Stopped(String),
    /// The mission ended (goal reached or given up) and `mission.stop_on_goal` is set.
    MissionEnded(String),
}

/// What the loop measured, kept after its ports are gone.
#[derive(Debug)]
pub struct LoopStats {
    /// The process table with per-process statistics.
    pub slots: Vec<Slot>,
    /// End-to-end latency of each finished frame, ns.
    pub end_to_end_ns: Vec<u64>,
    /// Frames finished.
    pub frames_completed: u64,
    /// Frames finished while a process was down or skipped them.
    pub frames_degraded: u64,
    /// Frames given up on.
    pub frames_abandoned: u64,
    /// Frames over the frame period end to end.
    pub end_to_end_misses: u64,
}

/// The supervisor's ports: one step publisher per slot, and ground truth for the status line.
pub struct SupervisorPorts {
    /// Step topic of each slot, in table order.
    pub step_publishers: Vec<Publisher<FrameTick>>,
    /// Ground truth for the status line only (which robot is where); never for control.
    pub truth: Option<Subscriber<BodyStates>>,
    /// Mission bookkeeping, when the graph runs a mission.
    pub mission: Option<MissionObserver>,
    /// Faults to inject.
    pub faults: FaultInjector,
    /// State relays of the stateful processes (their last pose, for a restart).
    pub relays: Vec<SlotRelays>,
}

/// State of a running launch.
pub struct FrameLoop {
    config: HopnavConfig,
    stats: LoopStats,
    step_publishers: Vec<Publisher<FrameTick>>,
    scheduler: FrameScheduler,
    namespace: Namespace,
    executable: PathBuf,
    config_path: PathBuf,
    status: StatusLine,
    /// Ground truth for the status line only (which robot is where); never for control.
    truth: Option<Subscriber<BodyStates>>,
    last_truth: Option<BodyStates>,
    mission: Option<MissionObserver>,
    relays: Vec<SlotRelays>,
    janitor: Janitor,
    faults: FaultInjector,
    fault_specs: Vec<hopnav_config::fault::FaultSpec>,
    fault_actions: Vec<FaultAction>,
    period: Duration,
    started: Instant,
    next_frame: u64,
    stop: Option<LoopEnd>,
}

impl FrameLoop {
    /// A loop over `slots`; nothing runs until [`Self::start_all`].
    pub fn new(
        config: HopnavConfig,
        slots: Vec<Slot>,
        ports: SupervisorPorts,
        namespace: Namespace,
        executable: PathBuf,
        config_path: PathBuf,
        status: StatusLine,
    ) -> Self {
        let stages: Vec<u32> = slots.iter().map(|slot| slot.config.stage).collect();
        let scheduler = FrameScheduler::new(&stages, config.run.lockstep);
        let period = Duration::from_secs_f64(config.run.frame_period_s());
        let fault_specs = config.faults.specs().unwrap_or_default();
        Self {
            stats: LoopStats {
                slots,
                end_to_end_ns: Vec::with_capacity(config.run.frames.min(1 << 22) as usize),
                frames_completed: 0,
                frames_degraded: 0,
                frames_abandoned: 0,
                end_to_end_misses: 0,
            },
            config,
            step_publishers: ports.step_publishers,
            scheduler,
            executable,
            config_path,
            status,
            truth: ports.truth,
            last_truth: None,
            mission: ports.mission,
            relays: ports.relays,
            janitor: Janitor::start(namespace.clone()),
            namespace,
            faults: ports.faults,
            fault_specs,
            fault_actions: Vec::new(),
            period,
            started: Instant::now(),
            next_frame: 0,
            stop: None,
        }
    }

    /// The measurements and the fault records; drops the ports.
    pub fn into_stats(self) -> (LoopStats, Vec<crate::fault_injector::FaultRecord>) {
        (self.stats, self.faults.into_records())
    }

    /// Sends the signals the fault injector asked for.
    fn execute_fault_actions(&mut self) {
        for action in std::mem::take(&mut self.fault_actions) {
            let (slot_index, signal) = match action {
                FaultAction::Kill(slot) => (slot, libc::SIGKILL),
                FaultAction::Stop(slot) => (slot, libc::SIGSTOP),
                FaultAction::Continue(slot) => (slot, libc::SIGCONT),
            };
            let Some(pid) = self.stats.slots[slot_index]
                .child
                .as_ref()
                .map(ChildProcess::pid)
            else {
                continue; // already down: nothing to signal
            };
            // SAFETY: kill(2) only sends a signal; `pid` is our own unreaped child (reaping
            // clears `child`), so the pid cannot have been reused by another process.
            let result = unsafe { libc::kill(pid as libc::pid_t, signal) };
            if result != 0 {
                eprintln!(
                    "\nfault injection: signal {signal} to {} (pid {pid}) failed: {}",
                    self.stats.slots[slot_index].name,
                    std::io::Error::last_os_error()
                );
            }
        }
    }

    /// The in-process faults of `slot_index`'s current incarnation, `HOPNAV_FAULTS` format.
    fn faults_env(&self, slot_index: usize) -> Option<String> {
        let slot = &self.stats.slots[slot_index];
        let own: Vec<_> = self
            .fault_specs
            .iter()
            .filter(|spec| spec.process == slot.name)
            .cloned()
            .collect();
        hopnav_ipc::fault::encode_env(self.config.faults.seed, slot.incarnation, &own)
    }

    fn child_spec(&self, slot_index: usize, standby: bool) -> ChildSpec<'_> {
        let slot = &self.stats.slots[slot_index];
        ChildSpec {
            faults_env: if standby {
                None
            } else {
                self.faults_env(slot_index)
            },
            executable: &self.executable,
            name: &slot.name,
            run_id: self.namespace.run_id(),
            slot: slot_index,
            incarnation: slot.incarnation,
            config_path: &self.config_path,
            heartbeat_period_ms: (self.period.as_millis() as u64).max(1),
            standby,
        }
    }

    /// Starts the current incarnation of `slot_index` from scratch.
    fn spawn(&mut self, slot_index: usize) -> Result<(), LaunchError> {
        let child = ChildProcess::spawn(&self.child_spec(slot_index, false)).map_err(|source| {
            LaunchError::Spawn {
                name: self.stats.slots[slot_index].name.clone(),
                source,
            }
        })?;
        self.stats.slots[slot_index].child = Some(child);
        self.begin_starting(slot_index);
        Ok(())
    }

    fn begin_starting(&mut self, slot_index: usize) {
        let slot = &mut self.stats.slots[slot_index];
        slot.begin_incarnation();
        slot.phase = Phase::Starting {
            since: Instant::now(),
        };
        slot.last_heartbeat = Instant::now();
        slot.silence_cpu_time_ns = None;
    }

    /// Starts a warm standby for `slot_index` if it may have one and has none.
    fn spawn_standby(&mut self, slot_index: usize) {
        let slot = &self.stats.slots[slot_index];
        let wanted = self.config.restart.warm_standby
            && slot.config.restart != hopnav_config::RestartPolicy::Never
            && slot.standby.is_none()
            && !slot.standby_failed
            && self.stop.is_none();
        if !wanted {
            return;
        }
        match ChildProcess::spawn(&self.child_spec(slot_index, true)) {
            Ok(child) => self.stats.slots[slot_index].standby = Some(child),
            Err(error) => {
                let slot = &mut self.stats.slots[slot_index];
                slot.standby_failed = true;
                eprintln!(
                    "\ncannot start a standby of {}: {error}; its restarts will be cold",
                    slot.name
                );
            }
        }
    }

    /// Restarts `slot_index` (its incarnation already counted up): promotes its standby if
    /// it has one, else starts it cold. Returns how.
    fn restart(&mut self, slot_index: usize) -> Result<&'static str, LaunchError> {
        if let Some(mut standby) = self.stats.slots[slot_index].standby.take() {
            let how = if standby.is_prepared() {
                "standby"
            } else {
                "standby (still preparing)"
            };
            let promotion = Promotion {
                incarnation: self.stats.slots[slot_index].incarnation,
                faults: self.faults_env(slot_index),
            };
            match standby.promote(&promotion) {
                Ok(()) => {
                    self.stats.slots[slot_index].child = Some(standby);
                    self.begin_starting(slot_index);
                    return Ok(how);
                }
                Err(error) => {
                    let slot = &mut self.stats.slots[slot_index];
                    slot.standby_failed = true;
                    eprintln!(
                        "\ncannot promote the standby of {}: {error}; starting it cold",
                        slot.name
                    );
                    standby.kill_and_reap();
                }
            }
        }
        self.spawn(slot_index).map(|()| "cold")
    }

    /// Spawns every process and waits until all report ready.
    pub fn start_all(
        &mut self,
        heartbeats: &Subscriber<Heartbeat>,
        waitset: &WaitSet<IpcService>,
    ) -> Result<(), LaunchError> {
        for slot_index in 0..self.stats.slots.len() {
            self.spawn(slot_index)?;
        }
        let timeout = Duration::from_secs_f64(self.config.run.startup_timeout_s);
        let deadline = Instant::now() + timeout;
        loop {
            self.receive_heartbeats(heartbeats);
            for slot in &mut self.stats.slots {
                if let Some(exit) = slot.child.as_mut().and_then(ChildProcess::try_reap) {
                    slot.child = None;
                    return Err(LaunchError::DiedAtStartup {
                        name: slot.name.clone(),
                        reason: exit.to_string(),
                    });
                }
            }
            let waiting: Vec<&str> = self
                .stats
                .slots
                .iter()
                .filter(|slot| matches!(slot.phase, Phase::Starting { .. }))
                .map(|slot| slot.name.as_str())
                .collect();
            if waiting.is_empty() {
                break;
            }
            if Instant::now() >= deadline {
                return Err(LaunchError::StartupTimeout {
                    names: waiting.join(", "),
                    timeout_s: self.config.run.startup_timeout_s,
                });
            }
            match waitset
                .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, HOUSEKEEPING)
            {
                Ok(WaitSetRunResult::TerminationRequest) => return Err(LaunchError::Interrupted),
                // A signal that only cut the wait short; termination shows up on the next wait.
                Ok(WaitSetRunResult::Interrupt) => continue,
                Ok(_) => {}
                Err(error) => return Err(LaunchError::Wait(format!("{error:?}"))),
            }
        }
        // The graph is up: now prepare the standbys (at idle priority) for quick restarts.
        for slot_index in 0..self.stats.slots.len() {
            self.spawn_standby(slot_index);
        }
        if self.config.run.lockstep {
            // Lockstep is about reproducible runs, not wall time: let the standbys finish
            // preparing first, so a restart at any frame is as quick as at any other.
            self.wait_for_standbys(heartbeats, waitset, Instant::now() + timeout)?;
        }
        self.started = Instant::now();
        Ok(())
    }

    /// Waits until every standby has prepared (or died, or the start-up deadline passed).
    fn wait_for_standbys(
        &mut self,
        heartbeats: &Subscriber<Heartbeat>,
        waitset: &WaitSet<IpcService>,
        deadline: Instant,
    ) -> Result<(), LaunchError> {
        loop {
            self.receive_heartbeats(heartbeats);
            let mut waiting = Vec::new();
            for slot in &mut self.stats.slots {
                let Some(standby) = slot.standby.as_mut() else {
                    continue;
                };
                if let Some(exit) = standby.try_reap() {
                    slot.standby = None;
                    slot.standby_failed = true;
                    eprintln!(
                        "the standby of {} {exit}; its restarts will be cold",
                        slot.name
                    );
                } else if !standby.is_prepared() {
                    waiting.push(slot.name.clone());
                }
            }
            if waiting.is_empty() {
                return Ok(());
            }
            if Instant::now() >= deadline {
                eprintln!(
                    "standbys still preparing after run.startup_timeout_s: {}",
                    waiting.join(", ")
                );
                return Ok(());
            }
            match waitset
                .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, HOUSEKEEPING)
            {
                Ok(WaitSetRunResult::TerminationRequest) => return Err(LaunchError::Interrupted),
                Ok(_) => {}
                Err(error) => return Err(LaunchError::Wait(format!("{error:?}"))),
            }
        }
    }

    /// Runs frames until all are done, a signal arrives, or the launch must stop.
    pub fn run(
        &mut self,
        heartbeats: &Subscriber<Heartbeat>,
        waitset: &WaitSet<IpcService>,
    ) -> LoopEnd {
        let frames = self.config.run.frames;
        let mut next_tick_at = Instant::now();
        loop {
            let now = Instant::now();
            let mut timeout = HOUSEKEEPING;
            if !self.config.run.lockstep && self.next_frame < frames {
                timeout = timeout.min(next_tick_at.saturating_duration_since(now));
            }
            match waitset
                .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, timeout)
            {
                Ok(WaitSetRunResult::TerminationRequest) => return LoopEnd::Interrupted,
                // Another signal cut the wait short (SIGCHLD: a child died): do the rounds now.
                // A termination request shows up on the next wait.
                Ok(_) => {}
                Err(error) => {
                    return LoopEnd::Stopped(format!("supervisor wait failed: {error:?}"));
                }
            }
            self.receive_heartbeats(heartbeats);
            for relay in self
                .relays
                .iter_mut()
                .flat_map(|slot| slot.relays.iter_mut())
            {
                relay.forward();
            }
            self.reap_children();
            self.watchdog(heartbeats);
            self.restart_due();
            self.faults
                .due_resumes(Instant::now(), &mut self.fault_actions);
            self.execute_fault_actions();
            self.observe_mission();

            if self.next_frame < frames {
                let tick_due = if self.config.run.lockstep {
                    self.scheduler.open_frame_count() == 0
                } else {
                    Instant::now() >= next_tick_at
                };
                if tick_due {
                    self.start_frame();
                    // Keep the cadence; if we fell more than a period behind, re-anchor.
                    next_tick_at += self.period;
                    if Instant::now() > next_tick_at + self.period {
                        next_tick_at = Instant::now() + self.period;
                    }
                }
            } else if self.scheduler.open_frame_count() == 0 {
                self.print_status(true);
                return LoopEnd::Completed;
            }
            if let Some(end) = self.stop.take() {
                self.print_status(true);
                return end;
            }
            self.print_status(false);
        }
    }

    /// Reads the mission topics; ends the launch when the mission is over (if configured).
    fn observe_mission(&mut self) {
        let Some(mission) = self.mission.as_mut() else {
            return;
        };
        mission.observe();
        if self.config.mission.stop_on_goal
            && self.stop.is_none()
            && let Some(reason) = mission.end_reason()
        {
            self.stop = Some(LoopEnd::MissionEnded(reason));
        }
    }

    /// The mission observer, taken for the report.
    pub fn take_mission(&mut self) -> Option<MissionObserver> {
        self.mission.take()
    }

    fn start_frame(&mut self) {
        let frame_index = self.next_frame;
        self.next_frame += 1;
        let since_start_s = self.started.elapsed().as_secs_f64();
        self.faults.on_frame_start(
            frame_index,
            Instant::now(),
            since_start_s,
            &mut self.fault_actions,
        );
        self.execute_fault_actions();
        let (releases, outcomes) = self.scheduler.start_frame(frame_index, monotonic_now_ns());
        self.record_outcomes(&outcomes);
        self.release(&releases);
    }

    fn release(&mut self, releases: &[Release]) {
        let period_ns = self.period.as_nanos() as u64;
        let mode = if self.config.run.lockstep {
            ClockMode::Lockstep
        } else {
            ClockMode::RealTime
        };
        for release in releases {
            let tick_stamp_ns = self
                .scheduler
                .tick_stamp_ns(release.frame_index)
                .unwrap_or(0);
            let Some(publisher) = self.step_publishers.get_mut(release.slot) else {
                continue;
            };
            let sent = publisher.send_with(|tick| {
                tick.stamp.frame_index = release.frame_index;
                tick.stamp.sim_time_ns = release.frame_index.saturating_mul(period_ns);
                tick.tick_stamp_ns = tick_stamp_ns;
                tick.period_ns = period_ns;
                tick.command = FrameCommand::Step.code();
                tick.mode = mode.code();
            });
            if let Err(error) = sent {
                self.stop = Some(LoopEnd::Stopped(format!(
                    "cannot release frame {} to {}: {error}",
                    release.frame_index, self.stats.slots[release.slot].name
                )));
            }
        }
    }

    fn record_outcomes(&mut self, outcomes: &[FrameOutcome]) {
        let period_ns = self.period.as_nanos() as u64;
        for outcome in outcomes {
            match outcome.end_to_end_ns {
                Some(latency_ns) => {
                    self.stats.frames_completed += 1;
                    self.stats.end_to_end_ns.push(latency_ns);
                    if latency_ns > period_ns {
                        self.stats.end_to_end_misses += 1;
                    }
                }
                None => {
                    self.stats.frames_abandoned += 1;
                    self.stats.end_to_end_misses += 1;
                }
            }
            if outcome.degraded {
                self.stats.frames_degraded += 1;
            }
        }
    }

    fn receive_heartbeats(&mut self, heartbeats: &Subscriber<Heartbeat>) {
        heartbeats.clear_events();
        while let Ok(Some(heartbeat)) = heartbeats.receive() {
            self.on_heartbeat(&heartbeat);
        }
    }

    fn on_heartbeat(&mut self, heartbeat: &Heartbeat) {
        let slot_index = heartbeat.slot as usize;
        let Some(slot) = self.stats.slots.get_mut(slot_index) else {
            return;
        };
        let from_current = heartbeat.incarnation == slot.incarnation
            && slot
                .child
                .as_ref()
                .is_some_and(|child| child.pid() == heartbeat.pid);
        if !from_current {
            return; // a late heartbeat of a previous incarnation
        }
        slot.last_heartbeat = Instant::now();
        slot.record_rejected(heartbeat.rejected_samples);
        let restarted = slot.incarnation > 0
            && matches!(slot.phase, Phase::Starting { .. })
            && heartbeat.state() == Some(ProcessState::Ready);
        self.faults.on_alive(slot_index, Instant::now(), restarted);
        let Some(slot) = self.stats.slots.get_mut(slot_index) else {
            return;
        };
        match heartbeat.state() {
            Some(ProcessState::Ready) if matches!(slot.phase, Phase::Starting { .. }) => {
                slot.phase = Phase::Running;
                if restarted {
                    // Before its first release: hand the restarted process its last state.
                    for relays in self.relays.iter_mut().filter(|r| r.slot == slot_index) {
                        relays.relays.iter_mut().for_each(|relay| relay.hand_over());
                    }
                }
                let Some(slot) = self.stats.slots.get_mut(slot_index) else {
                    return;
                };
                let startup_s = heartbeat.processing_time_ns as f64 * 1e-9;
                slot.last_startup_s = Some(startup_s);
                let since_start = self.started.elapsed().as_secs_f64();
                if let Some(exit) = slot.exits.last_mut()
                    && exit.recovered_after_s.is_none()
                {
                    exit.recovered_after_s = Some((since_start - exit.at_s).max(0.0));
                    exit.startup_s = Some(startup_s);
                }
                let (releases, outcomes) = self.scheduler.set_live(slot_index, true);
                self.record_outcomes(&outcomes);
                self.release(&releases);
                if restarted {
                    // The promoted standby is in service: prepare the next one.
                    self.spawn_standby(slot_index);
                }
            }
            Some(ProcessState::Completed) => {
                if let Some(frame_index) = heartbeat.completed_frame() {
                    slot.record_cycle(heartbeat.processing_time_ns);
                    let (releases, outcomes) = self.scheduler.on_completed(
                        slot_index,
                        frame_index,
                        heartbeat.stamp.publish_stamp_ns,
                    );
                    self.record_outcomes(&outcomes);
                    self.release(&releases);
                }
            }
            _ => {}
        }
    }

    fn reap_children(&mut self) {
        for slot in &mut self.stats.slots {
            // A standby that ended on its own (its `prepare` failed?) is not replaced: the
            // slot's restarts are cold from then on.
            if let Some(exit) = slot.standby.as_mut().and_then(ChildProcess::try_reap) {
                slot.standby = None;
                slot.standby_failed = true;
                eprintln!(
                    "\nthe standby of {} {exit}; its restarts will be cold",
                    slot.name
                );
            }
        }
        for slot_index in 0..self.stats.slots.len() {
            let slot = &mut self.stats.slots[slot_index];
            let Some(exit) = slot.child.as_mut().and_then(ChildProcess::try_reap) else {
                continue;
            };
            slot.child = None;
            let reason = match slot.killed_for_hang.take() {
                Some(why) => format!("hung ({why}), killed"),
                None => exit.to_string(),
            };
            self.faults.on_exit(slot_index, Instant::now(), &reason);
            let slot = &mut self.stats.slots[slot_index];
            slot.exits.push(ExitRecord {
                frame_index: self.next_frame.saturating_sub(1),
                at_s: self.started.elapsed().as_secs_f64(),
                reason: reason.clone(),
                recovered_after_s: None,
                restart: None,
                startup_s: None,
            });
            let name = slot.name.clone();
            let decision = slot.restarts.on_exit(&exit, Instant::now());
            let (releases, outcomes) = self.scheduler.set_live(slot_index, false);
            self.record_outcomes(&outcomes);
            self.release(&releases);
            // The dead node's ports count against the topics' limits until removed: one dead
            // and one new port fit every topic, so the restart need not wait for the clean-up.
            self.janitor.sweep();
            let slot = &mut self.stats.slots[slot_index];
            match decision {
                RestartDecision::RestartAfter(delay) => {
                    eprintln!("\n{name} {reason}; restarting in {} ms", delay.as_millis());
                    slot.phase = Phase::WaitingToRestart {
                        at: Instant::now() + delay,
                    };
                }
                RestartDecision::LeaveStopped => {
                    slot.phase = Phase::Stopped;
                    if self.config.run.lockstep {
                        self.stop = Some(LoopEnd::Stopped(format!(
                            "{name} {reason} and its restart policy is {:?}; lockstep cannot continue without it",
                            slot.config.restart
                        )));
                    } else {
                        eprintln!("\n{name} {reason}; left stopped by its restart policy");
                    }
                }
                RestartDecision::IntensityExceeded {
                    restarts_in_window,
                    window,
                } => {
                    slot.phase = Phase::Stopped;
                    self.stop = Some(LoopEnd::Stopped(format!(
                        "{name} {reason}: {restarts_in_window} restarts within {:.1} s exceed restart.max_restarts = {}",
                        window.as_secs_f64(),
                        self.config.restart.max_restarts
                    )));
                }
            }
        }
    }

    /// Kills processes that stopped heartbeating: after `watchdog.stall_timeout_frames` if
    /// they make no progress (stopped, or asleep without using CPU since the silence began),
    /// after `watchdog.heartbeat_timeout_frames` whatever they do, and after
    /// `run.startup_timeout_s` if they never got ready.
    fn watchdog(&mut self, heartbeats: &Subscriber<Heartbeat>) {
        // Judge on fresh news: whatever the loop did since it last read heartbeats (reaping,
        // cleaning up a dead node) must not count as the children's silence.
        self.receive_heartbeats(heartbeats);
        let judged_at = Instant::now();
        let hung = self.hung_processes();
        if hung.is_empty() {
            return;
        }
        // A last look, without reading /proc again: a process that was asleep when judged and
        // has heartbeated since was only slow to be scheduled (or the supervisor was).
        self.receive_heartbeats(heartbeats);
        for (slot_index, why) in hung {
            let slot = &mut self.stats.slots[slot_index];
            if slot.last_heartbeat >= judged_at {
                continue;
            }
            if let Some(child) = slot.child.as_mut() {
                slot.hangs_detected += 1;
                slot.killed_for_hang = Some(why);
                child.kill();
            }
        }
    }

    /// The processes the watchdog finds hung now, with the reason.
    fn hung_processes(&mut self) -> Vec<(usize, String)> {
        let mut hung = Vec::new();
        let period = self.period;
        let limits = SilenceLimits {
            period,
            stall: period.mul_f64(self.config.watchdog.stall_timeout_frames),
            hard_frames: self.config.watchdog.heartbeat_timeout_frames,
        };
        let startup_limit = Duration::from_secs_f64(self.config.run.startup_timeout_s);
        let now = Instant::now();
        for (slot_index, slot) in self.stats.slots.iter_mut().enumerate() {
            if slot.killed_for_hang.is_some() {
                continue; // killed already, waiting to be reaped
            }
            let Some(pid) = slot.child.as_ref().map(ChildProcess::pid) else {
                continue;
            };
            let silence = now.duration_since(slot.last_heartbeat);
            let why = match slot.phase {
                Phase::Starting { .. } if silence > startup_limit => Some(format!(
                    "not ready after {:.1} s (run.startup_timeout_s)",
                    silence.as_secs_f64()
                )),
                Phase::Running if silence > period => {
                    let progress = ProgressSample::read(pid);
                    let (baseline_cpu_time_ns, seen_at) = *slot
                        .silence_cpu_time_ns
                        .get_or_insert((progress.map_or(0, |sample| sample.cpu_time_ns), now));
                    let silence = Silence {
                        silent_for: silence,
                        watched_for: now.duration_since(seen_at),
                        baseline_cpu_time_ns,
                    };
                    hang_verdict(&limits, &silence, progress)
                }
                _ => {
                    slot.silence_cpu_time_ns = None;
                    None
                }
            };
            if let Some(why) = why {
                hung.push((slot_index, why));
            }
        }
        hung
    }

    fn restart_due(&mut self) {
        let now = Instant::now();
        for slot_index in 0..self.stats.slots.len() {
            let slot = &mut self.stats.slots[slot_index];
            if let Phase::WaitingToRestart { at } = slot.phase
                && now >= at
            {
                slot.incarnation += 1;
                match self.restart(slot_index) {
                    Ok(how) => {
                        if let Some(exit) = self.stats.slots[slot_index].exits.last_mut() {
                            exit.restart = Some(how.to_owned());
                        }
                    }
                    Err(error) => self.stop = Some(LoopEnd::Stopped(error.to_string())),
                }
            }
        }
    }

    fn print_status(&mut self, force: bool) {
        let frames = self.config.run.frames;
        let sim_s = self.next_frame as f64 * self.period.as_secs_f64();
        let slowest = self
            .stats
            .slots
            .iter()
            .max_by_key(|slot| slot.last_cycle_ns)
            .map(|slot| format!("{} {:.2} ms", slot.name, slot.last_cycle_ns as f64 / 1e6))
            .unwrap_or_default();
        let misses: u64 = self.stats.slots.iter().map(|slot| slot.budget_misses).sum();
        let restarts: u32 = self
            .stats
            .slots
            .iter()
            .map(|slot| slot.restarts.total_restarts())
            .sum();
        let (done, e2e_misses) = (self.stats.frames_completed, self.stats.end_to_end_misses);
        if let Some(truth) = &self.truth
            && let Ok(Some(latest)) = truth.receive_latest()
        {
            self.last_truth = Some(latest);
        }
        let robots = self.last_truth.map(|states| {
            let jumper = states.jumper.world_from_body.position_m;
            let rover = states.rover.world_from_body.position_m;
            format!(
                " | jumper ({:.1}, {:.1}) z {:.2} m {} | rover ({:.1}, {:.1})",
                jumper[0],
                jumper[1],
                jumper[2],
                if states.jumper.in_contact == 0 {
                    "in flight"
                } else {
                    "on ground"
                },
                rover[0],
                rover[1]
            )
        });
        self.status.update(force, || {
            format!(
                "frame {done}/{frames} | sim {sim_s:.1} s | slowest {slowest} | budget misses {misses} (end-to-end {e2e_misses}) | restarts {restarts}{}",
                robots.unwrap_or_default()
            )
        });
    }

    /// Asks every process to stop, waits for the grace period, then kills what is left.
    pub fn shutdown(&mut self) {
        self.status.finish();
        // Standbys end cleanly when their stdin closes (once prepared); the rest are killed.
        let mut standbys: Vec<ChildProcess> = self
            .stats
            .slots
            .iter_mut()
            .filter_map(|slot| slot.standby.take())
            .collect();
        standbys.iter_mut().for_each(ChildProcess::retire);
        let deadline = Instant::now() + Duration::from_millis(500);
        while !standbys.is_empty() && Instant::now() < deadline {
            standbys.retain_mut(|standby| standby.try_reap().is_none());
            std::thread::sleep(Duration::from_millis(2));
        }
        standbys.into_iter().for_each(ChildProcess::kill_and_reap);
        for (slot_index, publisher) in self.step_publishers.iter_mut().enumerate() {
            if self.stats.slots[slot_index].child.is_some() {
                let _ = publisher.send_with(|tick| {
                    tick.command = FrameCommand::Shutdown.code();
                    tick.mode = ClockMode::Lockstep.code();
                });
            }
        }
        let grace = Duration::from_secs_f64(self.config.run.shutdown_timeout_s);
        if !self.wait_for_exits(grace) {
            for slot in &mut self.stats.slots {
                if let Some(child) = slot.child.as_ref() {
                    eprintln!(
                        "{} did not stop within {:.1} s; sending SIGTERM",
                        slot.name,
                        grace.as_secs_f64()
                    );
                    child.terminate();
                }
            }
            if !self.wait_for_exits(Duration::from_secs(1)) {
                for slot in &mut self.stats.slots {
                    if let Some(child) = slot.child.as_mut() {
                        eprintln!("{} ignored SIGTERM; killing it", slot.name);
                        child.kill();
                    }
                }
                self.wait_for_exits(Duration::from_secs(5));
            }
        }
        for slot in &mut self.stats.slots {
            if !matches!(slot.phase, Phase::Stopped) {
                slot.phase = Phase::Stopped;
            }
        }
    }

    fn wait_for_exits(&mut self, limit: Duration) -> bool {
        let deadline = Instant::now() + limit;
        loop {
            for slot in &mut self.stats.slots {
                if slot
                    .child
                    .as_mut()
                    .and_then(ChildProcess::try_reap)
                    .is_some()
                {
                    slot.child = None;
                }
            }
            if self.stats.slots.iter().all(|slot| slot.child.is_none()) {
                return true;
            }
            if Instant::now() >= deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}
