//! `hopnav chaos`: random faults over N launches. Each launch gets a few faults drawn from the
//! enabled processes and the chosen kinds; the table shows what was injected, detected and
//! recovered, how long recovery took, the mission outcome, and hopnav's shared-memory and
//! node files counted before and after.
//!
//! Before the faulted launches, the same launch runs once without faults: its mission (frames
//! to B, executed path) is the reference each faulted mission is judged against
//! ([`hopnav_eval::faulted_mission`]), and faults are drawn inside its frames, so they hit the
//! traverse rather than the time after B. Every launch stops at B.

use std::path::PathBuf;
use std::process::ExitCode;

mod table;

use clap::Args;
use hopnav_config::HopnavConfig;
use hopnav_eval::faulted_mission::{FaultedMission, MissionOutcome, judge};
use hopnav_supervisor::fault_injector::FaultRecord;
use hopnav_supervisor::{LaunchError, LaunchOptions, LaunchOutcome, launch};
use serde::Serialize;

use crate::{registry, setup};
use table::{print_missions, print_reference, print_table};

#[derive(Debug, Args)]
pub struct ChaosArgs {
    /// TOML file overriding the embedded defaults (the graph to torment).
    config: Option<PathBuf>,
    /// Launches to run.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    runs: u64,
    /// Seed of the fault draw (and of in-process drop/corrupt decisions).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Faults per launch.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=1000))]
    faults_per_run: u64,
    /// Fault kinds to draw from (comma-separated): kill, stall, hang, drop, corrupt, delay.
    /// A stall freezes a process (SIGSTOP) for less than a frame period, which it survives; a
    /// hang freezes it until the watchdog kills it.
    #[arg(
        long,
        default_value = "kill,stall,hang,drop,corrupt,delay",
        value_delimiter = ','
    )]
    kinds: Vec<String>,
    /// Frames per launch at most (lockstep; a launch stops when the rover reaches B). Missions
    /// are judged only if the unfaulted launch reaches B within this many frames (the default
    /// terrain's mission takes about 1140).
    #[arg(long, default_value_t = 1500, value_parser = clap::value_parser!(u64).range(20..=1_000_000))]
    frames: u64,
    /// Folder for the run folders and chaos.json.
    #[arg(long, default_value = "runs/chaos")]
    out: PathBuf,
}

#[derive(Debug, Clone, Serialize)]
struct ChaosRun {
    run: u64,
    outcome: String,
    mission: Option<String>,
    /// The mission against the unfaulted launch's.
    vs_unfaulted: Option<FaultedMission>,
    faults: Vec<FaultRecord>,
    hopnav_files_before: usize,
    hopnav_files_after: usize,
    leftover_files: usize,
    panics: usize,
}

impl ChaosRun {
    /// A run whose launch never got going (no report: no mission, faults or panics).
    /// The record of a launch that ran; `missions` pairs the unfaulted reference with this
    /// run's mission, when both ran one.
    fn of_launch(
        run: u64,
        outcome: &LaunchOutcome,
        missions: Option<(MissionOutcome, MissionOutcome)>,
        (before, after): (usize, usize),
    ) -> Self {
        let panics = count_panics(&outcome.report);
        let vs_unfaulted =
            missions.map(|(reference, mission)| judge(&reference, mission, &outcome.report.faults));
        ChaosRun {
            vs_unfaulted,
            run,
            outcome: outcome.report.outcome.clone(),
            mission: outcome.report.mission.as_ref().map(|mission| {
                if mission.goal_reached {
                    "goal reached".to_owned()
                } else {
                    format!(
                        "{} m to go",
                        hopnav_eval::MissionEvaluation::of(mission)
                            .final_distance_to_goal_m
                            .map_or("?".into(), |m| format!("{m:.1}"))
                    )
                }
            }),
            faults: outcome.report.faults.clone(),
            hopnav_files_before: before,
            hopnav_files_after: after,
            leftover_files: outcome.report.leftover_files,
            panics,
        }
    }

    fn without_launch(run: u64, outcome: String, before: usize, after: usize) -> Self {
        Self {
            run,
            outcome,
            mission: None,
            vs_unfaulted: None,
            faults: Vec::new(),
            hopnav_files_before: before,
            hopnav_files_after: after,
            leftover_files: 0,
            panics: 0,
        }
    }
}

/// SplitMix64: a tiny seeded generator for the fault draw.
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
}

/// The topic each process publishes its main output on (drop/corrupt targets).
fn main_topic(process: &str) -> Option<&'static str> {
    Some(match process {
        "physics" => "physics/body_states",
        "camera" => "camera/jumper",
        "jumper_vo" => "jumper_vo/pose",
        "rover_vo" => "rover_vo/pose",
        "mapper" => "mapper/cells",
        "planner" => "planner/drive",
        "probe_source" => "probe_source/image",
        _ => return None,
    })
}

