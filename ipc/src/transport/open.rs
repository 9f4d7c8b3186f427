//! Opening the two services behind a topic with the topic's quality of service.

use core::fmt::Debug;

use iceoryx2::node::Node;
use iceoryx2::prelude::{IceoryxSend, ServiceName, ZeroCopySend};
use iceoryx2::service::builder::event::{EventOpenError, EventOpenOrCreateError};
use iceoryx2::service::builder::publish_subscribe::{
    self, PublishSubscribeOpenError, PublishSubscribeOpenOrCreateError,
};
use iceoryx2::service::port_factory::{self, event};

use super::OpenError;
use crate::IpcService;
use crate::topics::TopicSpec;

pub(crate) fn service_name(spec: &TopicSpec) -> Result<ServiceName, OpenError> {
    ServiceName::new(&spec.name).map_err(|_| OpenError::BadTopicName(spec.name.to_string()))
}

/// Whether opening a port may create the topic's services.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OpenMode {
    /// The graph's own ports: whoever comes first creates the topic.
    OpenOrCreate,
    /// A tool looking at a running launch: a missing topic is an error, never created.
    ExistingOnly,
}

pub(crate) fn event_service(
    node: &Node<IpcService>,
    spec: &TopicSpec,
    mode: OpenMode,
) -> Result<event::PortFactory<IpcService>, OpenError> {
    let builder = node
        .service_builder(&service_name(spec)?)
        .event()
        .max_notifiers(spec.max_publishers)
        .max_listeners(spec.max_subscribers)
        .max_nodes(spec.max_nodes());
    let opened = match mode {
        OpenMode::OpenOrCreate => builder.open_or_create(),
        OpenMode::ExistingOnly => builder
            .open()
            .map_err(EventOpenOrCreateError::EventOpenError),
    };
    opened.map_err(|error| match error {
        EventOpenOrCreateError::EventOpenError(EventOpenError::DoesNotExist) => {
            OpenError::NoSuchTopic(spec.name.to_string())
        }
        other => OpenError::EventService {
            topic: spec.name.to_string(),
            reason: format!("{other:?}"),
        },
    })
}

/// Applies the topic's quality of service to a publish-subscribe builder (fixed or slice).
fn with_qos<Payload, Header>(
    builder: publish_subscribe::Builder<Payload, Header, IpcService>,
    spec: &TopicSpec,
) -> publish_subscribe::Builder<Payload, Header, IpcService>
where
    Payload: Debug + IceoryxSend + ?Sized,
    Header: Debug + ZeroCopySend,
{
    builder
        .history_size(spec.history_size)
        .subscriber_max_buffer_size(spec.subscriber_buffer.max(spec.history_size).max(1))
        .subscriber_max_borrowed_samples(2)
        .max_publishers(spec.max_publishers)
        .max_subscribers(spec.max_subscribers)
        .max_nodes(spec.max_nodes())
        .enable_safe_overflow(true)
}

/// The error for a publish-subscribe service that could not be opened (or created).
fn data_error(spec: &TopicSpec, error: PublishSubscribeOpenOrCreateError) -> OpenError {
    match error {
        PublishSubscribeOpenOrCreateError::PublishSubscribeOpenError(
            PublishSubscribeOpenError::DoesNotExist,
        ) => OpenError::NoSuchTopic(spec.name.to_string()),
        other => OpenError::DataService {
            topic: spec.name.to_string(),
            reason: format!("{other:?}"),
        },
    }
}

/// Opens, or opens or creates, a configured publish-subscribe builder as `mode` says (a macro:
/// iceoryx2 offers `open` for fixed-size and slice payloads in separate impls).
macro_rules! open_data {
    ($builder:expr, $spec:expr, $mode:expr) => {{
        let builder = with_qos($builder, $spec);
        let opened = match $mode {
            OpenMode::OpenOrCreate => builder.open_or_create(),
            OpenMode::ExistingOnly => builder
                .open()
                .map_err(PublishSubscribeOpenOrCreateError::PublishSubscribeOpenError),
        };
        opened.map_err(|error| data_error($spec, error))
    }};
}

/// The data service of a topic carrying fixed-size `Payload`s.
pub(crate) fn data_service<Payload, Header>(
    node: &Node<IpcService>,
    spec: &TopicSpec,
    mode: OpenMode,
) -> Result<port_factory::publish_subscribe::PortFactory<IpcService, Payload, Header>, OpenError>
where
    Payload: Debug + ZeroCopySend + 'static,
    Header: Debug + Default + ZeroCopySend + 'static,
{
    let builder = node
        .service_builder(&service_name(spec)?)
        .publish_subscribe::<Payload>()
        .user_header::<Header>();
    open_data!(builder, spec, mode)
}

/// The data service of a topic carrying `[Element]` slices.
pub(crate) fn slice_data_service<Element, Header>(
    node: &Node<IpcService>,
    spec: &TopicSpec,
    mode: OpenMode,
) -> Result<port_factory::publish_subscribe::PortFactory<IpcService, [Element], Header>, OpenError>
where
    Element: Debug + ZeroCopySend + 'static,
    Header: Debug + Default + ZeroCopySend + 'static,
{
    let builder = node
        .service_builder(&service_name(spec)?)
        .publish_subscribe::<[Element]>()
        .user_header::<Header>();
    open_data!(builder, spec, mode)
}

pub(crate) fn port_error(spec: &TopicSpec, error: impl Debug) -> OpenError {
    OpenError::Port {
        topic: spec.name.to_string(),
        reason: format!("{error:?}"),
    }
}
