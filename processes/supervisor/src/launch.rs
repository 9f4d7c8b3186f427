//! `hopnav launch`: set up a run, start the graph, run the frame loop, tear down, report.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use hopnav_config::HopnavConfig;
use hopnav_ipc::IpcService;
use hopnav_ipc::latency::LatencySummary;
use hopnav_ipc::messages::{BodyStates, FrameTick, Heartbeat};
use hopnav_ipc::namespace::{self, Namespace};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, Subscriber};
use iceoryx2::node::Node;
use iceoryx2::prelude::WaitSetBuilder;

use crate::LaunchError;
use crate::fault_injector::{FaultInjector, FaultRecord};
use crate::frame_loop::{FrameLoop, LoopEnd, LoopStats, SupervisorPorts};
use crate::mission::MissionObserver;
use crate::mission_record::{Evaluation, MissionEvaluator, MissionRecord};
use crate::report::RunReport;
use crate::restart::RestartTracker;
use crate::slot::Slot;
use crate::status_line::StatusLine;

/// What to launch and how.
#[derive(Debug, Clone)]
pub struct LaunchOptions {
    /// The validated configuration (CLI overrides already applied).
    pub config: HopnavConfig,
    /// The hopnav executable children are started from.
    pub executable: PathBuf,
    /// Process names this executable can run.
    pub known_processes: Vec<String>,
    /// Run id to use instead of a fresh one (tests, tooling).
    pub run_id: Option<String>,
    /// Print the live status line.
    pub show_status: bool,
    /// Scores the mission against the truth at the end (the CLI passes `hopnav-eval`'s);
    /// `None` reports the runtime's own figures only.
    pub evaluator: Option<Arc<dyn MissionEvaluator>>,
}

/// What the mission observer found, kept after its ports are gone.
struct MissionSummary {
    report: crate::mission_report::MissionReport,
    record: MissionRecord,
}

/// A launch that ran its frame loop.
#[derive(Debug, Clone)]
pub struct LaunchOutcome {
    /// The report (also written to `run_dir/report.json`).
    pub report: RunReport,
    /// The run folder.
    pub run_dir: PathBuf,
    /// True when every requested frame completed, or the mission ended, and nothing stopped
    /// the launch.
    pub success: bool,
    /// True when SIGINT or SIGTERM stopped the launch: a command running many launches
    /// should stop too.
    pub interrupted: bool,
    /// What the supervisor recorded of the mission, when the graph ran one.
    pub mission_record: Option<MissionRecord>,
}

/// Runs a launch to its end. Setup failures are errors; anything after the graph started
/// ends in a report (with the outcome saying why it stopped).
pub fn launch(options: LaunchOptions) -> Result<LaunchOutcome, LaunchError> {
    let config = &options.config;
    let enabled = enabled_processes(&options)?;

    // A SIGINT or SIGTERM that arrived before this launch (e.g. between the runs of
    // `hopnav compare`) stops it before anything starts. This also installs the handler that
    // turns later signals into a clean stop instead of the default death.
    if crate::signals::termination_requested() {
        return Err(LaunchError::Interrupted);
    }
    crate::signals::wake_on_child_exit();
    let stale = clean_up_dead_runs();

    let run_id = options.run_id.clone().unwrap_or_else(namespace::new_run_id);
    // Before the run folder: a second launch with a live run id must not touch the first's.
    let namespace = Namespace::new(&run_id)?;
    let _claim = namespace.claim()?;
    let (run_dir, config_path) = prepare_run_dir(config, &run_id)?;

    let frames = config.run.frames as usize;
    let slots: Vec<Slot> = enabled
        .into_iter()
        .map(|(name, process)| {
            let tracker = RestartTracker::new(process.restart, &config.restart);
            Slot::new(name, process, tracker, frames)
        })
        .collect();
    announce(&run_id, slots.len(), config, &run_dir);

    let loop_started = Instant::now();
    let graph = run_graph(&options, &namespace, slots, config_path)?;
    let wall_time_s = loop_started.elapsed().as_secs_f64();
    let leftover_files = remove_namespace_files(&namespace);

    let cleanup = Cleanup {
        stale_runs: stale.dead_runs,
        leftover_files,
    };
    finish(&options, run_id, run_dir, wall_time_s, cleanup, graph)
}

