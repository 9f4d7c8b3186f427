//! `hopnav compare`: the paper's comparison. Runs the mission in cooperative and rover-only
//! mode on the same seeded terrains, with rock abundance k spread over the requested range,
//! and prints the table: success, executed path, replans, expansions, time.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_config::{HopnavConfig, MissionMode};
use hopnav_eval::figure::mission_figure;
use hopnav_eval::{MissionEvaluation, MissionTruth, TruthEvaluator};
use hopnav_metrics::map_plot::{Track, write_map_png};
use hopnav_supervisor::mission_report::MissionReport;
use hopnav_supervisor::{LaunchError, LaunchOptions, launch};
use serde::Serialize;

use crate::compare_verdict::{PairedOutcome, verdict_lines};
use crate::registry;

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// TOML file overriding the embedded defaults (the mission's A and B come from its
    /// [world.scenario]); seed and rock abundance are then set per run.
    config: Option<PathBuf>,
    /// Seeded terrains to run; each runs once per mode.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=1000))]
    seeds: u64,
    /// World seed of the first terrain (the others follow).
    #[arg(long, default_value_t = 1)]
    first_seed: u64,
    /// Golombek rock abundance k of the first terrain.
    #[arg(long, default_value_t = 0.07)]
    k_min: f64,
    /// k of the last terrain; the others are spread evenly between.
    #[arg(long, default_value_t = 0.16)]
    k_max: f64,
    /// Frame limit of each mission (it ends earlier at the goal).
    #[arg(long, default_value_t = 2400, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    frames: u64,
    /// Folder for the run folders, compare.csv, compare.json and compare_map.png.
    #[arg(long, default_value = "runs/compare")]
    out: PathBuf,
}

/// One mission of the comparison.
#[derive(Debug, Clone, Serialize)]
struct CompareRow {
    seed: u64,
    golombek_k: f64,
    mode: String,
    run_dir: String,
    runtime_ok: bool,
    mission: Option<MissionReport>,
}

fn set_value(config: &mut HopnavConfig, path: &[&str], value: toml::Value) {
    let Some((last, parents)) = path.split_last() else {
        return;
    };
    let mut table = &mut config.sections;
    for key in parents {
        let entry = table
            .entry((*key).to_owned())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = toml::Value::Table(toml::Table::new());
        }
        let Some(next) = entry.as_table_mut() else {
            return;
        };
        table = next;
    }
    table.insert((*last).to_owned(), value);
}

fn mission_config(
    base: &HopnavConfig,
    args: &CompareArgs,
    seed: u64,
    k: f64,
    mode: MissionMode,
) -> HopnavConfig {
    let mut config = base.clone();
    set_value(
        &mut config,
        &["world", "seed"],
        toml::Value::Integer(seed as i64),
    );
    set_value(
        &mut config,
        &["world", "rocks", "golombek_k"],
        toml::Value::Float(k),
    );
    config.mission.mode = mode;
    config.mission.stop_on_goal = true;
    config.run.lockstep = true;
    config.run.frames = args.frames;
    config.run.out_dir = args.out.display().to_string();
    config
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, count) = values.fold((0.0, 0usize), |(sum, count), value| {
        (sum + value, count + 1)
    });
    (count > 0).then(|| sum / count as f64)
}

