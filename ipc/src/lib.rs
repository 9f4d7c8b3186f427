//! hopnav's inter-process layer: message types, topic names, a typed zero-copy transport over
//! iceoryx2, the per-launch namespace and the lifecycle loop every process runs.
//!
//! No algorithms live here. Processes open [`transport`] ports on the [`topics`] and exchange
//! the `#[repr(C)]` types of [`messages`] in place in shared memory.
//!
//! ```no_run
//! use hopnav_ipc::{messages::Heartbeat, namespace::Namespace, topics, transport::Publisher};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let namespace = Namespace::new(&format!("doc-{}", std::process::id()))?;
//! let node = namespace.create_node("doc_example")?;
//! let mut publisher = Publisher::<Heartbeat>::open(&node, &topics::HEARTBEAT)?;
//! publisher.send_with(|heartbeat| heartbeat.stamp.frame_index = 7)?;
//! # Ok(())
//! # }
//! ```
#![warn(missing_docs)]

pub mod codec;
pub mod fault;
pub mod latency;
pub mod live;
pub mod messages;
pub mod namespace;
pub mod node_error;
pub mod process_loop;
pub mod stamp;
pub mod topics;
pub mod transport;
pub mod validate;
pub mod wire;

/// The iceoryx2 service flavour used by every hopnav port: inter-process, shared memory.
pub type IpcService = iceoryx2::prelude::ipc::Service;
