//! `hopnav compare`: the paper's comparison. Runs the mission in cooperative and rover-only
//! mode on the same seeded terrains, with rock abundance k spread over the requested range,
//! and prints the table and the paired figures (median and worst per-seed ratio, in words).
//! `--variant` also runs the same seeds with a config overlay and pairs them with the base;
//! `--pair` pairs finished comparisons without launching; `--expect` judges targets.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use hopnav_config::MissionMode;
use hopnav_eval::figure::mission_figure;
use hopnav_eval::{MissionTruth, TruthEvaluator};
use hopnav_metrics::map_plot::{Track, write_map_png};
use hopnav_supervisor::{LaunchError, LaunchOptions, launch};

use crate::compare_expect::Expectations;
use crate::compare_pair::comparisons;
use crate::compare_rows::{CompareRow, RunSet};
use crate::compare_table::{print_table, write_outputs};
use crate::compare_variant::{RunSetPlan, VariantMode, mission_config, run_set_plans};
use crate::compare_verdict::{comparison_lines, verdict_lines};
use crate::registry;
use crate::setup;

/// Examples and the targets file's keys, after the options in `--help`.
const AFTER_HELP: &str = "\
Examples:
  hopnav compare --seeds 20 --frames 3000 --out runs/cmp
  hopnav compare --seeds 20 --variant oracle.toml --variant-mode rover-only --out runs/oracle
  hopnav compare --pair runs/cmp runs/cmp-new-planner --expect targets.toml

A variant overlay is a config file holding only the keys it changes, e.g.
  [mapper]
  oracle_prior_map = true

A targets file (--expect) sets any of these; each judges every cooperative-vs-rover-only
comparison on the median per-seed ratio over the seeds both modes reached B:
  [paths]
  cooperative_shorter_by_percent = 15     # 0 <= value < 100
  [replans]
  fewer_by_percent = 20                   # 0 <= value <= 100
  [route_changes]
  fewer_by_percent = 10                   # 0 <= value <= 100
  [success]
  cooperative_at_least_rover_only = true  # reaches B on at least as many seeds";

#[derive(Debug, Args)]
#[command(after_long_help = AFTER_HELP)]
pub struct CompareArgs {
    /// TOML file overriding the embedded defaults (the mission's A and B come from its
    /// [world.scenario]); seed and rock abundance are then set per run.
    config: Option<PathBuf>,
    /// Seeded terrains to run; each runs once per mode (and once per variant mode).
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
    /// Folder for the run folders, compare.csv, compare.json and compare_map.png; a variant
    /// writes the same into its subfolder `variant/` (with a copy of its overlay).
    #[arg(long, default_value = "runs/compare")]
    out: PathBuf,
    /// Also run every seed with this TOML overlay merged over the config (any subset of keys,
    /// table by table, as a config file is merged over the defaults), then pair the variant's
    /// runs with the base's by seed and mode. A bad overlay stops before any launch (exit 2).
    /// It may not set what compare sets per run (seed, k, mode, frames, out).
    #[arg(long, value_name = "OVERLAY.toml")]
    variant: Option<PathBuf>,
    /// Which modes the variant runs [default: both]; a variant of one mode is compared with
    /// rover-only (or cooperative) by borrowing the base's runs of the other mode.
    #[arg(long, value_enum, value_name = "MODE", requires = "variant")]
    variant_mode: Option<VariantMode>,
    /// Launch nothing: pair the runs of finished compare folders (each holds compare.json).
    /// The first folder is the base; each other folder is paired with it by seed and mode,
    /// and every folder's cooperative runs with its rover-only runs by seed. After a
    /// `--variant` run, `--pair OUT OUT/variant` prints its pairing again.
    #[arg(
        long,
        value_name = "DIR",
        num_args = 1..,
        conflicts_with_all = [
            "config", "seeds", "first_seed", "k_min", "k_max", "frames", "out", "variant",
            "variant_mode",
        ]
    )]
    pair: Vec<PathBuf>,
    /// Judge the cooperative-vs-rover-only comparisons against the targets in this TOML file
    /// (its keys are listed at the end of --help); without it no verdict is printed. A bad
    /// file stops before any launch.
    #[arg(long, value_name = "TARGETS.toml")]
    expect: Option<PathBuf>,
}

/// The targets file and its path, as printed in the verdict.
type Targets = (String, Expectations);

