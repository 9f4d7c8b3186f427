//! State relays: the supervisor keeps the last sample of a process's state topic on a topic
//! of its own, and hands it to that process when it restarts.
//!
//! iceoryx2 keeps a publisher's history in the publishing process: when a VO process dies, the
//! history of its pose topic dies with it, and its restarted incarnation cannot read its last
//! pose back. The supervisor outlives every child, so it subscribes to the state topic,
//! republishes each newest sample on a resume topic (history 1), and when the process reports
//! ready after a restart it updates the resume publisher's connections, which delivers that
//! history to the new subscriber before the process is released its first frame.

use hopnav_ipc::IpcService;
use hopnav_ipc::topics::TopicSpec;
use hopnav_ipc::transport::{OpenError, Publisher, Subscriber};
use hopnav_ipc::validate::Message;
use iceoryx2::node::Node;
use iceoryx2::prelude::ZeroCopySend;

/// One relay: `from` (the process's own topic) → `to` (its resume topic).
pub struct Relay<M: Message + ZeroCopySend> {
    from: Subscriber<M>,
    to: Publisher<M>,
}

impl<M: Message + ZeroCopySend> Relay<M> {
    /// Opens both ends.
    pub fn open(
        node: &Node<IpcService>,
        from: &TopicSpec,
        to: &TopicSpec,
    ) -> Result<Self, OpenError> {
        Ok(Self {
            from: Subscriber::open(node, from)?,
            to: Publisher::open(node, to)?,
        })
    }
}

/// A relay of any message type, for the frame loop.
pub trait StateRelay {
    /// Republishes the newest sample that arrived since the last call, if any.
    fn forward(&mut self);
    /// Forwards, then delivers the resume topic's history to subscribers that appeared (the
    /// restarted process).
    fn hand_over(&mut self);
}

impl<M: Message + ZeroCopySend> StateRelay for Relay<M> {
    fn forward(&mut self) {
        let mut newest = None;
        while let Ok(Some(sample)) = self.from.receive() {
            newest = Some(sample);
        }
        if let Some(sample) = newest
            && let Err(error) = self.to.send(sample)
        {
            eprintln!("\nstate relay: {error}");
        }
    }

    fn hand_over(&mut self) {
        self.forward();
        if let Err(error) = self.to.update_connections() {
            eprintln!("\nstate relay: {error}");
        }
    }
}

/// The relays of one process slot.
pub struct SlotRelays {
    /// Slot of the process whose state is relayed.
    pub slot: usize,
    /// Its relays.
    pub relays: Vec<Box<dyn StateRelay>>,
}

/// Opens a relay as a trait object; one that cannot open is reported and left out.
fn relay<M: Message + ZeroCopySend>(
    node: &Node<IpcService>,
    from: &TopicSpec,
    to: &TopicSpec,
) -> Option<Box<dyn StateRelay>> {
    Relay::<M>::open(node, from, to)
        .map(|relay| Box::new(relay) as Box<dyn StateRelay>)
        .map_err(|error| eprintln!("state relay: {error}"))
        .ok()
}

/// The relays of the graph's stateful processes that are enabled (`slot_of` maps a name to
/// its slot). A relay that cannot open is reported and left out: restarts then start fresh.
pub fn open_relays(
    node: &Node<IpcService>,
    slot_of: impl Fn(&str) -> Option<usize>,
) -> Vec<SlotRelays> {
    use hopnav_ipc::messages::{HopLaunch, PhysicsState, PoseEstimate};
    use hopnav_ipc::topics;
    // Opened only for an enabled process, in graph order.
    let relays_of = |name: &str, open: &dyn Fn() -> Vec<Option<Box<dyn StateRelay>>>| {
        slot_of(name).map(|slot| SlotRelays {
            slot,
            relays: open().into_iter().flatten().collect(),
        })
    };
    [
        relays_of("physics", &|| {
            vec![relay::<PhysicsState>(
                node,
                &topics::PHYSICS_STATE,
                &topics::RESUME_PHYSICS_STATE,
            )]
        }),
        relays_of("jumper_vo", &|| {
            vec![
                relay::<PoseEstimate>(node, &topics::JUMPER_POSE, &topics::RESUME_JUMPER_POSE),
                relay::<HopLaunch>(node, &topics::HOP_LAUNCH, &topics::RESUME_HOP_LAUNCH),
            ]
        }),
        relays_of("rover_vo", &|| {
            vec![relay::<PoseEstimate>(
                node,
                &topics::ROVER_POSE,
                &topics::RESUME_ROVER_POSE,
            )]
        }),
    ]
    .into_iter()
    .flatten()
    .collect()
}
