//! `hopnav plan`: D* Lite on MovingAI benchmark maps, statically or with the map revealed as
//! the agent moves (against repeated A*).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_ipc::latency::LatencySummary;
use hopnav_planner::AStar;
use hopnav_planner::dynamic::{Algorithm, DynamicConfig, compare};
use hopnav_planner::movingai::{Scenario, load_map, load_scen};
use hopnav_planner::scenario::solve_scenario;

#[derive(Debug, Args)]
pub struct PlanArgs {
    /// MovingAI octile map (`.map`: '.', 'G', 'S' passable; '@', 'O', 'T', 'W' blocked).
    #[arg(long)]
    map: PathBuf,
    /// MovingAI scenario file (`.scen`, version 1) for that map.
    #[arg(long)]
    scen: PathBuf,
    /// Start with the map unknown and reveal it within R cells as the agent moves; compare
    /// D* Lite (incremental) with repeated A* on expansions, replans and time.
    #[arg(long, value_name = "R", value_parser = clap::value_parser!(u32).range(1..=1000))]
    dynamic: Option<u32>,
    /// Use at most this many scenarios (the first ones).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    limit: Option<u64>,
}

pub fn run(args: PlanArgs) -> ExitCode {
    let grid = match load_map(&args.map) {
        Ok(grid) => grid,
        Err(error) => {
            eprintln!("error: {error}");
            return ExitCode::from(crate::EXIT_CONFIG);
        }
    };
    let mut scenarios = match load_scen(&args.scen) {
        Ok(scenarios) => scenarios,
        Err(error) => {
            eprintln!("error: {error}");
            return ExitCode::from(crate::EXIT_CONFIG);
        }
    };
    if let Some(limit) = args.limit {
        scenarios.truncate(limit as usize);
    }
    let result = match args.dynamic {
        None => static_plans(&grid, &scenarios),
        Some(radius) => dynamic_plans(&grid, &scenarios, radius),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

/// Solves every scenario once; true when every cost matches the scenario's optimum.
fn static_plans(grid: &hopnav_planner::Grid, scenarios: &[Scenario]) -> Result<bool, String> {
    let mut astar = AStar::new(grid.cell_count());
    println!(
        "{:>5} {:>10} {:>10} {:>12} {:>12} {:>10} {:>10} {:>10} {:>5}",
        "#", "start", "goal", "cost", "optimal", "D* exp", "D* µs", "A* exp", "ok"
    );
    let mut mismatches = 0;
    for (number, scenario) in scenarios.iter().enumerate() {
        let outcome = solve_scenario(grid, scenario, &mut astar)
            .map_err(|e| format!("scenario {number}: {e}"))?;
        let ok = outcome.matches_optimal && outcome.planners_agree;
        mismatches += usize::from(!ok);
        println!(
            "{:>5} {:>10} {:>10} {:>12} {:>12.3} {:>10} {:>10.1} {:>10} {:>5}",
            number,
            outcome.start.to_string(),
            outcome.goal.to_string(),
            outcome
                .cost
                .map_or("unreachable".to_owned(), |cost| format!(
                    "{:.3}",
                    cost as f64 / 1000.0
                )),
            outcome.optimal_length,
            outcome.dstar_expansions,
            outcome.dstar_time.as_secs_f64() * 1e6,
            outcome.astar_expansions,
            if ok { "yes" } else { "NO" }
        );
    }
    println!(
        "{} scenarios, {mismatches} mismatches with the published optimum",
        scenarios.len()
    );
    Ok(mismatches == 0)
}

#[derive(Default)]
struct Totals {
    traverses: usize,
    reached: usize,
    expansions: u64,
    replans: u64,
    executed_cost: u64,
    replan_times_ns: Vec<u64>,
}

/// Traverses every scenario with the map revealed within `radius` cells, for every planner.
fn dynamic_plans(
    grid: &hopnav_planner::Grid,
    scenarios: &[Scenario],
    radius: u32,
) -> Result<bool, String> {
    let config = DynamicConfig {
        sensor_radius_cells: radius,
        max_steps: None,
    };
    let mut totals: Vec<(Algorithm, Totals)> = Vec::new();
    for (number, scenario) in scenarios.iter().enumerate() {
        eprint!("\rtraverse {}/{} …", number + 1, scenarios.len());
        let comparison = compare(grid, scenario.start, scenario.goal, &config)
            .map_err(|e| format!("scenario {number}: {e}"))?;
        for run in comparison.runs {
            let index = match totals
                .iter()
                .position(|(algorithm, _)| *algorithm == run.algorithm)
            {
                Some(index) => index,
                None => {
                    totals.push((run.algorithm, Totals::default()));
                    totals.len() - 1
                }
            };
            let entry = &mut totals[index].1;
            entry.traverses += 1;
            entry.reached += usize::from(run.reached_goal);
            entry.expansions += run.expansions;
            entry.replans += run.replans;
            entry.executed_cost += run.executed_cost;
            entry
                .replan_times_ns
                .extend(run.replan_times.iter().map(|time| time.as_nanos() as u64));
        }
    }
    eprintln!();
    println!(
        "\nmap revealed within {radius} cells; {} traverses per planner",
        scenarios.len()
    );
    println!(
        "{:<48} {:>8} {:>12} {:>9} {:>14} {:>11} {:>11}",
        "planner", "reached", "expansions", "replans", "path cost", "replan p50", "replan p99"
    );
    let dstar_expansions = totals
        .iter()
        .find(|(algorithm, _)| matches!(algorithm, Algorithm::DStarLite { .. }))
        .map(|(_, totals)| totals.expansions);
    for (algorithm, entry) in &mut totals {
        let replan = LatencySummary::from_ns(&mut entry.replan_times_ns);
        println!(
            "{:<48} {:>8} {:>12} {:>9} {:>14.1} {:>9.1}µs {:>9.1}µs",
            algorithm.to_string(),
            format!("{}/{}", entry.reached, entry.traverses),
            entry.expansions,
            entry.replans,
            entry.executed_cost as f64 / 1000.0,
            replan.p50_ms * 1e3,
            replan.p99_ms * 1e3
        );
    }
    if let Some(dstar) = dstar_expansions {
        println!("\nD* Lite (paper keys) expansions relative to each repeated A*:");
        for (algorithm, entry) in &totals {
            if matches!(algorithm, Algorithm::RepeatedAStar { .. }) && entry.expansions > 0 {
                println!(
                    "  {:<46} {:.3}x",
                    algorithm.to_string(),
                    dstar as f64 / entry.expansions as f64
                );
            }
        }
    }
    Ok(true)
}
