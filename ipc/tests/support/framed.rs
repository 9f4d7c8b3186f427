//! Serde shapes whose decoding can fail, for feeding arbitrary bytes to the codec. Shared by
//! `ipc/tests/corrupt_samples.rs` and the `codec_decode` fuzz target (through `#[path]`), so
//! both probe the same shapes.

/// The benchmark's framed message, plus fields whose decoding can fail.
#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)] // Only decoded, never read.
pub struct Framed {
    index: u64,
    fill_ns: u64,
    publish_stamp_ns: u64,
    label: String,
    flag: bool,
    letter: char,
    kind: Option<Kind>,
    payload: Vec<u8>,
    nested: Vec<Vec<f64>>,
}

/// An enum of each variant kind.
#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)] // Only decoded, never read.
pub enum Kind {
    Unit,
    Tuple(u32, f32),
    Struct { x: i16 },
}
