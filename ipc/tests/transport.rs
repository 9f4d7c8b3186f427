//! Round trips through real iceoryx2 shared memory, each test in its own namespace.

use hopnav_ipc::IpcService;
use hopnav_ipc::messages::{
    CameraIntrinsics, Heartbeat, ImageHeader, PixelFormat, ProcessState, Robot,
};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::topics::{self, TopicSpec};
use hopnav_ipc::transport::{Publisher, SendError, SlicePublisher, SliceSubscriber, Subscriber};
use iceoryx2::node::Node;

/// A namespace of its own that removes its files when the test ends.
struct TestNamespace(Namespace);

impl Drop for TestNamespace {
    fn drop(&mut self) {
        self.0.remove_files_if_unused();
    }
}

impl std::ops::Deref for TestNamespace {
    type Target = Namespace;
    fn deref(&self) -> &Namespace {
        &self.0
    }
}

/// A namespace of the test's own and a node in it (declare the namespace first, so the node
/// goes before the namespace removes its files).
fn namespace_and_node(test: &str) -> (TestNamespace, Node<IpcService>) {
    let namespace = TestNamespace(
        Namespace::new(&format!("t{}-{test}", std::process::id())).expect("namespace"),
    );
    let node = namespace.create_node("test").expect("node");
    (namespace, node)
}

type HeartbeatSub = Subscriber<Heartbeat>;
type HeartbeatPub = Publisher<Heartbeat>;

/// A heartbeat subscriber and publisher on `node`, subscriber first.
fn heartbeat_ports(node: &Node<IpcService>) -> (HeartbeatSub, HeartbeatPub) {
    let subscriber = Subscriber::open(node, &topics::HEARTBEAT).expect("sub");
    let publisher = Publisher::open(node, &topics::HEARTBEAT).expect("pub");
    (subscriber, publisher)
}

/// Every heartbeat waiting for `subscriber`.
fn receive_all(subscriber: &Subscriber<Heartbeat>) -> Vec<Heartbeat> {
    std::iter::from_fn(|| subscriber.receive().expect("receive")).collect()
}

#[path = "support/image_header.rs"]
mod image_header_fixture;

use image_header_fixture::image_header;

#[test]
fn fixed_messages_arrive_stamped_in_order() {
    let (_namespace, node) = namespace_and_node("fixed");
    let (subscriber, mut publisher) = heartbeat_ports(&node);
    for frame in 0..3 {
        publisher
            .send_with(|heartbeat| {
                heartbeat.stamp.frame_index = frame;
                heartbeat.state = ProcessState::Completed.code();
            })
            .expect("send");
    }
    let received = receive_all(&subscriber);
    assert_eq!(received.len(), 3);
    for (index, heartbeat) in received.iter().enumerate() {
        assert_eq!(heartbeat.stamp.frame_index, index as u64);
        assert_eq!(heartbeat.stamp.sequence, index as u64);
        assert!(heartbeat.stamp.publish_stamp_ns > 0);
    }
    assert_eq!(subscriber.rejected().total(), 0);
}

#[test]
fn corrupt_and_repeated_samples_are_rejected_and_counted() {
    let (_namespace, node) = namespace_and_node("corrupt");
    let (subscriber, mut publisher) = heartbeat_ports(&node);
    publisher
        .send_with(|heartbeat| heartbeat.state = 77)
        .expect("send");
    publisher.send_with(|_| {}).expect("send");
    publisher.continue_sequence_after(0); // replays sequence 1
    publisher.send_with(|_| {}).expect("send");
    let received = receive_all(&subscriber);
    assert_eq!(received.len(), 1, "only the valid, fresh sample passes");
    assert_eq!(subscriber.rejected().invalid, 1);
    assert_eq!(subscriber.rejected().stale, 1);
}

