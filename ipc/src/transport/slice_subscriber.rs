//! Subscriber of slices, validating each header against its slice.

use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber as RawSubscriber;
use iceoryx2::prelude::ZeroCopySend;
use iceoryx2::sample::Sample;

use super::intake::Intake;
use super::open::{event_service, port_error, slice_data_service};
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
        let data = slice_data_service::<H::Element, H>(node, spec)?;
        let events = event_service(node, spec)?;
        let port = data
            .subscriber_builder()
            .buffer_size(spec.subscriber_buffer.max(1))
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            port,
            intake: Intake::open(&events, spec)?,
        })
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
        loop {
            let Some(sample) = self
                .port
                .receive()
                .map_err(|error| self.intake.transport_error(error))?
            else {
                return Ok(None);
            };
            if self.check(&sample).is_ok() {
                return Ok(Some(ValidSlice { sample }));
            }
        }
    }

    /// Drains the buffer and returns the newest valid sample, if any arrived.
    pub fn receive_latest(&self) -> Result<Option<ValidSlice<H>>, ReceiveError> {
        let mut latest = None;
        while let Some(sample) = self.receive()? {
            latest = Some(sample);
        }
        Ok(latest)
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
