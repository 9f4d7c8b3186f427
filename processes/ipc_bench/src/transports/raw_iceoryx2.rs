//! (b) iceoryx2 with no hopnav layer: the floors. Event-driven (WaitSet on a listener) or
//! busy-polling `receive`.

use std::time::{Duration, Instant};

use hopnav_ipc::IpcService;
use hopnav_ipc::messages::ImageHeader;
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::stamp::monotonic_now_ns;
use iceoryx2::node::Node;
use iceoryx2::prelude::{AllocationStrategy, ServiceName};
use iceoryx2::service::port_factory::{event, publish_subscribe};

use super::{AckListener, AckNotifier, SampleTiming, wait_for_wakeup, waitset};
use crate::BenchError;
use crate::peer::{PeerArgs, bench_header, pause, payload_byte, signal_ready};

fn service_name(id: &str) -> Result<ServiceName, BenchError> {
    ServiceName::new(&format!("raw/bench/{id}/data")).map_err(|e| BenchError::transport("name", e))
}

/// The node and the two raw services (image slices with a header, and their events) that
/// both peers open identically.
struct RawEndpoint {
    node: Node<IpcService>,
    data: publish_subscribe::PortFactory<IpcService, [u8], ImageHeader>,
    events: event::PortFactory<IpcService>,
}

fn open_endpoint(args: &PeerArgs, node_name: &str) -> Result<RawEndpoint, BenchError> {
    let namespace = Namespace::new(&args.id).map_err(|e| BenchError::transport("namespace", e))?;
    let node = namespace
        .create_node(node_name)
        .map_err(|e| BenchError::transport("node", e))?;
    let name = service_name(&args.id)?;
    let data = node
        .service_builder(&name)
        .publish_subscribe::<[u8]>()
        .user_header::<ImageHeader>()
        .open_or_create()
        .map_err(|e| BenchError::transport("service", e))?;
    let events = node
        .service_builder(&name)
        .event()
        .open_or_create()
        .map_err(|e| BenchError::transport("event service", e))?;
    Ok(RawEndpoint { node, data, events })
}

pub(crate) fn publish(args: &PeerArgs, notify: bool) -> Result<(), BenchError> {
    let RawEndpoint { node, data, events } = open_endpoint(args, "raw_pub")?;
    let publisher = data
        .publisher_builder()
        .initial_max_slice_len(args.size_bytes)
        .allocation_strategy(AllocationStrategy::Static)
        .create()
        .map_err(|e| BenchError::transport("publisher", e))?;
    let notifier = events
        .notifier_builder()
        .create()
        .map_err(|e| BenchError::transport("notifier", e))?;
    let ack = AckListener::open(&node, &args.id)?;
    for index in 0..args.total_messages() {
        let fill_started_ns = monotonic_now_ns();
        let sample = publisher
            .loan_slice_uninit(args.size_bytes)
            .map_err(|e| BenchError::transport("loan", e))?;
        let mut sample = sample.write_from_fn(|byte| payload_byte(index, byte));
        let header = sample.user_header_mut();
        *header = bench_header(args.size_bytes, index);
        header.fill_time_ns = monotonic_now_ns().saturating_sub(fill_started_ns);
        header.stamp.publish_stamp_ns = monotonic_now_ns();
        sample
            .send()
            .map_err(|e| BenchError::transport("send", e))?;
        if notify {
            notifier
                .notify()
                .map_err(|e| BenchError::transport("notify", e))?;
        }
        ack.wait(Duration::from_secs(10))?;
        pause(args);
    }
    Ok(())
}

pub(crate) fn subscribe(args: &PeerArgs, poll: bool) -> Result<Vec<SampleTiming>, BenchError> {
    let RawEndpoint { node, data, events } = open_endpoint(args, "raw_sub")?;
    let subscriber = data
        .subscriber_builder()
        .create()
        .map_err(|e| BenchError::transport("subscriber", e))?;
    let listener = events
        .listener_builder()
        .create()
        .map_err(|e| BenchError::transport("listener", e))?;
    let ack = AckNotifier::open(&node, &args.id)?;
    let waitset = waitset()?;
    let _guard = waitset
        .attach_notification(&listener)
        .map_err(|e| BenchError::transport("attach", e))?;
    signal_ready();
    let mut timings = Vec::with_capacity(args.total_messages());
    let mut last_progress = Instant::now();
    while timings.len() < args.total_messages() {
        if !poll {
            wait_for_wakeup(&waitset)?;
            let _ = listener.try_wait(|_| {});
        }
        match subscriber
            .receive()
            .map_err(|e| BenchError::transport("receive", e))?
        {
            Some(sample) => {
                let received_ns = monotonic_now_ns();
                timings.push(SampleTiming::of_image(sample.user_header(), received_ns));
                crate::peer::check_payload(
                    sample.user_header().stamp.frame_index,
                    sample.payload(),
                )?;
                drop(sample);
                ack.ack()?;
                last_progress = Instant::now();
            }
            None if poll => {
                std::hint::spin_loop();
                if last_progress.elapsed() > Duration::from_secs(10) {
                    return Err(BenchError::Transport("no sample for 10 s".into()));
                }
            }
            None => {}
        }
    }
    Ok(timings)
}