pub fn run(args: CompareArgs) -> ExitCode {
    let targets: Option<Targets> = match &args.expect {
        None => None,
        Some(path) => match crate::compare_expect::load(path) {
            Ok(expect) => Some((path.display().to_string(), expect)),
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::from(crate::EXIT_CONFIG);
            }
        },
    };
    if !args.pair.is_empty() {
        return pair_folders(&args.pair, targets.as_ref());
    }
    let base = match setup::load_config(args.config.as_deref()) {
        Ok(config) => config,
        Err(code) => return code,
    };
    let k_valid = |k: f64| k.is_finite() && (0.0..=0.5).contains(&k);
    if !(k_valid(args.k_min) && k_valid(args.k_max) && args.k_min <= args.k_max) {
        eprintln!(
            "error: --k-min {} and --k-max {} must satisfy 0 <= k-min <= k-max <= 0.5",
            args.k_min, args.k_max
        );
        return ExitCode::from(crate::EXIT_CONFIG);
    }
    let overlay = match args
        .variant
        .as_deref()
        .map(crate::compare_variant::read_overlay)
    {
        Some(Err(error)) => {
            eprintln!("error: {error}");
            return ExitCode::from(crate::EXIT_CONFIG);
        }
        Some(Ok(overlay)) => Some(overlay),
        None => None,
    };
    let variant = match &overlay {
        None => None,
        Some(overlay) => match crate::compare_variant::apply(&base, overlay) {
            Ok(config) => Some((config, args.variant_mode.unwrap_or_default())),
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::from(crate::EXIT_CONFIG);
            }
        },
    };
    let plans = run_set_plans(&base, &args.out, variant);
    // Every run's config is checked before the first launch.
    for plan in &plans {
        for index in 0..args.seeds {
            let (seed, k) = seed_and_k(&args, index);
            for mode in &plan.modes {
                let config = mission_config(plan, args.frames, seed, k, *mode);
                if let Err(error) = registry::check_sections(&config) {
                    eprintln!("error: {} seed {seed}: {error}", plan.label);
                    return ExitCode::from(crate::EXIT_CONFIG);
                }
            }
        }
    }
    let executable = match setup::own_executable(" to start children") {
        Ok(path) => path,
        Err(code) => return code,
    };
    for plan in &plans {
        if let Err(error) = std::fs::create_dir_all(&plan.out) {
            eprintln!("error: cannot create {}: {error}", plan.out.display());
            return ExitCode::FAILURE;
        }
    }
    if let (Some(overlay), Some(plan)) = (&overlay, plans.get(1)) {
        let copy = plan.out.join("overlay.toml");
        if let Err(error) = std::fs::write(&copy, &overlay.text) {
            eprintln!("error: cannot write {}: {error}", copy.display());
            return ExitCode::FAILURE;
        }
    }
    let (sets, interrupted) = run_missions(&args, &plans, &executable);
    let mut code = ExitCode::SUCCESS;
    for (plan, set) in plans.iter().zip(&sets) {
        if plans.len() > 1 {
            println!("\n{} ({}):", set.label, plan.out.display());
        }
        print_table(&set.rows);
        if write_outputs(&plan.out, &set.rows) != ExitCode::SUCCESS {
            code = ExitCode::FAILURE;
        }
    }
    print_paired(&sets, targets.as_ref());
    if interrupted {
        let total: u64 = plans.iter().map(|plan| plan.modes.len() as u64).sum();
        let done: usize = sets.iter().map(|set| set.rows.len()).sum();
        eprintln!(
            "interrupted: stopped after {done} of {} launches",
            total * args.seeds
        );
        return ExitCode::from(crate::EXIT_INTERRUPTED);
    }
    code
}

/// Seed and rock abundance k of the `index`-th terrain.
fn seed_and_k(args: &CompareArgs, index: u64) -> (u64, f64) {
    let k = if args.seeds > 1 {
        args.k_min + (args.k_max - args.k_min) * index as f64 / (args.seeds - 1) as f64
    } else {
        args.k_min
    };
    (args.first_seed + index, k)
}

/// `hopnav compare --pair DIR...`: reads each folder's compare.json and prints the pairing.
fn pair_folders(dirs: &[PathBuf], targets: Option<&Targets>) -> ExitCode {
    let mut sets = Vec::new();
    for (index, dir) in dirs.iter().enumerate() {
        let rows = match crate::compare_rows::read_rows(dir) {
            Ok(rows) => rows,
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::from(crate::EXIT_CONFIG);
            }
        };
        let label = match (index, dirs.len()) {
            (0, _) => "base".to_owned(),
            (_, 2) => "variant".to_owned(),
            (index, _) => format!("variant {index}"),
        };
        let set = RunSet { label, rows };
        let modes: Vec<&str> = set.modes().iter().map(|mode| mode.name()).collect();
        println!(
            "{}: {} ({} runs: {})",
            set.label,
            dir.display(),
            set.rows.len(),
            modes.join(", ")
        );
        sets.push(set);
    }
    print_paired(&sets, targets);
    ExitCode::SUCCESS
}

