//! `hopnav bench ipc`: one-way latency of camera-sized messages between two processes.
//!
//! For every transport and payload size the coordinator starts a subscriber process, waits
//! for it to be ready, then starts a publisher process. The publisher writes the whole
//! payload every time (fill time, reported apart), stamps CLOCK_MONOTONIC right before
//! handing the message to the transport, and waits for the subscriber's acknowledgement
//! before the next one, so messages never queue. The subscriber stamps on receipt.
#![warn(missing_docs)]

mod coordinator;
mod peer;
mod results;
mod transports;

pub use coordinator::{BenchOptions, run_bench};
pub use peer::{PeerArgs, Role, run_peer};
pub use results::{BenchRow, BenchSummary};
pub use transports::Transport;

/// Payload sizes measured: a control message, a page, one 320² image, 1 MiB and 4 MiB.
pub const PAYLOAD_SIZES_BYTES: [usize; 5] = [64, 4096, 320 * 320, 1 << 20, 4 << 20];

/// Why the benchmark failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A peer process could not be started or failed.
    #[error("benchmark peer {role} ({transport}, {size_bytes} B): {message}")]
    Peer {
        /// pub or sub.
        role: &'static str,
        /// Transport name.
        transport: &'static str,
        /// Payload size.
        size_bytes: usize,
        /// What happened.
        message: String,
    },
    /// A transport operation failed inside a peer.
    #[error("{0}")]
    Transport(String),
    /// The results could not be written.
    #[error("cannot write {path}: {message}")]
    Output {
        /// File.
        path: String,
        /// Reason.
        message: String,
    },
}

impl BenchError {
    pub(crate) fn transport(context: &str, error: impl std::fmt::Debug) -> Self {
        BenchError::Transport(format!("{context}: {error:?}"))
    }
}
