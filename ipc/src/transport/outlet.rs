//! What both publishers keep beside their data port: the wake-up notifier, the sequence
//! counter and the topic's name, with the stamping, delivering and error wording they share.

use core::fmt::Debug;

use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::service::port_factory::event::PortFactory as EventService;

use super::open::port_error;
use super::{OpenError, SendError};
use crate::IpcService;
use crate::fault::PublishAction;
use crate::messages::SampleStamp;
use crate::stamp::monotonic_now_ns;
use crate::topics::TopicSpec;

/// A publisher's notifier, next sequence number and topic name.
#[derive(Debug)]
pub(super) struct Outlet {
    notifier: Notifier<IpcService>,
    topic: String,
    next_sequence: u64,
}

impl Outlet {
    /// Creates the notifier on the topic's event service.
    pub(super) fn open(
        events: &EventService<IpcService>,
        spec: &TopicSpec,
    ) -> Result<Self, OpenError> {
        let notifier = events
            .notifier_builder()
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            notifier,
            topic: spec.name.to_string(),
            next_sequence: 0,
        })
    }

    /// The injected-fault decision for the next sample on this topic.
    pub(super) fn fault_action(&self) -> PublishAction {
        crate::fault::on_publish(&self.topic)
    }

    /// Stamps the publish time and the next sequence number; an injected `Corrupt` fault
    /// garbles the header by repeating the last sequence number instead.
    pub(super) fn stamp(&mut self, stamp: &mut SampleStamp, action: PublishAction) {
        stamp.publish_stamp_ns = monotonic_now_ns();
        if action == PublishAction::Corrupt && self.next_sequence > 0 {
            stamp.sequence = self.next_sequence - 1;
        } else {
            stamp.sequence = self.next_sequence;
            self.next_sequence += 1;
        }
    }

    /// Takes the result of sending a sample and wakes the subscribers; returns how many
    /// subscribers the sample reached.
    pub(super) fn delivered(&self, sent: Result<usize, impl Debug>) -> Result<usize, SendError> {
        let reached = sent.map_err(|error| self.deliver_error(format!("{error:?}")))?;
        self.notifier
            .notify()
            .map_err(|error| self.deliver_error(format!("notify: {error:?}")))?;
        Ok(reached)
    }

    /// Connects subscribers that appeared since the last send and delivers the topic history
    /// to them.
    pub(super) fn update_connections(
        &self,
        port: &impl UpdateConnections,
    ) -> Result<(), SendError> {
        port.update_connections()
            .map_err(|error| self.deliver_error(format!("update connections: {error:?}")))
    }

    /// Sets the next sequence number, e.g. to continue after a restart from history.
    pub(super) fn continue_sequence_after(&mut self, last_sequence: u64) {
        self.next_sequence = last_sequence.saturating_add(1);
    }

    /// The error for a sample that could not be loaned.
    pub(super) fn loan_error(&self, error: impl Debug) -> SendError {
        SendError::Loan {
            topic: self.topic.clone(),
            reason: format!("{error:?}"),
        }
    }

    /// The topic's name, for errors the publisher words itself.
    pub(super) fn topic(&self) -> &str {
        &self.topic
    }

    fn deliver_error(&self, reason: String) -> SendError {
        SendError::Deliver {
            topic: self.topic.clone(),
            reason,
        }
    }
}