/// The paired comparisons of the base (first set) and its variants, then the verdicts.
fn print_paired(sets: &[RunSet], targets: Option<&Targets>) {
    let Some((base, variants)) = sets.split_first() else {
        return;
    };
    let mut out = std::io::stdout().lock();
    for set in sets {
        let _ = writeln!(out);
        for line in crate::compare_quality::quality_lines(set) {
            let _ = writeln!(out, "{line}");
        }
    }
    let all = comparisons(base, variants);
    for comparison in &all {
        let _ = writeln!(out);
        for line in comparison_lines(comparison) {
            let _ = writeln!(out, "{line}");
        }
    }
    if let Some((source, expect)) = targets {
        for comparison in &all {
            let lines = verdict_lines(expect, source, comparison);
            if !lines.is_empty() {
                let _ = writeln!(out);
            }
            for line in lines {
                let _ = writeln!(out, "{line}");
            }
        }
    }
}

/// Launches every mission, seed by seed (a seed's base runs, then its variant runs), and
/// writes each set's map figure: its first seed with both modes, the cooperative mission with
/// the world's rocks and the rover-only rover's track. Returns the sets and whether Ctrl-C
/// (or SIGTERM) stopped the comparison.
fn run_missions(
    args: &CompareArgs,
    plans: &[RunSetPlan],
    executable: &Path,
) -> (Vec<RunSet>, bool) {
    let total: u64 = plans
        .iter()
        .map(|plan| plan.modes.len() as u64)
        .sum::<u64>()
        * args.seeds;
    let mut sets: Vec<RunSet> = plans
        .iter()
        .map(|plan| RunSet {
            label: plan.label.clone(),
            rows: Vec::new(),
        })
        .collect();
    let mut figure_written = vec![false; plans.len()];
    let mut launched = 0;
    for index in 0..args.seeds {
        let (seed, k) = seed_and_k(args, index);
        for (plan_index, plan) in plans.iter().enumerate() {
            let mut figure = None;
            let mut rover_only_track = None;
            for &mode in &plan.modes {
                launched += 1;
                let set_name = if plan_index == 0 {
                    String::new()
                } else {
                    format!("{} ", plan.label)
                };
                eprintln!(
                    "[{launched}/{total}] {set_name}seed {seed}, k {k:.3}, {} ...",
                    mode.name()
                );
                let options = LaunchOptions {
                    config: mission_config(plan, args.frames, seed, k, mode),
                    executable: executable.to_owned(),
                    known_processes: registry::names(),
                    run_id: None,
                    show_status: false,
                    evaluator: Some(std::sync::Arc::new(TruthEvaluator)),
                };
                let figure_config = (mode == MissionMode::Cooperative
                    && !figure_written[plan_index])
                    .then(|| options.config.clone());
                let mut row = CompareRow {
                    seed,
                    golombek_k: k,
                    mode: mode.name().to_owned(),
                    run_dir: String::new(),
                    runtime_ok: false,
                    mission: None,
                };
                let interrupted = match launch(options) {
                    Err(LaunchError::Interrupted) => return (sets, true),
                    Err(error) => {
                        eprintln!("  launch failed: {error}");
                        false
                    }
                    Ok(outcome) => {
                        if let Some(mission) = &outcome.report.mission {
                            let _ = mission.print(&mut std::io::stderr());
                        }
                        for line in &outcome.report.evaluation_summary {
                            eprintln!("{line}");
                        }
                        let record = outcome.mission_record.as_ref();
                        match mode {
                            MissionMode::Cooperative => {
                                let truth =
                                    figure_config.as_ref().and_then(MissionTruth::from_config);
                                figure = record
                                    .zip(truth.as_ref())
                                    .and_then(|(record, truth)| mission_figure("", truth, record));
                            }
                            MissionMode::RoverOnly => {
                                rover_only_track =
                                    record.map(|record| record.rover_track_m.clone());
                            }
                        }
                        row.run_dir = outcome.run_dir.display().to_string();
                        row.runtime_ok = outcome.success;
                        row.mission = outcome.report.mission.clone();
                        outcome.interrupted
                    }
                };
                sets[plan_index].rows.push(row);
                if interrupted {
                    // Ctrl-C stops the whole comparison, not just this launch: the tables
                    // and files keep what finished.
                    return (sets, true);
                }
            }
            if !figure_written[plan_index]
                && let (Some(mut figure), Some(track)) = (figure, rover_only_track)
            {
                figure.title = format!("cooperative vs rover-only, seed {seed}, k {k:.3}");
                if plan_index > 0 {
                    figure.title.push_str(&format!(" ({})", plan.label));
                }
                figure.tracks.insert(
                    1,
                    Track {
                        label: "rover (rover-only)".into(),
                        points_m: track,
                        rgb: (120, 0, 160),
                        markers_only: false,
                    },
                );
                let path = plan.out.join("compare_map.png");
                match write_map_png(&path, &figure) {
                    Ok(()) => {
                        figure_written[plan_index] = true;
                        eprintln!("map figure: {}", path.display());
                    }
                    Err(error) => eprintln!("warning: {error}"),
                }
            }
        }
    }
    (sets, false)
}
