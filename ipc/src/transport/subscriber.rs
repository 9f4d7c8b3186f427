//! Subscriber of fixed-size messages, validating what it receives.

use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber as RawSubscriber;
use iceoryx2::prelude::ZeroCopySend;

use super::intake::{Intake, Role, newest, open_subscriber};
use super::open::{data_service, event_service};
use super::{OpenError, ReceiveError, RejectCounts};
use crate::IpcService;
use crate::topics::TopicSpec;
use crate::validate::{Message, Rejection};

/// Receives `M` from one topic. Invalid or out-of-order samples are dropped and counted.
#[derive(Debug)]
pub struct Subscriber<M: Message + ZeroCopySend> {
    port: RawSubscriber<IpcService, M, ()>,
    intake: Intake,
}

impl<M: Message + ZeroCopySend> Subscriber<M> {
    /// Opens (or creates) the topic and a subscriber port on it; receives the topic's history.
    pub fn open(node: &Node<IpcService>, spec: &TopicSpec) -> Result<Self, OpenError> {
        Self::open_as(node, spec, Role::Consumer)
    }

    /// Opens an extra subscriber on a topic of a running launch, for a tool: the topic must
    /// exist, a free subscriber slot must be left, and no history is taken. The topic's
    /// overflow policy keeps a slow tool from holding any publisher back.
    pub fn open_tap(node: &Node<IpcService>, spec: &TopicSpec) -> Result<Self, OpenError> {
        Self::open_as(node, spec, Role::Tap)
    }

    fn open_as(node: &Node<IpcService>, spec: &TopicSpec, role: Role) -> Result<Self, OpenError> {
        let data = data_service::<M, ()>(node, spec, role.open_mode())?;
        let events = event_service(node, spec, role.open_mode())?;
        let (port, intake) = open_subscriber(&data, &events, spec, role)?;
        Ok(Self { port, intake })
    }

    /// The event listener to attach to a WaitSet.
    pub fn listener(&self) -> &Listener<IpcService> {
        self.intake.listener()
    }

    /// Consumes pending wake-up events (call after waking, before receiving).
    pub fn clear_events(&self) {
        self.intake.clear_events();
    }

    /// The next valid sample, copied out (messages are small); `None` when drained.
    pub fn receive(&self) -> Result<Option<M>, ReceiveError> {
        self.intake.next_admitted(
            || self.port.receive(),
            |sample| {
                let message = *sample.payload();
                self.check(sample.origin(), &message).ok().map(|()| message)
            },
        )
    }

    /// Drains the buffer and returns the newest valid sample, if any arrived.
    pub fn receive_latest(&self) -> Result<Option<M>, ReceiveError> {
        newest(|| self.receive())
    }

    /// What this subscriber has rejected so far.
    pub fn rejected(&self) -> RejectCounts {
        self.intake.rejected()
    }

    fn check(&self, origin: UniquePublisherId, message: &M) -> Result<(), Rejection> {
        self.intake
            .admit(message.validate(), origin, message.stamp().sequence)
    }
}
