//! Any bytes given to the recording reader (`hopnav recording info`) give a summary or an
//! error that names the problem, without panicking.
#![no_main]

use hopnav_recorder::recording::inspect::{Depth, inspect};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for depth in [Depth::Summary, Depth::EveryMessage] {
        match inspect(data, depth) {
            Ok(info) => {
                let _ = info.duration_s();
            }
            Err(error) => {
                let _ = error.to_string();
            }
        }
    }
});
