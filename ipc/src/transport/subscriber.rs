//! Subscriber of fixed-size messages, validating what it receives.

use core::cell::{Cell, RefCell};

use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber as RawSubscriber;
use iceoryx2::prelude::ZeroCopySend;

use super::open::{data_service, event_service, port_error};
use super::{OpenError, ReceiveError, RejectCounts};
use crate::IpcService;
use crate::topics::TopicSpec;
use crate::validate::{Message, Rejection, SequenceGuard};

/// Receives `M` from one topic. Invalid or out-of-order samples are dropped and counted.
#[derive(Debug)]
pub struct Subscriber<M: Message + ZeroCopySend> {
    port: RawSubscriber<IpcService, M, ()>,
    listener: Listener<IpcService>,
    // Cells: receiving must work while a WaitSet borrows the listener.
    sequence_guard: RefCell<SequenceGuard<UniquePublisherId>>,
    rejected: Cell<RejectCounts>,
    topic: String,
}

impl<M: Message + ZeroCopySend> Subscriber<M> {
    /// Opens (or creates) the topic and a subscriber port on it; receives the topic's history.
    pub fn open(node: &Node<IpcService>, spec: &TopicSpec) -> Result<Self, OpenError> {
        let data = data_service::<M, ()>(node, spec)?;
        let events = event_service(node, spec)?;
        let port = data
            .subscriber_builder()
            .buffer_size(spec.subscriber_buffer.max(1))
            .create()
            .map_err(|error| port_error(spec, error))?;
        let listener = events
            .listener_builder()
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            port,
            listener,
            sequence_guard: RefCell::new(SequenceGuard::new(spec.max_publishers.max(1) * 2)),
            rejected: Cell::new(RejectCounts::default()),
            topic: spec.name.to_string(),
        })
    }

    /// The event listener to attach to a WaitSet.
    pub fn listener(&self) -> &Listener<IpcService> {
        &self.listener
    }

    /// Consumes pending wake-up events (call after waking, before receiving).
    pub fn clear_events(&self) {
        let _ = self.listener.try_wait(|_| {});
    }

    /// The next valid sample, copied out (messages are small); `None` when drained.
    pub fn receive(&self) -> Result<Option<M>, ReceiveError> {
        loop {
            let Some(sample) = self
                .port
                .receive()
                .map_err(|error| ReceiveError::Transport {
                    topic: self.topic.clone(),
                    reason: format!("{error:?}"),
                })?
            else {
                return Ok(None);
            };
            let message = *sample.payload();
            match self.check(sample.origin(), &message) {
                Ok(()) => return Ok(Some(message)),
                Err(_) => continue,
            }
        }
    }

    /// Drains the buffer and returns the newest valid sample, if any arrived.
    pub fn receive_latest(&self) -> Result<Option<M>, ReceiveError> {
        let mut latest = None;
        while let Some(message) = self.receive()? {
            latest = Some(message);
        }
        Ok(latest)
    }

    /// What this subscriber has rejected so far.
    pub fn rejected(&self) -> RejectCounts {
        self.rejected.get()
    }

    fn check(&self, origin: UniquePublisherId, message: &M) -> Result<(), Rejection> {
        if let Err(rejection) = message.validate() {
            let mut counts = self.rejected.get();
            counts.invalid += 1;
            self.rejected.set(counts);
            return Err(rejection);
        }
        if let Err(rejection) = self
            .sequence_guard
            .borrow_mut()
            .check(origin, message.stamp().sequence)
        {
            let mut counts = self.rejected.get();
            counts.stale += 1;
            self.rejected.set(counts);
            return Err(rejection);
        }
        Ok(())
    }
}