/// What the launch cleaned up around its run, for the report.
struct Cleanup {
    /// Dead runs whose files were removed before this one started.
    stale_runs: Vec<String>,
    /// Files of this run's namespace left after shutdown.
    leftover_files: usize,
}

/// Evaluates the mission, writes report.json and returns the outcome.
fn finish(
    options: &LaunchOptions,
    run_id: String,
    run_dir: PathBuf,
    wall_time_s: f64,
    cleanup: Cleanup,
    graph: GraphRun,
) -> Result<LaunchOutcome, LaunchError> {
    let config = &options.config;
    let GraphRun {
        stats: frame_loop,
        fault_records,
        end,
        mission,
    } = graph;
    let success = matches!(end, LoopEnd::Completed | LoopEnd::MissionEnded(_));
    let interrupted = end == LoopEnd::Interrupted;
    let outcome = outcome_text(&end);
    let (mission_report, evaluation) = evaluate_mission(options, mission.as_ref(), &run_dir);
    let mut end_to_end = frame_loop.end_to_end_ns.clone();
    let report = RunReport {
        run_id,
        mode: if config.run.lockstep {
            "lockstep"
        } else {
            "real-time"
        }
        .to_owned(),
        outcome,
        frames_requested: config.run.frames,
        frames_completed: frame_loop.frames_completed,
        frames_degraded: frame_loop.frames_degraded,
        frames_abandoned: frame_loop.frames_abandoned,
        frame_period_ms: config.run.frame_period_s() * 1e3,
        wall_time_s,
        end_to_end_latency: LatencySummary::from_ns(&mut end_to_end),
        end_to_end_misses: frame_loop.end_to_end_misses,
        processes: frame_loop.slots.iter().map(Slot::report).collect(),
        stale_runs_cleaned: cleanup.stale_runs,
        leftover_files: cleanup.leftover_files,
        faults: fault_records,
        mission: mission_report,
        mission_figure: evaluation.figure_path,
        evaluation_summary: evaluation.summary_lines,
        config: serde_json::to_value(config).unwrap_or(serde_json::Value::Null),
    };
    report
        .write_json(&run_dir)
        .map_err(|source| LaunchError::RunDir {
            path: run_dir.join("report.json"),
            source,
        })?;
    Ok(LaunchOutcome {
        report,
        run_dir,
        success,
        interrupted,
        mission_record: mission.map(|mission| mission.record),
    })
}

/// Once every node of the run is gone: gives the kernel a moment to let the last unmaps
/// settle, then removes what iceoryx2 keeps per namespace; returns how many files are left.
/// A tool watching from outside (`hopnav topic`) holds a node of the run too: it notices the
/// end within its one-second tick and leaves, so its node is waited for that long.
fn remove_namespace_files(namespace: &Namespace) -> usize {
    std::thread::sleep(Duration::from_millis(20));
    let tools_gone_by = Instant::now() + TOOLS_LEAVE_WITHIN;
    while namespace.remove_dead_nodes().alive > 0 && Instant::now() < tools_gone_by {
        std::thread::sleep(Duration::from_millis(50));
    }
    namespace.remove_files_if_unused();
    namespace.leftover_files().len()
}

/// How long a `hopnav topic` tool may take to leave a launch that ended (its tick is 1 s).
const TOOLS_LEAVE_WITHIN: Duration = Duration::from_millis(1500);

/// Removes what launches that died left behind (their nodes and files), saying so.
fn clean_up_dead_runs() -> namespace::StaleCleanup {
    let stale = namespace::cleanup_dead_runs();
    if !stale.dead_runs.is_empty() {
        eprintln!(
            "cleaned up {} dead earlier launch(es): {} stale node(s), {} file(s)",
            stale.dead_runs.len(),
            stale.removed_nodes,
            stale.removed_files
        );
    }
    stale
}

