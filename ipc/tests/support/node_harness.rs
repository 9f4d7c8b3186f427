//! A process under test in the supervisor's place: frame ticks, the process context, and
//! the run directory with its config. Shared by the node crates' IPC tests (through
//! `#[path]`).

use std::path::{Path, PathBuf};
use std::time::Duration;

use hopnav_ipc::messages::{FrameTick, SampleStamp};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::process_loop::{ProcessContext, ProcessIdentity};

/// The 10 fps clock's period, nanoseconds.
pub const PERIOD_NS: u64 = 100_000_000;

/// The clock's tick of frame `frame_index`.
pub fn tick(frame_index: u64) -> FrameTick {
    FrameTick {
        stamp: SampleStamp {
            frame_index,
            sim_time_ns: frame_index * PERIOD_NS,
            ..SampleStamp::default()
        },
        ..FrameTick::default()
    }
}

/// The context of process `name` (incarnation `incarnation`) reading `run_dir/config.toml`.
pub fn context(
    namespace: &Namespace,
    run_dir: &Path,
    name: &str,
    incarnation: u32,
) -> ProcessContext {
    ProcessContext {
        node: namespace.create_node(name).expect("node"),
        identity: ProcessIdentity {
            name: name.into(),
            run_id: namespace.run_id().into(),
            slot: 0,
            incarnation,
            heartbeat_period: Duration::from_millis(100),
            config_path: run_dir.join("config.toml"),
        },
    }
}

/// A temporary run directory `run_id` holding the config `text` (defaults for `None`), as the
/// supervisor writes it.
pub fn run_dir_with_config(run_id: &str, text: Option<&str>) -> PathBuf {
    let run_dir = std::env::temp_dir().join(run_id);
    std::fs::create_dir_all(&run_dir).expect("run dir");
    let config = hopnav_config::load(text).expect("config");
    std::fs::write(
        run_dir.join("config.toml"),
        hopnav_config::to_toml(&config).expect("toml"),
    )
    .expect("write config");
    run_dir
}
