//! Any bytes given to the codec decode to a value or an error, without panicking or
//! allocating beyond the codec's limit.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../ipc/tests/support/framed.rs"]
mod framed;

use framed::{Framed, Kind};

fuzz_target!(|data: &[u8]| {
    use hopnav_ipc::codec::decode;
    let _ = decode::<Framed>(data);
    let _ = decode::<Vec<String>>(data);
    let _ = decode::<(u8, Kind, std::collections::BTreeMap<u16, Vec<u8>>)>(data);
});