/// The one line that says what is about to run and where it writes.
fn announce(run_id: &str, process_count: usize, config: &HopnavConfig, run_dir: &Path) {
    eprintln!(
        "launch {run_id}: {} processes, {} frames at {} Hz{}, run folder {}",
        process_count,
        config.run.frames,
        config.run.frame_rate_hz,
        if config.run.lockstep {
            " (lockstep)"
        } else {
            ""
        },
        run_dir.display()
    );
}

/// What a run of the graph left once the supervisor's ports were closed.
struct GraphRun {
    stats: LoopStats,
    fault_records: Vec<FaultRecord>,
    end: LoopEnd,
    mission: Option<MissionSummary>,
}

/// Opens the supervisor's ports, starts every child, runs the frame loop to its end and
/// shuts the graph down. Every port of the supervisor is closed on return, so the namespace
/// can be cleaned up; a start-up failure cleans it up here and is returned.
fn run_graph(
    options: &LaunchOptions,
    namespace: &Namespace,
    slots: Vec<Slot>,
    config_path: PathBuf,
) -> Result<GraphRun, LaunchError> {
    let config = &options.config;
    let node = namespace.create_node("supervisor")?;
    let heartbeats = Subscriber::<Heartbeat>::open(&node, &topics::HEARTBEAT)?;
    let step_publishers = slots
        .iter()
        .map(|slot| Publisher::<FrameTick>::open(&node, &topics::step(&slot.name)))
        .collect::<Result<Vec<_>, _>>()?;
    let waitset = WaitSetBuilder::new()
        .create::<IpcService>()
        .map_err(|error| LaunchError::Wait(format!("{error:?}")))?;
    let guard = waitset
        .attach_notification(heartbeats.listener())
        .map_err(|error| LaunchError::Wait(format!("{error:?}")))?;
    let ports = open_ports(&node, config, &slots, step_publishers)?;
    let mut frame_loop = FrameLoop::new(
        config.clone(),
        slots,
        ports,
        namespace.clone(),
        options.executable.clone(),
        config_path,
        StatusLine::new(options.show_status),
    );
    let end = match frame_loop.start_all(&heartbeats, &waitset) {
        Ok(()) => Ok(frame_loop.run(&heartbeats, &waitset)),
        Err(error) => Err(error),
    };
    frame_loop.shutdown();
    let end = match end {
        Ok(end) => end,
        Err(error) => {
            // Start-up failed: the children are stopped; drop the supervisor's ports and
            // remove what the namespace left before reporting the error.
            drop(frame_loop);
            drop(guard);
            drop(waitset);
            drop(heartbeats);
            drop(node);
            std::thread::sleep(Duration::from_millis(20));
            namespace.remove_files_if_unused();
            return Err(error);
        }
    };
    // The mission's summary is taken now: its ports must die with the loop's, before the
    // namespace clean-up below.
    let mission = frame_loop.take_mission().map(|mut mission| {
        mission.observe();
        MissionSummary {
            report: mission.report(),
            record: mission.record(),
        }
    });
    let (stats, fault_records) = frame_loop.into_stats();
    Ok(GraphRun {
        stats,
        fault_records,
        end,
        mission,
    })
}

/// The supervisor's ports besides its heartbeat subscriber: the step publishers (one a slot,
/// already open), the truth for the status line, the mission observer when a planner runs,
/// the fault injector and the relays.
fn open_ports(
    node: &Node<IpcService>,
    config: &HopnavConfig,
    slots: &[Slot],
    step_publishers: Vec<Publisher<FrameTick>>,
) -> Result<SupervisorPorts, LaunchError> {
    // A small buffer: the status line only wants the newest state.
    let truth = Subscriber::<BodyStates>::open(node, &topics::BODY_STATES).ok();
    let runs_mission = config
        .processes
        .get("planner")
        .is_some_and(|planner| planner.enabled);
    let mission = runs_mission
        .then(|| MissionObserver::open(node, config))
        .flatten();
    let specs = config
        .faults
        .specs()
        .map_err(|error| LaunchError::Fault(error.to_string()))?;
    let faults = FaultInjector::new(&specs, config.run.frame_rate_hz, |name| {
        slots.iter().position(|slot| slot.name == name)
    })
    .map_err(LaunchError::Fault)?;
    let relays =
        crate::relay::open_relays(node, |name| slots.iter().position(|slot| slot.name == name));
    Ok(SupervisorPorts {
        step_publishers,
        truth,
        mission,
        faults,
        relays,
    })
}

