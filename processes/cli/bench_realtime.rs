//! `hopnav bench realtime`: the real-time launch on a loaded machine. It runs the mission for a
//! while as it is, then again with hogs beside it (threads that take the CPU or the memory
//! bandwidth), and reports frame misses, end-to-end latency and each stage's overruns, the
//! unloaded run beside the loaded one.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_supervisor::report::RunReport;
use hopnav_supervisor::{LaunchError, LaunchOptions, launch};
use serde::Serialize;

use crate::bench_hogs::{HogKind, Hogs};
use crate::{registry, setup};

#[derive(Debug, Args)]
pub struct RealtimeArgs {
    /// TOML file overriding the embedded defaults (the default cooperative mission runs
    /// without one); the launch is always real time.
    config: Option<PathBuf>,
    /// Hogs started beside the loaded launch (threads of this process, one per hog).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u64).range(1..=64))]
    hog: u64,
    /// What the hogs take: `cpu` (arithmetic in registers) or `memory` (a 64 MiB buffer
    /// streamed a cache line at a time, evicting the graph's working sets).
    #[arg(long, value_enum, default_value_t = HogKind::Cpu)]
    hog_kind: HogKind,
    /// Seconds each launch runs (real time: sim seconds are wall seconds).
    #[arg(long, default_value_t = 60.0)]
    duration: f64,
    /// Skip the unloaded launch (its figures are then not beside the loaded ones).
    #[arg(long)]
    no_baseline: bool,
    /// Folder for bench_realtime.json.
    #[arg(long, default_value = "runs/bench")]
    out: PathBuf,
}

/// One launch's figures.
#[derive(Debug, Clone, Serialize)]
struct LoadedRun {
    hogs: u64,
    hog_kind: &'static str,
    /// Rounds of work the hogs did during the launch (a hog that did none loaded nothing).
    hog_rounds: u64,
    run_id: String,
    frames_requested: u64,
    frames_completed: u64,
    frames_abandoned: u64,
    /// Frames some stage finished over its budget, summed over the stages.
    stage_misses: u64,
    /// `stage_misses` per requested frame, %.
    stage_miss_percent: f64,
    end_to_end_p50_ms: f64,
    end_to_end_p99_ms: f64,
    end_to_end_max_ms: f64,
    /// Frames whose end-to-end latency exceeded the frame period.
    end_to_end_misses: u64,
    /// Per process.
    stages: Vec<StageRun>,
}

/// One process of a launch.
#[derive(Debug, Clone, Serialize)]
struct StageRun {
    name: String,
    budget_misses: u64,
    cycle_p99_ms: f64,
    budget_ms: f64,
}

impl LoadedRun {
    fn of(report: &RunReport, hogs: u64, kind: HogKind) -> Self {
        let stage_misses = report.processes.iter().map(|p| p.budget_misses).sum();
        Self {
            hogs,
            hog_kind: if hogs == 0 { "-" } else { kind.name() },
            hog_rounds: 0,
            run_id: report.run_id.clone(),
            frames_requested: report.frames_requested,
            frames_completed: report.frames_completed,
            frames_abandoned: report.frames_abandoned,
            stage_misses,
            stage_miss_percent: 100.0 * stage_misses as f64 / report.frames_requested.max(1) as f64,
            end_to_end_p50_ms: report.end_to_end_latency.p50_ms,
            end_to_end_p99_ms: report.end_to_end_latency.p99_ms,
            end_to_end_max_ms: report.end_to_end_latency.max_ms,
            end_to_end_misses: report.end_to_end_misses,
            stages: report
                .processes
                .iter()
                .map(|p| StageRun {
                    name: p.name.clone(),
                    budget_misses: p.budget_misses,
                    cycle_p99_ms: p.cycle_time.p99_ms,
                    budget_ms: p.budget_ms,
                })
                .collect(),
        }
    }
}