#[test]
fn image_slices_are_drawn_in_place_and_validated() {
    let (_namespace, node) = namespace_and_node("slice");
    let spec = TopicSpec {
        subscriber_buffer: 4,
        ..topics::PROBE_IMAGE
    };
    let subscriber = SliceSubscriber::<ImageHeader>::open(&node, &spec).expect("sub");
    let mut publisher = SlicePublisher::<ImageHeader>::open(&node, &spec, 64 * 64).expect("pub");
    publisher
        .send_from_fn(
            64 * 64,
            |header| *header = image_header(64, 64, 1),
            |i| i as u8,
        )
        .expect("send");
    publisher
        .send_with(32 * 32, |header, pixels| {
            *header = image_header(32, 32, 1);
            pixels[5] = 200;
            Ok::<(), String>(())
        })
        .expect("send");
    // A header that lies about its size: rejected by the subscriber, not a crash.
    publisher
        .send_from_fn(10, |header| *header = image_header(64, 64, 1), |_| 0)
        .expect("send");

    let first = subscriber.receive().expect("receive").expect("first image");
    assert_eq!(first.header().width_px, 64);
    assert_eq!(first.elements()[300], (300 % 256) as u8);
    drop(first);
    let second = subscriber
        .receive()
        .expect("receive")
        .expect("second image");
    assert_eq!(second.elements()[5], 200);
    assert_eq!(second.elements()[6], 0);
    drop(second);
    assert!(subscriber.receive().expect("receive").is_none());
    assert_eq!(subscriber.rejected().invalid, 1);
}

#[test]
fn oversized_and_refused_fills_are_clear_errors() {
    let (_namespace, node) = namespace_and_node("oversize");
    let mut publisher =
        SlicePublisher::<ImageHeader>::open(&node, &topics::PROBE_IMAGE, 16).expect("pub");
    let error = publisher
        .send_from_fn(17, |_| {}, |_| 0)
        .expect_err("too long");
    assert!(matches!(
        error,
        SendError::SliceTooLong {
            requested: 17,
            max: 16,
            ..
        }
    ));
    let error = publisher
        .send_with(4, |_, _| Err("renderer refused"))
        .expect_err("fill refused");
    assert!(error.to_string().contains("renderer refused"));
}

#[test]
fn late_subscriber_recovers_last_value_from_history() {
    let (_namespace, node) = namespace_and_node("history");
    let spec = topics::step("history_probe");
    let mut publisher =
        Publisher::<hopnav_ipc::messages::FrameTick>::open(&node, &spec).expect("pub");
    publisher
        .send_with(|tick| {
            tick.stamp.frame_index = 41;
            tick.command = hopnav_ipc::messages::FrameCommand::Step.code();
            tick.mode = hopnav_ipc::messages::ClockMode::Lockstep.code();
        })
        .expect("send");
    let subscriber =
        Subscriber::<hopnav_ipc::messages::FrameTick>::open(&node, &spec).expect("sub");
    publisher.update_connections().expect("connect");
    let last = subscriber
        .receive_latest()
        .expect("receive")
        .expect("history");
    assert_eq!(last.stamp.frame_index, 41);
}

#[test]
fn exhausted_shared_memory_is_a_clear_error_not_a_crash() {
    let (_namespace, node) = namespace_and_node("exhausted");
    let mut publisher =
        SlicePublisher::<ImageHeader>::open(&node, &topics::PROBE_IMAGE, 64).expect("pub");
    let subscriber =
        SliceSubscriber::<ImageHeader>::open(&node, &topics::PROBE_IMAGE).expect("sub");
    // A consumer that keeps every sample it receives pins shared memory. The static pools are
    // sized for the configured borrows, so either side may be the one refused: the publisher
    // cannot loan, or the subscriber may not borrow more. Both must be clear errors naming
    // the topic, and nothing may crash.
    let mut held = Vec::new();
    let header = image_header(8, 8, 1);
    let mut refusal = None;
    for _ in 0..64 {
        if let Err(error) = publisher.send_from_fn(64, |h| *h = header, |_| 7) {
            refusal = Some(error.to_string());
            break;
        }
        match subscriber.receive() {
            Ok(Some(sample)) => held.push(sample),
            Ok(None) => {}
            Err(error) => {
                refusal = Some(error.to_string());
                break;
            }
        }
    }
    let message = refusal.expect("holding every sample must hit a limit");
    assert!(message.contains("hopnav/probe_source/image"), "{message}");
    // Releasing the held samples makes room again on both sides.
    held.clear();
    publisher
        .send_from_fn(64, |h| *h = header, |_| 7)
        .expect("room again");
    while subscriber.receive().expect("receive again").is_some() {}
}