/// The mission's report with the evaluator's fields moved into it, and the rest of the evaluation;
/// also writes the rover's true track into the run folder.
fn evaluate_mission(
    options: &LaunchOptions,
    mission: Option<&MissionSummary>,
    run_dir: &Path,
) -> (Option<crate::mission_report::MissionReport>, Evaluation) {
    let mut mission_report = mission.map(|mission| mission.report.clone());
    let mut evaluation = Evaluation::default();
    if let Some(mission) = mission {
        write_rover_track(run_dir, &mission.record.rover_track_m);
        if let Some(evaluator) = &options.evaluator {
            evaluation =
                evaluator.evaluate(&options.config, &mission.report, &mission.record, run_dir);
        }
    }
    if let Some(report) = mission_report.as_mut() {
        report.evaluation = std::mem::take(&mut evaluation.fields);
    }
    (mission_report, evaluation)
}

/// The enabled processes of `options`' config; an error names one this binary cannot run.
fn enabled_processes(
    options: &LaunchOptions,
) -> Result<Vec<(String, hopnav_config::ProcessConfig)>, LaunchError> {
    let enabled: Vec<(String, hopnav_config::ProcessConfig)> = options
        .config
        .processes
        .iter()
        .filter(|(_, process)| process.enabled)
        .map(|(name, process)| (name.clone(), process.clone()))
        .collect();
    if let Some((name, _)) = enabled
        .iter()
        .find(|(name, _)| !options.known_processes.contains(name))
    {
        return Err(LaunchError::UnknownProcess {
            name: name.clone(),
            known: options.known_processes.join(", "),
        });
    }
    Ok(enabled)
}

/// Creates `<out_dir>/<run id>/` and writes the `config.toml` the children read; returns
/// the folder and the config file's (canonical) path.
fn prepare_run_dir(config: &HopnavConfig, run_id: &str) -> Result<(PathBuf, PathBuf), LaunchError> {
    let run_dir = Path::new(&config.run.out_dir).join(run_id);
    std::fs::create_dir_all(&run_dir).map_err(|source| LaunchError::RunDir {
        path: run_dir.clone(),
        source,
    })?;
    let config_path = run_dir.join("config.toml");
    std::fs::write(&config_path, hopnav_config::to_toml(config)?).map_err(|source| {
        LaunchError::RunDir {
            path: config_path.clone(),
            source,
        }
    })?;
    let config_path = std::fs::canonicalize(&config_path).unwrap_or(config_path);
    Ok((run_dir, config_path))
}

/// The report's `outcome`.
fn outcome_text(end: &LoopEnd) -> String {
    match end {
        LoopEnd::Completed => "completed".to_owned(),
        LoopEnd::MissionEnded(reason) => format!("completed: mission over, {reason}"),
        LoopEnd::Interrupted => "interrupted".to_owned(),
        LoopEnd::Stopped(reason) => format!("stopped: {reason}"),
    }
}

/// Writes the rover's true track as `rover_track.csv` (a warning when it cannot).
fn write_rover_track(run_dir: &Path, track_m: &[(f64, f64)]) {
    let rows = track_m
        .iter()
        .map(|(x_m, y_m)| format!("{x_m:.3},{y_m:.3}\n"))
        .collect::<String>();
    let path = run_dir.join("rover_track.csv");
    if let Err(error) = std::fs::write(&path, format!("x_m,y_m\n{rows}")) {
        eprintln!("warning: cannot write {}: {error}", path.display());
    }
}
