//! The failures every node shares (its configuration, opening its ports, sending and
//! receiving samples), with room for the one kind of failure that is the node's own.

use std::convert::Infallible;

use hopnav_config::ConfigError;

use crate::transport::{OpenError, ReceiveError, SendError};

/// Why a node failed. `E` is the node's own failure (its algorithm, its world); a node that
/// has none keeps the default, [`Infallible`].
///
/// Config and port errors convert with `?`; the node's own error goes in with
/// `.map_err(NodeError::own)?`.
#[derive(Debug, thiserror::Error)]
pub enum NodeError<E = Infallible> {
    /// The configuration could not be loaded or is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] OpenError),
    /// A sample could not be sent.
    #[error(transparent)]
    Send(#[from] SendError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] ReceiveError),
    /// The node's own failure.
    #[error(transparent)]
    Own(E),
}

impl<E> NodeError<E> {
    /// Wraps the node's own failure, or anything that converts into it.
    pub fn own(error: impl Into<E>) -> Self {
        Self::Own(error.into())
    }
}
