//! The lifecycle every hopnav process runs: parse config, create the node, `new`, signal
//! ready, then `step` once per released frame with a heartbeat carrying the frame index and
//! its processing time, and stop cleanly on SIGTERM/SIGINT or the supervisor's shutdown.
//!
//! The loop waits on a WaitSet (its step topic's events) with a timeout that ends when the
//! next heartbeat is due: an idle process heartbeats once a period, so the supervisor can tell
//! idle from hung within a frame or two.
//!
//! **Warm standby.** Start-up work that depends only on the launch's configuration (terrain,
//! render scene, physics world) goes in [`Process::prepare`]. A standby (`hopnav run NAME
//! --standby`, [`StartMode::Standby`]) runs `prepare` at idle CPU priority ahead of need and
//! creates its node, then waits on stdin; when the supervisor promotes it (one line: the
//! incarnation and the in-process faults), it opens its ports, runs `new` — which takes the
//! prepared parts with [`take_prepared`] and resumes from history — and reports ready. A
//! restart then costs port set-up and state recovery, not process start-up.

use std::any::Any;
use std::io::BufRead as _;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use iceoryx2::node::Node;
use iceoryx2::prelude::{CallbackProgression, WaitSetBuilder};
use iceoryx2::waitset::WaitSetRunResult;

use crate::IpcService;
use crate::messages::{FrameCommand, FrameTick, Heartbeat, NO_FRAME, ProcessState};
use crate::namespace::{Namespace, NamespaceError};
use crate::stamp::monotonic_now_ns;
use crate::topics;
use crate::transport::{OpenError, Publisher, SendError, Subscriber};

/// Who this process is within a launch (from the supervisor's command line).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProcessIdentity {
    /// Process name, also its node name and step topic suffix.
    pub name: String,
    /// Run id of the launch (selects the iceoryx2 namespace).
    pub run_id: String,
    /// Index in the supervisor's process table.
    pub slot: u32,
    /// Starts of this slot before this one.
    pub incarnation: u32,
    /// Heartbeat period when idle.
    pub heartbeat_period: Duration,
    /// The resolved configuration file of the launch.
    pub config_path: std::path::PathBuf,
}

/// How `hopnav run` starts a process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartMode {
    /// Start at once (first start, or a restart without a standby).
    Cold,
    /// Prepare, then wait on stdin for the supervisor's promotion line.
    Standby,
}

/// What [`Process::prepare`] built, kept for [`Process::new`] (see [`take_prepared`]).
#[derive(Default)]
pub struct Prepared(Option<Box<dyn Any + Send>>);

impl Prepared {
    /// Keeps `value` for `new`.
    pub fn new<T: Any + Send>(value: T) -> Self {
        Self(Some(Box::new(value)))
    }
}

impl core::fmt::Debug for Prepared {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(if self.0.is_some() {
            "Prepared(..)"
        } else {
            "Prepared(none)"
        })
    }
}

/// What this OS process prepared (one process of the graph per OS process).
static PREPARED: Mutex<Option<Box<dyn Any + Send>>> = Mutex::new(None);

/// Takes what this process's [`Process::prepare`] built, if it is a `T` (once; `None` in
/// tests and tools that call `new` directly, which then build it themselves).
pub fn take_prepared<T: Any>() -> Option<T> {
    let boxed = PREPARED.lock().ok()?.take()?;
    boxed.downcast::<T>().ok().map(|value| *value)
}

/// What a process gets to open its ports and read its settings.
pub struct ProcessContext {
    /// The process's node; open topics on it.
    pub node: Node<IpcService>,
    /// Who this is.
    pub identity: ProcessIdentity,
}

/// A process of the frame graph. Allocate in `new`; `step` runs once per released frame.
pub trait Process: Sized {
    /// Why the process failed; a failure ends the process with a non-zero exit code.
    type Error: core::fmt::Display;

    /// Start-up work that depends only on the configuration file (no ports, no state): a warm
    /// standby does it before it is needed. Hand the result to `new` with [`Prepared::new`];
    /// `new` takes it back with [`take_prepared`]. Default: nothing.
    fn prepare(_identity: &ProcessIdentity) -> Result<Prepared, Self::Error> {
        Ok(Prepared::default())
    }

