//! Property test: after every D* Lite replan, g(start) equals an independent Dijkstra's cost
//! on the currently known map, and the extracted path is valid and costs exactly g(start).
//! Random grids, random obstacle additions AND removals, extra-cost changes, unknown cells,
//! and random start moves (both along the path and arbitrary jumps).

mod common;

use common::assert_valid_path;
use hopnav_planner::rng::SplitMix64;
use hopnav_planner::{
    AStar, Cell, CellChange, CellState, DStarLite, Grid, KeyTieBreak, PlanError, SearchDirection,
    TieBreak, dijkstra_cost,
};

fn random_cell(grid: &Grid, rng: &mut SplitMix64) -> Cell {
    Cell::new(rng.below_u32(grid.width()), rng.below_u32(grid.height()))
}

fn random_state(rng: &mut SplitMix64, obstacle_percent: u64) -> CellState {
    if rng.chance(obstacle_percent, 100) {
        CellState::Obstacle
    } else if rng.chance(1, 2) {
        CellState::Unknown
    } else {
        CellState::Free
    }
}

fn random_extra(rng: &mut SplitMix64) -> u32 {
    if rng.chance(1, 4) {
        rng.below_u32(3000)
    } else {
        0
    }
}

/// Checks the planner against the oracle; returns whether the goal was reachable.
fn check_replan(planner: &mut DStarLite, astar: &mut AStar, context: &str) -> bool {
    let outcome = planner.compute_shortest_path();
    let grid = planner.grid();
    let (start, goal) = (planner.start(), planner.goal());
    let oracle = dijkstra_cost(grid, start, goal);
    let g_start = planner.g_value(start).expect("start in grid");
    match (outcome, oracle) {
        (Ok(stats), Some(expected)) => {
            assert_eq!(stats.cost, expected, "{context}: reported cost");
            assert_eq!(g_start, expected, "{context}: g(start)");
            assert_eq!(planner.cost_to_goal(), Some(expected), "{context}");
            let path = planner
                .path()
                .unwrap_or_else(|| panic!("{context}: no path"));
            let path_cost = assert_valid_path(grid, &path, start, goal);
            assert_eq!(path_cost, expected, "{context}: path cost");
            let astar_cost = astar
                .search(grid, start, goal)
                .map(|found| found.stats.cost);
            assert_eq!(astar_cost, Ok(expected), "{context}: A*");
            let mut backward = AStar::configured(0, TieBreak::SmallerG, SearchDirection::Backward);
            let found = backward.search(grid, start, goal).expect("backward A*");
            assert_eq!(found.stats.cost, expected, "{context}: backward A*");
            assert_eq!(assert_valid_path(grid, &found.path, start, goal), expected);
            true
        }
        (Err(PlanError::Unreachable), None) => {
            assert_eq!(planner.cost_to_goal(), None, "{context}");
            assert_eq!(planner.path(), None, "{context}");
            assert_eq!(
                astar
                    .search(grid, start, goal)
                    .map(|found| found.stats.cost),
                Err(PlanError::Unreachable),
                "{context}: A*"
            );
            false
        }
        (outcome, oracle) => panic!("{context}: D* Lite {outcome:?} but Dijkstra {oracle:?}"),
    }
}

#[test]
fn g_start_matches_dijkstra_after_every_replan() {
    oracle_property(KeyTieBreak::Paper, 0x5EED_D57A);
}

#[test]
fn g_start_matches_dijkstra_after_every_replan_toward_start_ties() {
    oracle_property(KeyTieBreak::TowardStart, 0x5EED_D57B);
}

