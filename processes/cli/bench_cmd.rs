//! `hopnav bench …`: benchmarks with their own harness (p50/p99/max, ratios to baselines
//! measured in the same run).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Subcommand};
use hopnav_ipc_bench::{BenchOptions, PeerArgs, Role, Transport, run_bench, run_peer};

use crate::setup;

#[derive(Debug, Subcommand)]
pub enum BenchCommand {
    /// One-way latency of 64 B … 4 MiB messages between two processes: hopnav topics,
    /// raw iceoryx2 (event-driven and busy-polling) and bincode over a Unix socket.
    Ipc(IpcArgs),
    /// Render time of one 320² jumper image of the default world from jumper-like poses
    /// (0.5–15 m above ground, looking down), on one core.
    Render(RenderArgs),
    /// Physics step time per 100 ms frame (10 substeps) on the default world with its rocks,
    /// the jumper hopping and the rover driving.
    Physics(PhysicsArgs),
    /// Jumper VO cost per frame (`process_frame`) at 320² with up to 1000 features, over the
    /// rendered Table 1 hop.
    Vo(VoBenchArgs),
    /// Rover stereo VO cost per 320×240 stereo frame over a rendered traverse (wall and
    /// thread-CPU p50/p99/max).
    RoverVo(crate::rover_vo_cmd::RoverVoBenchArgs),
    /// The real-time mission on a loaded machine: a launch as it is, then one with hogs
    /// beside it (CPU spinners or memory streamers); frame misses, end-to-end p50/p99 and
    /// each stage's overruns, side by side.
    Realtime(crate::bench_realtime::RealtimeArgs),
    /// One peer of `bench ipc` (started by it; not for direct use).
    #[command(hide = true)]
    IpcPeer(IpcPeerArgs),
}

#[derive(Debug, Args)]
pub struct IpcArgs {
    /// Fewer messages per point (300 instead of 3000): a minute instead of several.
    #[arg(long)]
    quick: bool,
    /// Measured messages per transport and size (overrides --quick).
    #[arg(long, value_parser = clap::value_parser!(u64).range(10..=1_000_000))]
    samples: Option<u64>,
    /// Folder for ipc_latency.csv, .json and .svg.
    #[arg(long, default_value = "runs/bench")]
    out: PathBuf,
    /// Pause between messages in microseconds, so the receiver is asleep when a message
    /// comes (what an event-driven 10 fps pipeline sees).
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(0..=1_000_000))]
    gap_us: u64,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Frames timed.
    #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    frames: u64,
    /// Renders per pose; the fastest counts (filters out preemption on a loaded machine).
    /// 1 = plain per-frame timing.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100))]
    best_of: u64,
}

#[derive(Debug, Args)]
pub struct PhysicsArgs {
    /// Frames timed.
    #[arg(long, default_value_t = 2000, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    frames: u32,
}

#[derive(Debug, Args)]
pub struct VoBenchArgs {
    /// Times the whole hop is processed.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=1000))]
    repeats: u64,
}

#[derive(Debug, Args)]
pub struct IpcPeerArgs {
    /// pub or sub.
    role: String,
    /// Transport name.
    transport: String,
    /// Payload bytes.
    size_bytes: usize,
    #[arg(long)]
    samples: usize,
    #[arg(long)]
    warmup: usize,
    #[arg(long)]
    id: String,
    #[arg(long)]
    socket: PathBuf,
    #[arg(long)]
    gap_us: u64,
}

pub fn run(command: BenchCommand) -> ExitCode {
    match command {
        BenchCommand::Ipc(args) => ipc(args),
        BenchCommand::IpcPeer(args) => ipc_peer(args),
        BenchCommand::Render(args) => render(args),
        BenchCommand::Physics(args) => physics(args),
        BenchCommand::Vo(args) => vo(args),
        BenchCommand::RoverVo(args) => crate::rover_vo_cmd::bench(args),
        BenchCommand::Realtime(args) => crate::bench_realtime::run(args),
    }
}

fn vo(args: VoBenchArgs) -> ExitCode {
    use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};
    eprintln!(
        "rendering the Table 1 hop, then timing the VO over it {} times …",
        args.repeats
    );
    let hop = match simulate_hop(&SimConfig::default()) {
        Ok(hop) => hop,
        Err(error) => {
            eprintln!("error: {error}");
            return ExitCode::FAILURE;
        }
    };
    // The same hop without the bundle adjustment, in the same run: its cost is the difference.
    let with_ba = hopnav_jumper_vo::config::JumperVoConfig::default();
    let without_ba = hopnav_jumper_vo::config::JumperVoConfig {
        bundle_adjustment: false,
        ..with_ba.clone()
    };
    let repeats = args.repeats as usize;
    let outcome = hopnav_jumper_vo::bench::bench_hop(&hop, &with_ba, repeats).and_then(|with| {
        hopnav_jumper_vo::bench::bench_hop(&hop, &without_ba, repeats)
            .map(|without| (with, without))
    });
    setup::report_outcome(outcome, |(with, without)| {
        println!(
            "jumper VO per frame, with the local bundle adjustment (target p99 <= 10 ms): {with}"
        );
        println!("jumper VO per frame, without it: {without}");
    })
}

fn physics(args: PhysicsArgs) -> ExitCode {
    let options = hopnav_physics::bench::PhysicsBenchConfig {
        frames: args.frames,
        ..Default::default()
    };
    eprintln!("stepping {} frames of the default world …", options.frames);
    setup::report_outcome(
        hopnav_physics::bench::run_physics_bench(&options),
        |report| println!("{report}"),
    )
}

fn render(args: RenderArgs) -> ExitCode {
    let options = hopnav_world::bench::RenderBenchOptions {
        frames: args.frames as usize,
        repeats_per_pose: args.best_of as usize,
        ..Default::default()
    };
    eprintln!(
        "rendering {} frames of 320x320 (best of {} per pose) …",
        options.frames, options.repeats_per_pose
    );
    setup::report_outcome(hopnav_world::bench::render_bench(&options), |report| {
        println!("{report}")
    })
}

fn ipc(args: IpcArgs) -> ExitCode {
    let executable = match setup::own_executable("") {
        Ok(path) => path,
        Err(code) => return code,
    };
    let samples = args
        .samples
        .map(|samples| samples as usize)
        .unwrap_or(if args.quick { 300 } else { 3000 });
    let options = BenchOptions {
        executable,
        samples,
        warmup: (samples / 10).clamp(10, 200),
        gap: Duration::from_micros(args.gap_us),
        transports: Transport::ALL.to_vec(),
        out_dir: args.out,
    };
    match run_bench(&options) {
        Ok(_) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("\nerror: {error}");
            ExitCode::FAILURE
        }
    }
}

fn ipc_peer(args: IpcPeerArgs) -> ExitCode {
    let role = match args.role.as_str() {
        "pub" => Role::Publisher,
        "sub" => Role::Subscriber,
        other => {
            eprintln!("error: role must be pub or sub, got {other:?}");
            return ExitCode::from(crate::EXIT_CONFIG);
        }
    };
    let Some(transport) = Transport::from_name(&args.transport) else {
        eprintln!("error: unknown transport {:?}", args.transport);
        return ExitCode::from(crate::EXIT_CONFIG);
    };
    let peer = PeerArgs {
        role,
        transport,
        size_bytes: args.size_bytes.max(1),
        samples: args.samples,
        warmup: args.warmup,
        id: args.id,
        socket_path: args.socket,
        gap: Duration::from_micros(args.gap_us),
    };
    match run_peer(&peer) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