    /// Opens ports, recovers state from history and allocates everything the steps need.
    fn new(context: &ProcessContext) -> Result<Self, Self::Error>;

    /// Processes frame `tick.stamp.frame_index`.
    fn step(&mut self, context: &ProcessContext, tick: &FrameTick) -> Result<(), Self::Error>;

    /// Samples this process has rejected so far (reported in heartbeats).
    fn rejected_samples(&self) -> u64 {
        0
    }

    /// Last words before exit (flush files, publish final state).
    fn stop(&mut self, _context: &ProcessContext) {}
}

/// Why a process loop ended with an error.
#[derive(Debug, thiserror::Error)]
pub enum LoopError {
    /// The namespace or node could not be set up.
    #[error(transparent)]
    Namespace(#[from] NamespaceError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] OpenError),
    /// A heartbeat could not be sent.
    #[error("heartbeat: {0}")]
    Heartbeat(#[from] SendError),
    /// The WaitSet failed.
    #[error("waiting for frames failed: {0}")]
    Wait(String),
    /// The standby could not read its promotion.
    #[error("standby: {0}")]
    Standby(String),
    /// The process's own `prepare`, `new` or `step` failed.
    #[error("{stage} failed: {reason}")]
    Process {
        /// `prepare`, `new` or `step`.
        stage: &'static str,
        /// The process's reason.
        reason: String,
    },
}

/// How the loop ended without error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoopExit {
    /// The supervisor asked for shutdown.
    Shutdown,
    /// SIGTERM or SIGINT.
    Signal,
}

struct HeartbeatSender {
    publisher: Publisher<Heartbeat>,
    template: Heartbeat,
    last_sent_ns: u64,
}

impl HeartbeatSender {
    fn send(&mut self, state: ProcessState, rejected_samples: u64) -> Result<(), SendError> {
        self.template.state = state.code();
        self.template.rejected_samples = rejected_samples;
        let template = self.template;
        self.publisher.send_with(|heartbeat| {
            *heartbeat = Heartbeat {
                stamp: heartbeat.stamp,
                ..template
            };
            heartbeat.stamp.frame_index = template.stamp.frame_index;
            heartbeat.stamp.sim_time_ns = template.stamp.sim_time_ns;
        })?;
        self.last_sent_ns = monotonic_now_ns();
        Ok(())
    }
}

/// Runs process `P` until shutdown or a termination signal (a cold start).
pub fn run_process<P: Process>(identity: ProcessIdentity) -> Result<LoopExit, LoopError> {
    run_process_with::<P>(identity, StartMode::Cold)
}

/// Environment variable that makes a process print how long each start-up phase took.
pub const TRACE_STARTUP_ENV: &str = "HOPNAV_TRACE_STARTUP";

/// Start-up phases, printed to stderr when `HOPNAV_TRACE_STARTUP` is set.
struct StartupTrace {
    name: String,
    started: Instant,
    last: Instant,
    enabled: bool,
}

impl StartupTrace {
    fn new(name: &str) -> Self {
        let now = Instant::now();
        Self {
            name: name.to_owned(),
            started: now,
            last: now,
            enabled: std::env::var_os(TRACE_STARTUP_ENV).is_some(),
        }
    }

    fn restart_clock(&mut self) {
        self.started = Instant::now();
        self.last = self.started;
    }

