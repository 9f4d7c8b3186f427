//! Supervisor → process: the frame clock, one step topic per process.

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, coded_enum};

coded_enum! {
    /// What the supervisor asks of a process.
    FrameCommand {
        /// Process frame `stamp.frame_index`.
        Step = 1,
        /// Finish and exit cleanly.
        Shutdown = 2,
    }
}

coded_enum! {
    /// How the supervisor paces frames.
    ClockMode {
        /// Frames start every period of wall-clock time; late work is a budget miss.
        RealTime = 1,
        /// Frame k+1 starts when every stage has finished frame k; reproducible.
        Lockstep = 2,
    }
}

/// Releases a frame to one process. `stamp.publish_stamp_ns` is when this process was released
/// (its upstream stages had finished the frame).
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::FrameTick")]
pub struct FrameTick {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// CLOCK_MONOTONIC when the frame started (the tick of stage 0).
    pub tick_stamp_ns: u64,
    /// Nominal frame period, nanoseconds.
    pub period_ns: u64,
    /// A [`FrameCommand`] code.
    pub command: u32,
    /// A [`ClockMode`] code.
    pub mode: u32,
}

impl FrameTick {
    /// The command, if its code is known.
    pub fn command(&self) -> Option<FrameCommand> {
        FrameCommand::from_code(self.command)
    }
}

const _: () = assert!(size_of::<FrameTick>() == 56);
