//! `hopnav chaos`: random faults over N launches. Each launch gets a few faults drawn from the
//! enabled processes and the chosen kinds; the table shows what was injected, detected and
//! recovered, how long recovery took, the mission outcome, and hopnav's shared-memory and
//! node files counted before and after.
//!
//! Before the faulted launches, the same launch runs once without faults: its mission (frames
//! to B, executed path) is the reference each faulted mission is judged against
//! ([`hopnav_eval::faulted_mission`]), and faults are drawn inside its frames, so they hit the
//! traverse rather than the time after B. Every launch stops at B.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_config::HopnavConfig;
use hopnav_eval::faulted_mission::{FaultedMission, MissionOutcome, Verdict, judge};
use hopnav_supervisor::fault_injector::FaultRecord;
use hopnav_supervisor::{LaunchError, LaunchOptions, LaunchOutcome, launch};
use serde::Serialize;

use crate::compare_quality::median_and_worst;
use crate::registry;

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
    let loaded = match &args.config {
        Some(path) => hopnav_config::load_file(path),
        None => hopnav_config::load(None),
    };
    let base = match loaded {
        Ok(config) => config,
        Err(error) => {
            eprintln!("error: {error}");
            return ExitCode::from(crate::EXIT_CONFIG);
        }
    };
    if let Err(error) = registry::check_sections(&base) {
        eprintln!("error: {error}");
        return ExitCode::from(crate::EXIT_CONFIG);
    }
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
        return ExitCode::from(crate::EXIT_CONFIG);
    }
    let processes: Vec<String> = base
        .processes
        .iter()
        .filter(|(_, process)| process.enabled)
        .map(|(name, _)| name.clone())
        .collect();
    let executable = match std::env::current_exe() {
        Ok(path) => path,
        Err(error) => {
            eprintln!("error: cannot find the hopnav executable: {error}");
            return ExitCode::FAILURE;
        }
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
    // A graph runs a mission when its planner runs (as the supervisor decides).
    let runs_mission = base
        .processes
        .get("planner")
        .is_some_and(|planner| planner.enabled);
    let reference = if runs_mission {
        eprintln!("[unfaulted] the same launch without faults, the missions' reference");
        match launch_once(chaos_config(args.seed), &executable) {
            Ok(outcome) if outcome.interrupted => {
                eprintln!("interrupted: stopped during the unfaulted launch, before any run");
                return ExitCode::from(crate::EXIT_INTERRUPTED);
            }
            Err(LaunchError::Interrupted) => {
                eprintln!(
                    "interrupted: stopped while the unfaulted launch started, before any run"
                );
                return ExitCode::from(crate::EXIT_INTERRUPTED);
            }
            Ok(outcome) => mission_outcome(&outcome, base.run.frame_period_s()),
            Err(error) => {
                eprintln!("error: the unfaulted launch failed: {error}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        None
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
        let mut faults = Vec::new();
        let mut attempts = 0;
        while (faults.len() as u64) < args.faults_per_run && attempts < 100 {
            attempts += 1;
            if let Some(fault) = draw_fault(
                &mut draw,
                &args.kinds,
                &processes,
                fault_frames,
                frame_period_ms,
                watchdog_ms,
            ) {
                faults.push(fault);
            }
        }
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
                let panics = count_panics(&outcome.report);
                let vs_unfaulted = reference
                    .zip(mission_outcome(&outcome, base.run.frame_period_s()))
                    .map(|(reference, mission)| judge(&reference, mission, &outcome.report.faults));
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

fn print_reference(reference: Option<&MissionOutcome>, frames: u64) {
    match reference {
        Some(mission) if mission.goal_reached => eprintln!(
            "[unfaulted] B reached in {} frames, {:.1} m driven; faults are drawn inside those frames",
            mission.frames, mission.executed_path_m
        ),
        Some(mission) => eprintln!(
            "[unfaulted] B not reached in {frames} frames ({:.1} m driven): missions are not judged; give --frames enough for the mission",
            mission.executed_path_m
        ),
        None => eprintln!("[unfaulted] this graph runs no mission: missions are not judged"),
    }
}

/// The mission column of a run: the verdict against the unfaulted mission.
fn mission_cell(run: &ChaosRun) -> String {
    let Some(judged) = run.vs_unfaulted else {
        return run.mission.clone().unwrap_or_else(|| "-".into());
    };
    let percent = |excess: Option<f64>| excess.map_or("?".into(), |e| format!("{:+.1} %", e * 1e2));
    match judged.verdict {
        Verdict::Reached => format!(
            "B in {} f, path {}",
            judged.outcome.frames,
            percent(judged.path_excess)
        ),
        Verdict::ReachedLate => format!(
            "B late: {} f > {} allowed, path {}",
            judged.outcome.frames,
            judged.allowed_frames.unwrap_or(0),
            percent(judged.path_excess)
        ),
        Verdict::Lost => format!(
            "lost: {}",
            run.mission.as_deref().unwrap_or("B not reached")
        ),
        Verdict::NoReference => run.mission.clone().unwrap_or_else(|| "-".into()),
    }
}

/// The missions against the unfaulted one: reached, late, lost; path and time excess.
fn print_missions(runs: &[ChaosRun], reference: Option<&MissionOutcome>) {
    let Some(reference) = reference.filter(|mission| mission.goal_reached) else {
        return;
    };
    let judged: Vec<&FaultedMission> = runs
        .iter()
        .filter_map(|run| run.vs_unfaulted.as_ref())
        .collect();
    let count = |verdict: Verdict| judged.iter().filter(|j| j.verdict == verdict).count();
    let mut paths: Vec<f64> = judged.iter().filter_map(|j| j.path_excess).collect();
    let mut times: Vec<f64> = judged.iter().filter_map(|j| j.time_excess).collect();
    let spread = |values: &mut [f64]| {
        median_and_worst(values).map_or("-".to_owned(), |(median, worst)| {
            format!("median {:+.1} %, worst {:+.1} %", median * 1e2, worst * 1e2)
        })
    };
    println!(
        "missions against the unfaulted one (B in {} frames, {:.1} m): B reached in time {}/{}, late {}, lost {}; path {}; frames to B {}",
        reference.frames,
        reference.executed_path_m,
        count(Verdict::Reached),
        judged.len(),
        count(Verdict::ReachedLate),
        count(Verdict::Lost),
        spread(&mut paths),
        spread(&mut times),
    );
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

fn print_table(runs: &[ChaosRun], frame_period_s: f64) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "\n{:>4} {:>8} {:>8} {:>9} {:>13} {:>13} {:>12} {:>7} {:<36} outcome",
        "run",
        "injected",
        "detected",
        "recovered",
        "recover p50",
        "recover max",
        "files b/a",
        "panics",
        "mission"
    );
    let mut all_recoveries = Vec::new();
    let mut all_detections = Vec::new();
    let (mut injected_total, mut recovered_total, mut kills, mut kills_fast) = (0, 0, 0, 0);
    let (mut hangs, mut hangs_fast) = (0, 0);
    for run in runs {
        let fired: Vec<&FaultRecord> = run
            .faults
            .iter()
            .filter(|fault| fault.injected_frame.is_some())
            .collect();
        let detected = fired
            .iter()
            .filter(|fault| fault.detected_after_s.is_some())
            .count();
        let mut recoveries: Vec<f64> = fired
            .iter()
            .filter_map(|fault| fault.recovered_after_s)
            .collect();
        recoveries.sort_by(f64::total_cmp);
        all_detections.extend(fired.iter().filter_map(|fault| fault.detected_after_s));
        for fault in &fired {
            // A freeze longer than two frame periods is a hang the watchdog must catch.
            let freeze_ms = fault
                .fault
                .parse::<hopnav_config::fault::FaultSpec>()
                .ok()
                .and_then(|spec| match spec.kind {
                    hopnav_config::fault::FaultKind::Stall { duration_ms } => Some(duration_ms),
                    _ => None,
                });
            if freeze_ms.is_some_and(|ms| ms as f64 > 2e3 * frame_period_s) {
                hangs += 1;
                if fault
                    .detected_after_s
                    .is_some_and(|s| s <= 2.0 * frame_period_s)
                {
                    hangs_fast += 1;
                }
            }
            if fault.fault.starts_with("kill:") {
                kills += 1;
                if fault
                    .recovered_after_s
                    .is_some_and(|s| s <= 2.0 * frame_period_s)
                {
                    kills_fast += 1;
                }
            }
        }
        injected_total += run.faults.len();
        recovered_total += recoveries.len();
        all_recoveries.extend(recoveries.iter().copied());
        let ms =
            |value: Option<&f64>| value.map_or("-".to_owned(), |s| format!("{:.0} ms", s * 1e3));
        let _ = writeln!(
            out,
            "{:>4} {:>8} {:>8} {:>9} {:>13} {:>13} {:>12} {:>7} {:<36} {}",
            run.run,
            run.faults.len(),
            detected,
            format!("{}/{}", recoveries.len(), fired.len()),
            ms(recoveries.get(recoveries.len() / 2)),
            ms(recoveries.last()),
            format!("{}/{}", run.hopnav_files_before, run.hopnav_files_after),
            run.panics,
            mission_cell(run),
            run.outcome
        );
    }
    all_recoveries.sort_by(f64::total_cmp);
    let leaked: usize = runs.iter().map(|run| run.leftover_files).sum();
    let _ = writeln!(
        out,
        "\n{} faults injected ({} fired with a time), {} recovered; recovery p50 {}, max {}; kills recovered within 2 frame periods: {kills_fast}/{kills}; leaked files {leaked}; panics {}",
        injected_total,
        runs.iter()
            .flat_map(|run| &run.faults)
            .filter(|fault| fault.injected_frame.is_some())
            .count(),
        recovered_total,
        all_recoveries
            .get(all_recoveries.len() / 2)
            .map_or("-".into(), |s| format!("{:.0} ms", s * 1e3)),
        all_recoveries
            .last()
            .map_or("-".into(), |s| format!("{:.0} ms", s * 1e3)),
        runs.iter().map(|run| run.panics).sum::<usize>()
    );
    all_detections.sort_by(f64::total_cmp);
    let _ = writeln!(
        out,
        "detection p50 {}, max {}; hangs detected within 2 frame periods: {hangs_fast}/{hangs}",
        all_detections
            .get(all_detections.len() / 2)
            .map_or("-".into(), |s| format!("{:.0} ms", s * 1e3)),
        all_detections
            .last()
            .map_or("-".into(), |s| format!("{:.0} ms", s * 1e3)),
    );
}
