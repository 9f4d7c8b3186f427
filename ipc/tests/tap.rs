//! The tools' extra subscriber (`Subscriber::open_tap`): it opens only topics that exist,
//! takes no history and leaves a subscriber slot free for the graph.

use std::borrow::Cow;

use hopnav_ipc::messages::Heartbeat;
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::topics::TopicSpec;
use hopnav_ipc::transport::{OpenError, Publisher, Subscriber};

/// A namespace of its own that removes its files when the test ends.
struct TestNamespace(Namespace);

impl Drop for TestNamespace {
    fn drop(&mut self) {
        self.0.remove_files_if_unused();
    }
}

fn namespace(test: &str) -> TestNamespace {
    TestNamespace(Namespace::new(&format!("t{}-{test}", std::process::id())).expect("namespace"))
}

/// A topic with history 1 and three subscriber slots.
fn small_topic() -> TopicSpec {
    TopicSpec {
        name: Cow::Borrowed("test/tap"),
        history_size: 1,
        subscriber_buffer: 4,
        max_publishers: 1,
        max_subscribers: 3,
    }
}

#[test]
fn a_tap_never_creates_a_topic() {
    let namespace = namespace("tap-missing");
    let node = namespace.0.create_node("test").expect("node");
    let tapped = Subscriber::<Heartbeat>::open_tap(&node, &small_topic());
    assert!(
        matches!(tapped, Err(OpenError::NoSuchTopic(ref name)) if name == "test/tap"),
        "{tapped:?}"
    );
    // Nothing was created: a second look finds no topic either.
    assert!(matches!(
        Subscriber::<Heartbeat>::open_tap(&node, &small_topic()),
        Err(OpenError::NoSuchTopic(_))
    ));
}

#[test]
fn a_tap_takes_no_history_and_receives_what_follows() {
    let namespace = namespace("tap-history");
    let node = namespace.0.create_node("test").expect("node");
    let mut publisher = Publisher::<Heartbeat>::open(&node, &small_topic()).expect("pub");
    publisher
        .send_with(|heartbeat| heartbeat.stamp.frame_index = 1)
        .expect("send");
    let tap = Subscriber::<Heartbeat>::open_tap(&node, &small_topic()).expect("tap");
    publisher
        .send_with(|heartbeat| heartbeat.stamp.frame_index = 2)
        .expect("send");
    let received: Vec<u64> = std::iter::from_fn(|| tap.receive().expect("receive"))
        .map(|heartbeat| heartbeat.stamp.frame_index)
        .collect();
    assert_eq!(received, [2]);
}

#[test]
fn a_tap_leaves_a_slot_for_the_graph_and_says_so() {
    let namespace = namespace("tap-slots");
    let node = namespace.0.create_node("test").expect("node");
    let _publisher = Publisher::<Heartbeat>::open(&node, &small_topic()).expect("pub");
    let _consumer = Subscriber::<Heartbeat>::open(&node, &small_topic()).expect("consumer");
    // 1 of 3 in use: a tap may take one and leave one.
    let _tap = Subscriber::<Heartbeat>::open_tap(&node, &small_topic()).expect("tap");
    let second = Subscriber::<Heartbeat>::open_tap(&node, &small_topic());
    match second {
        Err(error @ OpenError::NoFreeSubscriberSlot { .. }) => {
            let text = error.to_string();
            assert!(text.contains("2 of 3 in use"), "{text}");
        }
        other => panic!("expected no free slot, got {other:?}"),
    }
    // The graph's own consumer still finds its slot.
    Subscriber::<Heartbeat>::open(&node, &small_topic()).expect("a restarted consumer");
}
