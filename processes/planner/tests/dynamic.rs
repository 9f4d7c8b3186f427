//! Unknown-terrain traverse simulation: all planners reach reachable goals along legal
//! moves, unreachable goals end the traverse cleanly, and runs are deterministic.

mod common;

use common::grid_from_rows;
use hopnav_planner::cost::path_cost;
use hopnav_planner::dynamic::{COMPARED_ALGORITHMS, DynamicConfig, compare, simulate};
use hopnav_planner::random_map::{RandomMapConfig, clustered_obstacles};
use hopnav_planner::rng::SplitMix64;
use hopnav_planner::{Cell, dijkstra_cost};

const CONFIG: DynamicConfig = DynamicConfig {
    sensor_radius_cells: 3,
    max_steps: None,
};

#[test]
fn all_planners_reach_the_goal_on_random_maps() {
    let map = RandomMapConfig {
        width: 40,
        height: 40,
        obstacle_fraction: 0.18,
        max_cluster_radius: 3,
        clear_radius: 2,
    };
    let (start, goal) = (Cell::new(1, 1), Cell::new(38, 38));
    let mut tested = 0;
    for seed in 0..12 {
        let truth =
            clustered_obstacles(&map, &[start, goal], &mut SplitMix64::new(seed)).expect("map");
        let Some(optimal) = dijkstra_cost(&truth, start, goal) else {
            continue;
        };
        tested += 1;
        let comparison = compare(&truth, start, goal, &CONFIG).expect("simulated");
        assert_eq!(comparison.runs.len(), COMPARED_ALGORITHMS.len());
        for run in &comparison.runs {
            assert!(run.reached_goal, "{} failed on seed {seed}", run.algorithm);
            assert_eq!(
                path_cost(&truth, &run.executed_path),
                Some(run.executed_cost),
                "executed path must be legal on the true map"
            );
            assert!(run.executed_cost >= optimal);
        }
    }
    assert!(tested >= 8);
}

#[test]
fn unreachable_goal_ends_the_traverse_without_success() {
    let rows = [
        "..........",
        "..........",
        "......####",
        "......#...",
        "......#...",
    ];
    let truth = grid_from_rows(&rows);
    let (start, goal) = (Cell::new(0, 0), Cell::new(8, 4));
    for algorithm in COMPARED_ALGORITHMS {
        let run = simulate(&truth, start, goal, algorithm, &CONFIG).expect("simulated");
        assert!(!run.reached_goal, "{algorithm}");
        assert!(run.executed_path.len() < 100);
    }
}

#[test]
fn traverses_are_deterministic_apart_from_timing() {
    let map = RandomMapConfig {
        width: 32,
        height: 32,
        ..RandomMapConfig::default()
    };
    let (start, goal) = (Cell::new(1, 1), Cell::new(30, 30));
    let truth = clustered_obstacles(&map, &[start, goal], &mut SplitMix64::new(5)).expect("map");
    let first = simulate(&truth, start, goal, COMPARED_ALGORITHMS[0], &CONFIG).expect("run");
    let second = simulate(&truth, start, goal, COMPARED_ALGORITHMS[0], &CONFIG).expect("run");
    assert_eq!(first.executed_path, second.executed_path);
    assert_eq!(first.expansions, second.expansions);
    assert_eq!(first.replans, second.replans);
}
