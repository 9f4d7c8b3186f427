//! `hopnav eval traversability`: rover-only missions at k = 0.07, 0.10, 0.13 and 0.16, and
//! how much ground each final map shuts the rover's centre out of where its camera had the
//! ground in sight within 5 m (ground hidden behind a rock left out) against what the rocks really block (blocked-area ratio), how many truly lethal
//! cells it left traversable (missed) or held uncertain (maybe too tall, at a cost), and how
//! many it called lethal wrongly; the share left open to the rover's centre (missed or
//! uncertain) is also given over every mapped cell within 5 m of the track; a map figure per k.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_config::MissionMode;
use hopnav_eval::traversability::MissedCauses;
use hopnav_eval::{MissionEvaluation, TruthEvaluator};
use hopnav_supervisor::{LaunchError, LaunchOptions, launch};
use serde::Serialize;

use crate::compare_quality::median_and_worst;
use crate::compare_variant::{RunSetPlan, mission_config};
use crate::registry;
use crate::setup;

/// The rock abundances the targets are set at (Golombek k).
const ABUNDANCES: [f64; 4] = [0.07, 0.10, 0.13, 0.16];

#[derive(Debug, Args)]
pub struct TraversabilityArgs {
    /// TOML file overriding the embedded defaults (e.g. `[mapper] obstacle_model =
    /// "traversability"`); seed, k and mode are set per mission.
    config: Option<PathBuf>,
    /// Seeded terrains per k.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=1000))]
    seeds: u64,
    /// World seed of the first terrain.
    #[arg(long, default_value_t = 1)]
    first_seed: u64,
    /// Frame limit of each mission (it ends earlier at the goal).
    #[arg(long, default_value_t = 2400, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    frames: u64,
    /// Folder for the run folders, eval_traversability.json and a map PNG per k.
    #[arg(long, default_value = "runs/eval-traversability")]
    out: PathBuf,
}

/// One mission's figures.
#[derive(Debug, Clone, Serialize)]
struct MissionRow {
    golombek_k: f64,
    seed: u64,
    run_dir: String,
    goal_reached: bool,
    collisions: u32,
    /// Each rock contact: the rover's motion, the rock met and the map's word on it then.
    contacts: Vec<hopnav_eval::contact_judge::JudgedContact>,
    blocked_area_ratio: Option<f64>,
    /// Truly lethal cells mapped traversable, % of the truly lethal.
    missed_lethal_percent: Option<f64>,
    /// Truly lethal cells mapped uncertain (maybe too tall), %.
    uncertain_lethal_percent: Option<f64>,
    /// Truly lethal cells the rover's centre may enter (missed or uncertain), %.
    open_lethal_percent: Option<f64>,
    /// The open share over every mapped cell within 5 m of the track, whichever way the
    /// camera looked.
    open_lethal_percent_near_track: Option<f64>,
    /// The missed share over every cell in the camera's field of view within 5 m, hidden or
    /// not (the judge before it had a line of sight).
    missed_lethal_percent_in_view: Option<f64>,
    /// The blocked-area ratio over those cells.
    blocked_area_ratio_in_view: Option<f64>,
    /// The missed share with the map carried onto the truth by the rover VO's alignment (the
    /// VO's misplacement of the whole map left out).
    missed_lethal_percent_map_frame: Option<f64>,
    false_lethal_cells: Option<usize>,
    judged_cells: Option<usize>,
    /// The missed cells by the rock that makes each lethal and what the map made of it.
    missed_by_cause: Option<MissedCauses>,
}

