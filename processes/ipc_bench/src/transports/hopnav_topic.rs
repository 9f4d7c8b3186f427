//! (a) hopnav topics: `SlicePublisher<ImageHeader>` → `SliceSubscriber`, woken by a WaitSet.

use std::borrow::Cow;
use std::time::Duration;

use hopnav_ipc::messages::ImageHeader;
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::stamp::monotonic_now_ns;
use hopnav_ipc::topics::TopicSpec;
use hopnav_ipc::transport::{SlicePublisher, SliceSubscriber};

use super::{AckListener, AckNotifier, SampleTiming, wait_for_wakeup, waitset};
use crate::BenchError;
use crate::peer::{PeerArgs, bench_header, pause, payload_byte, signal_ready};

fn topic(id: &str) -> TopicSpec {
    TopicSpec {
        name: Cow::Owned(format!("hopnav/bench/{id}/data")),
        history_size: 0,
        subscriber_buffer: 2,
        max_publishers: 1,
        max_subscribers: 1,
    }
}

pub(crate) fn publish(args: &PeerArgs) -> Result<(), BenchError> {
    let namespace = Namespace::new(&args.id).map_err(|e| BenchError::transport("namespace", e))?;
    let node = namespace
        .create_node("bench_pub")
        .map_err(|e| BenchError::transport("node", e))?;
    let mut publisher =
        SlicePublisher::<ImageHeader>::open(&node, &topic(&args.id), args.size_bytes)
            .map_err(|e| BenchError::transport("publisher", e))?;
    let ack = AckListener::open(&node, &args.id)?;
    for index in 0..args.total_messages() {
        let fill_started_ns = monotonic_now_ns();
        publisher
            .send_from_fn(
                args.size_bytes,
                |header| {
                    *header = bench_header(args.size_bytes, index);
                    header.fill_time_ns = monotonic_now_ns().saturating_sub(fill_started_ns);
                },
                |byte| payload_byte(index, byte),
            )
            .map_err(|e| BenchError::transport("send", e))?;
        ack.wait(Duration::from_secs(10))?;
        pause(args);
    }
    Ok(())
}

pub(crate) fn subscribe(args: &PeerArgs) -> Result<Vec<SampleTiming>, BenchError> {
    let namespace = Namespace::new(&args.id).map_err(|e| BenchError::transport("namespace", e))?;
    let node = namespace
        .create_node("bench_sub")
        .map_err(|e| BenchError::transport("node", e))?;
    let subscriber = SliceSubscriber::<ImageHeader>::open(&node, &topic(&args.id))
        .map_err(|e| BenchError::transport("subscriber", e))?;
    let ack = AckNotifier::open(&node, &args.id)?;
    let waitset = waitset()?;
    let _guard = waitset
        .attach_notification(subscriber.listener())
        .map_err(|e| BenchError::transport("attach", e))?;
    signal_ready();
    let mut timings = Vec::with_capacity(args.total_messages());
    while timings.len() < args.total_messages() {
        wait_for_wakeup(&waitset)?;
        subscriber.clear_events();
        while let Some(sample) = subscriber
            .receive()
            .map_err(|e| BenchError::transport("receive", e))?
        {
            let received_ns = monotonic_now_ns();
            let index = sample.header().stamp.frame_index;
            timings.push(SampleTiming::of_image(sample.header(), received_ns));
            crate::peer::check_payload(index, sample.elements())?;
            drop(sample);
            ack.ack()?;
        }
        if subscriber.rejected().total() > 0 {
            return Err(BenchError::Transport("subscriber rejected a sample".into()));
        }
    }
    Ok(timings)
}
