//! Publisher of fixed-size messages.

use iceoryx2::node::Node;
use iceoryx2::port::publisher::Publisher as RawPublisher;
use iceoryx2::prelude::ZeroCopySend;

use super::open::{OpenMode, data_service, event_service, port_error};
use super::outlet::Outlet;
use super::{OpenError, SendError};
use crate::IpcService;
use crate::fault::PublishAction;
use crate::topics::TopicSpec;
use crate::validate::Message;

/// Publishes `M` on one topic: loans a sample, lets the caller fill it in place, stamps the
/// sequence and publish time, sends, and wakes the subscribers.
#[derive(Debug)]
pub struct Publisher<M: Message + ZeroCopySend> {
    port: RawPublisher<IpcService, M, ()>,
    outlet: Outlet,
}

impl<M: Message + ZeroCopySend> Publisher<M> {
    /// Opens (or creates) the topic and a publisher port on it.
    pub fn open(node: &Node<IpcService>, spec: &TopicSpec) -> Result<Self, OpenError> {
        let data = data_service::<M, ()>(node, spec, OpenMode::OpenOrCreate)?;
        let events = event_service(node, spec, OpenMode::OpenOrCreate)?;
        let port = data
            .publisher_builder()
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            port,
            outlet: Outlet::open(&events, spec)?,
        })
    }

    /// Fills a loaned sample with `fill` (starting from `M::default()`), stamps it, sends it and
    /// notifies. Returns the number of subscribers reached.
    pub fn send_with(&mut self, fill: impl FnOnce(&mut M)) -> Result<usize, SendError> {
        let action = self.outlet.fault_action();
        if action == PublishAction::Drop {
            return Ok(0);
        }
        let sample = self
            .port
            .loan_uninit()
            .map_err(|error| self.outlet.loan_error(error))?;
        let mut sample = sample.write_payload(M::default());
        let message = sample.payload_mut();
        fill(message);
        self.outlet.stamp(message.stamp_mut(), action);
        self.outlet.delivered(sample.send())
    }

    /// Sends a copy of `message` (stamped like [`Self::send_with`]).
    pub fn send(&mut self, message: M) -> Result<usize, SendError> {
        self.send_with(|slot| *slot = message)
    }

    /// Connects subscribers that appeared since the last send and delivers the topic history
    /// to them (a restarted process recovers its last state this way).
    pub fn update_connections(&self) -> Result<(), SendError> {
        self.outlet.update_connections(&self.port)
    }

    /// Sets the next sequence number, e.g. to continue after a restart from history.
    pub fn continue_sequence_after(&mut self, last_sequence: u64) {
        self.outlet.continue_sequence_after(last_sequence);
    }
}
