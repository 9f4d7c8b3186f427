//! Process → supervisor: liveness, readiness and per-frame processing time.

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, coded_enum};

coded_enum! {
    /// What a process reports about itself.
    ProcessState {
        /// Ports are open and the process waits for its first frame.
        Ready = 1,
        /// The process finished frame `stamp.frame_index`; `processing_time_ns` is its cost.
        Completed = 2,
        /// The process is alive and waiting; sent once per period without work.
        Idle = 3,
        /// The process is shutting down cleanly.
        Stopping = 4,
    }
}

/// Sentinel frame index for "no frame completed yet".
pub const NO_FRAME: u64 = u64::MAX;

/// One heartbeat; every process publishes on the shared heartbeat topic.
/// `stamp.frame_index` is the last completed frame (or [`NO_FRAME`]) and
/// `stamp.publish_stamp_ns` is when the heartbeat was sent, for `Completed` when the frame
/// finished.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::Heartbeat")]
pub struct Heartbeat {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Time the process spent in `step` for the completed frame, nanoseconds.
    pub processing_time_ns: u64,
    /// Samples this process rejected so far (bad headers, non-finite values, stale sequence).
    pub rejected_samples: u64,
    /// Index of the process in the supervisor's process table.
    pub slot: u32,
    /// How often this slot was started before (0 for the first start).
    pub incarnation: u32,
    /// OS process id of the sender.
    pub pid: u32,
    /// A [`ProcessState`] code.
    pub state: u32,
}

impl Default for Heartbeat {
    fn default() -> Self {
        Self {
            stamp: SampleStamp {
                frame_index: NO_FRAME,
                ..SampleStamp::default()
            },
            processing_time_ns: 0,
            rejected_samples: 0,
            slot: 0,
            incarnation: 0,
            pid: 0,
            state: ProcessState::Idle.code(),
        }
    }
}

impl Heartbeat {
    /// The state, if its code is known.
    pub fn state(&self) -> Option<ProcessState> {
        ProcessState::from_code(self.state)
    }

    /// The last completed frame, `None` before the first.
    pub fn completed_frame(&self) -> Option<u64> {
        (self.stamp.frame_index != NO_FRAME).then_some(self.stamp.frame_index)
    }
}

const _: () = assert!(size_of::<Heartbeat>() == 64);
