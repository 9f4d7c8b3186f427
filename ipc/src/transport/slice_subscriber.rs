//! Subscriber of slices, validating each header against its slice.

use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber as RawSubscriber;
use iceoryx2::prelude::ZeroCopySend;
use iceoryx2::sample::Sample;

use super::intake::{Intake, Role, newest, open_subscriber};
use super::open::{event_service, slice_data_service};
use super::{OpenError, ReceiveError, RejectCounts};
use crate::IpcService;
use crate::topics::TopicSpec;
use crate::validate::{Rejection, SliceHeader};

/// A received slice sample whose header matched its payload. Borrowed from shared memory:
/// read it in place (no copy) and drop it to return the memory to the publisher.
#[derive(Debug)]
pub struct ValidSlice<H: SliceHeader + ZeroCopySend>
where
    H::Element: ZeroCopySend,
{
    sample: Sample<IpcService, [H::Element], H>,
}

impl<H: SliceHeader + ZeroCopySend> ValidSlice<H>
where
    H::Element: ZeroCopySend,
{
    /// The validated header.
    pub fn header(&self) -> &H {
        self.sample.user_header()
    }

    /// The validated elements, in shared memory.
    pub fn elements(&self) -> &[H::Element] {
        self.sample.payload()
    }
}

/// Receives `[H::Element]` slices from one topic; rejected samples are dropped and counted.
#[derive(Debug)]
pub struct SliceSubscriber<H: SliceHeader + ZeroCopySend>
where
    H::Element: ZeroCopySend,
{
    port: RawSubscriber<IpcService, [H::Element], H>,
    intake: Intake,
}

impl<H: SliceHeader + ZeroCopySend> SliceSubscriber<H>
where
    H::Element: ZeroCopySend,
{
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
        let data = slice_data_service::<H::Element, H>(node, spec, role.open_mode())?;
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

    /// The next valid sample, in place; `None` when drained.
    pub fn receive(&self) -> Result<Option<ValidSlice<H>>, ReceiveError> {
        self.intake.next_admitted(
            || self.port.receive(),
            |sample| self.check(&sample).ok().map(|()| ValidSlice { sample }),
        )
    }

    /// Drains the buffer and returns the newest valid sample, if any arrived.
    pub fn receive_latest(&self) -> Result<Option<ValidSlice<H>>, ReceiveError> {
        newest(|| self.receive())
    }

    /// What this subscriber has rejected so far.
    pub fn rejected(&self) -> RejectCounts {
        self.intake.rejected()
    }

    fn check(&self, sample: &Sample<IpcService, [H::Element], H>) -> Result<(), Rejection> {
        let header = sample.user_header();
        self.intake.admit(
            header.validate_slice(sample.payload()),
            sample.origin(),
            header.stamp().sequence,
        )
    }
}
