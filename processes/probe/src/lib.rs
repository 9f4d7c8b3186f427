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

/// Why a probe process failed.
#[derive(Debug, thiserror::Error)]
pub enum ProbeError {
    /// The configuration could not be loaded.
    #[error(transparent)]
    Config(#[from] hopnav_config::ConfigError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] hopnav_ipc::transport::OpenError),
    /// A sample could not be sent.
    #[error(transparent)]
    Send(#[from] hopnav_ipc::transport::SendError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] hopnav_ipc::transport::ReceiveError),
}
