//! The live view (`hopnav launch --viewer [ADDR]`): the recording's Foxglove channels served
//! over the Foxglove WebSocket protocol (`foxglove.websocket.v1`), so Foxglove shows a running
//! launch. A channel costs nothing until a client subscribes to it; a client that reads too
//! slowly loses its oldest messages (the server's bounded queue), so no client ever holds
//! the recorder, let alone the graph, back.

use std::net::SocketAddr;
use std::sync::Arc;

use foxglove::{Context, PartialMetadata, RawChannel, WebSocketServer, WebSocketServerHandle};
use hopnav_ipc::messages::SampleStamp;

use crate::error_chain::error_chain;
use crate::recording::FoxgloveTopic;

/// The address `--viewer` serves on without one: this machine only.
pub const DEFAULT_VIEWER_ADDRESS: &str = "127.0.0.1:8765";

/// Why the live view could not start.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    /// The address is not an IP address and port.
    #[error("viewer address {address:?} is not IP:PORT (e.g. {DEFAULT_VIEWER_ADDRESS})")]
    BadAddress {
        /// As given.
        address: String,
    },
    /// The address cannot be bound (a port in use, an address of no interface here).
    #[error("viewer cannot listen on {address}: {reason}")]
    Bind {
        /// As given.
        address: String,
        /// The OS's or the server's refusal.
        reason: String,
    },
}

/// `address` as a socket address.
pub fn parse_viewer_address(address: &str) -> Result<SocketAddr, ViewerError> {
    address.trim().parse().map_err(|_| ViewerError::BadAddress {
        address: address.to_owned(),
    })
}

/// Checks that the viewer can listen on `address` (binding it and letting go at once), so a
/// launch refuses a taken port before anything starts.
pub fn check_viewer_address(address: &str) -> Result<(), ViewerError> {
    let socket = parse_viewer_address(address)?;
    std::net::TcpListener::bind(socket)
        .map(drop)
        .map_err(|error| ViewerError::Bind {
            address: address.to_owned(),
            reason: error.to_string(),
        })
}

/// A running WebSocket server with one channel per [`FoxgloveTopic`].
pub struct Viewer {
    /// Holds the channels: they and the server refer to it weakly only.
    _context: Arc<Context>,
    server: Option<WebSocketServerHandle>,
    /// Indexed like [`FoxgloveTopic::ALL`].
    channels: Vec<Arc<RawChannel>>,
    address: SocketAddr,
}

impl Viewer {
    /// Starts serving on `address` (port 0: a free port, see [`Viewer::address`]).
    pub fn start(address: &str) -> Result<Self, ViewerError> {
        let socket = parse_viewer_address(address)?;
        let bind_error = |reason: String| ViewerError::Bind {
            address: address.to_owned(),
            reason,
        };
        // A context of its own: only these channels, never another library's.
        let context = Context::new();
        let channels = FoxgloveTopic::ALL
            .into_iter()
            .map(|topic| {
                context
                    .channel_builder(topic.topic())
                    .message_encoding(topic.message_encoding())
                    .schema(topic.schema())
                    .build_raw()
                    .map_err(|error| bind_error(format!("channel {}: {error}", topic.topic())))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let server = WebSocketServer::new()
            .name("hopnav")
            .context(&context)
            .bind(socket.ip().to_string(), socket.port())
            .start_blocking()
            .map_err(|error| bind_error(error_chain(&error)))?;
        let address = SocketAddr::new(socket.ip(), server.port());
        Ok(Self {
            _context: context,
            server: Some(server),
            channels,
            address,
        })
    }

    /// Where it listens (the bound port when started on port 0).
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// Whether a client subscribes to `topic` (converting a sample for it is worth it).
    pub fn wants(&self, topic: FoxgloveTopic) -> bool {
        self.channels
            .get(topic.index())
            .is_some_and(|channel| channel.has_sinks())
    }

    /// Sends an encoded message to the subscribers of `topic`, stamped with sim time.
    pub fn send(&self, topic: FoxgloveTopic, stamp: SampleStamp, encoded: &[u8]) {
        if let Some(channel) = self.channels.get(topic.index()) {
            let log_time = Some(stamp.sim_time_ns);
            channel.log_with_meta(encoded, PartialMetadata { log_time });
        }
    }

    /// Closes every connection and stops listening.
    pub fn stop(&mut self) {
        if let Some(server) = self.server.take() {
            server.stop().wait_blocking();
        }
    }
}
