//! The latency probe: the smallest honest graph for the runtime. `probe_source` writes one
//! image-sized sample per frame into loaned shared memory; `probe_sink` checks the header
//! against the slice, checks every byte against the pattern the frame index predicts, and
//! measures the one-way delivery latency. Neither pretends to do VO or rendering.
#![warn(missing_docs)]

pub mod pattern;
mod sink;
mod source;

pub use sink::ProbeSink;
pub use source::ProbeSource;

/// Why a probe process failed: only the plumbing every node shares.
pub type ProbeError = hopnav_ipc::node_error::NodeError;
