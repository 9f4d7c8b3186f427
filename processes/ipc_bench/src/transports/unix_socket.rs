//! (c) The copying baseline: the same message bincode-serialized (hopnav's codec module)
//! over a Unix domain socket, length-prefixed, deserialized on the other side.

use std::io::{Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::time::Duration;

use hopnav_ipc::codec;
use hopnav_ipc::stamp::monotonic_now_ns;
use serde::{Deserialize, Serialize};

use super::SampleTiming;
use crate::BenchError;
use crate::peer::{PeerArgs, pause, payload_byte, signal_ready};

/// What travels: a header and the payload as a byte buffer (serde_bytes: one memcpy, the
/// fair way to serialize bytes, not one call per byte).
#[derive(Serialize, Deserialize)]
struct Message {
    index: u64,
    fill_ns: u64,
    publish_stamp_ns: u64,
    #[serde(with = "serde_bytes")]
    payload: Vec<u8>,
}

fn io(context: &'static str) -> impl Fn(std::io::Error) -> BenchError {
    move |error| BenchError::transport(context, error)
}

pub(crate) fn publish(args: &PeerArgs) -> Result<(), BenchError> {
    let mut stream = UnixStream::connect(&args.socket_path).map_err(io("connect"))?;
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .map_err(io("timeout"))?;
    let mut message = Message {
        index: 0,
        fill_ns: 0,
        publish_stamp_ns: 0,
        payload: vec![0; args.size_bytes],
    };
    let mut buffer = Vec::with_capacity(args.size_bytes + 64);
    let mut ack = [0_u8; 1];
    for index in 0..args.total_messages() {
        let fill_started_ns = monotonic_now_ns();
        for (byte_index, byte) in message.payload.iter_mut().enumerate() {
            *byte = payload_byte(index, byte_index);
        }
        message.index = index as u64;
        message.fill_ns = monotonic_now_ns().saturating_sub(fill_started_ns);
        message.publish_stamp_ns = monotonic_now_ns();
        codec::encode_into(&message, &mut buffer)
            .map_err(|e| BenchError::transport("encode", e))?;
        stream
            .write_all(&(buffer.len() as u64).to_le_bytes())
            .and_then(|()| stream.write_all(&buffer))
            .map_err(io("write"))?;
        stream.read_exact(&mut ack).map_err(io("ack"))?;
        pause(args);
    }
    Ok(())
}

pub(crate) fn subscribe(args: &PeerArgs) -> Result<Vec<SampleTiming>, BenchError> {
    let _ = std::fs::remove_file(&args.socket_path);
    let listener = UnixListener::bind(&args.socket_path).map_err(io("bind"))?;
    signal_ready();
    let (mut stream, _) = listener.accept().map_err(io("accept"))?;
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .map_err(io("timeout"))?;
    let mut timings = Vec::with_capacity(args.total_messages());
    let mut buffer = Vec::new();
    let mut length = [0_u8; 8];
    while timings.len() < args.total_messages() {
        stream.read_exact(&mut length).map_err(io("read length"))?;
        let length = u64::from_le_bytes(length) as usize;
        if length > codec::MAX_DECODE_BYTES {
            return Err(BenchError::Transport(format!(
                "frame of {length} bytes is too large"
            )));
        }
        buffer.resize(length, 0);
        stream.read_exact(&mut buffer).map_err(io("read frame"))?;
        let message: Message =
            codec::decode(&buffer).map_err(|e| BenchError::transport("decode", e))?;
        let received_ns = monotonic_now_ns();
        timings.push(SampleTiming::new(
            message.fill_ns,
            message.publish_stamp_ns,
            received_ns,
        ));
        crate::peer::check_payload(message.index, &message.payload)?;
        stream.write_all(&[1]).map_err(io("ack"))?;
    }
    let _ = std::fs::remove_file(&args.socket_path);
    Ok(timings)
}
