//! One side of one measurement, run as its own process (`hopnav bench ipc-peer …`).

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use hopnav_ipc::messages::{CameraIntrinsics, ImageHeader, PixelFormat};

use crate::BenchError;
use crate::transports::{SampleTiming, Transport, hopnav_topic, raw_iceoryx2, unix_socket};

/// Publisher or subscriber.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Writes and sends.
    Publisher,
    /// Receives, stamps, acknowledges, and prints the timings as JSON.
    Subscriber,
}

/// Everything a peer needs to know.
#[derive(Debug, Clone)]
pub struct PeerArgs {
    /// Which side.
    pub role: Role,
    /// Which transport.
    pub transport: Transport,
    /// Payload bytes per message.
    pub size_bytes: usize,
    /// Measured messages.
    pub samples: usize,
    /// Unmeasured messages first (page faults, connection set-up).
    pub warmup: usize,
    /// iceoryx2 namespace / run id shared by the pair.
    pub id: String,
    /// Socket path for the Unix socket transport.
    pub socket_path: PathBuf,
    /// Pause between messages, so the subscriber is asleep when the next one comes.
    pub gap: Duration,
}

impl PeerArgs {
    pub(crate) fn total_messages(&self) -> usize {
        self.warmup + self.samples
    }
}

/// Runs one peer. The subscriber prints `ready` when it can receive and, at the end, one
/// JSON line with the measured timings.
pub fn run_peer(args: &PeerArgs) -> Result<(), BenchError> {
    match args.role {
        Role::Publisher => match args.transport {
            Transport::Hopnav => hopnav_topic::publish(args),
            Transport::RawEvent => raw_iceoryx2::publish(args, true),
            Transport::RawPolling => raw_iceoryx2::publish(args, false),
            Transport::UnixSocketBincode => unix_socket::publish(args),
        },
        Role::Subscriber => {
            let timings = match args.transport {
                Transport::Hopnav => hopnav_topic::subscribe(args)?,
                Transport::RawEvent => raw_iceoryx2::subscribe(args, false)?,
                Transport::RawPolling => raw_iceoryx2::subscribe(args, true)?,
                Transport::UnixSocketBincode => unix_socket::subscribe(args)?,
            };
            let measured: Vec<SampleTiming> = timings.into_iter().skip(args.warmup).collect();
            let line = serde_json::to_string(&measured)
                .map_err(|error| BenchError::transport("encode results", error))?;
            println!("{line}");
            Ok(())
        }
    }
}

pub(crate) fn signal_ready() {
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(stdout, "ready");
    let _ = stdout.flush();
}

pub(crate) fn pause(args: &PeerArgs) {
    if !args.gap.is_zero() {
        std::thread::sleep(args.gap);
    }
}

/// Byte `byte_index` of message `index`: every message differs, so a stale buffer shows.
#[inline]
pub(crate) fn payload_byte(index: usize, byte_index: usize) -> u8 {
    (byte_index as u8).wrapping_mul(31) ^ (index as u8)
}

/// Spot-checks first, middle and last byte (after the receipt stamp, outside the timing).
pub(crate) fn check_payload(index: u64, payload: &[u8]) -> Result<(), BenchError> {
    let len = payload.len();
    for byte_index in [0, len / 2, len.saturating_sub(1)] {
        if len > 0 && payload[byte_index] != payload_byte(index as usize, byte_index) {
            return Err(BenchError::Transport(format!(
                "message {index}: byte {byte_index} does not match what was sent"
            )));
        }
    }
    Ok(())
}

pub(crate) fn bench_header(size_bytes: usize, index: usize) -> ImageHeader {
    let mut header = ImageHeader {
        intrinsics: CameraIntrinsics::default(),
        width_px: size_bytes as u32,
        height_px: 1,
        stride_bytes: size_bytes as u32,
        format: PixelFormat::Mono8.code(),
        view_count: 1,
        ..ImageHeader::default()
    };
    header.stamp.frame_index = index as u64;
    header
}
