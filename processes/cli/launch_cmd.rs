//! `hopnav launch`: the supervisor.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_config::HopnavConfig;
use hopnav_supervisor::{LaunchError, LaunchOptions, LaunchOutcome, launch};

use crate::registry;
use crate::setup;

#[derive(Debug, Args)]
pub struct LaunchArgs {
    /// TOML file overriding the embedded defaults (any subset of keys). Without it the
    /// embedded default configuration runs.
    config: Option<PathBuf>,
    /// Lockstep: frame k+1 starts when every stage finished frame k; reproducible and as fast
    /// as the machine allows. Default: real time at run.frame_rate_hz.
    #[arg(long)]
    lockstep: bool,
    /// Number of frames to run (overrides run.frames).
    #[arg(long, conflicts_with = "duration", value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    frames: Option<u64>,
    /// Simulated seconds to run (frames = duration × frame rate).
    #[arg(long)]
    duration: Option<f64>,
    /// Folder for run folders (overrides run.out_dir); the report goes to OUT/<run id>/.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Use this run id instead of a fresh one ([A-Za-z0-9-], for tooling and tests); refused
    /// while another launch runs under it.
    #[arg(long)]
    run_id: Option<String>,
    /// Record the camera streams (PGM + CSV index), sensor CSVs, intrinsics and TUM ground
    /// truth into DIR, for external VO tools (enables the recorder process).
    #[arg(long, value_name = "DIR")]
    export_dataset: Option<PathBuf>,
    /// Record every topic into one MCAP file, in hopnav's own encoding, with the launch's
    /// config and the build's commit (enables the recorder process; in lockstep it is complete).
    #[arg(long, value_name = "FILE.mcap")]
    record: Option<PathBuf>,
    /// Serve the Foxglove channels of --record (images, clouds, frames, map, path) live over
    /// the Foxglove WebSocket protocol on ADDR (IP:PORT; default 127.0.0.1:8765, this machine
    /// only; port 0 picks a free one), for Foxglove's "Open connection" (enables the recorder
    /// process; or `[recorder] viewer`). A slow client loses messages, never holds the
    /// launch back.
    #[arg(
        long,
        value_name = "ADDR",
        num_args = 0..=1,
        default_missing_value = hopnav_recorder::DEFAULT_VIEWER_ADDRESS
    )]
    viewer: Option<String>,
    /// Inject a fault (repeatable; adds to faults.inject). Kinds:
    /// kill:PROC@3s (SIGKILL at 3 s of sim time), stall:PROC@5s+800ms (SIGSTOP, SIGCONT
    /// after 800 ms), drop:PROC/TOPIC@10% (the publisher drops 10 % of its samples on
    /// hopnav/PROC/TOPIC), corrupt:PROC/TOPIC@5% (garbled headers that consumers must reject),
    /// delay:PROC@50ms (every step 50 ms late). Times also as f30 (frame 30).
    #[arg(long, value_name = "SPEC")]
    fault: Vec<String>,
    /// No live status line.
    #[arg(long)]
    quiet: bool,
}

pub fn run(args: LaunchArgs) -> ExitCode {
    let mut config = match setup::load_checked_config(args.config.as_deref()) {
        Ok(config) => config,
        Err(code) => return code,
    };
    if let Err(code) = apply_options(&args, &mut config) {
        return code;
    }
    let executable = match setup::own_executable(" to start children") {
        Ok(path) => path,
        Err(code) => return code,
    };
    let recording = config
        .processes
        .get("recorder")
        .is_some_and(|recorder| recorder.enabled)
        && !config.recorder.mcap.is_empty();
    let options = LaunchOptions {
        config,
        executable,
        known_processes: registry::names(),
        run_id: args.run_id,
        show_status: !args.quiet,
        evaluator: Some(std::sync::Arc::new(hopnav_eval::TruthEvaluator)),
    };
    report(launch(options), recording)
}