    fn phase(&mut self, what: &str) {
        let now = Instant::now();
        if self.enabled {
            eprintln!(
                "[{}] start-up: {what} {:.1} ms (total {:.1} ms)",
                self.name,
                (now - self.last).as_secs_f64() * 1e3,
                (now - self.started).as_secs_f64() * 1e3
            );
        }
        self.last = now;
    }
}

/// Runs process `P` until shutdown or a termination signal; a [`StartMode::Standby`] first
/// prepares and waits for its promotion (stdin closing instead ends it quietly).
pub fn run_process_with<P: Process>(
    mut identity: ProcessIdentity,
    mode: StartMode,
) -> Result<LoopExit, LoopError> {
    let mut trace = StartupTrace::new(&identity.name);
    let Some(Started { node, step_delay }) = start_up::<P>(&mut identity, mode, &mut trace)? else {
        return Ok(LoopExit::Shutdown); // the supervisor no longer needs us
    };
    trace.phase("node");
    let context = ProcessContext { node, identity };
    let step_commands =
        Subscriber::<FrameTick>::open(&context.node, &topics::step(&context.identity.name))?;
    let mut heartbeat = HeartbeatSender {
        publisher: Publisher::open(&context.node, &topics::HEARTBEAT)?,
        template: Heartbeat {
            slot: context.identity.slot,
            incarnation: context.identity.incarnation,
            pid: std::process::id(),
            ..Heartbeat::default()
        },
        last_sent_ns: 0,
    };
    trace.phase("step and heartbeat ports");
    let mut process = P::new(&context).map_err(|error| LoopError::Process {
        stage: "new",
        reason: error.to_string(),
    })?;
    trace.phase("new");
    // A ready heartbeat carries the start-up time (from start, or from promotion).
    heartbeat.template.processing_time_ns = trace.started.elapsed().as_nanos() as u64;
    heartbeat.send(ProcessState::Ready, 0)?;
    heartbeat.template.processing_time_ns = 0;
    trace.phase("ready");
    serve_steps(
        &mut process,
        &context,
        &step_commands,
        &mut heartbeat,
        step_delay,
    )
}

/// A process that is prepared, promoted if it was a standby, and has its node.
struct Started {
    node: Node<IpcService>,
    /// The injected slow-step delay, if any.
    step_delay: Option<Duration>,
}

/// Prepares `P`, creates the node (ahead, for a standby) and installs the faults; a standby
/// waits for its promotion in between. Returns the node and the injected step delay, or
/// `None` when a standby is no longer needed.
fn start_up<P: Process>(
    identity: &mut ProcessIdentity,
    mode: StartMode,
    trace: &mut StartupTrace,
) -> Result<Option<Started>, LoopError> {
    if mode == StartMode::Standby {
        set_idle_priority(true);
    }
    let prepared = P::prepare(identity).map_err(|error| LoopError::Process {
        stage: "prepare",
        reason: error.to_string(),
    })?;
    if let Ok(mut slot) = PREPARED.lock() {
        *slot = prepared.0;
    }
    trace.phase("prepare");
    let namespace = Namespace::new(&identity.run_id)?.without_dead_node_scans();
    // A standby creates its node ahead too (no ports: it receives nothing, blocks no topic).
    let standby_node = match mode {
        StartMode::Standby => Some(namespace.create_node(&identity.name)?),
        StartMode::Cold => None,
    };
    match mode {
        StartMode::Cold => crate::fault::install_from_env(),
        StartMode::Standby => {
            notify_prepared();
            let Some(promotion) = wait_for_promotion()? else {
                return Ok(None);
            };
            set_idle_priority(false);
            trace.restart_clock();
            identity.incarnation = promotion.incarnation;
            crate::fault::install(promotion.faults.as_deref())
        }
    }
    .map_err(|error| LoopError::Process {
        stage: "faults",
        reason: error.to_string(),
    })?;
    let step_delay = crate::fault::step_delay();
    let node = match standby_node {
        Some(node) => node,
        None => namespace.create_node(&identity.name)?,
    };
    Ok(Some(Started { node, step_delay }))
}

/// The frame loop of a started process: waits for step commands (waking for each heartbeat
/// that falls due), steps the newest released frame, reports each step and idle period in a
/// heartbeat; at shutdown or a termination signal stops the process and says so.
fn serve_steps<P: Process>(
    process: &mut P,
    context: &ProcessContext,
    step_commands: &Subscriber<FrameTick>,
    heartbeat: &mut HeartbeatSender,
    step_delay: Option<Duration>,
) -> Result<LoopExit, LoopError> {
    let waitset = WaitSetBuilder::new()
        .create::<IpcService>()
        .map_err(|error| LoopError::Wait(format!("{error:?}")))?;
    let _step_guard = waitset
        .attach_notification(step_commands.listener())
        .map_err(|error| LoopError::Wait(format!("{error:?}")))?;
    let period_ns = context.identity.heartbeat_period.as_nanos() as u64;
    let mut last_frame = NO_FRAME;

    let exit = loop {
        // Wake when the next heartbeat is due, not a full period after any event: the
        // supervisor's watchdog counts on one heartbeat per period.
        let since_heartbeat_ns = monotonic_now_ns().saturating_sub(heartbeat.last_sent_ns);
        let until_heartbeat = Duration::from_nanos(period_ns.saturating_sub(since_heartbeat_ns))
            .max(Duration::from_millis(1));
        let wait = waitset
            .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, until_heartbeat);
        match wait {
            Ok(WaitSetRunResult::TerminationRequest) => break LoopExit::Signal,
            // Any other signal (SIGCONT after a stop, …) only cut the wait short; a SIGTERM or
            // SIGINT shows up as a termination request on the next wait.
            Ok(WaitSetRunResult::Interrupt) => continue,
            Ok(_) => {}
            Err(error) => return Err(LoopError::Wait(format!("{error:?}"))),
        }
        step_commands.clear_events();
        let (newest_step, shutdown) = receive_step_commands(step_commands, last_frame)?;
        if let Some(tick) = newest_step {
            let started_ns = monotonic_now_ns();
            if let Some(delay) = step_delay {
                // Injected fault: a slow process.
                std::thread::sleep(delay);
            }
            process
                .step(context, &tick)
                .map_err(|error| LoopError::Process {
                    stage: "step",
                    reason: error.to_string(),
                })?;
            last_frame = tick.stamp.frame_index;
            heartbeat.template.stamp.frame_index = last_frame;
            heartbeat.template.stamp.sim_time_ns = tick.stamp.sim_time_ns;
            heartbeat.template.processing_time_ns = monotonic_now_ns().saturating_sub(started_ns);
            let rejected = process.rejected_samples() + step_commands.rejected().total();
            heartbeat.send(ProcessState::Completed, rejected)?;
        }
        if shutdown {
            break LoopExit::Shutdown;
        }
        if monotonic_now_ns().saturating_sub(heartbeat.last_sent_ns) >= period_ns {
            let rejected = process.rejected_samples() + step_commands.rejected().total();
            heartbeat.send(ProcessState::Idle, rejected)?;
        }
    };
    process.stop(context);
    let rejected = process.rejected_samples() + step_commands.rejected().total();
    let _ = heartbeat.send(ProcessState::Stopping, rejected);
    Ok(exit)
}

