//! The harness's back channel: the subscriber acknowledges each message so the publisher
//! never sends into a queue. Not part of what is measured.

use std::time::Duration;

use hopnav_ipc::IpcService;
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::prelude::ServiceName;

use crate::BenchError;

fn ack_service(
    node: &Node<IpcService>,
    id: &str,
) -> Result<iceoryx2::service::port_factory::event::PortFactory<IpcService>, BenchError> {
    let name = ServiceName::new(&format!("hopnav/bench/{id}/ack"))
        .map_err(|error| BenchError::transport("ack service name", error))?;
    node.service_builder(&name)
        .event()
        .open_or_create()
        .map_err(|error| BenchError::transport("ack service", error))
}

/// Subscriber side: says "got it".
pub(crate) struct AckNotifier(Notifier<IpcService>);

impl AckNotifier {
    pub(crate) fn open(node: &Node<IpcService>, id: &str) -> Result<Self, BenchError> {
        let notifier = ack_service(node, id)?
            .notifier_builder()
            .create()
            .map_err(|error| BenchError::transport("ack notifier", error))?;
        Ok(Self(notifier))
    }

    pub(crate) fn ack(&self) -> Result<(), BenchError> {
        self.0
            .notify()
            .map(|_| ())
            .map_err(|error| BenchError::transport("ack notify", error))
    }
}

/// Publisher side: waits for "got it".
pub(crate) struct AckListener(Listener<IpcService>);

impl AckListener {
    pub(crate) fn open(node: &Node<IpcService>, id: &str) -> Result<Self, BenchError> {
        let listener = ack_service(node, id)?
            .listener_builder()
            .create()
            .map_err(|error| BenchError::transport("ack listener", error))?;
        Ok(Self(listener))
    }

    pub(crate) fn wait(&self, timeout: Duration) -> Result<(), BenchError> {
        let received = self
            .0
            .timed_wait(|_| {}, timeout)
            .map_err(|error| BenchError::transport("ack wait", error))?;
        if received == 0 {
            return Err(BenchError::Transport(format!(
                "no acknowledgement from the subscriber within {timeout:?}"
            )));
        }
        Ok(())
    }
}