pub fn run(args: TraversabilityArgs) -> ExitCode {
    let base = match setup::load_checked_config(args.config.as_deref()) {
        Ok(config) => config,
        Err(code) => return code,
    };
    if let Err(error) = std::fs::create_dir_all(&args.out) {
        eprintln!("error: cannot create {}: {error}", args.out.display());
        return ExitCode::FAILURE;
    }
    let executable = match setup::own_executable("") {
        Ok(path) => path,
        Err(code) => return code,
    };
    let plan = RunSetPlan {
        label: "traversability".into(),
        out: args.out.clone(),
        config: base,
        modes: vec![MissionMode::RoverOnly],
    };
    let total = ABUNDANCES.len() as u64 * args.seeds;
    let mut rows = Vec::new();
    for k in ABUNDANCES {
        for seed in args.first_seed..args.first_seed + args.seeds {
            eprintln!(
                "[{}/{total}] k {k:.2}, seed {seed}, rover-only ...",
                rows.len() + 1
            );
            let options = LaunchOptions {
                config: mission_config(&plan, args.frames, seed, k, MissionMode::RoverOnly),
                executable: executable.clone(),
                known_processes: registry::names(),
                run_id: None,
                show_status: false,
                evaluator: Some(std::sync::Arc::new(TruthEvaluator)),
            };
            match launch(options) {
                Err(LaunchError::Interrupted) => return finish(&args, &rows, true),
                Err(error) => eprintln!("  launch failed: {error}"),
                Ok(outcome) => {
                    let row = mission_row(k, seed, &outcome);
                    if seed == args.first_seed {
                        copy_figure(&args, k, &outcome.run_dir);
                    }
                    eprintln!(
                        "  blocked-area ratio {}, truly lethal ground mapped traversable {}, uncertain {}",
                        fmt(row.blocked_area_ratio, ""),
                        fmt(row.missed_lethal_percent, " %"),
                        fmt(row.uncertain_lethal_percent, " %")
                    );
                    let interrupted = outcome.interrupted;
                    rows.push(row);
                    if interrupted {
                        return finish(&args, &rows, true);
                    }
                }
            }
        }
    }
    finish(&args, &rows, false)
}

fn mission_row(k: f64, seed: u64, outcome: &hopnav_supervisor::LaunchOutcome) -> MissionRow {
    let mission = outcome.report.mission.as_ref();
    let evaluation = mission.map(MissionEvaluation::of);
    let blocked = evaluation
        .as_ref()
        .and_then(|evaluation| evaluation.blocked_area);
    let near_track = evaluation
        .as_ref()
        .and_then(|evaluation| evaluation.blocked_area_near_track);
    let in_view = evaluation
        .as_ref()
        .and_then(|evaluation| evaluation.blocked_area_in_view);
    let map_frame = evaluation
        .as_ref()
        .and_then(|evaluation| evaluation.blocked_area_map_frame);
    MissionRow {
        golombek_k: k,
        seed,
        run_dir: outcome.run_dir.display().to_string(),
        goal_reached: mission.is_some_and(|mission| mission.goal_reached),
        collisions: mission.map_or(0, |mission| mission.collisions),
        contacts: evaluation.map_or_else(Vec::new, |evaluation| evaluation.contacts),
        blocked_area_ratio: blocked.and_then(|b| b.blocked_area_ratio),
        missed_lethal_percent: blocked.and_then(|b| b.missed_lethal_percent()),
        uncertain_lethal_percent: blocked.and_then(|b| b.uncertain_lethal_percent()),
        open_lethal_percent: blocked.and_then(|b| b.open_lethal_percent()),
        open_lethal_percent_near_track: near_track.and_then(|b| b.open_lethal_percent()),
        missed_lethal_percent_in_view: in_view.and_then(|b| b.missed_lethal_percent()),
        blocked_area_ratio_in_view: in_view.and_then(|b| b.blocked_area_ratio),
        missed_lethal_percent_map_frame: map_frame.and_then(|b| b.missed_lethal_percent()),
        false_lethal_cells: blocked.map(|b| b.false_lethal_cells),
        judged_cells: blocked.map(|b| b.judged_cells),
        missed_by_cause: blocked.map(|b| b.missed_by_cause),
    }
}

/// The first seed's map of each k, as `traversability_k0.07.png`.
fn copy_figure(args: &TraversabilityArgs, k: f64, run_dir: &std::path::Path) {
    let from = run_dir.join("mission_map.png");
    let to = args.out.join(format!("traversability_k{k:.2}.png"));
    if let Err(error) = std::fs::copy(&from, &to) {
        eprintln!("warning: no map figure for k {k:.2}: {error}");
    }
}

fn fmt(value: Option<f64>, unit: &str) -> String {
    value.map_or("-".to_owned(), |value| format!("{value:.2}{unit}"))
}

