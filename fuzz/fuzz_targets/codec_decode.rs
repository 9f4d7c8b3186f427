//! Any bytes given to the codec decode to a value or an error, without panicking or
//! allocating beyond the codec's limit.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// The benchmark's framed message, plus fields whose decoding can fail.
#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)] // Only decoded.
struct Framed {
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

#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)] // Only decoded.
enum Kind {
    Unit,
    Tuple(u32, f32),
    Struct { x: i16 },
}

fuzz_target!(|data: &[u8]| {
    use hopnav_ipc::codec::decode;
    let _ = decode::<Framed>(data);
    let _ = decode::<Vec<String>>(data);
    let _ = decode::<(u8, Kind, std::collections::BTreeMap<u16, Vec<u8>>)>(data);
});