pub fn run(args: CompareArgs) -> ExitCode {
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
    let k_valid = |k: f64| k.is_finite() && (0.0..=0.5).contains(&k);
    if !(k_valid(args.k_min) && k_valid(args.k_max) && args.k_min <= args.k_max) {
        eprintln!(
            "error: --k-min {} and --k-max {} must satisfy 0 <= k-min <= k-max <= 0.5",
            args.k_min, args.k_max
        );
        return ExitCode::from(crate::EXIT_CONFIG);
    }
    let executable = match std::env::current_exe() {
        Ok(path) => path,
        Err(error) => {
            eprintln!("error: cannot find the hopnav executable to start children: {error}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(error) = std::fs::create_dir_all(&args.out) {
        eprintln!("error: cannot create {}: {error}", args.out.display());
        return ExitCode::FAILURE;
    }
    let modes = [MissionMode::Cooperative, MissionMode::RoverOnly];
    let mut rows = Vec::new();
    let mut figure_written = false;
    let mut interrupted = false;
    'seeds: for index in 0..args.seeds {
        let seed = args.first_seed + index;
        let k = if args.seeds > 1 {
            args.k_min + (args.k_max - args.k_min) * index as f64 / (args.seeds - 1) as f64
        } else {
            args.k_min
        };
        let mut figure = None;
        let mut rover_only_track = None;
        for mode in modes {
            let config = mission_config(&base, &args, seed, k, mode);
            if let Err(error) = registry::check_sections(&config) {
                eprintln!("error: seed {seed}: {error}");
                return ExitCode::from(crate::EXIT_CONFIG);
            }
            eprintln!(
                "[{}/{}] seed {seed}, k {k:.3}, {} ...",
                rows.len() + 1,
                args.seeds * 2,
                mode.name()
            );
            let options = LaunchOptions {
                config,
                executable: executable.clone(),
                known_processes: registry::names(),
                run_id: None,
                show_status: false,
                evaluator: Some(std::sync::Arc::new(TruthEvaluator)),
            };
            // The figure shows the first seed's cooperative mission (with the world's rocks).
            let figure_config = (mode == MissionMode::Cooperative && !figure_written)
                .then(|| options.config.clone());
            let row = match launch(options) {
                Err(LaunchError::Interrupted) => {
                    interrupted = true;
                    break 'seeds;
                }
                Ok(outcome) => {
                    interrupted = outcome.interrupted;
                    if let Some(mission) = &outcome.report.mission {
                        let _ = mission.print(&mut std::io::stderr());
                    }
                    for line in &outcome.report.evaluation_summary {
                        eprintln!("{line}");
                    }
                    let record = outcome.mission_record.as_ref();
                    match mode {
                        MissionMode::Cooperative => {
                            let truth = figure_config.as_ref().and_then(MissionTruth::from_config);
                            figure = record
                                .zip(truth.as_ref())
                                .and_then(|(record, truth)| mission_figure("", truth, record));
                        }
                        MissionMode::RoverOnly => {
                            rover_only_track = record.map(|record| record.rover_track_m.clone());
                        }
                    }
                    CompareRow {
                        seed,
                        golombek_k: k,
                        mode: mode.name().to_owned(),
                        run_dir: outcome.run_dir.display().to_string(),
                        runtime_ok: outcome.success,
                        mission: outcome.report.mission.clone(),
                    }
                }
                Err(error) => {
                    eprintln!("  launch failed: {error}");
                    CompareRow {
                        seed,
                        golombek_k: k,
                        mode: mode.name().to_owned(),
                        run_dir: String::new(),
                        runtime_ok: false,
                        mission: None,
                    }
                }
            };
            rows.push(row);
            if interrupted {
                // Ctrl-C (or SIGTERM) stops the whole comparison, not just this launch:
                // the table and files below keep what finished.
                break 'seeds;
            }
        }
        if !figure_written && let (Some(mut figure), Some(track)) = (figure, rover_only_track) {
            figure.title = format!("cooperative vs rover-only, seed {seed}, k {k:.3}");
            figure.tracks.insert(
                1,
                Track {
                    label: "rover (rover-only)".into(),
                    points_m: track,
                    rgb: (120, 0, 160),
                    markers_only: false,
                },
            );
            let path = args.out.join("compare_map.png");
            match write_map_png(&path, &figure) {
                Ok(()) => {
                    figure_written = true;
                    eprintln!("map figure: {}", path.display());
                }
                Err(error) => eprintln!("warning: {error}"),
            }
        }
    }
    print_table(&rows);
    let code = write_outputs(&args, &rows);
    if interrupted {
        eprintln!(
            "interrupted: stopped after {} of {} launches",
            rows.len(),
            args.seeds * 2
        );
        return ExitCode::from(crate::EXIT_INTERRUPTED);
    }
    code
}

fn print_table(rows: &[CompareRow]) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "\n{:>5} {:>6} {:<12} {:>8} {:>9} {:>9} {:>9} {:>8} {:>7} {:>11} {:>7} {:>6} {:>10}",
        "seed",
        "k",
        "mode",
        "reached",
        "path m",
        "best m",
        "built m",
        "replans",
        "routes",
        "expansions",
        "time s",
        "hops",
        "collisions"
    );
    for row in rows {
        match &row.mission {
            Some(mission) => {
                let _ = writeln!(
                    out,
                    "{:>5} {:>6.3} {:<12} {:>8} {:>9.1} {:>9} {:>9} {:>8} {:>7} {:>11} {:>7.1} {:>6} {:>10}",
                    row.seed,
                    row.golombek_k,
                    row.mode,
                    if mission.goal_reached { "yes" } else { "no" },
                    mission.executed_path_m,
                    fmt_opt(full_knowledge_m(mission)),
                    fmt_opt(built_map_m(mission)),
                    mission.replans,
                    mission.route_changes,
                    mission.node_expansions,
                    mission.mission_time_s,
                    mission.jumper_hops,
                    mission.collisions
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "{:>5} {:>6.3} {:<12} launch failed",
                    row.seed, row.golombek_k, row.mode
                );
            }
        }
    }
    let of_mode = |mode: MissionMode| {
        rows.iter()
            .filter(move |row| row.mode == mode.name())
            .filter_map(|row| row.mission.as_ref().map(|mission| (row.seed, mission)))
    };
    let _ = writeln!(out);
    for mode in [MissionMode::Cooperative, MissionMode::RoverOnly] {
        let total = rows.iter().filter(|row| row.mode == mode.name()).count();
        let reached = of_mode(mode)
            .filter(|(_, mission)| mission.goal_reached)
            .count();
        let _ = writeln!(
            out,
            "{:<12} success {reached}/{total}, mean path {} m, mean replans {} (of them moving the route {}), mean expansions {}",
            mode.name(),
            fmt_opt(mean(
                of_mode(mode)
                    .filter(|(_, m)| m.goal_reached)
                    .map(|(_, m)| m.executed_path_m)
            )),
            fmt_opt(mean(of_mode(mode).map(|(_, m)| m.replans as f64))),
            fmt_opt(mean(of_mode(mode).map(|(_, m)| m.route_changes as f64))),
            fmt_opt(mean(of_mode(mode).map(|(_, m)| m.node_expansions as f64))),
        );
    }
    // Paired over the seeds where both modes reached the goal.
    let pairs: Vec<(&MissionReport, &MissionReport)> = of_mode(MissionMode::Cooperative)
        .filter_map(|(seed, cooperative)| {
            of_mode(MissionMode::RoverOnly)
                .find(|(other, _)| *other == seed)
                .map(|(_, rover_only)| (cooperative, rover_only))
        })
        .filter(|(cooperative, rover_only)| cooperative.goal_reached && rover_only.goal_reached)
        .collect();
    // (cooperative mean, rover-only mean) of one field over the pairs.
    let paired_means = |field: fn(&MissionReport) -> f64| {
        mean(pairs.iter().map(|(c, _)| field(c))).zip(mean(pairs.iter().map(|(_, r)| field(r))))
    };
    let path_ratio = paired_means(|m| m.executed_path_m);
    // The most scouting could save: the planner's path with every rock known from the start.
    let best_m = mean(pairs.iter().filter_map(|(_, r)| full_knowledge_m(r)));
    let replan_ratio = paired_means(|m| m.replans as f64);
    let route_ratio = paired_means(|m| m.route_changes as f64);
    if let (Some(path_m), Some(replans)) = (path_ratio, replan_ratio) {
        let (cooperative_m, rover_m) = path_m;
        let reached = |mode| {
            of_mode(mode)
                .filter(|(_, mission)| mission.goal_reached)
                .count()
        };
        let outcome = PairedOutcome {
            paired_seeds: pairs.len(),
            seeds_per_mode: rows
                .iter()
                .filter(|row| row.mode == MissionMode::RoverOnly.name())
                .count(),
            cooperative_reached: reached(MissionMode::Cooperative),
            rover_only_reached: reached(MissionMode::RoverOnly),
            path_m,
            replans,
            route_changes: route_ratio.unwrap_or((0.0, 0.0)),
        };
        for line in verdict_lines(&outcome) {
            let _ = writeln!(out, "{line}");
        }
        if let Some(best_m) = best_m {
            let _ = writeln!(
                out,
                "  over the same seeds: full-knowledge path {best_m:.1} m (the planner's path with every rock known from the start); rover-only drove {:+.1} %, cooperative {:+.1} % more; a scout revealing every rock would shorten rover-only's path by about {:.1} %",
                100.0 * (rover_m / best_m.max(1e-9) - 1.0),
                100.0 * (cooperative_m / best_m.max(1e-9) - 1.0),
                100.0 * (1.0 - best_m / rover_m.max(1e-9))
            );
        }
        // Where the excess over the full-knowledge path comes from, per mode: the map's errors
        // (its built-map path against full knowledge) or learning it on the way (the drive
        // against the built-map path, what an earlier scout can win back).
        let built = paired_means(|m| built_map_m(m).unwrap_or(f64::NAN));
        if let (Some(best_m), Some((cooperative_built_m, rover_built_m))) = (best_m, built)
            && cooperative_built_m.is_finite()
            && rover_built_m.is_finite()
        {
            let _ = writeln!(
                out,
                "  built-map path (the final map known from the start): rover-only {rover_built_m:.1} m, cooperative {cooperative_built_m:.1} m; map errors cost rover-only {:+.1} m, cooperative {:+.1} m; learning the map on the way cost rover-only {:+.1} m, cooperative {:+.1} m",
                rover_built_m - best_m,
                cooperative_built_m - best_m,
                rover_m - rover_built_m,
                cooperative_m - cooperative_built_m
            );
        }
    } else {
        let _ = writeln!(
            out,
            "no seed where both modes reached the goal: no paired comparison"
        );
    }
}

