//! Publisher of fixed-size messages.

use iceoryx2::node::Node;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher as RawPublisher;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::ZeroCopySend;

use super::open::{data_service, event_service, port_error};
use super::{OpenError, SendError};
use crate::IpcService;
use crate::stamp::monotonic_now_ns;
use crate::topics::TopicSpec;
use crate::validate::Message;

/// Publishes `M` on one topic: loans a sample, lets the caller fill it in place, stamps the
/// sequence and publish time, sends, and wakes the subscribers.
#[derive(Debug)]
pub struct Publisher<M: Message + ZeroCopySend> {
    port: RawPublisher<IpcService, M, ()>,
    notifier: Notifier<IpcService>,
    topic: String,
    next_sequence: u64,
}

impl<M: Message + ZeroCopySend> Publisher<M> {
    /// Opens (or creates) the topic and a publisher port on it.
    pub fn open(node: &Node<IpcService>, spec: &TopicSpec) -> Result<Self, OpenError> {
        let data = data_service::<M, ()>(node, spec)?;
        let events = event_service(node, spec)?;
        let port = data
            .publisher_builder()
            .create()
            .map_err(|error| port_error(spec, error))?;
        let notifier = events
            .notifier_builder()
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            port,
            notifier,
            topic: spec.name.to_string(),
            next_sequence: 0,
        })
    }

    /// Fills a loaned sample with `fill` (starting from `M::default()`), stamps it, sends it and
    /// notifies. Returns the number of subscribers reached.
    pub fn send_with(&mut self, fill: impl FnOnce(&mut M)) -> Result<usize, SendError> {
        let action = crate::fault::on_publish(&self.topic);
        if action == crate::fault::PublishAction::Drop {
            return Ok(0);
        }
        let sample = self.port.loan_uninit().map_err(|error| SendError::Loan {
            topic: self.topic.clone(),
            reason: format!("{error:?}"),
        })?;
        let mut sample = sample.write_payload(M::default());
        let message = sample.payload_mut();
        fill(message);
        let stamp = message.stamp_mut();
        stamp.publish_stamp_ns = monotonic_now_ns();
        if action == crate::fault::PublishAction::Corrupt && self.next_sequence > 0 {
            // Injected fault: a garbled header, which repeats the last sequence number.
            stamp.sequence = self.next_sequence - 1;
        } else {
            stamp.sequence = self.next_sequence;
            self.next_sequence += 1;
        }
        let reached = sample.send().map_err(|error| SendError::Deliver {
            topic: self.topic.clone(),
            reason: format!("{error:?}"),
        })?;
        self.notify()?;
        Ok(reached)
    }

    /// Sends a copy of `message` (stamped like [`Self::send_with`]).
    pub fn send(&mut self, message: M) -> Result<usize, SendError> {
        self.send_with(|slot| *slot = message)
    }

    /// Connects subscribers that appeared since the last send and delivers the topic history
    /// to them (a restarted process recovers its last state this way).
    pub fn update_connections(&self) -> Result<(), SendError> {
        self.port
            .update_connections()
            .map_err(|error| SendError::Deliver {
                topic: self.topic.clone(),
                reason: format!("update connections: {error:?}"),
            })
    }

    /// Sets the next sequence number, e.g. to continue after a restart from history.
    pub fn continue_sequence_after(&mut self, last_sequence: u64) {
        self.next_sequence = last_sequence.saturating_add(1);
    }

    fn notify(&self) -> Result<(), SendError> {
        self.notifier
            .notify()
            .map(|_| ())
            .map_err(|error| SendError::Deliver {
                topic: self.topic.clone(),
                reason: format!("notify: {error:?}"),
            })
    }
}
