//! `hopnav run <process>`: one child of the supervisor.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use hopnav_ipc::process_loop::{ProcessIdentity, StartMode};

use crate::registry;

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Process to run (one of the names in the config's [processes] table).
    process: String,
    /// Run id of the launch; selects the shared-memory namespace.
    #[arg(long)]
    run_id: String,
    /// Index of the process in the supervisor's table.
    #[arg(long, default_value_t = 0)]
    slot: u32,
    /// How often this slot was started before.
    #[arg(long, default_value_t = 0)]
    incarnation: u32,
    /// Resolved configuration file written by the supervisor.
    #[arg(long)]
    config: PathBuf,
    /// Heartbeat period while idle, milliseconds.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=60_000))]
    heartbeat_ms: u64,
    /// Warm standby: prepare, then wait for the supervisor's promotion line on stdin.
    #[arg(long)]
    standby: bool,
}

pub fn run(args: RunArgs) -> ExitCode {
    let Some(entry) = registry::find(&args.process) else {
        eprintln!(
            "error: unknown process {:?} (known: {})",
            args.process,
            registry::names().join(", ")
        );
        return ExitCode::from(crate::EXIT_CONFIG);
    };
    let identity = ProcessIdentity {
        name: args.process.clone(),
        run_id: args.run_id,
        slot: args.slot,
        incarnation: args.incarnation,
        heartbeat_period: Duration::from_millis(args.heartbeat_ms),
        config_path: args.config,
    };
    let mode = if args.standby {
        StartMode::Standby
    } else {
        StartMode::Cold
    };
    match entry(identity, mode) {
        Ok(_) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("[{}] error: {error}", args.process);
            ExitCode::FAILURE
        }
    }
}
