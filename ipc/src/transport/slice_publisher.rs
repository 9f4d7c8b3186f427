//! Publisher of slices (images, clouds, cell updates) with an announcing header.

use core::mem::MaybeUninit;

use iceoryx2::node::Node;
use iceoryx2::port::publisher::Publisher as RawPublisher;
use iceoryx2::prelude::{AllocationStrategy, ZeroCopySend};

use super::open::{OpenMode, event_service, port_error, slice_data_service};
use super::outlet::Outlet;
use super::{OpenError, SendError};
use crate::IpcService;
use crate::fault::PublishAction;
use crate::topics::TopicSpec;
use crate::validate::SliceHeader;

/// A loaned, not yet written slice sample.
type UninitSlice<H> = iceoryx2::sample_mut_uninit::SampleMutUninit<
    IpcService,
    [MaybeUninit<<H as SliceHeader>::Element>],
    H,
>;

/// Publishes `[H::Element]` slices with header `H`. Memory is allocated once, statically, for
/// the largest slice the port was opened for: no growth, no reallocation on the hot path.
#[derive(Debug)]
pub struct SlicePublisher<H: SliceHeader + ZeroCopySend>
where
    H::Element: ZeroCopySend,
{
    port: RawPublisher<IpcService, [H::Element], H>,
    outlet: Outlet,
    max_len: usize,
    /// The injected-fault decision for the sample being sent.
    action: PublishAction,
}

impl<H: SliceHeader + ZeroCopySend> SlicePublisher<H>
where
    H::Element: ZeroCopySend,
{
    /// Opens the topic with a publisher able to send slices of up to `max_len` elements.
    pub fn open(
        node: &Node<IpcService>,
        spec: &TopicSpec,
        max_len: usize,
    ) -> Result<Self, OpenError> {
        let data = slice_data_service::<H::Element, H>(node, spec, OpenMode::OpenOrCreate)?;
        let events = event_service(node, spec, OpenMode::OpenOrCreate)?;
        let port = data
            .publisher_builder()
            .initial_max_slice_len(max_len.max(1))
            .allocation_strategy(AllocationStrategy::Static)
            .create()
            .map_err(|error| port_error(spec, error))?;
        Ok(Self {
            port,
            outlet: Outlet::open(&events, spec)?,
            max_len: max_len.max(1),
            action: PublishAction::Send,
        })
    }

    /// Loans `len` elements and writes element `i` as `element(i)` straight into shared
    /// memory (one pass, no zeroing); then `header` fills the header (so it can record how
    /// long the fill took), and the sample is stamped, sent and notified.
    pub fn send_from_fn(
        &mut self,
        len: usize,
        header: impl FnOnce(&mut H),
        element: impl FnMut(usize) -> H::Element,
    ) -> Result<usize, SendError> {
        if self.dropped_by_fault() {
            return Ok(0);
        }
        let mut sample = self.loan(len)?.write_from_fn(element);
        *sample.user_header_mut() = H::default();
        header(sample.user_header_mut());
        self.finish(sample)
    }

    /// Loans `len` elements initialised to `H::Element::default()` and hands them, with the
    /// header, to `fill`, which draws in place (a renderer writes pixels in any order). If
    /// `fill` fails, nothing is sent and its reason is returned.
    pub fn send_with<E: core::fmt::Display>(
        &mut self,
        len: usize,
        fill: impl FnOnce(&mut H, &mut [H::Element]) -> Result<(), E>,
    ) -> Result<usize, SendError> {
        if self.dropped_by_fault() {
            return Ok(0);
        }
        let sample = self.loan(len)?;
        let mut sample = sample.write_from_fn(|_| H::Element::default());
        // The header is a few dozen bytes: fill a local copy, then write it into the sample,
        // so header and payload are never borrowed mutably at once.
        let mut header = H::default();
        fill(&mut header, sample.payload_mut()).map_err(|error| SendError::Fill {
            topic: self.outlet.topic().to_string(),
            reason: error.to_string(),
        })?;
        *sample.user_header_mut() = header;
        self.finish(sample)
    }

    /// The largest slice this port can send.
    pub fn max_len(&self) -> usize {
        self.max_len
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

    /// Draws the injected-fault decision for the next sample; true when it is to be dropped.
    fn dropped_by_fault(&mut self) -> bool {
        self.action = self.outlet.fault_action();
        self.action == PublishAction::Drop
    }

    fn loan(&self, len: usize) -> Result<UninitSlice<H>, SendError> {
        if len > self.max_len {
            return Err(SendError::SliceTooLong {
                topic: self.outlet.topic().to_string(),
                requested: len,
                max: self.max_len,
            });
        }
        self.port
            .loan_slice_uninit(len)
            .map_err(|error| self.outlet.loan_error(error))
    }

    fn finish(
        &mut self,
        mut sample: iceoryx2::sample_mut::SampleMut<IpcService, [H::Element], H>,
    ) -> Result<usize, SendError> {
        self.outlet
            .stamp(sample.user_header_mut().stamp_mut(), self.action);
        self.outlet.delivered(sample.send())
    }
}
