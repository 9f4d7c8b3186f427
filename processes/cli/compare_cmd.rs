//! `hopnav compare`: the paper's comparison. Runs the mission in cooperative and rover-only
//! mode on the same seeded terrains, with rock abundance k spread over the requested range,
//! and prints the table and the paired figures (median and worst per-seed ratio, in words).
//! `--variant` also runs the same seeds with a config overlay and pairs them with the base;
//! `--pair` pairs finished comparisons without launching; `--expect` judges targets.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use hopnav_config::HopnavConfig;

use crate::compare_expect::Expectations;
use crate::compare_launch::run_missions;
use crate::compare_pair::comparisons;
use crate::compare_rows::RunSet;
use crate::compare_table::{print_table, write_outputs};
use crate::compare_variant::{
    Overlay, RunSetPlan, VariantError, VariantMode, mission_config, run_set_plans,
};
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

/// The variant's config and the modes it runs.
type Variant = (HopnavConfig, VariantMode);

pub fn run(args: CompareArgs) -> ExitCode {
    let targets = match load_targets(args.expect.as_deref()) {
        Ok(targets) => targets,
        Err(code) => return code,
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
    let (overlay, variant) = match variant_config(&args, &base) {
        Ok(variant) => variant,
        Err(code) => return code,
    };
    let plans = run_set_plans(&base, &args.out, variant);
    let seeds: Vec<(u64, f64)> = (0..args.seeds)
        .map(|index| seed_and_k(&args, index))
        .collect();
    if let Err(code) = check_mission_configs(&plans, &seeds, args.frames) {
        return code;
    }
    let executable = match setup::own_executable(" to start children") {
        Ok(path) => path,
        Err(code) => return code,
    };
    if let Err(code) = create_out_folders(&plans, overlay.as_ref()) {
        return code;
    }
    let (sets, interrupted) = run_missions(&seeds, args.frames, &plans, &executable);
    report(&plans, &sets, targets.as_ref(), interrupted, args.seeds)
}

/// The `--expect` targets file, read before anything launches.
fn load_targets(path: Option<&Path>) -> Result<Option<Targets>, ExitCode> {
    let Some(path) = path else {
        return Ok(None);
    };
    match crate::compare_expect::load(path) {
        Ok(expect) => Ok(Some((path.display().to_string(), expect))),
        Err(error) => {
            eprintln!("error: {error}");
            Err(ExitCode::from(crate::EXIT_CONFIG))
        }
    }
}

/// The `--variant` overlay and the config it makes of `base`, with the modes it runs.
fn variant_config(
    args: &CompareArgs,
    base: &HopnavConfig,
) -> Result<(Option<Overlay>, Option<Variant>), ExitCode> {
    let config_error = |error: VariantError| {
        eprintln!("error: {error}");
        ExitCode::from(crate::EXIT_CONFIG)
    };
    let Some(path) = args.variant.as_deref() else {
        return Ok((None, None));
    };
    let overlay = crate::compare_variant::read_overlay(path).map_err(config_error)?;
    let config = crate::compare_variant::apply(base, &overlay).map_err(config_error)?;
    let mode = args.variant_mode.unwrap_or_default();
    Ok((Some(overlay), Some((config, mode))))
}

/// Checks every run's config before the first launch.
fn check_mission_configs(
    plans: &[RunSetPlan],
    seeds: &[(u64, f64)],
    frames: u64,
) -> Result<(), ExitCode> {
    for plan in plans {
        for &(seed, k) in seeds {
            for mode in &plan.modes {
                let config = mission_config(plan, frames, seed, k, *mode);
                if let Err(error) = registry::check_sections(&config) {
                    eprintln!("error: {} seed {seed}: {error}", plan.label);
                    return Err(ExitCode::from(crate::EXIT_CONFIG));
                }
            }
        }
    }
    Ok(())
}

/// Creates each set's output folder; the variant's also gets a copy of its overlay.
fn create_out_folders(plans: &[RunSetPlan], overlay: Option<&Overlay>) -> Result<(), ExitCode> {
    for plan in plans {
        if let Err(error) = std::fs::create_dir_all(&plan.out) {
            eprintln!("error: cannot create {}: {error}", plan.out.display());
            return Err(ExitCode::FAILURE);
        }
    }
    if let (Some(overlay), Some(plan)) = (overlay, plans.get(1)) {
        let copy = plan.out.join("overlay.toml");
        if let Err(error) = std::fs::write(&copy, &overlay.text) {
            eprintln!("error: cannot write {}: {error}", copy.display());
            return Err(ExitCode::FAILURE);
        }
    }
    Ok(())
}

/// Prints and writes each set's table, then the pairing; the exit code says whether every
/// file was written and whether Ctrl-C cut the comparison short.
fn report(
    plans: &[RunSetPlan],
    sets: &[RunSet],
    targets: Option<&Targets>,
    interrupted: bool,
    seeds: u64,
) -> ExitCode {
    let mut code = ExitCode::SUCCESS;
    for (plan, set) in plans.iter().zip(sets) {
        if plans.len() > 1 {
            println!("\n{} ({}):", set.label, plan.out.display());
        }
        print_table(&set.rows);
        if write_outputs(&plan.out, &set.rows) != ExitCode::SUCCESS {
            code = ExitCode::FAILURE;
        }
    }
    print_paired(sets, targets);
    if interrupted {
        let total: u64 = plans.iter().map(|plan| plan.modes.len() as u64).sum();
        let done: usize = sets.iter().map(|set| set.rows.len()).sum();
        eprintln!(
            "interrupted: stopped after {done} of {} launches",
            total * seeds
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