/// Drains the step commands: the newest released frame after `last_frame` to step (a
/// release overtaken by a newer one, in real-time mode when we were late, is skipped), and
/// whether a shutdown was asked for.
fn receive_step_commands(
    step_commands: &Subscriber<FrameTick>,
    last_frame: u64,
) -> Result<(Option<FrameTick>, bool), LoopError> {
    let mut shutdown = false;
    let mut newest_step: Option<FrameTick> = None;
    while let Some(tick) = step_commands
        .receive()
        .map_err(|error| LoopError::Wait(error.to_string()))?
    {
        match tick.command() {
            Some(FrameCommand::Shutdown) => shutdown = true,
            Some(FrameCommand::Step) => {
                let is_new = last_frame == NO_FRAME || tick.stamp.frame_index > last_frame;
                if is_new {
                    newest_step = Some(tick);
                }
            }
            None => {}
        }
    }
    Ok((newest_step, shutdown))
}

/// The supervisor's promotion of a standby.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Promotion {
    /// Starts of this slot before this one.
    pub incarnation: u32,
    /// In-process faults in the `HOPNAV_FAULTS` format, if any.
    pub faults: Option<String>,
}

impl Promotion {
    /// The line the supervisor writes to the standby's stdin.
    pub fn to_line(&self) -> String {
        let faults = self.faults.as_deref().unwrap_or("").replace('\n', " ");
        format!("promote {} {faults}\n", self.incarnation)
    }