pub fn run(args: RealtimeArgs) -> ExitCode {
    let mut config = match setup::load_checked_config(args.config.as_deref()) {
        Ok(config) => config,
        Err(code) => return code,
    };
    if !(args.duration.is_finite() && (1.0..=86_400.0).contains(&args.duration)) {
        eprintln!(
            "error: --duration must be within [1, 86400] seconds, got {}",
            args.duration
        );
        return ExitCode::from(crate::EXIT_CONFIG);
    }
    config.run.lockstep = false;
    config.run.frames = (args.duration * config.run.frame_rate_hz).ceil().max(1.0) as u64;
    let executable = match setup::own_executable("") {
        Ok(path) => path,
        Err(code) => return code,
    };
    let mut loads = Vec::new();
    if !args.no_baseline {
        loads.push(0);
    }
    loads.push(args.hog);
    let mut runs = Vec::new();
    for hogs in loads {
        eprintln!(
            "real-time launch for {:.0} s with {hogs} {} hog(s) …",
            args.duration,
            args.hog_kind.name()
        );
        let started = match Hogs::start(hogs as usize, args.hog_kind) {
            Ok(started) => started,
            Err(error) => {
                eprintln!("error: cannot start the hogs: {error}");
                return ExitCode::FAILURE;
            }
        };
        let options = LaunchOptions {
            config: config.clone(),
            executable: executable.clone(),
            known_processes: registry::names(),
            run_id: None,
            show_status: false,
            evaluator: None,
        };
        let outcome = launch(options);
        let hog_rounds = started.rounds();
        drop(started);
        match outcome {
            Err(LaunchError::Interrupted) => return ExitCode::from(crate::EXIT_INTERRUPTED),
            Err(error) => {
                eprintln!("error: the launch failed: {error}");
                return ExitCode::FAILURE;
            }
            Ok(outcome) => {
                let mut run = LoadedRun::of(&outcome.report, hogs, args.hog_kind);
                run.hog_rounds = hog_rounds;
                runs.push(run);
            }
        }
    }
    print_table(&runs);
    write_json(&args, &runs)
}

fn print_table(runs: &[LoadedRun]) {
    println!(
        "\n{:>6} {:>7} {:>8} {:>10} {:>13} {:>11} {:>11} {:>11} {:>10}",
        "hogs",
        "kind",
        "frames",
        "abandoned",
        "stage misses",
        "e2e p50 ms",
        "e2e p99 ms",
        "e2e max ms",
        "e2e misses"
    );
    for run in runs {
        println!(
            "{:>6} {:>7} {:>8} {:>10} {:>6} ({:.2} %) {:>11.1} {:>11.1} {:>11.1} {:>10}",
            run.hogs,
            run.hog_kind,
            run.frames_completed,
            run.frames_abandoned,
            run.stage_misses,
            run.stage_miss_percent,
            run.end_to_end_p50_ms,
            run.end_to_end_p99_ms,
            run.end_to_end_max_ms,
            run.end_to_end_misses
        );
    }
    if let [baseline, loaded] = runs {
        println!(
            "end-to-end p99 loaded / unloaded: {:.2}",
            loaded.end_to_end_p99_ms / baseline.end_to_end_p99_ms.max(1e-9)
        );
    }
    if let Some(loaded) = runs.last() {
        println!(
            "\nstages with {} hog(s) ({} rounds of hog work): budget misses, cycle p99 against the budget",
            loaded.hogs, loaded.hog_rounds
        );
        for stage in &loaded.stages {
            println!(
                "  {:<12} {:>5} misses, p99 {:>6.2} ms of {:.0} ms",
                stage.name, stage.budget_misses, stage.cycle_p99_ms, stage.budget_ms
            );
        }
    }
}

fn write_json(args: &RealtimeArgs, runs: &[LoadedRun]) -> ExitCode {
    let path = args.out.join("bench_realtime.json");
    let written = std::fs::create_dir_all(&args.out)
        .and_then(|()| serde_json::to_string_pretty(runs).map_err(std::io::Error::other))
        .and_then(|text| std::fs::write(&path, text));
    match written {
        Ok(()) => {
            println!("results: {}", path.display());
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: cannot write {}: {error}", path.display());
            ExitCode::FAILURE
        }
    }
}