fn oracle_property(tie_break: KeyTieBreak, seed: u64) {
    let mut rng = SplitMix64::new(seed);
    let mut replans = 0;
    let mut reachable = 0;
    let mut removals = 0;
    for world in 0..60 {
        let width = 4 + rng.below_u32(24);
        let height = 4 + rng.below_u32(24);
        let obstacle_percent = 5 + rng.below(20);
        let mut grid = Grid::new(width, height, CellState::Free).expect("grid");
        for index in 0..grid.cell_count() {
            let cell = grid.cell_at(index).expect("cell");
            let state = random_state(&mut rng, obstacle_percent);
            let extra = random_extra(&mut rng);
            grid.set(cell, state, extra).expect("set");
        }
        let start = random_cell(&grid, &mut rng);
        let goal = random_cell(&grid, &mut rng);
        let mut planner = DStarLite::with_tie_break(grid, start, goal, tie_break).expect("planner");
        let mut astar = AStar::new(planner.grid().cell_count());
        reachable += usize::from(check_replan(&mut planner, &mut astar, "initial"));
        replans += 1;
        for round in 0..25 {
            // Move the start: usually one step along the path, sometimes a jump.
            if rng.chance(1, 5) {
                let jump = random_cell(planner.grid(), &mut rng);
                planner.move_start(jump).expect("in grid");
            } else {
                for _ in 0..=rng.below(3) {
                    if let Some(next) = planner.next_step() {
                        planner.move_start(next).expect("in grid");
                    }
                }
            }
            // Change a few cells, mostly near the start or on the path.
            let path = planner.path().unwrap_or_default();
            let mut changes = Vec::new();
            for _ in 0..1 + rng.below(6) {
                let cell = if !path.is_empty() && rng.chance(1, 2) {
                    path[rng.below(path.len() as u64) as usize]
                } else {
                    random_cell(planner.grid(), &mut rng)
                };
                // Keep the density roughly stable: obstacles are often removed, free cells
                // sometimes blocked.
                let was_obstacle = planner.grid().state(cell) == Some(CellState::Obstacle);
                let state = random_state(&mut rng, if was_obstacle { 30 } else { 20 });
                if was_obstacle && state != CellState::Obstacle {
                    removals += 1;
                }
                changes.push(CellChange::new(cell, state, random_extra(&mut rng)));
            }
            planner.update_cells(&changes).expect("changes in grid");
            let context = format!("world {world} round {round}");
            reachable += usize::from(check_replan(&mut planner, &mut astar, &context));
            replans += 1;
        }
    }
    assert!(replans >= 1000, "only {replans} replans");
    assert!(
        reachable > replans / 3,
        "too few reachable cases: {reachable}/{replans}"
    );
    assert!(removals > 200, "too few obstacle removals: {removals}");
}

#[test]
fn long_traverse_with_many_small_updates_stays_exact() {
    long_traverse(KeyTieBreak::Paper);
    long_traverse(KeyTieBreak::TowardStart);
}

/// One larger world, many consecutive replans: exercises k_m accumulation.
fn long_traverse(tie_break: KeyTieBreak) {
    let mut rng = SplitMix64::new(42);
    let mut grid = Grid::new(48, 48, CellState::Unknown).expect("grid");
    for index in 0..grid.cell_count() {
        if rng.chance(1, 6) {
            let cell = grid.cell_at(index).expect("cell");
            grid.set(cell, CellState::Obstacle, 0).expect("set");
        }
    }
    let start = Cell::new(0, 0);
    let goal = Cell::new(47, 47);
    grid.set(start, CellState::Free, 0).expect("set");
    grid.set(goal, CellState::Free, 0).expect("set");
    let mut planner = DStarLite::with_tie_break(grid, start, goal, tie_break).expect("planner");
    let mut astar = AStar::new(48 * 48);
    check_replan(&mut planner, &mut astar, "initial");
    for round in 0..400 {
        if let Some(next) = planner.next_step() {
            planner.move_start(next).expect("in grid");
        }
        if planner.start() == goal {
            planner
                .move_start(random_cell(planner.grid(), &mut rng))
                .expect("in grid");
        }
        let mut changes = Vec::new();
        for _ in 0..3 {
            let near = planner.start();
            let x = (near.x + rng.below_u32(7)).saturating_sub(3).min(47);
            let y = (near.y + rng.below_u32(7)).saturating_sub(3).min(47);
            let cell = Cell::new(x, y);
            if cell == planner.start() || cell == goal {
                continue;
            }
            let state = if rng.chance(1, 3) {
                CellState::Obstacle
            } else {
                CellState::Free
            };
            changes.push(CellChange::new(cell, state, random_extra(&mut rng)));
        }
        planner.update_cells(&changes).expect("changes in grid");
        check_replan(&mut planner, &mut astar, &format!("round {round}"));
    }
}
