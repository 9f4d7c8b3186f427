//! `hopnav`: the one executable. The supervisor re-executes it as `hopnav run <process>` for
//! every child, so all processes share one build and one message layout.

mod bench_cmd;
mod bench_hogs;
mod bench_realtime;
mod chaos_cmd;
mod compare_cmd;
mod compare_expect;
mod compare_launch;
mod compare_pair;
mod compare_quality;
mod compare_rows;
mod compare_table;
mod compare_variant;
mod compare_verdict;
mod defaults_cmd;
mod eval_cmd;
mod eval_traversability_cmd;
mod eval_vo_cases_cmd;
mod jumper_clouds_cmd;
mod launch_cmd;
mod plan_cmd;
mod recording_cmd;
mod registry;
mod rover_vo_cmd;
mod run_cmd;
mod setup;
mod text_table;
mod top_cmd;
mod top_table;
mod topic_bw;
mod topic_cmd;
mod topic_echo;
mod topic_hz;
mod topic_window;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Cooperative Mars exploration runtime: a jumping scout and a ground rover as separate
/// processes over iceoryx2 zero-copy shared memory, under a 10 fps supervisor.
#[derive(Debug, Parser)]
#[command(name = "hopnav", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Launch the process graph under the supervisor and write a run report.
    Launch(launch_cmd::LaunchArgs),
    /// Run one process of the graph (the supervisor starts these; not for direct use).
    Run(run_cmd::RunArgs),
    /// Benchmarks.
    #[command(subcommand)]
    Bench(bench_cmd::BenchCommand),
    /// D* Lite on MovingAI maps: solve scenarios, or reveal the map as the agent moves and
    /// compare with repeated A* (--dynamic R).
    Plan(plan_cmd::PlanArgs),
    /// Cooperative vs rover-only missions over N seeded terrains (the paper's comparison):
    /// success, executed path, replans, expansions; CSV, JSON and a Fig.-6 map.
    Compare(compare_cmd::CompareArgs),
    /// Random faults over N launches: injected, detected and recovered faults, recovery
    /// times, mission outcome, leaked shared-memory files.
    Chaos(chaos_cmd::ChaosArgs),
    /// Accuracy evaluations against ground truth.
    #[command(subcommand)]
    Eval(eval_cmd::EvalCommand),
    /// Print the whole default configuration (the embedded file merged over every process
    /// library's defaults): every key a config file may override, with its value.
    Defaults(defaults_cmd::DefaultsArgs),
    /// Look at the topics of a running launch: list them with their types, processes and
    /// sizes, measure one's rate or bandwidth, or print its samples (`--run ID` when several launches run).
    #[command(subcommand)]
    Topic(topic_cmd::TopicCommand),
    /// The processes of a running launch, live: CPU, memory, frame time p50/p99 against
    /// each one's budget, budget misses and restarts (`--run ID` when several launches run).
    Top(top_cmd::TopArgs),
    /// Look into a recording (`launch --record FILE.mcap`): check it and list its channels,
    /// message counts, time span, run id and commit.
    #[command(subcommand)]
    Recording(recording_cmd::RecordingCommand),
}

/// Exit code for a bad configuration or usage, as documented in the README.
pub const EXIT_CONFIG: u8 = 2;
/// Exit code after SIGINT or SIGTERM (128 + SIGINT, as shells report Ctrl-C).
pub const EXIT_INTERRUPTED: u8 = 130;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Launch(args) => launch_cmd::run(args),
        Command::Run(args) => run_cmd::run(args),
        Command::Bench(command) => bench_cmd::run(command),
        Command::Eval(command) => eval_cmd::run(command),
        Command::Plan(args) => plan_cmd::run(args),
        Command::Compare(args) => compare_cmd::run(args),
        Command::Chaos(args) => chaos_cmd::run(args),
        Command::Defaults(args) => defaults_cmd::run(args),
        Command::Topic(command) => topic_cmd::run(command),
        Command::Top(args) => top_cmd::run(&args),
        Command::Recording(command) => recording_cmd::run(command),
    }
}