    /// Parses [`Self::to_line`]'s output.
    pub fn parse(line: &str) -> Option<Self> {
        let rest = line
            .trim_end_matches(['\n', '\r'])
            .strip_prefix("promote ")?;
        let (incarnation, faults) = rest.split_once(' ').unwrap_or((rest, ""));
        Some(Self {
            incarnation: incarnation.parse().ok()?,
            faults: (!faults.is_empty()).then(|| faults.to_owned()),
        })
    }
}

/// Blocks until the supervisor writes the promotion line; `None` when stdin closes first.
fn wait_for_promotion() -> Result<Option<Promotion>, LoopError> {
    let mut line = String::new();
    let read = std::io::stdin()
        .lock()
        .read_line(&mut line)
        .map_err(|error| LoopError::Standby(format!("reading the promotion: {error}")))?;
    if read == 0 {
        return Ok(None);
    }
    Promotion::parse(&line)
        .map(Some)
        .ok_or_else(|| LoopError::Standby(format!("bad promotion line {line:?}")))
}

/// File descriptor on which a standby tells the supervisor it has prepared (see
/// `hopnav_supervisor`'s child module): one line, then closed.
pub const PREPARED_FD: i32 = 3;

/// Tells the supervisor that `prepare` is done (a standby only; the supervisor gave it the
/// write end of a pipe as fd [`PREPARED_FD`]).
fn notify_prepared() {
    let line = b"prepared\n";
    // SAFETY: fstat fills a zeroed stat buffer we own; write and close touch fd PREPARED_FD
    // only if it is a pipe (the supervisor's, set up for `--standby` children) and take no
    // Rust-owned memory but `line`, which outlives the call. A failure only means the
    // supervisor learns less.
    unsafe {
        let mut stat: libc::stat = std::mem::zeroed();
        let is_pipe = libc::fstat(PREPARED_FD, &mut stat) == 0
            && (stat.st_mode & libc::S_IFMT) == libc::S_IFIFO;
        if is_pipe {
            libc::write(PREPARED_FD, line.as_ptr().cast(), line.len());
            libc::close(PREPARED_FD);
        }
    }
}

/// A standby prepares at idle priority (SCHED_IDLE), so it never takes CPU from the running
/// graph; promotion restores the normal policy.
fn set_idle_priority(idle: bool) {
    let policy = if idle {
        libc::SCHED_IDLE
    } else {
        libc::SCHED_OTHER
    };
    let param = libc::sched_param { sched_priority: 0 };
    // SAFETY: sched_setscheduler on the calling thread (pid 0) with a valid, initialised
    // sched_param; it only changes scheduling, and a failure leaves the policy as it was.
    let result = unsafe { libc::sched_setscheduler(0, policy, &param) };
    if result != 0 {
        eprintln!(
            "warning: cannot set scheduling policy {policy}: {}",
            std::io::Error::last_os_error()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn promotion_lines_round_trip() {
        for promotion in [
            Promotion {
                incarnation: 3,
                faults: None,
            },
            Promotion {
                incarnation: 1,
                faults: Some("seed=1;incarnation=1;drop:camera/jumper@10%".into()),
            },
        ] {
            assert_eq!(Promotion::parse(&promotion.to_line()), Some(promotion));
        }
        assert_eq!(Promotion::parse("hello\n"), None);
        assert_eq!(Promotion::parse("promote x\n"), None);
    }

    #[test]
    fn prepared_parts_are_taken_once_and_by_type() {
        if let Ok(mut slot) = PREPARED.lock() {
            *slot = Prepared::new(42_u32).0;
        }
        assert_eq!(take_prepared::<String>(), None); // wrong type: dropped
        if let Ok(mut slot) = PREPARED.lock() {
            *slot = Prepared::new(42_u32).0;
        }
        assert_eq!(take_prepared::<u32>(), Some(42));
        assert_eq!(take_prepared::<u32>(), None);
    }
}