fn draw_fault(
    draw: &mut Draw,
    kinds: &[String],
    processes: &[String],
    frames: u64,
    frame_period_ms: u64,
    watchdog_ms: u64,
) -> Option<String> {
    let kind = &kinds[draw.below(kinds.len() as u64) as usize];
    let process = &processes[draw.below(processes.len() as u64) as usize];
    // Leave the first and last tenth of the launch alone: start-up and shutdown are not the
    // subject here.
    let frame = frames / 10 + draw.below((frames * 8 / 10).max(1));
    Some(match kind.as_str() {
        "kill" => format!("kill:{process}@f{frame}"),
        // Silence counts from the last heartbeat (up to a period before the stop), so a stall
        // the watchdog lets pass is shorter than half a period.
        "stall" => format!(
            "stall:{process}@f{frame}+{}ms",
            10 + draw.below((frame_period_ms * 4 / 10).max(1))
        ),
        // Longer than any watchdog limit: only a kill ends it.
        "hang" => format!("stall:{process}@f{frame}+{}ms", watchdog_ms * 2),
        "drop" => format!("drop:{}@{}%", main_topic(process)?, 5 + draw.below(20)),
        "corrupt" => format!("corrupt:{}@{}%", main_topic(process)?, 5 + draw.below(20)),
        "delay" => format!("delay:{process}@{}ms", 5 + draw.below(40)),
        _ => return None,
    })
}

pub fn run(args: ChaosArgs) -> ExitCode {
    let base = match load_checked_config(&args) {
        Ok(config) => config,
        Err(code) => return code,
    };
    let processes: Vec<String> = base
        .processes
        .iter()
        .filter(|(_, process)| process.enabled)
        .map(|(name, _)| name.clone())
        .collect();
    let executable = match setup::own_executable("") {
        Ok(path) => path,
        Err(code) => return code,
    };
    let frame_period_ms = (base.run.frame_period_s() * 1e3) as u64;
    let watchdog_ms = base.watchdog.heartbeat_timeout_frames as u64 * frame_period_ms;
    let chaos_config = |faults_seed: u64| {
        let mut config = base.clone();
        config.run.lockstep = true;
        config.run.frames = args.frames;
        config.run.out_dir = args.out.display().to_string();
        config.mission.stop_on_goal = true;
        config.faults.seed = faults_seed;
        // Faults from the config file would make the reference faulted; each run sets its own.
        config.faults.inject.clear();
        config
    };
    let reference = match unfaulted_reference(&base, chaos_config(args.seed), &executable) {
        Ok(reference) => reference,
        Err(code) => return code,
    };
    print_reference(reference.as_ref(), args.frames);
    // Faults fall inside the traverse (its first and last tenth spared, see `draw_fault`).
    let fault_frames = reference
        .filter(|mission| mission.goal_reached)
        .map_or(args.frames, |mission| mission.frames.max(20));
    let mut draw = Draw(args.seed);
    let mut runs = Vec::new();
    let mut interrupted = false;
    for run in 0..args.runs {
        let mut config = chaos_config(args.seed.wrapping_add(run));
        let faults = draw_faults(
            &mut draw,
            &args,
            &processes,
            fault_frames,
            (frame_period_ms, watchdog_ms),
        );
        config.faults.inject = faults.clone();
        eprintln!("[{}/{}] {}", run + 1, args.runs, faults.join(" "));
        let before = hopnav_ipc::namespace::hopnav_files().len();
        let outcome = launch_once(config, &executable);
        let after = hopnav_ipc::namespace::hopnav_files().len();
        let record = match outcome {
            Err(LaunchError::Interrupted) => {
                interrupted = true;
                ChaosRun::without_launch(run, "interrupted (during start-up)".into(), before, after)
            }
            Ok(outcome) => {
                interrupted = outcome.interrupted;
                let mission = mission_outcome(&outcome, base.run.frame_period_s());
                ChaosRun::of_launch(run, &outcome, reference.zip(mission), (before, after))
            }
            Err(error) => {
                ChaosRun::without_launch(run, format!("launch failed: {error}"), before, after)
            }
        };
        runs.push(record);
        if interrupted {
            // Ctrl-C (or SIGTERM) stops the whole chaos run, not just this launch; the table
            // and chaos.json below keep what finished.
            break;
        }
    }
    print_table(&runs, base.run.frame_period_s());
    print_missions(&runs, reference.as_ref());
    finish(&runs, &args, interrupted)
}