/// Sets what the command-line options override in `config`; a bad option exits with the
/// config error code before anything starts.
fn apply_options(args: &LaunchArgs, config: &mut HopnavConfig) -> Result<(), ExitCode> {
    config.run.lockstep |= args.lockstep;
    if let Some(frames) = args.frames {
        config.run.frames = frames;
    }
    if let Some(duration_s) = args.duration {
        if !(duration_s.is_finite() && duration_s > 0.0 && duration_s <= 1e6) {
            eprintln!("error: --duration must be in (0, 1e6] seconds, got {duration_s}");
            return Err(ExitCode::from(crate::EXIT_CONFIG));
        }
        config.run.frames = (duration_s * config.run.frame_rate_hz).ceil().max(1.0) as u64;
    }
    if let Some(dir) = &args.export_dataset {
        enable_recorder(config, "--export-dataset")?;
        config.recorder.dir = absolute(dir);
    }
    if let Some(file) = &args.record {
        enable_recorder(config, "--record")?;
        config.recorder.mcap = absolute(file);
    }
    if let Some(address) = &args.viewer {
        enable_recorder(config, "--viewer")?;
        config.recorder.viewer = address.clone();
    }
    let recorder_enabled = config
        .processes
        .get("recorder")
        .is_some_and(|recorder| recorder.enabled);
    // Refuse a bad or taken viewer address before anything starts, not in the recorder.
    if recorder_enabled
        && !config.recorder.viewer.trim().is_empty()
        && let Err(error) = hopnav_recorder::check_viewer_address(&config.recorder.viewer)
    {
        eprintln!("error: {error}");
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    }
    let recording = config.recorder.mcap.trim().to_owned();
    if recorder_enabled && !recording.is_empty() {
        config.recorder.mcap = absolute(std::path::Path::new(&recording));
        // Refuse a path that cannot be written before anything starts, not in the recorder.
        let path = std::path::Path::new(&config.recorder.mcap);
        if let Err(error) = hopnav_recorder::check_writable(path) {
            eprintln!("error: {error}");
            return Err(ExitCode::from(crate::EXIT_CONFIG));
        }
    }
    config.faults.inject.extend(args.fault.iter().cloned());
    if let Err(error) = config.faults.specs() {
        eprintln!("error: --fault: {error}");
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    }
    if let Some(out) = &args.out {
        config.run.out_dir = out.display().to_string();
    }
    if let Some(run_id) = &args.run_id
        && (run_id.is_empty()
            || run_id.contains('_')
            || hopnav_ipc::namespace::Namespace::new(run_id).is_err())
    {
        eprintln!("error: --run-id {run_id:?} must be 1..=48 characters of [A-Za-z0-9-]");
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    }
    Ok(())
}

/// Turns on the recorder process, which `option` needs.
fn enable_recorder(config: &mut HopnavConfig, option: &str) -> Result<(), ExitCode> {
    let Some(recorder) = config.processes.get_mut("recorder") else {
        eprintln!("error: {option} needs a [processes.recorder] entry in the config");
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    };
    recorder.enabled = true;
    Ok(())
}

/// `path` made absolute against the launch's folder, as config text: the config the children
/// read must not depend on their working folder.
fn absolute(path: &std::path::Path) -> String {
    std::path::absolute(path)
        .unwrap_or_else(|_| path.to_owned())
        .display()
        .to_string()
}

/// Prints the launch's summary and turns its outcome into the exit code.
fn report(result: Result<LaunchOutcome, LaunchError>, recording: bool) -> ExitCode {
    match result {
        Ok(outcome) => {
            let mut stdout = std::io::stdout().lock();
            let _ = outcome.report.print_summary(&mut stdout);
            if recording {
                match hopnav_recorder::RecordingSummary::read_from(&outcome.run_dir) {
                    Some(summary) => {
                        let _ = summary.print_line(&mut stdout);
                    }
                    None => println!("record: FAILED: the recorder left no summary"),
                }
            }
            println!("report: {}", outcome.run_dir.join("report.json").display());
            if outcome.interrupted {
                ExitCode::from(crate::EXIT_INTERRUPTED)
            } else if outcome.success {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        Err(LaunchError::Interrupted) => {
            eprintln!("interrupted before the launch ran");
            ExitCode::from(crate::EXIT_INTERRUPTED)
        }
        Err(error @ (LaunchError::UnknownProcess { .. } | LaunchError::Fault(_))) => {
            eprintln!("error: {error}");
            ExitCode::from(crate::EXIT_CONFIG)
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
