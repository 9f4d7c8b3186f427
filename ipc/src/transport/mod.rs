//! Typed, event-driven ports over iceoryx2: loan, fill in place, send, notify.
//!
//! Each topic pairs a publish-subscribe service with an event service of the same name.
//! [`Publisher::send_with`] writes the message straight into loaned shared memory, stamps it
//! and wakes subscribers; subscribers attach their [`Subscriber::listener`] to a WaitSet and
//! drain validated samples with [`Subscriber::receive`]. Slices (images, clouds, cells) go
//! through [`SlicePublisher`] and [`SliceSubscriber`] with a header that announces them.

mod error;
mod intake;
mod keyframe_cloud;
pub(crate) mod open;
mod outlet;
mod publisher;
mod slice_publisher;
mod slice_subscriber;
mod subscriber;

pub use error::{OpenError, ReceiveError, SendError};
/// The bound of every type a port carries, for code generic over ports outside this crate.
pub use iceoryx2::prelude::ZeroCopySend;
pub use publisher::Publisher;
pub use slice_publisher::SlicePublisher;
pub use slice_subscriber::{SliceSubscriber, ValidSlice};
pub use subscriber::Subscriber;

/// Rejection counts of one subscriber.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct RejectCounts {
    /// Samples whose fields failed validation.
    pub invalid: u64,
    /// Samples that repeated or regressed their publisher's sequence.
    pub stale: u64,
}

impl RejectCounts {
    /// All rejected samples.
    pub fn total(&self) -> u64 {
        self.invalid + self.stale
    }
}