/// The evaluator's full-knowledge path of a mission, metres.
fn full_knowledge_m(mission: &MissionReport) -> Option<f64> {
    MissionEvaluation::of(mission).full_knowledge_path_m
}

/// The evaluator's built-map path of a mission, metres.
fn built_map_m(mission: &MissionReport) -> Option<f64> {
    MissionEvaluation::of(mission).built_map_path_m
}

fn fmt_opt(value: Option<f64>) -> String {
    value.map_or("-".to_owned(), |value| format!("{value:.1}"))
}

fn write_outputs(args: &CompareArgs, rows: &[CompareRow]) -> ExitCode {
    let mut csv = String::from(
        "seed,golombek_k,mode,runtime_ok,goal_reached,executed_path_m,full_knowledge_path_m,built_map_path_m,replans,route_changes,node_expansions,mission_time_s,jump_requests,jumper_hops,collisions,run_dir\n",
    );
    for row in rows {
        let mission = row.mission.as_ref();
        csv.push_str(&format!(
            "{},{:.4},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            row.seed,
            row.golombek_k,
            row.mode,
            row.runtime_ok,
            mission.is_some_and(|m| m.goal_reached),
            mission.map_or(String::new(), |m| format!("{:.3}", m.executed_path_m)),
            mission
                .and_then(full_knowledge_m)
                .map_or(String::new(), |m| format!("{m:.3}")),
            mission
                .and_then(built_map_m)
                .map_or(String::new(), |m| format!("{m:.3}")),
            mission.map_or(String::new(), |m| m.replans.to_string()),
            mission.map_or(String::new(), |m| m.route_changes.to_string()),
            mission.map_or(String::new(), |m| m.node_expansions.to_string()),
            mission.map_or(String::new(), |m| format!("{:.2}", m.mission_time_s)),
            mission.map_or(String::new(), |m| m.jump_requests.to_string()),
            mission.map_or(String::new(), |m| m.jumper_hops.to_string()),
            mission.map_or(String::new(), |m| m.collisions.to_string()),
            row.run_dir
        ));
    }
    let csv_path = args.out.join("compare.csv");
    let json_path = args.out.join("compare.json");
    let json = serde_json::to_string_pretty(rows).unwrap_or_default();
    for (path, text) in [(&csv_path, csv), (&json_path, json)] {
        if let Err(error) = std::fs::write(path, text) {
            eprintln!("error: cannot write {}: {error}", path.display());
            return ExitCode::FAILURE;
        }
    }
    println!(
        "results: {} and {}",
        csv_path.display(),
        json_path.display()
    );
    if rows.iter().all(|row| row.runtime_ok) {
        ExitCode::SUCCESS
    } else {
        eprintln!("some launches failed: see the run folders");
        ExitCode::FAILURE
    }
}
