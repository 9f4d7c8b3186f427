//! Solves every scenario of a MovingAI `.scen` file on its `.map`.
//!
//! `cargo run --release --example plan_movingai -- MAP.map MAP.map.scen`

use std::path::PathBuf;

use hopnav_planner::AStar;
use hopnav_planner::movingai::{load_map, load_scen};
use hopnav_planner::scenario::solve_scenario;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1).map(PathBuf::from);
    let (Some(map_path), Some(scen_path)) = (args.next(), args.next()) else {
        return Err("usage: plan_movingai MAP.map MAP.map.scen".into());
    };
    let grid = load_map(&map_path)?;
    let scenarios = load_scen(&scen_path)?;
    let mut astar = AStar::new(grid.cell_count());
    println!(
        "{:>5} {:>10} {:>10} {:>12} {:>12} {:>9} {:>12} {:>9} {:>5}",
        "#", "start", "goal", "cost", "optimal", "D* exp", "D* µs", "A* exp", "ok"
    );
    let mut mismatches = 0;
    for (number, scenario) in scenarios.iter().enumerate() {
        let outcome = solve_scenario(&grid, scenario, &mut astar)?;
        mismatches += usize::from(!outcome.matches_optimal || !outcome.planners_agree);
        println!(
            "{:>5} {:>10} {:>10} {:>12} {:>12.3} {:>9} {:>12.1} {:>9} {:>5}",
            number,
            outcome.start.to_string(),
            outcome.goal.to_string(),
            outcome
                .cost
                .map_or("unreachable".to_string(), |cost| format!(
                    "{:.3}",
                    cost as f64 / 1000.0
                )),
            outcome.optimal_length,
            outcome.dstar_expansions,
            outcome.dstar_time.as_secs_f64() * 1e6,
            outcome.astar_expansions,
            if outcome.matches_optimal && outcome.planners_agree {
                "yes"
            } else {
                "NO"
            },
        );
    }
    println!("{} scenarios, {mismatches} mismatches", scenarios.len());
    Ok(())
}
