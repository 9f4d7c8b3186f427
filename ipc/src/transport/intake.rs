//! What both subscribers keep beside their data port: the wake-up listener, the
//! per-publisher sequence guard and the rejection counts, with the admission rule they share.

use core::cell::{Cell, RefCell};
use core::fmt::Debug;

use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::port::listener::{Listener, ListenerCreateError};
use iceoryx2::port::subscriber::{Subscriber as RawSubscriber, SubscriberCreateError};
use iceoryx2::prelude::{IceoryxSend, ZeroCopySend};
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::port_factory::event::PortFactory as EventService;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as DataService;

use super::open::{OpenMode, port_error};
use super::{OpenError, ReceiveError, RejectCounts};
use crate::IpcService;
use crate::topics::TopicSpec;
use crate::validate::{Rejection, SequenceGuard};

/// A subscriber's listener, sequence guard and rejection counts.
#[derive(Debug)]
pub(super) struct Intake {
    listener: Listener<IpcService>,
    // Cells: receiving must work while a WaitSet borrows the listener.
    sequence_guard: RefCell<SequenceGuard<UniquePublisherId>>,
    rejected: Cell<RejectCounts>,
    topic: String,
}

/// Who a subscriber is, which decides how its port is opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Role {
    /// A process of the graph: may create the topic, receives its history.
    Consumer,
    /// A tool watching a running launch (`hopnav topic`): opens only a topic that exists,
    /// takes no history (it wants what is published from now on) and refuses to take a
    /// subscriber slot that is not free.
    Tap,
}

impl Role {
    /// How this role opens the topic's services.
    pub(super) fn open_mode(self) -> OpenMode {
        match self {
            Self::Consumer => OpenMode::OpenOrCreate,
            Self::Tap => OpenMode::ExistingOnly,
        }
    }
}

/// Subscriber slots a tap leaves free: a consumer restarted while its dead predecessor's port
/// is not yet cleaned needs one more slot for a moment.
const TAP_SPARE_SLOTS: usize = 1;

/// Opens a subscriber port on the topic's data service (buffering what the topic keeps) and
/// its intake on the event service.
pub(super) fn open_subscriber<Payload, Header>(
    data: &DataService<IpcService, Payload, Header>,
    events: &EventService<IpcService>,
    spec: &TopicSpec,
    role: Role,
) -> Result<(RawSubscriber<IpcService, Payload, Header>, Intake), OpenError>
where
    Payload: Debug + IceoryxSend + ?Sized,
    Header: Debug + ZeroCopySend,
{
    let max_subscribers = data.static_config().max_subscribers();
    let no_free_slot = |in_use| OpenError::NoFreeSubscriberSlot {
        topic: spec.name.to_string(),
        in_use,
        max_subscribers,
    };
    let mut builder = data
        .subscriber_builder()
        .buffer_size(spec.subscriber_buffer.max(1));
    if role == Role::Tap {
        let in_use = data.dynamic_config().number_of_subscribers();
        if in_use + 1 + TAP_SPARE_SLOTS > max_subscribers {
            return Err(no_free_slot(in_use));
        }
        builder = builder.history_request(0);
    }
    // A slot taken meanwhile (by anyone) fails here.
    let port = builder.create().map_err(|error| match error {
        SubscriberCreateError::ExceedsMaxSupportedSubscribers if role == Role::Tap => {
            no_free_slot(max_subscribers)
        }
        other => port_error(spec, other),
    })?;
    let listener = events
        .listener_builder()
        .create()
        .map_err(|error| match error {
            ListenerCreateError::ExceedsMaxSupportedListeners if role == Role::Tap => {
                no_free_slot(max_subscribers)
            }
            other => port_error(spec, other),
        })?;
    Ok((port, Intake::new(listener, spec)))
}

/// Drains `receive` and returns the newest item it gave, if any.
pub(super) fn newest<T>(
    mut receive: impl FnMut() -> Result<Option<T>, ReceiveError>,
) -> Result<Option<T>, ReceiveError> {
    let mut latest = None;
    while let Some(item) = receive()? {
        latest = Some(item);
    }
    Ok(latest)
}

impl Intake {
    /// The intake of a subscriber woken by `listener`.
    fn new(listener: Listener<IpcService>, spec: &TopicSpec) -> Self {
        Self {
            listener,
            sequence_guard: RefCell::new(SequenceGuard::new(spec.max_publishers.max(1) * 2)),
            rejected: Cell::new(RejectCounts::default()),
            topic: spec.name.to_string(),
        }
    }

    /// The event listener to attach to a WaitSet.
    pub(super) fn listener(&self) -> &Listener<IpcService> {
        &self.listener
    }

    /// Consumes pending wake-up events.
    pub(super) fn clear_events(&self) {
        let _ = self.listener.try_wait(|_| {});
    }

    /// What has been rejected so far.
    pub(super) fn rejected(&self) -> RejectCounts {
        self.rejected.get()
    }

    /// The first sample `receive` gives that `admit` turns into a `T` (it returns `None` for
    /// a rejected sample, which is dropped); `None` when drained.
    pub(super) fn next_admitted<S, T, E: Debug>(
        &self,
        mut receive: impl FnMut() -> Result<Option<S>, E>,
        mut admit: impl FnMut(S) -> Option<T>,
    ) -> Result<Option<T>, ReceiveError> {
        loop {
            let Some(sample) = receive().map_err(|error| self.transport_error(error))? else {
                return Ok(None);
            };
            if let Some(admitted) = admit(sample) {
                return Ok(Some(admitted));
            }
        }
    }

    /// The error for a failed receive on this topic.
    fn transport_error(&self, error: impl Debug) -> ReceiveError {
        ReceiveError::Transport {
            topic: self.topic.clone(),
            reason: format!("{error:?}"),
        }
    }

    /// Admits a sample whose own check gave `validity`, from publisher `origin` with
    /// `sequence`: an invalid sample counts as invalid, a repeated or regressed sequence as
    /// stale (checked only for valid samples).
    pub(super) fn admit(
        &self,
        validity: Result<(), Rejection>,
        origin: UniquePublisherId,
        sequence: u64,
    ) -> Result<(), Rejection> {
        if let Err(rejection) = validity {
            let mut counts = self.rejected.get();
            counts.invalid += 1;
            self.rejected.set(counts);
            return Err(rejection);
        }
        if let Err(rejection) = self.sequence_guard.borrow_mut().check(origin, sequence) {
            let mut counts = self.rejected.get();
            counts.stale += 1;
            self.rejected.set(counts);
            return Err(rejection);
        }
        Ok(())
    }
}
