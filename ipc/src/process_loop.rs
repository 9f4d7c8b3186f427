//! The lifecycle every hopnav process runs: parse config, create the node, `new`, signal
//! ready, then `step` once per released frame with a heartbeat carrying the frame index and
//! its processing time, and stop cleanly on SIGTERM/SIGINT or the supervisor's shutdown.
//!
//! The loop waits on a WaitSet (its step topic's events) with a timeout of one frame period:
//! an idle process still heartbeats once a period, so the supervisor can tell idle from hung.

use std::time::Duration;

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

    /// Opens ports and allocates everything the steps need.
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
    /// The process's own `new` or `step` failed.
    #[error("{stage} failed: {reason}")]
    Process {
        /// `new` or `step`.
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

/// Runs process `P` until shutdown or a termination signal.
pub fn run_process<P: Process>(identity: ProcessIdentity) -> Result<LoopExit, LoopError> {
    crate::fault::install_from_env().map_err(|error| LoopError::Process {
        stage: "faults",
        reason: error.to_string(),
    })?;
    let step_delay = crate::fault::step_delay();
    let namespace = Namespace::new(&identity.run_id)?;
    let node = namespace.create_node(&identity.name)?;
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
    let mut process = P::new(&context).map_err(|error| LoopError::Process {
        stage: "new",
        reason: error.to_string(),
    })?;
    heartbeat.send(ProcessState::Ready, 0)?;

    let waitset = WaitSetBuilder::new()
        .create::<IpcService>()
        .map_err(|error| LoopError::Wait(format!("{error:?}")))?;
    let _step_guard = waitset
        .attach_notification(step_commands.listener())
        .map_err(|error| LoopError::Wait(format!("{error:?}")))?;
    let period_ns = context.identity.heartbeat_period.as_nanos() as u64;
    let mut last_frame = NO_FRAME;

    let exit = loop {
        let wait = waitset.wait_and_process_once_with_timeout(
            |_| CallbackProgression::Continue,
            context.identity.heartbeat_period,
        );
        match wait {
            Ok(WaitSetRunResult::TerminationRequest) => break LoopExit::Signal,
            // Any other signal (SIGCONT after a stop, …) only cut the wait short; a SIGTERM or
            // SIGINT shows up as a termination request on the next wait.
            Ok(WaitSetRunResult::Interrupt) => continue,
            Ok(_) => {}
            Err(error) => return Err(LoopError::Wait(format!("{error:?}"))),
        }
        step_commands.clear_events();
        let mut shutdown = false;
        // Step every released frame in order; a release that was overtaken by a newer one
        // (real-time mode, we were late) is skipped by stepping only the newest.
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
        if let Some(tick) = newest_step {
            let started_ns = monotonic_now_ns();
            if let Some(delay) = step_delay {
                // Injected fault: a slow process.
                std::thread::sleep(delay);
            }
            process
                .step(&context, &tick)
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
    process.stop(&context);
    let rejected = process.rejected_samples() + step_commands.rejected().total();
    let _ = heartbeat.send(ProcessState::Stopping, rejected);
    Ok(exit)
}
