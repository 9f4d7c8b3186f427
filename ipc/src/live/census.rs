//! `hopnav topic list`: every publish-subscribe topic of a running launch, with its type,
//! size and the processes that hold its ports, as iceoryx2 records them.

use std::collections::{BTreeMap, HashMap};

use iceoryx2::identifiers::UniqueNodeId;
use iceoryx2::node::Node;
use iceoryx2::prelude::{CallbackProgression, ZeroCopySend};
use iceoryx2::service::Service as _;
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::static_config::message_type_details::{
    MessageTypeDetails, TypeDetail, TypeVariant,
};
use iceoryx2::service::static_config::messaging_pattern::MessagingPattern;

use super::LiveError;
use super::catalog::{KindVisitor, known_topic};
use super::runs::live_node_names;
use crate::IpcService;
use crate::namespace::Namespace;
use crate::topics::TopicSpec;
use crate::transport::OpenError;
use crate::transport::open::{OpenMode, data_service, slice_data_service};
use crate::validate::{Message, SliceHeader};

/// One topic of a running launch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicRow {
    /// Topic name.
    pub name: String,
    /// Message type: `Type`, or `Header + [Element]` for a slice topic.
    pub message_type: String,
    /// Processes (iceoryx2 node names) holding a publisher, with how many each.
    pub publishers: Vec<(String, usize)>,
    /// Processes holding a subscriber, with how many each.
    pub subscribers: Vec<(String, usize)>,
    /// Subscriber slots the topic has.
    pub max_subscribers: usize,
    /// Bytes of one sample: the message, or the header plus the longest slice a publisher
    /// allocates (`None` for a slice topic without a publisher).
    pub sample_bytes: Option<usize>,
    /// False when the ports could not be read (a topic hopnav does not know, or one opened
    /// with another quality of service): the port lists are then empty.
    pub ports_known: bool,
}

/// What iceoryx2 keeps about one topic's service.
struct ServiceFacts {
    name: String,
    types: MessageTypeDetails,
    max_subscribers: usize,
}

/// Publishers (node and slice length) and subscribers (node) of a topic.
#[derive(Default)]
struct PortIds {
    publishers: Vec<(UniqueNodeId, usize)>,
    subscribers: Vec<UniqueNodeId>,
}

/// Every publish-subscribe topic of the launch of `namespace`, sorted by name.
pub fn topic_census(namespace: &Namespace) -> Result<Vec<TopicRow>, LiveError> {
    let node = namespace.create_node("topic_list")?;
    let mut services = Vec::new();
    IpcService::list(namespace.config(), |details| {
        if let MessagingPattern::PublishSubscribe(pattern) =
            details.static_details.messaging_pattern()
        {
            services.push(ServiceFacts {
                name: details.static_details.name().to_string(),
                types: *pattern.message_type_details(),
                max_subscribers: pattern.max_subscribers(),
            });
        }
        CallbackProgression::Continue
    })
    .map_err(|error| LiveError::Iceoryx(format!("cannot list the launch's topics: {error:?}")))?;
    let names = live_node_names(namespace);
    let mut rows: Vec<TopicRow> = services
        .into_iter()
        .map(|facts| row(&node, &names, facts))
        .collect();
    rows.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(rows)
}

fn row(
    node: &Node<IpcService>,
    names: &HashMap<UniqueNodeId, String>,
    facts: ServiceFacts,
) -> TopicRow {
    let ports = known_topic(&facts.name).and_then(|topic| {
        topic
            .kind
            .visit(ReadPorts {
                node,
                spec: &topic.spec,
            })
            .ok()
    });
    let ports_known = ports.is_some();
    let ports = ports.unwrap_or_default();
    let is_slice = facts.types.payload.variant() == TypeVariant::Dynamic;
    let longest_slice = ports.publishers.iter().map(|&(_, len)| len).max();
    let sample_bytes = if is_slice {
        longest_slice.map(|len| facts.types.user_header.size() + len * facts.types.payload.size())
    } else {
        Some(facts.types.payload.size())
    };
    let name_of = |id: &UniqueNodeId| names.get(id).cloned().unwrap_or_else(|| "?".to_owned());
    TopicRow {
        message_type: type_label(&facts.types, is_slice),
        publishers: counted(ports.publishers.iter().map(|(id, _)| name_of(id))),
        subscribers: counted(ports.subscribers.iter().map(name_of)),
        max_subscribers: facts.max_subscribers,
        sample_bytes,
        ports_known,
        name: facts.name,
    }
}

/// `Type` or `Header + [Element]`, without the `hopnav::` prefix.
fn type_label(types: &MessageTypeDetails, is_slice: bool) -> String {
    let short = |detail: &TypeDetail| {
        let name = detail.type_name().to_string();
        name.strip_prefix("hopnav::").unwrap_or(&name).to_owned()
    };
    if is_slice {
        format!(
            "{} + [{}]",
            short(&types.user_header),
            short(&types.payload)
        )
    } else {
        short(&types.payload)
    }
}

/// Each name once, with how often it came, in name order.
fn counted(names: impl Iterator<Item = String>) -> Vec<(String, usize)> {
    let mut counts = BTreeMap::new();
    for name in names {
        *counts.entry(name).or_insert(0) += 1;
    }
    counts.into_iter().collect()
}

/// Opens a topic's existing service (no port) and reads who holds its ports.
struct ReadPorts<'a> {
    node: &'a Node<IpcService>,
    spec: &'a TopicSpec,
}

/// The [`PortIds`] of a port factory's dynamic config (a macro: the config's type names a
/// container family of iceoryx2's internal crate).
macro_rules! port_ids {
    ($config:expr) => {{
        let config = $config;
        let mut ids = PortIds::default();
        config.list_publishers(|publisher| {
            ids.publishers
                .push((publisher.node_id, publisher.max_slice_len));
            CallbackProgression::Continue
        });
        config.list_subscribers(|subscriber| {
            ids.subscribers.push(subscriber.node_id);
            CallbackProgression::Continue
        });
        ids
    }};
}

impl KindVisitor for ReadPorts<'_> {
    type Output = Result<PortIds, OpenError>;

    fn fixed<M: Message + ZeroCopySend>(self) -> Self::Output {
        let data = data_service::<M, ()>(self.node, self.spec, OpenMode::ExistingOnly)?;
        Ok(port_ids!(data.dynamic_config()))
    }

    fn slice<H: SliceHeader + ZeroCopySend>(self) -> Self::Output
    where
        H::Element: ZeroCopySend,
    {
        let data =
            slice_data_service::<H::Element, H>(self.node, self.spec, OpenMode::ExistingOnly)?;
        Ok(port_ids!(data.dynamic_config()))
    }
}