/// The configuration (file or defaults) with its sections and `--kinds` checked; the exit
/// code to end with when it is unusable.
fn load_checked_config(args: &ChaosArgs) -> Result<HopnavConfig, ExitCode> {
    let base = setup::load_checked_config(args.config.as_deref())?;
    const KINDS: [&str; 6] = ["kill", "stall", "hang", "drop", "corrupt", "delay"];
    if let Some(bad) = args
        .kinds
        .iter()
        .find(|kind| !KINDS.contains(&kind.as_str()))
    {
        eprintln!(
            "error: --kinds: unknown kind {bad:?} (known: {})",
            KINDS.join(", ")
        );
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    }
    Ok(base)
}

/// The missions' reference: the same launch without faults, when the graph runs a mission
/// (when its planner runs, as the supervisor decides); the exit code to end with when it
/// was interrupted or failed.
fn unfaulted_reference(
    base: &HopnavConfig,
    config: HopnavConfig,
    executable: &std::path::Path,
) -> Result<Option<MissionOutcome>, ExitCode> {
    let runs_mission = base
        .processes
        .get("planner")
        .is_some_and(|planner| planner.enabled);
    if !runs_mission {
        return Ok(None);
    }
    eprintln!("[unfaulted] the same launch without faults, the missions' reference");
    match launch_once(config, executable) {
        Ok(outcome) if outcome.interrupted => {
            eprintln!("interrupted: stopped during the unfaulted launch, before any run");
            Err(ExitCode::from(crate::EXIT_INTERRUPTED))
        }
        Err(LaunchError::Interrupted) => {
            eprintln!("interrupted: stopped while the unfaulted launch started, before any run");
            Err(ExitCode::from(crate::EXIT_INTERRUPTED))
        }
        Ok(outcome) => Ok(mission_outcome(&outcome, base.run.frame_period_s())),
        Err(error) => {
            eprintln!("error: the unfaulted launch failed: {error}");
            Err(ExitCode::FAILURE)
        }
    }
}

/// Up to `--faults-per-run` faults for one run (100 draws at most).
fn draw_faults(
    draw: &mut Draw,
    args: &ChaosArgs,
    processes: &[String],
    fault_frames: u64,
    (frame_period_ms, watchdog_ms): (u64, u64),
) -> Vec<String> {
    let mut faults = Vec::new();
    let mut attempts = 0;
    while (faults.len() as u64) < args.faults_per_run && attempts < 100 {
        attempts += 1;
        if let Some(fault) = draw_fault(
            draw,
            &args.kinds,
            processes,
            fault_frames,
            frame_period_ms,
            watchdog_ms,
        ) {
            faults.push(fault);
        }
    }
    faults
}

/// Writes `chaos.json` and picks the exit code: interrupted, or success when every run
/// completed with no leftover files and no panics.
fn finish(runs: &[ChaosRun], args: &ChaosArgs, interrupted: bool) -> ExitCode {
    let path = args.out.join("chaos.json");
    let json = serde_json::to_string_pretty(&runs).unwrap_or_default();
    if let Err(error) =
        std::fs::create_dir_all(&args.out).and_then(|()| std::fs::write(&path, json))
    {
        eprintln!("error: cannot write {}: {error}", path.display());
        return ExitCode::FAILURE;
    }
    println!("details: {}", path.display());
    if interrupted {
        eprintln!(
            "interrupted: stopped after {} of {} runs",
            runs.len(),
            args.runs
        );
        return ExitCode::from(crate::EXIT_INTERRUPTED);
    }
    let clean = runs.iter().all(|run| {
        run.outcome.starts_with("completed") && run.leftover_files == 0 && run.panics == 0
    });
    if clean {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// One lockstep launch with the truth evaluator (the mission's scores in its report).
fn launch_once(
    config: HopnavConfig,
    executable: &std::path::Path,
) -> Result<LaunchOutcome, LaunchError> {
    launch(LaunchOptions {
        config,
        executable: executable.to_path_buf(),
        known_processes: registry::names(),
        run_id: None,
        show_status: false,
        evaluator: Some(std::sync::Arc::new(hopnav_eval::TruthEvaluator)),
    })
}

/// The launch's mission in frames and metres, if the graph ran one.
fn mission_outcome(outcome: &LaunchOutcome, frame_period_s: f64) -> Option<MissionOutcome> {
    let mission = outcome.report.mission.as_ref()?;
    Some(MissionOutcome {
        goal_reached: mission.goal_reached,
        frames: (mission.mission_time_s / frame_period_s).round().max(0.0) as u64,
        executed_path_m: mission.executed_path_m,
    })
}

/// Exits whose reason shows a Rust panic (exit code 101).
fn count_panics(report: &hopnav_supervisor::report::RunReport) -> usize {
    report
        .processes
        .iter()
        .flat_map(|process| process.exits.iter())
        .filter(|exit| exit.reason.contains("code 101"))
        .count()
}