/// Where the missed cells of each k lie, summed over its missions.
fn print_missed_causes(rows: &[MissionRow]) {
    println!(
        "\nMissed cells by the rock that makes each lethal (summed): rim = the rock is lethal on the map and the cell\nin the outer cell's width of its truly lethal disc; inside = deeper; costly = the rock only costly; free = seen\nand left free; unseen = no mapped cell over it; near limit = of all, rocks within 5 cm of the climb limit;\nunobserved = of all, cells no feature landed in (their class comes from the rocks around them).\n"
    );
    println!(
        "{:>5} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11} {:>11}",
        "k",
        "missed",
        "rim",
        "inside",
        "costly",
        "free",
        "unseen",
        "steep",
        "near limit",
        "unobserved"
    );
    for k in ABUNDANCES {
        let mut sum = MissedCauses::default();
        let mut missions = 0;
        for causes in rows
            .iter()
            .filter(|row| row.golombek_k == k)
            .filter_map(|row| row.missed_by_cause)
        {
            missions += 1;
            sum += causes;
        }
        if missions == 0 {
            continue;
        }
        println!(
            "{:>5.2} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11} {:>11}",
            k,
            sum.missed(),
            sum.rim_of_lethal_rock,
            sum.inside_of_lethal_rock,
            sum.rock_only_costly,
            sum.rock_seen_free,
            sum.rock_not_seen,
            sum.too_steep,
            sum.near_limit_rock,
            sum.unobserved
        );
    }
}

/// Prints the table per k and writes eval_traversability.json.
fn finish(args: &TraversabilityArgs, rows: &[MissionRow], interrupted: bool) -> ExitCode {
    println!(
        "\nTruly lethal ground (the rover's body touches an unclimbable rock, or too steep) where the rover's camera had it in sight within 5 m,\nby what the final map made of it: missed = mapped traversable, uncertain = mapped maybe too tall (a cost), open = both;\nthe rocks' footprints are their collision hulls; in-view missed: over the camera's field of view, ground hidden behind rocks too;\nmap-frame missed: in sight, the map carried onto the truth by the rover VO's best rigid fit.\n"
    );
    println!(
        "{:>5} {:>9} {:>8} {:>10} {:>16} {:>16} {:>16} {:>16} {:>12} {:>16} {:>16}",
        "k",
        "missions",
        "reached",
        "collisions",
        "blocked ratio",
        "missed %",
        "uncertain %",
        "open %",
        "false cells",
        "in-view missed %",
        "map-frame missed %"
    );
    println!("{:>52}", "(median / worst)");
    for k in ABUNDANCES {
        let of_k: Vec<&MissionRow> = rows.iter().filter(|row| row.golombek_k == k).collect();
        if of_k.is_empty() {
            continue;
        }
        let spread = |figure: fn(&MissionRow) -> Option<f64>| {
            let mut values: Vec<f64> = of_k.iter().filter_map(|row| figure(row)).collect();
            median_and_worst(&mut values).map_or("-".to_owned(), |(median, worst)| {
                format!("{median:.2} / {worst:.2}")
            })
        };
        println!(
            "{:>5.2} {:>9} {:>8} {:>10} {:>16} {:>16} {:>16} {:>16} {:>12} {:>16} {:>16}",
            k,
            of_k.len(),
            of_k.iter().filter(|row| row.goal_reached).count(),
            of_k.iter().map(|row| row.collisions).sum::<u32>(),
            spread(|row| row.blocked_area_ratio),
            spread(|row| row.missed_lethal_percent),
            spread(|row| row.uncertain_lethal_percent),
            spread(|row| row.open_lethal_percent),
            of_k.iter()
                .filter_map(|row| row.false_lethal_cells)
                .sum::<usize>(),
            spread(|row| row.missed_lethal_percent_in_view),
            spread(|row| row.missed_lethal_percent_map_frame),
        );
    }
    print_missed_causes(rows);
    let contacts: Vec<_> = rows.iter().flat_map(|row| &row.contacts).collect();
    if !contacts.is_empty() {
        println!(
            "{}",
            hopnav_eval::mission::contacts_line(contacts.iter().copied())
        );
    }
    let path = args.out.join("eval_traversability.json");
    let written = serde_json::to_string_pretty(rows)
        .map_err(std::io::Error::other)
        .and_then(|text| std::fs::write(&path, text));
    if let Err(error) = written {
        eprintln!("error: cannot write {}: {error}", path.display());
        return ExitCode::FAILURE;
    }
    println!(
        "results: {} and traversability_k*.png in {}",
        path.display(),
        args.out.display()
    );
    if interrupted {
        eprintln!("interrupted after {} missions", rows.len());
        return ExitCode::from(crate::EXIT_INTERRUPTED);
    }
    ExitCode::SUCCESS
}
