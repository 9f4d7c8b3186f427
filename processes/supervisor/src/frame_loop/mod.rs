//! The supervisor's event loop: start the graph, tick frames, release stages, watch
//! heartbeats, reap and restart children, and shut down.

mod health;
mod lifecycle;

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
}
