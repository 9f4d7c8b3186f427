//! Looking at a running launch from outside the graph (`hopnav topic`): which launches run,
//! which topics they have and who uses them, and what arrives on one topic.
//!
//! Nothing here creates a topic, takes history, or takes a subscriber slot that is not free:
//! a tool must never change what the graph does.

mod bandwidth;
mod catalog;
mod census;
mod rate;
mod runs;
mod tap;

pub use bandwidth::{BandwidthStats, ByteTotals, ByteWindow, human_bytes};
pub use catalog::{KindVisitor, KnownTopic, MessageKind, known_topic};
pub use census::{TopicRow, topic_census};
pub use rate::{ArrivalWindow, RateStats, RateTotals, rate_stats};
pub use runs::{RunSelectError, find_launch, is_running, running_launches, select_run};
pub use tap::{TapSample, WatchEnd, Watcher, fixed_message, watch};

/// Why a look at a running launch failed.
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// No launch, or not the one asked for.
    #[error(transparent)]
    Run(#[from] RunSelectError),
    /// The tool's own iceoryx2 node could not be made.
    #[error(transparent)]
    Namespace(#[from] crate::namespace::NamespaceError),
    /// The topic or its port could not be opened.
    #[error(transparent)]
    Open(#[from] crate::transport::OpenError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] crate::transport::ReceiveError),
    /// iceoryx2 could not list the launch's services or nodes, or wait.
    #[error("{0}")]
    Iceoryx(String),
}
