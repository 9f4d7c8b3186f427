//! The transports under test. Each has a publisher and a subscriber half; both halves run in
//! their own process.

mod ack;
pub(crate) mod hopnav_topic;
pub(crate) mod raw_iceoryx2;
pub(crate) mod unix_socket;
mod wake;

pub(crate) use ack::{AckListener, AckNotifier};
pub(crate) use wake::{wait_for_wakeup, waitset};

/// A transport to measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transport {
    /// hopnav's typed topics, subscriber woken through a WaitSet.
    Hopnav,
    /// iceoryx2 with no hopnav layer, subscriber woken through a WaitSet (the floor for a).
    RawEvent,
    /// iceoryx2 with no hopnav layer, subscriber spinning on `receive` (the absolute floor).
    RawPolling,
    /// The copying baseline: bincode-serialized over a Unix domain socket.
    UnixSocketBincode,
}

impl Transport {
    /// All transports in report order.
    pub const ALL: [Transport; 4] = [
        Transport::Hopnav,
        Transport::RawEvent,
        Transport::RawPolling,
        Transport::UnixSocketBincode,
    ];

    /// Stable name used on the command line and in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Transport::Hopnav => "hopnav-event",
            Transport::RawEvent => "iceoryx2-event",
            Transport::RawPolling => "iceoryx2-polling",
            Transport::UnixSocketBincode => "uds-bincode",
        }
    }

    /// The transport with the given [`Self::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|transport| transport.name() == name)
    }
}

/// One received message's timings.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub struct SampleTiming {
    /// Publisher: time to write the whole payload, ns.
    pub fill_ns: u64,
    /// Publish stamp to receipt, ns.
    pub transport_ns: u64,
}

impl SampleTiming {
    /// The timings of a message filled in `fill_ns`, stamped at `publish_stamp_ns` and received
    /// at `received_ns`.
    pub(crate) fn new(fill_ns: u64, publish_stamp_ns: u64, received_ns: u64) -> Self {
        Self {
            fill_ns,
            transport_ns: received_ns.saturating_sub(publish_stamp_ns),
        }
    }

    /// The timings of a benchmark image received at `received_ns`, from its header.
    pub(crate) fn of_image(header: &hopnav_ipc::messages::ImageHeader, received_ns: u64) -> Self {
        Self::new(
            header.fill_time_ns,
            header.stamp.publish_stamp_ns,
            received_ns,
        )
    }
}
